// Light paths stored in chain slots (shared/chain_types.h) and what the mutations need to
// compare two of them: the throughput P (RGB) and the geometric factors of the target
// function in each mutation's own measure.
//
// Target function. ERPT and PMC-ER redistribute the luminance of the measurement contribution
// (ERPT sec. 2.3: "energy" = luminance; Veach 1997 ch. 8). A mutation perturbs some parameters
// nu of the path (a raster position, solid angles at scattering vertices) with a proposal that
// is symmetric in nu, and the Metropolis ratio must compare F_nu = F_A |dA/dnu|, the contribution
// per unit of nu (the change of measure a path tracer's density ratios express in ERPT's rules
// 1-5). Writing F_A with the shading normals a path tracer uses (f_s and |cos_s| at the
// scattering vertex, |cos_g| / d^2 converting solid angle to area at the receiving one):
//   F_nu(x) = lum(P(x)) * Gamma(x), P = prod of f_s (D vertices), specular weights (S), Le,
// and Gamma collects the geometric factors that do not cancel between x and y:
//   lens      (nu = raster position u, and solid angle at each D vertex whose outgoing
//              direction is perturbed): Gamma = prod_perturbed |cos_s(out)| *
//              |cos_s(x_c -> x_c+1)| |cos_g(x_c+1)| / |x_c - x_c+1|^2, the reconnection x_c -> x_c+1
//              in area measure. The camera's and the specular chains' Jacobians cancel because u
//              and the solid angles are the parameters themselves (ERPT rules 1-3).
//   caustic   (nu = solid angle at the head x_h, whose direction is perturbed):
//              Gamma = rasterDensity(x1) * |cos_s(x1 -> x2)| / |cos_g(x1 -> x2)| * |cos_g(x_h)| *
//              prod_transmissions eta^2, with rasterDensity = |cos_g(x1)| / (d^2 cos^3 theta A_pixel)
//              (ERPT rule 5) and the specular chain x_h -> x1 handled by conservation of etendue
//              (n^2 cos dA dw is invariant along the chain, Veach 1997 sec. 5.2): its Jacobian is
//              (n_h / n_1)^2 / |cos_g(x1)|, whose (n_h / n_1)^2 is the product of the chain's eta^2.
//              A delta lobe about an interpolated shading normal conserves n^2 |cos_s| dw, not
//              n^2 |cos_g| dw, so each S vertex also contributes
//              |cos_s(in)| |cos_g(out)| / (|cos_g(in)| |cos_s(out)|) (mutate_caustic.glsl; a
//              smooth clear coat's mirror takes its own normal n_c for n_s).
// When x_k is a punctual light or the environment (light_vertex.glsl has their measures):
//   lens      the reconnection x_c -> x_k is |cos_s(x_c -> p)| / |x_c - p|^2 to a point or spot
//             light at p (no area at the light, so no |cos_g| there), and |cos_s(x_c, w)| to a
//             direction w (the environment, a directional light), which the reconnection keeps:
//             the light vertex is then a parameter held fixed in solid angle, as x_c+1 is held
//             fixed in area otherwise. A proposal whose specular chain must reach the light
//             traces it: a ray that escapes reaches the environment in a new direction w (whose
//             solid angle is then not a parameter but follows from the perturbed ones, and
//             L_env(w) enters P like Le), and no ray reaches a delta light (such proposals are
//             invalid, probability one: the chain stays put, which keeps detailed balance).
//   caustic   at a point or spot light head, Gamma has no |cos_g(x_h)|: the light position is
//             held fixed and its measure is a delta, not dA (a point light is the limit of a
//             small area light of intensity Le |cos_g| dA). With a direction at the head
//             (environment, directional light) the caustic perturbation does not apply
//             (mutate_caustic.glsl causticHead says why).
// tests/gpu/test_erpt_densities.cpp checks these Jacobians against finite differences.
// Factors outside the perturbed part are equal for x and y and cancel, except in P, which is
// RGB and enters through its luminance, so P is always evaluated over the whole path.
#ifndef PMCR_PATH_SPACE_GLSL
#define PMCR_PATH_SPACE_GLSL

#include "common/camera.glsl"
#include "common/shading.glsl"
#include "methods/energy_redistribution/light_vertex.glsl"

layout(set = WORK_SET, binding = ERPT_BINDING_CHAIN_VERTICES, scalar) buffer ChainVertexBuffer {
    ChainVertex chainVertices[];
};

// Index of vertex x1 of a chain's slot.
uint pathBase(uint chain, uint slot) { return (chain * 2u + slot) * CHAIN_MAX_VERTICES; }

bool vertexSpecular(ChainVertex v) { return (v.flags & VERTEX_SPECULAR) != 0u; }
bool vertexTransmits(ChainVertex v) { return (v.flags & VERTEX_TRANSMISSION) != 0u; }
bool vertexEmitter(ChainVertex v) { return (v.flags & VERTEX_EMITTER) != 0u; }
uint vertexLobe(ChainVertex v) { return (v.flags >> CHAIN_LOBE_SHIFT) & 15u; }

ChainVertex makeChainVertex(uint triangle, vec2 b, uint flags) {
    ChainVertex v;
    v.triangle = triangle;
    v.b1 = b.x;
    v.b2 = b.y;
    v.flags = flags;
    return v;
}

// The surface point of v; for a punctual light or the environment, light_vertex.glsl's stand-in.
SurfacePoint vertexPoint(ChainVertex v) {
#ifdef PMCR_OTHER_LIGHTS
    if (vertexPunctual(v) || vertexEnvironment(v)) return lightVertexPoint(v);
#endif
    return surfaceAt(v.triangle, vec2(v.b1, v.b2));
}
SurfacePoint pathPoint(uint base, uint i) { return vertexPoint(chainVertices[base + i]); }

// |cos| between the geometric normal at s and the unit direction w.
float absCosGeometric(SurfacePoint s, vec3 w) { return abs(dot(s.normal, w)); }

// The unit direction from `from` towards vertex v at s (a direction vertex: its direction).
vec3 directionTowards(ChainVertex v, SurfacePoint s, vec3 from) {
#ifdef PMCR_OTHER_LIGHTS
    if (vertexIsDirection(v)) return vertexDirection(v);
#endif
    return normalize(s.position - from);
}

// P(x): the product of the scattering factors of x1..x_k-1 (f_s at D vertices, the delta lobe's
// weight at S vertices, evaluated for light flowing from x_k towards the eye as a path tracer
// does), the absorption of the segments that end on surfaces (segmentTransmittance) and the
// emission of x_k towards x_k-1 (lightVertexEmission: Le, or I, E, L_env). Zero when a vertex
// cannot scatter as its type says.
vec3 pathThroughput(uint base, uint k) {
    vec3 P = vec3(1.0);
    vec3 previous = sceneInfo.cameraPosition;
    SurfacePoint current = pathPoint(base, 0u);
    for (uint i = 0u; i + 1u < k; ++i) {
        ChainVertex nextVertex = chainVertices[base + i + 1u];
        SurfacePoint next = vertexPoint(nextVertex);
        vec3 toCurrent = current.position - previous;
        P *= segmentTransmittance(current, normalize(toCurrent), length(toCurrent));
        vec3 wo = normalize(previous - current.position);
        vec3 wi = directionTowards(nextVertex, next, current.position);
        ShadingPoint sh = makeShadingPoint(current, wo);
        ChainVertex v = chainVertices[base + i];
        if (vertexSpecular(v)) {
            vec3 wiLocal, weight;
            if (!bsdfSpecular(sh.bsdf, sh.woLocal, vertexLobe(v), vertexTransmits(v), wiLocal, weight))
                return vec3(0.0);
            P *= weight;
        } else {
            float pdf, absCos;
            P *= shadingEval(sh, wi, pdf, absCos);
        }
        previous = current.position;
        current = next;
    }
    ChainVertex light = chainVertices[base + k - 1u];
    bool surfaceLight = true;  // an emitter point; punctual lights and directions end on none
#ifdef PMCR_OTHER_LIGHTS
    surfaceLight = !vertexPunctual(light) && !vertexIsDirection(light);
#endif
    if (surfaceLight) {
        vec3 toLight = current.position - previous;
        P *= segmentTransmittance(current, normalize(toLight), length(toLight));
    }
    return P * lightVertexEmission(light, current, previous);
}

// |cos_s(a -> b)| |cos_g(b)| / |a - b|^2: the area-measure reconnection factor of the lens
// perturbation (a scatters with its shading normal, b receives).
float reconnectionFactor(SurfacePoint a, vec3 woA, SurfacePoint b) {
    vec3 d = b.position - a.position;
    float dist2 = dot(d, d);
    vec3 w = d * inversesqrt(dist2);
    ShadingPoint sh = makeShadingPoint(a, woA);
    return abs(dot(sh.frame.n, w)) * absCosGeometric(b, w) / dist2;
}

// reconnectionFactor to vertex bv at b, whatever it is: for a point or spot light
// |cos_s(a -> p)| / |a - p|^2, for a direction w |cos_s(a, w)| (the header's measures).
float reconnectionFactorTo(SurfacePoint a, vec3 woA, ChainVertex bv, SurfacePoint b) {
#ifdef PMCR_OTHER_LIGHTS
    if (vertexIsDirection(bv)) {
        ShadingPoint sh = makeShadingPoint(a, woA);
        return abs(dot(sh.frame.n, vertexDirection(bv)));
    }
    if (vertexPunctual(bv)) {
        vec3 d = b.position - a.position;
        float dist2 = dot(d, d);
        ShadingPoint sh = makeShadingPoint(a, woA);
        return abs(dot(sh.frame.n, d * inversesqrt(dist2))) / dist2;
    }
#endif
    return reconnectionFactor(a, woA, b);
}

// |du / dA(x1)| of a pinhole in raster units: |cos_g(x1)| / (d^2 cos^3 theta A_pixel)
// (ERPT eq. 13, rule 5).
float rasterDensity(SurfacePoint x1) {
    vec3 d = x1.position - sceneInfo.cameraPosition;
    float dist2 = dot(d, d);
    vec3 w = d * inversesqrt(dist2);
    float cosCamera = dot(w, sceneInfo.cameraForward);
    if (cosCamera <= 0.0) return 0.0;
    return absCosGeometric(x1, w) / (dist2 * cosCamera * cosCamera * cosCamera * cameraPixelArea());
}

// Pixel index of a raster position inside the image.
uint rasterPixel(vec2 raster) {
    uvec2 p = uvec2(clamp(raster, vec2(0.0), vec2(sceneInfo.width - 1u, sceneInfo.height - 1u)));
    return p.y * sceneInfo.width + p.x;
}

#endif
