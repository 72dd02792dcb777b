#version 460
// Test kernel for shaders/common/bsdf.glsl (tests/gpu/test_bsdf.cpp): one material, built by
// makeBsdf from the push constants. Invocation i:
//   mode 0: bsdfSample(wo) with uLobe, u from rngCreate(hashCombine(i, seed)):
//           results[2i] = (wi, pdf), results[2i + 1] = (f, ok + 2 delta + 4 lobe)
//   mode 1: results[i] = (bsdfEval, bsdfPdf) at wo = inputs[2i].xyz, wi = inputs[2i + 1].xyz
//   mode 2 (one invocation): results[0] = lobeSelectProbabilities(wo),
//           results[1] = (dielectricReflectance(wo.z), eta, bsdfHasNonDelta, wPass),
//           results[2] = (clearcoatLobeProbability, clearcoatAttenuation(wo), max(C) E(wo),
//                        sheenLobeProbability)
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

#include "common/bsdf.glsl"
#include "common/rng.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) readonly buffer Inputs { vec4 inputs[]; };
layout(set = WORK_SET, binding = 1, scalar) writeonly buffer Results { vec4 results[]; };
layout(push_constant, scalar) uniform Push {
    uint mode;
    uint count;
    uint seed;
    uint frontSide;
    vec3 baseColor;
    float metallic;
    float roughness;
    float transmission;
    float ior;
    vec3 wo;
    uint thin;
    float coverage;
    float specularWeight;  // KHR_materials_specular; negative: none
    vec3 specularColor;
    float clearcoat;       // KHR_materials_clearcoat; 0: none
    float clearcoatRoughness;
    vec3 sheenColor;       // KHR_materials_sheen; black: none
    float sheenRoughness;
    vec3 clearcoatNormal;  // the coat's own normal in the local frame; zero: the shading normal's
    uint adjoint;          // the coat's adjoint term (light-side walks)
} push;

// The material for outgoing direction wo (the sheen's albedo at wo is part of it).
Bsdf material(vec3 wo) {
    Bsdf b = makeBsdf(push.baseColor, push.metallic, push.roughness, push.transmission, push.ior,
                      push.frontSide != 0u, push.thin != 0u, push.coverage);
    if (push.specularWeight >= 0.0) bsdfSetSpecular(b, push.specularWeight, push.specularColor);
    if (push.clearcoat > 0.0) bsdfSetClearcoat(b, push.clearcoat, push.clearcoatRoughness);
    if (push.clearcoat > 0.0 && dot(push.clearcoatNormal, push.clearcoatNormal) > 0.0)
        bsdfSetClearcoatNormal(b, push.clearcoatNormal);
    b.adjoint = push.adjoint != 0u;
    if (maxComponent(push.sheenColor) > 0.0) bsdfSetSheen(b, push.sheenColor, push.sheenRoughness, wo);
    return b;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    Bsdf b = material(push.wo);
    if (push.mode == 0u) {
        Rng rng = rngCreate(hashCombine(i, push.seed));
        float uLobe = rngNext(rng);
        BsdfSample s;
        bool ok = bsdfSample(b, push.wo, uLobe, rngNext2(rng), s);
        results[2u * i] = vec4(s.wi, s.pdf);
        results[2u * i + 1u] =
            vec4(s.f, float((ok ? 1u : 0u) + (s.delta ? 2u : 0u) + 4u * s.lobe));
    } else if (push.mode == 1u) {
        vec3 wo = inputs[2u * i].xyz;
        vec3 wi = inputs[2u * i + 1u].xyz;
        // The material made for push.wo, turned to this wo (bsdfSetOutgoing: what a
        // bidirectional method does), which the sampled directions' values and reciprocity
        // check against a material made for each wo.
        bsdfSetOutgoing(b, push.frontSide != 0u, wo);
        results[i] = vec4(bsdfEval(b, wo, wi), bsdfPdf(b, wo, wi));
    } else {
        results[0] = lobeSelectProbabilities(b, push.wo);
        results[1] = vec4(dielectricReflectance(b, push.wo.z), b.eta,
                          bsdfHasNonDelta(b) ? 1.0 : 0.0, b.wPass);
        results[2] = vec4(clearcoatLobeProbability(b, push.wo), clearcoatAttenuation(b, push.wo),
                          b.sheenAlbedoO, sheenLobeProbability(b, push.wo));
    }
}
