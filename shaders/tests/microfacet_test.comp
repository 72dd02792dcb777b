#version 460
// Test kernel for shaders/common/microfacet.glsl (tests/gpu/test_microfacet.cpp). Invocation i:
//   mode 0: m = inputs[i].xyz: results[i] = (ggxD(m), ggxVisibleNormalPdf(wo, m), ggxG1(m), 0)
//   mode 1: results[i] = (ggxSampleVisibleNormal(wo, alpha, u), 0), u from
//           rngCreate(hashCombine(i, seed))
//   mode 2: (cosThetaI, eta, f0) = inputs[i].xyz: results[i] = (fresnelDielectric(cosThetaI, eta),
//           fresnelSchlick(vec3(f0), cosThetaI).x, 0, 0)
//   mode 3: w = inputs[2i].xyz, eta = inputs[2i].w, n = inputs[2i + 1].xyz:
//           results[i] = (wt, 1) from refractDirection(w, n, eta, wt), or (0, 0, 0, 0) when it fails
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

#include "common/microfacet.glsl"
#include "common/rng.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) readonly buffer Inputs { vec4 inputs[]; };
layout(set = WORK_SET, binding = 1, scalar) writeonly buffer Results { vec4 results[]; };
layout(push_constant, scalar) uniform Push {
    uint mode;
    uint count;
    uint seed;
    float alpha;
    vec3 wo;
} push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    if (push.mode == 0u) {
        vec3 m = inputs[i].xyz;
        results[i] = vec4(ggxD(m, push.alpha), ggxVisibleNormalPdf(push.wo, m, push.alpha),
                          ggxG1(m, push.alpha), 0.0);
    } else if (push.mode == 1u) {
        Rng rng = rngCreate(hashCombine(i, push.seed));
        results[i] = vec4(ggxSampleVisibleNormal(push.wo, push.alpha, rngNext2(rng)), 0.0);
    } else if (push.mode == 2u) {
        vec4 q = inputs[i];
        results[i] = vec4(fresnelDielectric(q.x, q.y), fresnelSchlick(vec3(q.z), q.x).x, 0.0, 0.0);
    } else {
        vec4 q = inputs[2u * i];
        vec3 wt;
        bool ok = refractDirection(q.xyz, inputs[2u * i + 1u].xyz, q.w, wt);
        results[i] = ok ? vec4(wt, 1.0) : vec4(0.0);
    }
}
