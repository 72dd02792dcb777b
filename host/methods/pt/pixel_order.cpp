#include "methods/pt/pixel_order.h"

#include <algorithm>

namespace pmcr {

uint32_t mortonCode(uint32_t x, uint32_t y) {
    auto spread = [](uint32_t v) {
        v &= 0xffffu;
        v = (v | (v << 8)) & 0x00ff00ffu;
        v = (v | (v << 4)) & 0x0f0f0f0fu;
        v = (v | (v << 2)) & 0x33333333u;
        v = (v | (v << 1)) & 0x55555555u;
        return v;
    };
    return spread(x) | (spread(y) << 1);
}

std::vector<uint32_t> mortonPixelOrder(int width, int height) {
    const uint32_t w = uint32_t(width), pixels = w * uint32_t(height);
    std::vector<uint32_t> order(pixels);
    for (uint32_t p = 0; p < pixels; ++p) order[p] = p;
    std::sort(order.begin(), order.end(), [w](uint32_t a, uint32_t b) {
        return mortonCode(a % w, a / w) < mortonCode(b % w, b / w);
    });
    return order;
}

}  // namespace pmcr
