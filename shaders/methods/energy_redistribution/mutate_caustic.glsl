// Caustic perturbation (ERPT sec. 4.3 and appendix A; Veach and Guibas 1997 sec. 5.3.2): for a
// path whose suffix is (D|L) S* D E, the direction leaving the head x_h (the first non-specular
// vertex after x1, counted from the eye) is perturbed by an angle theta, the specular chain is
// retraced with the same bounce types to a new x1, and x1 is connected to the eye: the raster
// position follows from the path.
//
// Angles: log-uniform in [thetaMin, thetaMax] (ERPT footnote 4, after Veach), symmetric; or, for
// PMC-ER's radius-d components, uniform in [0, thetaMax(d)] with (PMC-ER eq. 6)
//   thetaMax(d) = theta(d) |x0 - x1| / sum_{i=1}^{h-1} |x_i - x_i+1|,
// theta(d) being the angle that moves the image point by d pixels: rotating the head's direction
// by theta moves x1 by about theta * (chain length), i.e. the image point by that over
// |x0 - x1|. (The paper's eq. 6 reads |y_n-1 - y_n-2|, the x1-x2 distance; the eye distance is
// what makes the move d pixels, so pmcr uses it. Either way the state-dependent thetaMax enters
// the acceptance through T(y->x) / T(x->y) = thetaMax(x) / thetaMax(y), so it stays unbiased.)
#ifndef PMCR_MUTATE_CAUSTIC_GLSL
#define PMCR_MUTATE_CAUSTIC_GLSL

#include "methods/energy_redistribution/mutation.glsl"

// Index of the head x_h: the first non-specular vertex after x1. Returns 0 when the caustic
// perturbation does not apply (x1 specular or an emitter, or a path of one vertex), and when the
// head is a direction (the environment, a directional light): turning "the direction leaving
// the head" is then meaningless. A direction vertex is the whole beam of parallel rays arriving
// along w; which surface point x_h-1 they hit is a position on x_h-1's surface, not a function
// of w, and perturbing w alone leaves x_h-1 where it is (the specular chain could not move
// towards a new x1). A correct proposal would perturb x_h-1's position in area measure with
// the direction held fixed (a different mutation, not the caustic one). So such paths get no
// caustic proposals: in the ERPT and mix modes they take the lens perturbation, in caustic-only
// mode they stay put (a proposal that always returns the current state is in detailed balance
// with any target). Deciding by the light vertex's kind keeps the choice of mutation a function
// of the path's type, which no perturbation changes.
uint causticHead(uint base, uint k) {
    if (k < 2u) return 0u;
    ChainVertex x1 = chainVertices[base];
    if (vertexSpecular(x1) || vertexEmitter(x1)) return 0u;
    for (uint i = 1u; i < k; ++i) {
        ChainVertex v = chainVertices[base + i];
#ifdef PMCR_OTHER_LIGHTS
        if (!vertexSpecular(v)) return vertexIsDirection(v) ? 0u : i;
#else
        if (!vertexSpecular(v)) return i;
#endif
    }
    return 0u;
}

// |cos_g| at the head x_h towards x_h-1 in the caustic Gamma: 1 at a point or spot light, whose
// measure is a delta in position, not area (path_space.glsl).
float headCosine(uint base, uint h, SurfacePoint head, vec3 towardsEye) {
#ifdef PMCR_OTHER_LIGHTS
    if (vertexPunctual(chainVertices[base + h])) return 1.0;
#endif
    return absCosGeometric(head, towardsEye);
}

// Gamma of the caustic measure (path_space.glsl) for the path at `base` with head h.
float causticGamma(uint base, uint h) {
    SurfacePoint x1 = pathPoint(base, 0u);
    SurfacePoint x2 = pathPoint(base, 1u);
    SurfacePoint head = pathPoint(base, h);
    SurfacePoint beforeHead = pathPoint(base, h - 1u);
    vec3 toEye = normalize(sceneInfo.cameraPosition - x1.position);
    vec3 w12 = normalize(x2.position - x1.position);
    ShadingPoint sh1 = makeShadingPoint(x1, toEye);
    float cosG1 = absCosGeometric(x1, w12);
    if (cosG1 <= 0.0) return 0.0;
    float gamma = rasterDensity(x1) * abs(dot(sh1.frame.n, w12)) / cosG1 *
                  headCosine(base, h, head, normalize(beforeHead.position - head.position));
    // Conservation of etendue through the chain, vertex by vertex. Free flight keeps
    // |cos_g| dA dw; a delta lobe about the shading normal n_s maps solid angle as
    // eta_in^2 |cos_s(in)| dw_in = eta_out^2 |cos_s(out)| dw_out at a fixed point (its dependence
    // on the position drops out of the determinant), so each S vertex contributes eta^2 (on a
    // refraction; 1 through a thin sheet or a BLEND pass, bsdfLobeEta) and, where n_s is not the geometric normal (interpolated normals), the
    // factor |cos_s(in)| |cos_g(out)| / (|cos_g(in)| |cos_s(out)|), in = the light's side. A
    // smooth clear coat mirrors about its own normal n_c (bsdf.glsl clearcoatNormal), which then
    // takes n_s's place: the factor is |cos_g(out)| / |cos_g(in)| (a mirror keeps |cos_c|).
    vec3 previous = x1.position;
    for (uint i = 1u; i < h; ++i) {
        ChainVertex v = chainVertices[base + i];
        SurfacePoint s = pathPoint(base, i);
        vec3 wEye = normalize(previous - s.position);
        vec3 wLight = normalize(pathPoint(base, i + 1u).position - s.position);
        ShadingPoint sh = makeShadingPoint(s, wEye);
        gamma *= sqr(bsdfLobeEta(sh.bsdf, vertexLobe(v), vertexTransmits(v)));
        vec3 n = sh.frame.n;
        if (sh.bsdf.clearcoatTilted && vertexLobe(v) == LOBE_CLEARCOAT)
            n = toWorld(sh.frame, sh.bsdf.clearcoatNormal);
        float denominator = abs(dot(s.normal, wLight)) * abs(dot(n, wEye));
        if (!(denominator > 0.0)) return 0.0;
        gamma *= abs(dot(n, wLight)) * abs(dot(s.normal, wEye)) / denominator;
        previous = s.position;
    }
    return gamma;
}

// Total length of the chain from the head to x1, and the eye distance (PMC-ER eq. 6). Capped at
// pi / 2 (a large radius on a small image asks for more): beyond pi the angles would cover
// directions twice and the density 1 / (2 pi thetaMax sin theta) the acceptance uses would not
// hold. The cap is part of the state-dependent law, so T(y->x) / T(x->y) stays exact.
float causticThetaMax(uint base, uint h, float thetaPerPixels) {
    float chain = 0.0;
    for (uint i = 0u; i < h; ++i)
        chain += length(pathPoint(base, i + 1u).position - pathPoint(base, i).position);
    float eye = length(pathPoint(base, 0u).position - sceneInfo.cameraPosition);
    return chain > 0.0 ? min(thetaPerPixels * eye / chain, 0.5 * PI) : 0.0;
}

// The density in theta of the uniform law's mixture over radii at the path in `base` (PMC-ER
// eq. 8 restricted to the caustic components): sum_j alpha_j [theta <= thetaMax_j] / thetaMax_j,
// thetaMax_j = causticThetaMax(theta(d_j)). The solid-angle density divides it by
// 2 pi sin theta, the same at x and y.
float causticMixtureDensity(AngleSampler angle, uint base, uint h, float theta) {
    float p = 0.0;
    for (uint j = 0u; j < angle.mixtureCount; ++j) {
        float thetaMax = causticThetaMax(base, h, angle.mixtureThetas[j]);
        if (thetaMax > 0.0 && theta <= thetaMax) p += angle.mixtureWeights[j] / thetaMax;
    }
    return p;
}

// `angle.thetaMax` is the log-uniform upper bound, or for the uniform law theta(d) (radians for
// d pixels), scaled per path by causticThetaMax. With a mixture (angle.mixtureCount > 0) the
// angle comes from the component angle.thetaMax and T(y->x) / T(x->y) is the ratio of the whole
// mixture's densities: the reverse move may come from any radius, so y is valid when one reaches.
bool mutateCaustic(uint xBase, uint yBase, uint k, vec3 throughputX, AngleSampler angle,
                   inout Rng rng, inout uint rays, out MutationResult r) {
    r.targetX = 0.0;
    r.targetY = 0.0;
    r.transitionRatio = 1.0;
    r.throughputY = vec3(0.0);
    r.rasterY = vec2(-1.0);
    uint h = causticHead(xBase, k);
    if (h == 0u) return false;

    SurfacePoint head = pathPoint(xBase, h);
    vec3 center = normalize(pathPoint(xBase, h - 1u).position - head.position);
    AngleSampler law = angle;
    float thetaMaxX = 0.0;
    if (angle.uniformLaw) {
        thetaMaxX = causticThetaMax(xBase, h, angle.thetaMax);
        law.thetaMax = thetaMaxX;
    }
    vec2 u = rngNext2(rng);
    float theta = sampleTheta(law, u.x);
    vec3 dir = rotateAround(center, theta, TWO_PI * u.y);
    vec3 origin = offsetRayOrigin(head.position, dot(dir, head.normal) > 0.0 ? head.normal : -head.normal);
#ifdef PMCR_OTHER_LIGHTS
    // A point light's position is not on a surface: its rays leave from it.
    if (vertexPunctual(chainVertices[xBase + h])) origin = head.position;
#endif

    // Retrace the chain from the head towards the eye: x_h-1 ... x1.
    SurfacePoint s;
    for (int i = int(h) - 1; i >= 0; --i) {
        ChainVertex xv = chainVertices[xBase + uint(i)];
        vec2 b;
        if (!traceToSurface(origin, dir, rays, s, b)) return false;
        chainVertices[yBase + uint(i)] = makeChainVertex(s.triangle, b, xv.flags);
        if (i > 0) {
            if (!followSpecular(s, dir, xv, dir, origin)) return false;
        } else if (!bsdfHasNonDelta(makeShadingPoint(s, -dir).bsdf)) {
            return false;
        }
    }
    copyVertices(xBase, yBase, h, k);

    // Connect the new x1 to the eye: inside the image and unoccluded.
    vec3 toX1 = s.position - sceneInfo.cameraPosition;
    float dist = length(toX1);
    if (!cameraRasterPosition(toX1 / dist, r.rasterY)) return false;
    vec3 fromX1 = offsetRayOrigin(s.position, dot(toX1, s.normal) < 0.0 ? s.normal : -s.normal);
    vec3 e = sceneInfo.cameraPosition - fromX1;
    rays += 1u;
    if (traceAny(fromX1, normalize(e), length(e))) return false;

    if (angle.uniformLaw && angle.mixtureCount > 0u) {
        float pY = causticMixtureDensity(angle, yBase, h, theta);
        if (!(pY > 0.0)) return false;
        r.transitionRatio = pY / causticMixtureDensity(angle, xBase, h, theta);
    } else if (angle.uniformLaw) {
        float thetaMaxY = causticThetaMax(yBase, h, angle.thetaMax);
        if (!(theta <= thetaMaxY) || !(thetaMaxY > 0.0)) return false;
        r.transitionRatio = thetaMaxX / thetaMaxY;
    }
    r.throughputY = pathThroughput(yBase, k);
    r.targetY = luminance(r.throughputY) * causticGamma(yBase, h);
    r.targetX = luminance(throughputX) * causticGamma(xBase, h);
    return r.targetY > 0.0;
}

#endif
