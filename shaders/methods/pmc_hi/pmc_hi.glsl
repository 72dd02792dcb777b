// PMC-HI, the adaptive hemispheric-integral sampler (Fan, Lai, Chenney and Dyer, "Population
// Monte Carlo Samplers for Rendering", sec. 5) for direct lighting: each estimate of the light
// reflected at a shading point runs a tiny population Monte Carlo over incident directions.
//
// Kernel (eq. 7): K = a_BSDF h_BSDF + sum_l a_l h_l + a_cone h_cone (+ a_env h_env), one light
// component per light (light_groups.glsl) or one shared by all (the group of all emitters), and
// in a scene with an environment light one more component, the environment's own importance
// sampling (common/environment.glsl envSample; issue 22: "each light (or group) is a mixture
// component, the environment one more").
// Each iteration draws N = populationPerComponent * m directions (m = slots in use, the cone
// included; iteration 0 initialPopulationPerComponent * m) by deterministic mixture sampling,
// traces one ray per direction and weights it by w = f / K (eq. 8, the full mixture:
// Rao-Blackwellised); the weights' shares per component give the next a_k (eq. 9), their mean
// direction and spread the next cone. The estimate is the average of all the iterations' w
// (eq. 1): each iteration's (1/N) sum w is unbiased given its kernel, and the fixed weights
// N / (all samples) sum to 1.
//
// Unbiasedness: given the kernel, E[(1/N) sum f/K] = sum_k (E[n_k]/N) int h_k f/K = int f,
// since E[n_k] = N a_k and sum_k a_k h_k = K, wherever K > 0. The kernel of iteration t depends
// only on earlier iterations, and a defensive floor on the BSDF and light weights keeps K > 0
// wherever f > 0 (every emitter direction is covered by a light component, every delta lobe by
// the BSDF component), so every iteration, and their fixed-weight average, is unbiased.
//
// Densities are those of the sampled direction: a light component's density of w is its area
// density at the first surface the ray from x along w hits, converted to solid angle, when that
// surface is one of its emitters. A light-sampled direction is traced as a shadow ray to the
// sampled point and scores 0 unless it is visible -- so a point behind another part of a
// non-convex light scores 0 too, and the density of the directions that score is exactly that
// first-hit density. Likewise an environment-sampled direction is traced to infinity and scores
// only when it escapes: the environment component's density of the directions that score is
// envPdf where a ray escapes and 0 where it hits a surface, and a BSDF or cone direction that
// escapes scores the environment's radiance with the full mixture density there (the cone's,
// the BSDF's and the environment's; no light component reaches an escaping direction).
//
// Punctual lights are not components: a point, spot or directional light illuminates x from one
// direction, a delta distribution with no density that K could include, and no BSDF, cone or
// environment direction ever reaches it (a set of measure zero). Their direct lighting is added
// beside the mixture by a separate, unweighted next-event estimate (pmcHiPunctualDirect), which
// is unbiased alone; the PMC-HI estimate covers everything else, so the sum is unbiased.
#ifndef PMCR_PMC_HI_GLSL
#define PMCR_PMC_HI_GLSL

#include "methods/pmc_hi/light_groups.glsl"
#include "common/environment.glsl"
#include "common/punctual_sampling.glsl"
#include "common/sampler.glsl"
#include "common/shading.glsl"

// Whether the environment is a component: only in the kernel variant with it compiled in
// (PMCR_OTHER_LIGHTS), so that scenes lit by emitters alone pay nothing for it.
bool pmcHiHasEnvironment(PmcHiParams p) {
    return hasEnvironment() && (p.flags & PMC_HI_FLAG_ENVIRONMENT) != 0u;
}

// The environment's slot (when it is a component): after the light components'.
uint pmcHiEnvironmentSlot(PmcHiParams p) { return PMC_HI_LIGHT + p.lightComponents; }

// Slots in use: BSDF, cone, the light components, and the environment's.
uint pmcHiSlots(PmcHiParams p) {
    return pmcHiEnvironmentSlot(p) + (pmcHiHasEnvironment(p) ? 1u : 0u);
}

// Deterministic mixture sampling (Hesterberg 1995; the paper's sec. 4.3): floor(N a_k) samples
// from each of the first m components, the R = N - sum floor(N a_k) others by systematic
// sampling of the residuals r_k = N a_k - floor(N a_k) (points u + j, j < R, on their cumulative
// sum scaled to R). E[counts_k] = N a_k and the counts sum to N.
void pmcHiAllocate(float alpha[PMC_HI_MAX_COMPONENTS], uint m, uint N, float u,
                   out uint counts[PMC_HI_MAX_COMPONENTS]) {
    float residual[PMC_HI_MAX_COMPONENTS];
    uint assigned = 0u;
    float residualSum = 0.0;
    uint lastResidual = 0u;
    for (uint k = 0u; k < PMC_HI_MAX_COMPONENTS; ++k) {
        counts[k] = 0u;
        residual[k] = 0.0;
        if (k >= m) continue;
        float target = float(N) * max(alpha[k], 0.0);
        float whole = min(floor(target), float(N - assigned));
        counts[k] = uint(whole);
        residual[k] = max(target - whole, 0.0);
        assigned += counts[k];
        residualSum += residual[k];
        if (residual[k] > 0.0) lastResidual = k;
    }
    uint R = N - assigned;
    if (R == 0u) return;
    float scale = residualSum > 0.0 ? float(R) / residualSum : 0.0;
    float cumulative = 0.0;
    uint given = 0u;
    for (uint k = 0u; k < m; ++k) {
        cumulative += residual[k] * scale;
        // Points u + j below `cumulative`; the last positive residual takes what rounding left.
        uint upTo = k >= lastResidual ? R : uint(clamp(ceil(cumulative - u), 0.0, float(R)));
        upTo = max(upTo, given);
        counts[k] += upTo - given;
        given = upTo;
    }
}

// Uniform direction in the cone around unit `axis` with 1 - cos(half-angle) = oneMinusCos
// (written this way to keep narrow cones precise); density 1 / (2 pi oneMinusCos) inside.
vec3 pmcHiSampleCone(vec3 axis, float oneMinusCos, vec2 u) {
    float x = u.x * oneMinusCos;
    float cosTheta = 1.0 - x;
    float sinTheta = safeSqrt(x * (2.0 - x));
    float phi = TWO_PI * u.y;
    vec3 t, b;
    orthonormalBasis(axis, t, b);
    return normalize(sinTheta * cos(phi) * t + sinTheta * sin(phi) * b + cosTheta * axis);
}

float pmcHiConePdf(vec3 axis, float oneMinusCos, vec3 w) {
    return oneMinusCos > 0.0 && 1.0 - dot(w, axis) <= oneMinusCos ? 1.0 / (TWO_PI * oneMinusCos) : 0.0;
}

// The light group that light component `light` samples: the light itself, or with one shared
// light component the group of all emitters, which follows the lights (host/scene/scene.h).
uint pmcHiLightGroup(PmcHiParams p, uint light) {
    return p.sharedLight != 0u ? sceneInfo.lightCount : light;
}

// Solid-angle density, seen from `from`, with which a light component samples the direction to
// emitter point `l`, and that component's slot (PMC_HI_MAX_COMPONENTS when l does not emit).
float pmcHiLightDensity(PmcHiParams p, vec3 from, SurfacePoint l, out uint slot) {
    slot = PMC_HI_MAX_COMPONENTS;
    uint light = triangleLights[l.triangle];
    if (light == LIGHT_NONE) return 0.0;
    slot = PMC_HI_LIGHT + (p.sharedLight != 0u ? 0u : light);
    float pdfArea = lightGroupAreaPdf(pmcHiLightGroup(p, light), l.triangle);
    return areaToSolidAngle(pdfArea, from, l.position, l.normal);
}

// The mixture's state between iterations: the weights and the cone.
struct PmcHiKernel {
    float alpha[PMC_HI_MAX_COMPONENTS];
    vec3 coneAxis;
    float coneOneMinusCos;  // 0: no cone yet
};

// A direction drawn from one component, before it is traced.
struct PmcHiDraw {
    vec3 wi;
    vec3 fr;               // f_r |cos| for wi (a delta lobe: its weight, bs.f |cos|)
    float pdfBsdf;         // BSDF density of wi (a delta lobe: its discrete probability)
    bool delta;            // drawn by a delta lobe of the BSDF
    bool fromLight;        // drawn by a light component: `lightPoint` is the sampled point
    bool fromEnvironment;  // drawn by the environment component
    SurfacePoint lightPoint;
    vec2 lightBarycentrics;  // its barycentrics on triangle lightPoint.triangle
};

// Draws a direction from component k of `kern`; false when no direction results (the sample
// still counts in N, with w = 0).
bool pmcHiDrawDirection(ShadingPoint sh, PmcHiParams p, uint k, PmcHiKernel kern, float u1, vec2 u2,
                        out PmcHiDraw d) {
    d.wi = vec3(0.0);
    d.fr = vec3(0.0);
    d.pdfBsdf = 0.0;
    d.delta = false;
    d.fromLight = false;
    d.fromEnvironment = false;
    d.lightPoint.position = vec3(0.0);
    d.lightPoint.normal = vec3(0.0, 0.0, 1.0);
    d.lightPoint.shadingNormal = vec3(0.0, 0.0, 1.0);
    d.lightPoint.uv = vec2(0.0);
    d.lightPoint.triangle = 0u;
    d.lightPoint.material = 0u;
    d.lightBarycentrics = vec2(0.0);
    // One BSDF evaluation (value and density together) for every component, at one call site:
    // the invocations of a SIMD group that draw from different components then share it.
    vec3 wiLocal;
    if (k == PMC_HI_BSDF) {
        BsdfSample bs;
        if (!shadingSampleDirection(sh, u1, u2, bs, d.wi)) return false;
        if (bs.delta) {
            d.delta = true;
            d.fr = bs.f * abs(bs.wi.z);
            d.pdfBsdf = bs.pdf;
            return true;
        }
        wiLocal = bs.wi;
    } else if (k == PMC_HI_CONE) {
        if (kern.coneOneMinusCos <= 0.0) return false;
        d.wi = pmcHiSampleCone(kern.coneAxis, kern.coneOneMinusCos, u2);
    } else if (pmcHiHasEnvironment(p) && k == pmcHiEnvironmentSlot(p)) {
        // A pixel by the environment's alias table (u1), a point in it (u2).
        d.wi = envSample(u1, u2).wi;
        d.fromEnvironment = true;
    } else {
        LightSample ls = sampleLightGroup(pmcHiLightGroup(p, k - PMC_HI_LIGHT), u1, u2);
        vec3 toLight = ls.point.position - sh.surface.position;
        float distance = length(toLight);
        if (!(distance > 0.0)) return false;
        d.wi = toLight / distance;
        d.fromLight = true;
        d.lightPoint = ls.point;
        d.lightBarycentrics = ls.barycentrics;
    }
    if (k != PMC_HI_BSDF) wiLocal = toLocal(sh.frame, d.wi);
    vec3 f = shadingEvalLocal(sh, d.wi, wiLocal, d.pdfBsdf);
    d.fr = f * abs(wiLocal.z);
    // A BSDF sample the BSDF gives no value or density fails, as in bsdfSample.
    return k != PMC_HI_BSDF || (d.pdfBsdf > 0.0 && maxComponent(f) > 0.0);
}

// The mixture K of eq. 7 at a non-delta direction wi when k == PMC_HI_MAX_COMPONENTS, else
// component k's own h_k, given the BSDF density, the density pdfLight of the one light
// component (slot lightSlot; PMC_HI_MAX_COMPONENTS for none) that can reach what wi first hits,
// and the environment component's density pdfEnv of wi when wi escapes the scene (else 0).
float pmcHiMixtureDensity(PmcHiParams p, PmcHiKernel kern, vec3 wi, float pdfBsdf, float pdfLight,
                          uint lightSlot, float pdfEnv, uint k) {
    float pdfCone = pmcHiConePdf(kern.coneAxis, kern.coneOneMinusCos, wi);
    const bool env = pmcHiHasEnvironment(p);
    const uint envSlot = pmcHiEnvironmentSlot(p);
    if (k == PMC_HI_MAX_COMPONENTS) {
        // Only one light component can reach the point the ray hits, and the environment only
        // a direction that hits none.
        float K = kern.alpha[PMC_HI_BSDF] * pdfBsdf + kern.alpha[PMC_HI_CONE] * pdfCone;
        if (lightSlot < PMC_HI_MAX_COMPONENTS) K += kern.alpha[lightSlot] * pdfLight;
        if (env) K += kern.alpha[envSlot] * pdfEnv;
        return K;
    }
    return k == PMC_HI_BSDF ? pdfBsdf
         : k == PMC_HI_CONE ? pdfCone
         : env && k == envSlot ? pdfEnv
         : k == lightSlot ? pdfLight : 0.0;
}

// Density of a non-delta direction wi whose ray first hits `l` (when `hit`; else it escapes):
// the mixture K of eq. 7 when k == PMC_HI_MAX_COMPONENTS, else component k's own h_k.
float pmcHiDensity(PmcHiParams p, PmcHiKernel kern, vec3 from, vec3 wi, float pdfBsdf, bool hit,
                   SurfacePoint l, uint k) {
    uint lightSlot = PMC_HI_MAX_COMPONENTS;
    float pdfLight = hit ? pmcHiLightDensity(p, from, l, lightSlot) : 0.0;
    float pdfEnv = !hit && pmcHiHasEnvironment(p) ? envPdf(wi) : 0.0;
    return pmcHiMixtureDensity(p, kern, wi, pdfBsdf, pdfLight, lightSlot, pdfEnv, k);
}

// Draws one direction from component k of `kern` with (u1, u2), traces it and scores it:
// w = f / K (eq. 8, Rao-Blackwellised) or f / h_k (the per-component variant of sec. 7),
// f = Le f_r |cos|. Returns false for a sample that produced no direction (w = 0).
//
// Every sample, whatever its component, goes through one traversal call (a light-sampled
// direction as a shadow ray to the sampled point, an environment-sampled one as a shadow ray to
// infinity, the others as a closest hit) and one scoring of one emitter point (the sampled point
// when it is visible, else the first hit) or of the environment (a ray that escaped). On lavapipe,
// which runs 8 invocations as the lanes of one vector, every branch runs both its sides under
// masks, so each call site costs every sample: scoring the light-sampled points and the hit
// points separately made a PMC-HI sample cost about two MIS samples.
bool pmcHiSample(ShadingPoint sh, PmcHiParams p, uint k, PmcHiKernel kern, float u1, vec2 u2,
                 inout uint rays, out vec3 w, out vec3 wi) {
    w = vec3(0.0);
    const bool rb = (p.flags & PMC_HI_FLAG_RAO_BLACKWELL) != 0u;
    PmcHiDraw d;
    bool drawn = pmcHiDrawDirection(sh, p, k, kern, u1, u2, d);
    wi = d.wi;
    if (!drawn || !(maxComponent(d.fr) > 0.0)) return drawn;

    const bool env = pmcHiHasEnvironment(p);
    const bool shadow = d.fromLight || d.fromEnvironment;  // scores only when nothing is hit
    ShadowRay ray = d.fromLight ? shadowRay(sh, d.lightPoint)
                                : ShadowRay(spawnOrigin(sh, d.wi), d.wi, FLOAT_MAX);
    Hit hit;
    rays += 1u;
    bool found = bvhTraverse(ray.origin, ray.dir, ray.tMax, shadow, hit);
    // The ray left the scene: the environment's radiance scores (none without an environment).
    const bool escaped = env && !found && !d.fromLight;
    if (shadow ? found : !found && !escaped) return true;  // occluded, or nothing seen
    SurfacePoint l = surfaceAt(d.fromLight ? d.lightPoint.triangle : escaped ? 0u : hit.triangle,
                               d.fromLight ? d.lightBarycentrics : escaped ? vec2(0.0) : vec2(hit.b1, hit.b2));
    vec3 Le = escaped ? envRadiance(d.wi) : emittedRadiance(l, -d.wi);
    if (maxComponent(Le) <= 0.0) return true;
    vec3 f = d.fr * Le;

    // A delta lobe's direction is an atom only the BSDF component has: K = a_BSDF P(lobe).
    if (d.delta) {
        w = f / (rb ? kern.alpha[PMC_HI_BSDF] * d.pdfBsdf : d.pdfBsdf);
        return true;
    }
    // For a point light component k sampled, the slot found is k itself.
    uint lightSlot;
    float pdfLight = pmcHiLightDensity(p, sh.surface.position, l, lightSlot);
    if (escaped) lightSlot = PMC_HI_MAX_COMPONENTS;
    float pdfEnv = escaped ? envPdf(d.wi) : 0.0;
    float density = pmcHiMixtureDensity(p, kern, d.wi, d.pdfBsdf, pdfLight, lightSlot, pdfEnv,
                                        rb ? PMC_HI_MAX_COMPONENTS : k);
    if (density > 0.0) w = f / density;
    return true;
}

// The sampler of sample j of component k in iteration t of an estimate. Each (t, k) has its own
// pair of dimensions and draws points j = 0, 1, ... of an aligned block of
// PMC_HI_STREAM_BLOCK indices inside the camera sample's block: the samples one component
// draws in one iteration are the first points of a (0, 2)-sequence block, a net, so they are
// stratified among themselves (sampler.glsl: the index scramble keeps aligned blocks), and
// sample (t, k, j) of successive camera samples of a pixel continues the same sequence. A
// dimension then always serves the same component, whatever the deterministic mixture counts.
const uint PMC_HI_STREAM_DIMENSION = 0x40000000u;  // far from the camera sample's dimensions

Sampler pmcHiStream(Sampler smp, uint t, uint k, uint j) {
    Sampler s = smp;
    s.index = smp.index * PMC_HI_STREAM_BLOCK + j;
    s.dimension = PMC_HI_STREAM_DIMENSION + 2u * (t * PMC_HI_MAX_COMPONENTS + k) + 0x1000u * smp.dimension;
    return s;
}

// Unnormalised weight of slot k in the first iteration without feedback. The paper's sec. 5.2
// makes them equal; with one component per light, pmcr gives the BSDF component its equal share
// 1 / (1 + lights) and splits the lights' share in proportion to their power, as light
// selection does in MIS direct lighting (lights.glsl): a dim light gets fewer samples than a
// bright one until the adaptation says otherwise. Equal for lights of equal power. The
// environment counts as one more light: the lights' and the environment's share is split
// between the emitters and the environment as light selection splits it (envSelectPmf against
// the emitters', host/scene/light_choice.h). With a shared light component, every component
// gets the same weight. Weights the user gave (--initial-alpha) take the defensive floor, as
// feedback weights do.
float pmcHiInitialWeight(PmcHiParams p, uint k) {
    if ((p.flags & PMC_HI_FLAG_INITIAL_ALPHA) != 0u) return max(p.initialAlpha[k], p.alphaFloor);
    if (k == PMC_HI_BSDF || p.sharedLight != 0u) return 1.0;
    const bool env = pmcHiHasEnvironment(p);
    // The emitters' part of the lights' share (1 without an environment).
    float emitters = 1.0;
    if (env) {
        float pEmitters = sceneInfo.totalEmitterPower > 0.0 ? emittersSelectPmf() : 0.0;
        float pEnv = sceneInfo.envSelectPmf;
        emitters = pEmitters + pEnv > 0.0 ? pEmitters / (pEmitters + pEnv) : 0.0;
    }
    const float share = float(p.lightComponents + (env ? 1u : 0u));
    if (env && k == pmcHiEnvironmentSlot(p)) return share * (1.0 - emitters);
    return share * emitters * lightGroupAt(k - PMC_HI_LIGHT).power / sceneInfo.totalEmitterPower;
}

// One PMC-HI estimate of the light reflected at `sh` (the integral of eq. 4, direct lighting
// only; emission at sh not included). The first iteration's weights are `start` when `hasStart`
// (the PMC-IP feedback of sec. 6.1: weights adapted at this pixel in an earlier image-plane
// iteration; the cone, which has no axis yet, left out and the floor applied), else a_cone = 0
// and the others equal (sec. 5.2). `alphaOut` receives the weights adapted from the last
// iteration (figure 7), `adapted` whether there was anything to adapt (false for a BSDF of delta
// lobes only, which the BSDF component samples alone).
vec3 pmcHiEstimate(ShadingPoint sh, PmcHiParams p, float start[PMC_HI_MAX_COMPONENTS], bool hasStart,
                   inout Sampler smp, inout uint rays, out float alphaOut[PMC_HI_MAX_COMPONENTS],
                   out bool adapted) {
    const uint m = pmcHiSlots(p);  // slots in use
    // Samples in all: iteration 0 draws initialPopulationPerComponent * m, the others
    // populationPerComponent * m each.
    const uint samples = (p.initialPopulationPerComponent + (p.iterations - 1u) * p.populationPerComponent) * m;
    adapted = bsdfHasNonDelta(sh.bsdf);

    PmcHiKernel kern;
    float startSum = 0.0;
    for (uint k = 0u; k < PMC_HI_MAX_COMPONENTS; ++k) {
        kern.alpha[k] = 0.0;
        if (!adapted || k >= m || k == PMC_HI_CONE) continue;
        kern.alpha[k] = hasStart ? max(start[k], p.alphaFloor) : pmcHiInitialWeight(p, k);
        startSum += kern.alpha[k];
    }
    for (uint k = 0u; k < m; ++k) kern.alpha[k] /= max(startSum, 1e-30);
    if (!adapted) kern.alpha[PMC_HI_BSDF] = 1.0;
    kern.coneAxis = sh.frame.n;
    kern.coneOneMinusCos = 0.0;

    vec3 total = vec3(0.0);
    for (uint t = 0u; t < p.iterations; ++t) {
        const uint N = (t == 0u ? p.initialPopulationPerComponent : p.populationPerComponent) * m;
        uint counts[PMC_HI_MAX_COMPONENTS];
        pmcHiAllocate(kern.alpha, m, N, samplerGet1D(smp), counts);
        vec3 sum = vec3(0.0);
        float wSum[PMC_HI_MAX_COMPONENTS];
        for (uint k = 0u; k < PMC_HI_MAX_COMPONENTS; ++k) wSum[k] = 0.0;
        float wTotal = 0.0;
        vec3 wDirection = vec3(0.0);
        // One flat loop of N samples, component k for counts[k] of them in turn: the same trip
        // count in every invocation (nested loops over k and counts[k] would run, in a SIMD
        // group, the sum over k of the largest counts[k], far more than N once the counts
        // differ between invocations).
        uint k = 0u;
        uint j = 0u;  // index of the sample within component k
        for (uint i = 0u; i < N; ++i) {
            while (j >= counts[k] && k + 1u < m) {
                k += 1u;
                j = 0u;
            }
            // Component k's samples of this iteration are consecutive points of one stratified
            // stream (pmcHiStream), whatever the other components' counts.
            Sampler stream = pmcHiStream(smp, t, k, j);
            j += 1u;
            float u1 = samplerGet1D(stream);
            vec2 u2 = samplerGet2D(stream);
            vec3 w, wi;
            if (!pmcHiSample(sh, p, k, kern, u1, u2, rays, w, wi)) continue;
            float wl = max(luminance(w), 0.0);
            if (!isFinite(wl)) continue;
            sum += w;
            wSum[k] += wl;
            wTotal += wl;
            wDirection += wl * wi;
        }
        // Eq. 1: the average of every iteration's weighted samples.
        total += sum;
        if (!adapted) continue;

        // Adapt (sec. 5.2). Without any weight there is nothing to learn: keep the kernel.
        if (wTotal > 0.0) {
            const bool hadCone = kern.coneOneMinusCos > 0.0;
            // Eq. 9: each component's share of the weight, taken in full (the paper) or, with
            // --adapt-rate below 1, part of the way from the current weights.
            for (uint k = 0u; k < m; ++k) kern.alpha[k] = mix(kern.alpha[k], wSum[k] / wTotal, p.adaptRate);
            // Cone axis: the weighted mean direction; half-angle beta: the weighted RMS angle
            // about it in chord measure (2 sin(beta/2) = RMS |w_i - axis|), for which
            // 1 - cos(beta) = 1 - |mean of w_i| exactly.
            float len = length(wDirection / wTotal);
            if (len > 0.0) {
                kern.coneAxis = normalize(wDirection);
                kern.coneOneMinusCos = max(1.0 - min(len, 1.0), 2.0 * sqr(sin(0.5 * PMC_HI_CONE_MIN_ANGLE)));
            } else {
                kern.coneOneMinusCos = 0.0;
            }
            if (!hadCone && kern.coneOneMinusCos > 0.0) {
                // The cone's first axis (after iteration 0 unless every weight was 0): it has
                // no samples yet, so a_cone = coneInitial and the others make room.
                for (uint k = 0u; k < m; ++k) kern.alpha[k] *= 1.0 - p.coneInitial;
                kern.alpha[PMC_HI_CONE] = p.coneInitial;
            }
            if (kern.coneOneMinusCos <= 0.0) kern.alpha[PMC_HI_CONE] = 0.0;
        }
        // Defensive floor on the BSDF and light weights, then normalise.
        float alphaSum = 0.0;
        for (uint k = 0u; k < m; ++k) {
            if (k != PMC_HI_CONE) kern.alpha[k] = max(kern.alpha[k], p.alphaFloor);
            alphaSum += kern.alpha[k];
        }
        for (uint k = 0u; k < m; ++k) kern.alpha[k] /= alphaSum;
    }
    alphaOut = kern.alpha;
    return total / float(samples);
}

// The punctual lights' direct lighting at `sh`, beside the PMC-HI estimate (which covers every
// other light): one punctual light by the alias table over their power, unweighted (see the
// header: a delta light cannot be a component of the mixture). u: the light's pick.
vec3 pmcHiPunctualDirect(ShadingPoint sh, float u, inout uint rays) {
    if (!hasPunctualLights() || !bsdfHasNonDelta(sh.bsdf)) return vec3(0.0);
    return punctualDirectLighting(sh, u, rays);
}

#endif
