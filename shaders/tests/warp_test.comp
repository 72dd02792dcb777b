#version 460
// Test kernel for the warps of shaders/common/sampling.glsl (tests/gpu/test_sampling.cpp).
// Sampling modes draw u from rngCreate(hashCombine(i, seed)) and write results[i]:
//   0: (sampleUniformDiskConcentric(u), 0, 0)
//   1: (sampleCosineHemisphere(u), cosineHemispherePdf of its z)
//   2: (sampleUniformSphere(u), 0)
//   3: (sampleUniformCone(u, cosThetaMax), uniformConePdf(cosThetaMax))
//   4: (sampleUniformTriangle(u), 0, 0)
// Mode 5 evaluates densities at directions[i]: (cosineHemispherePdf(z), uniformConePdf, 0, 0).
// Mode 6 evaluates the MIS heuristics at pdfs (a, b) = directions[i].xy and sample counts
// (nA, nB) = directions[i].zw: (powerHeuristic(nA, a, nB, b), powerHeuristic(nB, b, nA, a),
// balanceHeuristic(nA, a, nB, b), balanceHeuristic(nB, b, nA, a)).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

#include "common/rng.glsl"
#include "common/sampling.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) readonly buffer Directions { vec4 directions[]; };
layout(set = WORK_SET, binding = 1, scalar) writeonly buffer Results { vec4 results[]; };
layout(push_constant, scalar) uniform Push {
    uint mode;
    uint count;
    uint seed;
    float cosThetaMax;
} push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    if (push.mode == 6u) {
        vec4 v = directions[i];
        results[i] = vec4(powerHeuristic(v.z, v.x, v.w, v.y),
                          powerHeuristic(v.w, v.y, v.z, v.x),
                          balanceHeuristic(v.z, v.x, v.w, v.y),
                          balanceHeuristic(v.w, v.y, v.z, v.x));
        return;
    }
    if (push.mode == 5u) {
        results[i] = vec4(cosineHemispherePdf(directions[i].z), uniformConePdf(push.cosThetaMax),
                          0.0, 0.0);
        return;
    }
    Rng rng = rngCreate(hashCombine(i, push.seed));
    vec2 u = rngNext2(rng);
    vec4 r = vec4(0.0);
    if (push.mode == 0u) {
        r.xy = sampleUniformDiskConcentric(u);
    } else if (push.mode == 1u) {
        r.xyz = sampleCosineHemisphere(u);
        r.w = cosineHemispherePdf(r.z);
    } else if (push.mode == 2u) {
        r.xyz = sampleUniformSphere(u);
    } else if (push.mode == 3u) {
        r.xyz = sampleUniformCone(u, push.cosThetaMax);
        r.w = uniformConePdf(push.cosThetaMax);
    } else {
        r.xy = sampleUniformTriangle(u);
    }
    results[i] = r;
}
