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
//              |cos_s(in)| |cos_g(out)| / (|cos_g(in)| |cos_s(out)|) (mutate_caustic.glsl).
// tests/gpu/test_erpt_densities.cpp checks these Jacobians against finite differences.
// Factors outside the perturbed part are equal for x and y and cancel, except in P, which is
// RGB and enters through its luminance, so P is always evaluated over the whole path.
#ifndef PMCR_PATH_SPACE_GLSL
#define PMCR_PATH_SPACE_GLSL

#include "common/camera.glsl"
#include "common/shading.glsl"

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

SurfacePoint vertexPoint(ChainVertex v) { return surfaceAt(v.triangle, vec2(v.b1, v.b2)); }
SurfacePoint pathPoint(uint base, uint i) { return vertexPoint(chainVertices[base + i]); }

// |cos| between the geometric normal at s and the unit direction w.
float absCosGeometric(SurfacePoint s, vec3 w) { return abs(dot(s.normal, w)); }

// P(x): the product of the scattering factors of x1..x_k-1 (f_s at D vertices, the delta lobe's
// weight at S vertices, evaluated for light flowing from x_k towards the eye as a path tracer
// does), the segments' absorption (segmentTransmittance) and Le(x_k -> x_k-1). Zero when a vertex cannot scatter as its type says.
vec3 pathThroughput(uint base, uint k) {
    vec3 P = vec3(1.0);
    vec3 previous = sceneInfo.cameraPosition;
    SurfacePoint current = pathPoint(base, 0u);
    for (uint i = 0u; i + 1u < k; ++i) {
        SurfacePoint next = pathPoint(base, i + 1u);
        vec3 toCurrent = current.position - previous;
        P *= segmentTransmittance(current, normalize(toCurrent), length(toCurrent));
        vec3 wo = normalize(previous - current.position);
        vec3 wi = normalize(next.position - current.position);
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
    vec3 toLight = current.position - previous;
    P *= segmentTransmittance(current, normalize(toLight), length(toLight));
    return P * emittedRadiance(current, normalize(previous - current.position));
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
