// Lens perturbation (ERPT sec. 4.3 and appendix A; Veach and Guibas 1997 sec. 5.3.1): the
// raster position moves uniformly within a disk of `radius` pixels, the eye subpath is retraced
// through the same specular bounces to the first D vertex, and
//  - if the next vertex is not specular, the new vertex is reconnected to it;
//  - otherwise the direction leaving the D vertex is perturbed by an angle (the same law as the
//    caustic perturbation) and the next specular chain is traced to the next D vertex, and so on
//    until two non-specular vertices follow each other ("E S* D (S+ D)* (D|L)").
// A proposal that changes the type sequence, misses, is occluded or leaves the image is invalid.
// Other lights (light_vertex.glsl, path_space.glsl): a reconnection to a punctual light or a
// direction keeps the light vertex (a point light's position, the direction towards the
// environment or a directional light); an eye subpath or specular chain that must reach the
// light is traced, and it reaches the environment when it escapes (a new direction), a
// punctual light never (invalid: a delta that no traced ray meets).
// The proposal is symmetric in its parameters (disk, and symmetric angle laws), so
// T(y->x) / T(x->y) = 1 and the acceptance compares F_nu (path_space.glsl).
#ifndef PMCR_MUTATE_LENS_GLSL
#define PMCR_MUTATE_LENS_GLSL

#include "methods/energy_redistribution/mutation.glsl"

// |cos_s| of the direction x_i -> x_i+1 at vertex i of the path at `base` (wo towards x_i-1).
float outgoingShadingCos(uint base, uint i) {
    SurfacePoint s = pathPoint(base, i);
    vec3 previous = i == 0u ? sceneInfo.cameraPosition : pathPoint(base, i - 1u).position;
    ShadingPoint sh = makeShadingPoint(s, normalize(previous - s.position));
    return abs(dot(sh.frame.n, normalize(pathPoint(base, i + 1u).position - s.position)));
}

bool mutateLens(uint xBase, uint yBase, uint k, vec2 raster, vec3 throughputX, float radius,
                AngleSampler angle, inout Rng rng, inout uint rays, out MutationResult r) {
    r.targetX = 0.0;
    r.targetY = 0.0;
    r.transitionRatio = 1.0;
    r.throughputY = vec3(0.0);
    r.rasterY = raster + radius * sampleUniformDiskConcentric(rngNext2(rng));
    if (any(lessThan(r.rasterY, vec2(0.0))) ||
        any(greaterThanEqual(r.rasterY, vec2(sceneInfo.width, sceneInfo.height))))
        return false;

    vec3 origin = sceneInfo.cameraPosition;
    vec3 dir = cameraDirection(r.rasterY);
    float gammaX = 1.0, gammaY = 1.0;
    for (uint i = 0u; i < k; ++i) {
        ChainVertex xv = chainVertices[xBase + i];
#ifdef PMCR_OTHER_LIGHTS
        if (vertexPunctual(xv) || vertexEnvironment(xv)) {
            // The light vertex reached by tracing (E S* L or after a perturbed direction).
            if (!vertexEnvironment(xv)) return false;
            rays += 1u;
            if (traceAny(origin, dir, FLOAT_MAX)) return false;
            chainVertices[yBase + i] = makeChainVertex(xv.triangle, octEncode(dir), xv.flags);
            break;
        }
#endif
        SurfacePoint s;
        vec2 b;
        if (!traceToSurface(origin, dir, rays, s, b)) return false;
        chainVertices[yBase + i] = makeChainVertex(s.triangle, b, xv.flags);
        if (vertexEmitter(xv)) {
            // The eye subpath ends on the light itself (E S* L): nothing to reconnect.
            if (i + 1u != k || maxComponent(emittedRadiance(s, -dir)) <= 0.0) return false;
            break;
        }
        if (vertexSpecular(xv)) {
            if (!followSpecular(s, dir, xv, dir, origin)) return false;
            continue;
        }
        // A D vertex.
        ShadingPoint sh = makeShadingPoint(s, -dir);
        if (!bsdfHasNonDelta(sh.bsdf)) return false;
        ChainVertex xNext = chainVertices[xBase + i + 1u];
        if (!vertexSpecular(xNext)) {
            // Reconnect to x_i+1 and keep the rest of the path.
            SurfacePoint next = vertexPoint(xNext);
            if (!vertexVisible(s, xNext, next, rays)) return false;
            copyVertices(xBase, yBase, i + 1u, k);
            gammaY *= reconnectionFactorTo(s, -dir, xNext, next);
            SurfacePoint xi = pathPoint(xBase, i);
            vec3 xPrevious = i == 0u ? sceneInfo.cameraPosition : pathPoint(xBase, i - 1u).position;
            gammaX *= reconnectionFactorTo(xi, normalize(xPrevious - xi.position), xNext, next);
            break;
        }
        // Perturb the direction leaving this D vertex around x's direction x_i -> x_i+1.
        vec3 center = normalize(pathPoint(xBase, i + 1u).position - pathPoint(xBase, i).position);
        vec2 u = rngNext2(rng);
        vec3 newDir = rotateAround(center, sampleTheta(angle, u.x), TWO_PI * u.y);
        gammaY *= abs(dot(sh.frame.n, newDir));
        gammaX *= outgoingShadingCos(xBase, i);
        dir = newDir;
        origin = spawnOrigin(sh, dir);
    }
    r.throughputY = pathThroughput(yBase, k);
    r.targetY = luminance(r.throughputY) * gammaY;
    r.targetX = luminance(throughputX) * gammaX;
    return r.targetY > 0.0;
}

#endif
