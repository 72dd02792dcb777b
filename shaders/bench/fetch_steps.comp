#version 460
// The memory part of the traversal alone (bench/throughput --fetch-ceiling): ray i takes as many
// steps as the real traversal took for it (steps[i], from trace_rays_steps.comp), each step
// doing the texel fetches of a wide-node step and nothing else: no slab tests, no sorting, no
// stack. A step fetches kFetchesPerStep texels of a node (7: the whole node, as bvhStep does; 4:
// three box texels and the refs, what a node compressed to four texels would fetch), then goes
// to one of the node's children picked by a hash; at a leaf it fetches the leaf's triangles the
// same way and starts again at the root. So the fetches run at the real steps per ray, with the
// same idle lanes (a vector's loop runs for its longest ray) and a cache at least as warm as the
// traversal's (every descent restarts at the root): an upper bound on the rays per second of
// any traversal that fetches that much per step.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) readonly buffer Steps { uint steps[]; };
layout(set = WORK_SET, binding = 1, scalar) writeonly buffer Out { uvec4 results[]; };
layout(push_constant, scalar) uniform Push { uint count; } push;
// The texels a step fetches, 7 or 4: a specialization constant (vk::Kernel's constant 1), not a
// push constant, since lavapipe would run the fetches under an `if` whatever its condition.
layout(constant_id = 1) const uint kFetchesPerStep = 7u;

#include "common/bvh.glsl"
#include "common/rng.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    uint n = steps[i];
    uvec4 acc = uvec4(i);
    uint address = 0u;  // the root
    uint count = 0u;  // a leaf's triangles left (0: a wide node), as in bvhStep
    for (uint s = 0u; s < n; ++s) {
        bool leaf = count > 0u;
        bool one = leaf && count < 2u;  // bvhStep's addresses: none past the last triangle
        uvec4 w0 = bvhTexel(address);
        uvec4 w1 = bvhTexel(address + 1u);
        uvec4 w2 = bvhTexel(address + 2u);
        uvec4 w6 = bvhTexel(leaf ? address : address + BVH_NODE_REFS_TEXEL);
        acc ^= w0 ^ w1 ^ w2 ^ w6;
        if (kFetchesPerStep > 4u) {
            acc ^= bvhTexel(one ? address : address + 3u) ^
                   bvhTexel(one ? address + 1u : address + 4u) ^
                   bvhTexel(one ? address + 2u : address + 5u);
        }
        uint ref = w6[hash3(i, s, acc.x) & 3u];
        bool restart = leaf || ref == BVH_EMPTY_CHILD;
        count = restart ? 0u : ref & 7u;
        address = restart ? 0u : ref >> 3;
    }
    results[i] = acc;
}
