// The order in which the adaptive samplers (PMC-IP, PMC-PT) hand pixels to the path tracer:
// Morton order (the Z-order curve), so that neighbouring invocations trace neighbouring camera
// rays, which share BVH nodes and material branches.
#pragma once

#include <cstdint>
#include <vector>

namespace pmcr {

// Interleaves the bits of x and y (x in the even bits).
uint32_t mortonCode(uint32_t x, uint32_t y);

// The linear indices of a width x height image's pixels, sorted by Morton code.
std::vector<uint32_t> mortonPixelOrder(int width, int height);

}  // namespace pmcr
