// The mutation contract (Mitsuba 0.6 bidir/mutator.h shape): a perturbation says whether it
// applies to a path, proposes a new path into the chain's other slot, and returns what the
// Metropolis-Hastings acceptance needs: the target function of both paths in its own measure
// (path_space.glsl) and the ratio of transition densities T(y->x) / T(x->y) in that
// measure. Counting proposals and acceptances per type is the caller's job.
#ifndef PMCR_MUTATION_GLSL
#define PMCR_MUTATION_GLSL

#include "methods/energy_redistribution/path_space.glsl"
#include "common/rng.glsl"

struct MutationResult {
    float targetX;          // F_nu(x) = lum(P(x)) * Gamma(x)
    float targetY;          // F_nu(y)
    float transitionRatio;  // T(y -> x) / T(x -> y)
    vec3 throughputY;       // P(y), RGB
    vec2 rasterY;           // film position of y's x1
};

// a(x -> y) = min(1, F(y) T(y->x) / (F(x) T(x->y)))  (ERPT sec. 2.4; PMC-ER eq. 7)
float acceptance(MutationResult r) {
    if (!(r.targetY > 0.0) || !(r.transitionRatio > 0.0)) return 0.0;
    if (!(r.targetX > 0.0)) return 1.0;
    float a = r.targetY * r.transitionRatio / r.targetX;
    return isinf(a) || isnan(a) ? (isnan(a) ? 0.0 : 1.0) : min(1.0, a);
}

// How the angular perturbation of a direction is drawn.
struct AngleSampler {
    float thetaMin;    // log-uniform between thetaMin and thetaMax (Veach and Guibas 1997),
    float thetaMax;    // or uniform in [0, thetaMax] when `uniformLaw` (PMC-ER sec. 4.4)
    bool uniformLaw;
    // The uniform law's angle was drawn from one component of a mixture over `mixtureCount`
    // (0: none) upper bounds theta(d_j) with weights alpha_j (PMC-ER eq. 8, the radii); the
    // acceptance then uses the density of the whole mixture (mutate_caustic.glsl).
    uint mixtureCount;
    vec3 mixtureWeights;
    vec3 mixtureThetas;
};

AngleSampler angleSampler(float thetaMin, float thetaMax, bool uniformLaw) {
    AngleSampler s;
    s.thetaMin = thetaMin;
    s.thetaMax = thetaMax;
    s.uniformLaw = uniformLaw;
    s.mixtureCount = 0u;
    s.mixtureWeights = vec3(0.0);
    s.mixtureThetas = vec3(0.0);
    return s;
}

// Samples a perturbation angle; with the log-uniform law p(theta) ~ 1/theta the proposal is
// symmetric in solid angle, because the reverse move needs the same angle.
float sampleTheta(AngleSampler s, float u) {
    if (s.uniformLaw) return u * s.thetaMax;
    return s.thetaMax * exp(-log(s.thetaMax / s.thetaMin) * u);
}

// The unit direction at angle theta from `center`, at azimuth phi.
vec3 rotateAround(vec3 center, float theta, float phi) {
    vec3 t, b;
    orthonormalBasis(center, t, b);
    float s = sin(theta);
    return normalize(cos(theta) * center + s * (cos(phi) * t + sin(phi) * b));
}

// Traces to the next surface; false on a miss.
bool traceToSurface(vec3 origin, vec3 dir, inout uint rays, out SurfacePoint s, out vec2 b) {
    Hit hit;
    rays += 1u;
    if (!traceClosest(origin, dir, FLOAT_MAX, hit)) return false;
    b = vec2(hit.b1, hit.b2);
    s = surfaceAt(hit.triangle, b);
    return true;
}

// Follows a delta lobe from `s` hit by a ray travelling along `dir`: the new direction and the
// origin of the next ray. False when the material has no such lobe or the shading and the
// geometric normal disagree on the side of the new direction.
bool followSpecular(SurfacePoint s, vec3 dir, ChainVertex like, out vec3 nextDir, out vec3 origin) {
    ShadingPoint sh = makeShadingPoint(s, -dir);
    vec3 wiLocal, weight;
    nextDir = vec3(0.0);
    origin = vec3(0.0);
    if (!bsdfSpecular(sh.bsdf, sh.woLocal, vertexLobe(like), vertexTransmits(like), wiLocal, weight))
        return false;
    nextDir = toWorld(sh.frame, wiLocal);
    if ((dot(nextDir, sh.ng) > 0.0) != (wiLocal.z > 0.0)) return false;
    origin = spawnOrigin(sh, nextDir);
    return true;
}

// Unoccluded segment between two surface points.
bool segmentVisible(SurfacePoint a, SurfacePoint b, inout uint rays) {
    vec3 d = b.position - a.position;
    vec3 origin = offsetRayOrigin(a.position, dot(d, a.normal) > 0.0 ? a.normal : -a.normal);
    vec3 target = offsetRayOrigin(b.position, dot(d, b.normal) < 0.0 ? b.normal : -b.normal);
    vec3 e = target - origin;
    float dist = length(e);
    rays += 1u;
    return dist > 0.0 && !traceAny(origin, e / dist, dist * (1.0 - 1e-4));
}

// Unoccluded segment from surface point a to vertex bv at b: to a surface point, to a point
// or spot light's position, or a ray along a direction that escapes the scene.
bool vertexVisible(SurfacePoint a, ChainVertex bv, SurfacePoint b, inout uint rays) {
#ifndef PMCR_OTHER_LIGHTS
    return segmentVisible(a, b, rays);
#else
    if (!vertexIsDirection(bv) && !vertexPunctual(bv)) return segmentVisible(a, b, rays);
    vec3 w = vertexIsDirection(bv) ? vertexDirection(bv) : b.position - a.position;
    vec3 origin = offsetRayOrigin(a.position, dot(w, a.normal) > 0.0 ? a.normal : -a.normal);
    rays += 1u;
    if (vertexIsDirection(bv)) return !traceAny(origin, w, FLOAT_MAX);
    vec3 e = b.position - origin;
    float dist = length(e);
    return dist > 0.0 && !traceAny(origin, e / dist, dist * (1.0 - 1e-4));
#endif
}

// Copies vertices [from, to) of slot `src` into slot `dst` (the unchanged part of a path).
void copyVertices(uint src, uint dst, uint from, uint to) {
    for (uint i = from; i < to; ++i) chainVertices[dst + i] = chainVertices[src + i];
}

#endif
