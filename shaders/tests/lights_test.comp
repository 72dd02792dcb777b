#version 460
// Test kernel for shaders/common/lights.glsl over the bound scene (tests/gpu/test_lights.cpp).
//   mode 0: sampleLight with uSelect, uPoint from rngCreate(hashCombine(i, seed)):
//           results[2i] = (position, triangle), results[2i + 1] = (normal, pdfArea)
//   mode 1: triangle i: results[i] = (emitterPower, emitterSelectPmf, emitterAreaPdf, triangleArea)
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

#include "common/lights.glsl"
#include "common/rng.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) writeonly buffer Results { vec4 results[]; };
layout(push_constant, scalar) uniform Push {
    uint mode;
    uint count;
    uint seed;
} push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    if (push.mode == 0u) {
        Rng rng = rngCreate(hashCombine(i, push.seed));
        float uSelect = rngNext(rng);
        LightSample ls = sampleLight(uSelect, rngNext2(rng));
        results[2u * i] = vec4(ls.point.position, float(ls.point.triangle));
        results[2u * i + 1u] = vec4(ls.point.normal, ls.pdfArea);
    } else {
        results[i] = vec4(emitterPower(i), emitterSelectPmf(i), emitterAreaPdf(i), triangleArea(i));
    }
}
