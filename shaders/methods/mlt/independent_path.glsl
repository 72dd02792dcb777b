// MLT's independent mutation (--method mlt, host/methods/mlt): a fresh light path, drawn with
// the path tracer's own BSDF and light sampling (path_tracer.glsl sampleLightFrom, shading.glsl
// shadingSample), one path per sample instead of the path tracer's tree of light paths, so that
// its density p(y) can be evaluated for any path the perturbations make. The Metropolis ratio
// of an independent proposal y from x is then a = min(1, W(y) / W(x)) with W = F / p
// (Veach 1997 sec. 11.4, independence sampler; Tierney 1994), and the bootstrap that estimates
// b = integral of F is the mean of W over such samples (host/methods/metropolis/bootstrap.h).
//
// The sampler. The raster position is uniform over the image (density 1 / (width height) per
// unit raster area); x1 is traced from it. At each vertex x_j (1-based) it chooses uniformly
// among the options that vertex has:
//   end      x_j emits towards x_j-1: the path x1..x_j ends on this emitter (implicit path);
//   connect  x_j has a non-delta lobe and j <= maxDepth: a light sample y from x_j (the light
//            choice and density of next-event estimation) ends the path x1..x_j y if visible;
//   next     j <= maxDepth: the BSDF is sampled and the ray traced to x_j+1 (a ray that escapes
//            reaches the environment, which ends the path).
// Failing walks (a miss with no environment, an occluded connection, a failed BSDF sample) give
// no path (F = 0). So paths have at most maxDepth + 1 vertices, as pt's (maxDepth bounces).
//
// Its density, in the measure of path_space.glsl's target F (raster position u, then per D
// vertex the solid angle it scatters into, delta choices at S vertices, the light vertex's own
// measure for the last segment), is a product of the choices. The last vertex x_k can be reached
// two ways from a D vertex x_k-1, and p sums them (a one-sample combination of the path tracer's
// two strategies, Veach 1997 sec. 9.2.4):
//   p(x) = 1/(width height) * prod_{j<k-1} o_next(x_j) p_dir(x_j -> x_j+1)
//          * [o_connect(x_k-1) p_light(x_k) + o_next(x_k-1) p_dir(x_k-1 -> x_k) o_end(x_k)]
// with p_dir = pdf_w |cos_g(x_j+1)| / d^2 in area measure at a D vertex (the |cos_g| / d^2 cancel
// with F's, except at x_k), the delta lobe's selection probability at an S vertex, o_end = 1 at
// the environment (a ray that escapes ends there) and 0 at a punctual light (no ray reaches it).
// W = F / p is P(x) (path_space.glsl pathThroughput) times the geometric factors of F over p.
// tests/stat/test_mlt.cpp checks p against what the sampler draws: the W-weighted image of
// independent samples equals path tracing's.
#ifndef PMCR_INDEPENDENT_PATH_GLSL
#define PMCR_INDEPENDENT_PATH_GLSL

#include "methods/energy_redistribution/path_space.glsl"
#include "methods/pt/path_tracer.glsl"

// The probabilities of a vertex's options (the header's end, connect, next), uniform over those
// it has; x_j is vertex j (1-based).
struct PathOptions {
    float end;
    float connect;
    float next;
};

PathOptions pathOptions(bool emits, bool nonDelta, uint j, uint maxDepth) {
    float e = emits ? 1.0 : 0.0;
    float c = nonDelta && j <= maxDepth ? 1.0 : 0.0;
    float n = j <= maxDepth ? 1.0 : 0.0;
    float total = max(e + c + n, 1.0);
    return PathOptions(e / total, c / total, n / total);
}

PathOptions pathOptionsAt(ShadingPoint sh, vec3 wo, uint j, uint maxDepth) {
    bool emits = maxComponent(emittedRadiance(sh.surface, wo)) > 0.0;
    return pathOptions(emits, bsdfHasNonDelta(sh.bsdf), j, maxDepth);
}

// Probability that bsdfSample picks delta lobe `lobe`, reflecting or transmitting, at wo
// (bsdf.glsl bsdfSampleDirection: the lobe's selection probability, times F or 1 - F for the
// dielectric's choice; 1 - coverage for a BLEND pass; the clear coat's share for its mirror).
float deltaLobeProbability(Bsdf b, vec3 wo, uint lobe, bool transmit) {
    if (wo.z <= 0.0) return 0.0;
    vec4 p = lobeSelectProbabilities(b, wo);
    if (lobe == LOBE_COAT) return p.y;
    if (lobe == LOBE_CONDUCTOR) return p.z;
    if (lobe == LOBE_DIELECTRIC) {
        float F = dielectricReflectance(b, wo.z);
        return p.w * (transmit ? 1.0 - F : F);
    }
    if (lobe == LOBE_PASS) return transmit ? b.wPass : 0.0;
    if (lobe == LOBE_CLEARCOAT) return transmit ? 0.0 : clearcoatLobeProbability(b, wo);
    return 0.0;
}

// Draws a path into the chain slot at `base` (the header's sampler): its vertices x1..x_k, its
// raster position and k. False when the walk found no light path.
bool sampleIndependentPath(uint base, uint maxDepth, inout Rng rng, inout uint rays,
                           out vec2 raster, out uint k) {
    vec2 size = vec2(sceneInfo.width, sceneInfo.height);
    raster = min(rngNext2(rng) * size, size * ONE_MINUS_EPSILON);
    k = 0u;
    vec3 origin = sceneInfo.cameraPosition;
    vec3 dir = cameraDirection(raster);
    for (uint j = 1u; j <= maxDepth + 1u; ++j) {
        Hit hit;
        rays += 1u;
        if (!traceClosest(origin, dir, FLOAT_MAX, hit)) {
#ifdef PMCR_OTHER_LIGHTS
            if (!hasEnvironment()) return false;
            chainVertices[base + j - 1u] =
                makeChainVertex(0u, octEncode(dir), VERTEX_EMITTER | VERTEX_ENVIRONMENT);
            k = j;
            return true;
#else
            return false;
#endif
        }
        vec2 b = vec2(hit.b1, hit.b2);
        SurfacePoint s = surfaceAt(hit.triangle, b);
        ShadingPoint sh = makeShadingPoint(s, -dir);
        PathOptions o = pathOptionsAt(sh, -dir, j, maxDepth);
        float u = rngNext(rng);
        if (u < o.end) {
            chainVertices[base + j - 1u] = makeChainVertex(hit.triangle, b, VERTEX_EMITTER);
            k = j;
            return true;
        }
        if (u < o.end + o.connect) {
            chainVertices[base + j - 1u] = makeChainVertex(hit.triangle, b, 0u);
            float uLight = rngNext(rng);
            vec2 uPoint = rngNext2(rng);
            LightSampleFrom ls = sampleLightFrom(sh, uLight, uPoint);
            if (!(ls.pdf > 0.0)) return false;
            ChainVertex light = makeChainVertex(ls.area.point.triangle, ls.area.barycentrics, VERTEX_EMITTER);
#ifdef PMCR_OTHER_LIGHTS
            if (ls.environment)
                light = makeChainVertex(0u, octEncode(ls.wi), VERTEX_EMITTER | VERTEX_ENVIRONMENT);
            else if (ls.delta)
                light = makeChainVertex(ls.punctual, vec2(0.0), VERTEX_EMITTER | VERTEX_PUNCTUAL);
#endif
            rays += 1u;
            if (traceAny(ls.ray.origin, ls.ray.dir, ls.ray.tMax)) return false;
            chainVertices[base + j] = light;
            k = j + 1u;
            return true;
        }
        float uLobe = rngNext(rng);
        vec2 uDir = rngNext2(rng);
        BsdfSample bs;
        vec3 wi;
        if (!(o.next > 0.0) || !shadingSample(sh, uLobe, uDir, bs, wi)) return false;
        uint flags = 0u;
        if (bs.delta) {
            flags = VERTEX_SPECULAR | (bs.lobe << CHAIN_LOBE_SHIFT);
            if (bs.wi.z < 0.0) flags |= VERTEX_TRANSMISSION;
        }
        chainVertices[base + j - 1u] = makeChainVertex(hit.triangle, b, flags);
        origin = spawnOrigin(sh, wi);
        dir = wi;
    }
    return false;
}

// The probability that the sampler ends at light vertex v (at s, reached by a ray from `from`,
// as vertex k): 1 at the environment, o_end at an emitter point, 0 at a punctual light.
float endProbability(ChainVertex v, SurfacePoint s, vec3 from, uint k, uint maxDepth) {
#ifdef PMCR_OTHER_LIGHTS
    if (vertexEnvironment(v)) return 1.0;
    if (vertexPunctual(v)) return 0.0;
#endif
    vec3 wo = normalize(from - s.position);
    return pathOptionsAt(makeShadingPoint(s, wo), wo, k, maxDepth).end;
}

// W(x) = F(x) / p(x) (RGB: P(x) times the scalar ratio; the header's density) of the path of k
// vertices at `base`; P receives P(x). Zero where F(x) = 0; not finite where p(x) = 0 < F(x)
// (a path the sampler cannot draw: an independent proposal never replaces it).
vec3 independentWeight(uint base, uint k, uint maxDepth, out vec3 P) {
    P = pathThroughput(base, k);
    if (!(maxComponent(P) > 0.0)) return vec3(0.0);
    float ratio = float(sceneInfo.width) * float(sceneInfo.height);  // 1 / p(u)
    vec3 previous = sceneInfo.cameraPosition;
    SurfacePoint current = pathPoint(base, 0u);
    if (k == 1u) return P * (ratio / endProbability(chainVertices[base], current, previous, 1u, maxDepth));
    for (uint i = 0u; i + 1u < k; ++i) {
        uint j = i + 1u;  // x_j scatters towards x_j+1
        ChainVertex v = chainVertices[base + i];
        ChainVertex nextVertex = chainVertices[base + i + 1u];
        SurfacePoint next = vertexPoint(nextVertex);
        vec3 wo = normalize(previous - current.position);
        ShadingPoint sh = makeShadingPoint(current, wo);
        PathOptions o = pathOptionsAt(sh, wo, j, maxDepth);
        vec3 wi = directionTowards(nextVertex, next, current.position);
        bool last = j + 1u == k;
        float pEnd = last ? endProbability(nextVertex, next, current.position, k, maxDepth) : 1.0;
        if (vertexSpecular(v)) {
            // P holds the lobe's weight f |cos| / delta; the density is the lobe's choice.
            ratio /= o.next * deltaLobeProbability(sh.bsdf, sh.woLocal, vertexLobe(v), vertexTransmits(v)) * pEnd;
        } else {
            float pdf, absCos;
            shadingEval(sh, wi, pdf, absCos);
            if (!last) {
                ratio *= absCos / (o.next * pdf);
            } else {
                // The light vertex: connection or BSDF sampling, in the light vertex's measure.
                float geometry = absCos;  // F's factor of the last segment
                float pConnect, pNext;
#ifdef PMCR_OTHER_LIGHTS
                if (vertexEnvironment(nextVertex)) {
                    pConnect = envPdf(wi) * sceneInfo.envSelectPmf;
                    pNext = pdf;
                } else if (vertexPunctual(nextVertex)) {
                    if (!vertexIsDirection(nextVertex)) {
                        vec3 d = next.position - current.position;
                        geometry /= dot(d, d);
                    }
                    pConnect = punctualLightPmf(nextVertex.triangle) * sceneInfo.punctualSelectPmf;
                    pNext = 0.0;
                } else
#endif
                {
                    vec3 d = next.position - current.position;
                    float toArea = absCosGeometric(next, wi) / dot(d, d);
                    geometry *= toArea;
                    pConnect = emitterAreaPdf(nextVertex.triangle);
                    pNext = pdf * toArea;
                }
                ratio *= geometry / (o.connect * pConnect + o.next * pNext * pEnd);
            }
        }
        previous = current.position;
        current = next;
    }
    return P * ratio;
}

#endif
