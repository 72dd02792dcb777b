#include "render/stratified_pixel_pool.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace pmcr {

namespace {

int bitsFor(int n) {
    int b = 0;
    while ((1 << b) < n) ++b;
    return b;
}

// Morton index -> (x, y) on a 2^bx by 2^by grid: bits interleaved x, y, x, y, ... from the
// lowest, the longer side's extra bits on top.
glm::ivec2 demorton(uint64_t code, int bx, int by) {
    int x = 0, y = 0, bit = 0;
    for (int i = 0; i < std::max(bx, by); ++i) {
        if (i < bx) x |= int((code >> bit++) & 1u) << i;
        if (i < by) y |= int((code >> bit++) & 1u) << i;
    }
    return {x, y};
}

uint64_t reverseBits(uint64_t v, int bits) {
    uint64_t r = 0;
    for (int i = 0; i < bits; ++i) r |= ((v >> i) & 1u) << (bits - 1 - i);
    return r;
}

}  // namespace

StratifiedPixelPool::StratifiedPixelPool(int width, int height, uint32_t rounds, Pcg32& rng)
    : m_width(width), m_height(height), m_rounds(rounds), m_rng(rng.nextUint(), rng.nextUint()) {
    if (width < 1 || height < 1 || rounds < 1) throw Error("stratified pixel pool: empty");
    m_bitsX = bitsFor(width);
    m_bitsY = bitsFor(height);
    m_rotation.resize(size_t(width) * size_t(height));
    for (auto& r : m_rotation) r = glm::vec2(float(m_rng.nextDouble()), float(m_rng.nextDouble()));
    m_shift = {int(m_rng.nextBelow(uint32_t(width))), int(m_rng.nextBelow(uint32_t(height)))};
}

bool StratifiedPixelPool::advance() {
    const uint64_t codes = uint64_t(1) << (m_bitsX + m_bitsY);
    for (;;) {
        if (m_code == codes) {
            if (++m_round >= m_rounds) return false;
            m_code = 0;
            m_shift = {int(m_rng.nextBelow(uint32_t(m_width))), int(m_rng.nextBelow(uint32_t(m_height)))};
        }
        const glm::ivec2 p = demorton(reverseBits(m_code, m_bitsX + m_bitsY), m_bitsX, m_bitsY);
        if (p.x < m_width && p.y < m_height) return true;
        ++m_code;
    }
}

std::vector<glm::dvec2> StratifiedPixelPool::next(uint32_t count) {
    // R2: x_n = frac(n / g, n / g^2), g the plastic number (root of g^3 = g + 1).
    constexpr double g = 1.32471795724474602596;
    constexpr double a1 = 1.0 / g, a2 = 1.0 / (g * g);
    std::vector<glm::dvec2> positions;
    positions.reserve(size_t(std::min<uint64_t>(count, remaining())));
    while (positions.size() < count && advance()) {
        const glm::ivec2 c = demorton(reverseBits(m_code, m_bitsX + m_bitsY), m_bitsX, m_bitsY);
        ++m_code;
        const int x = (c.x + m_shift.x) % m_width, y = (c.y + m_shift.y) % m_height;
        const glm::vec2 r = m_rotation[size_t(y) * size_t(m_width) + size_t(x)];
        const double n = double(m_round);
        const double u = std::fmod(0.5 + a1 * n + double(r.x), 1.0);
        const double v = std::fmod(0.5 + a2 * n + double(r.y), 1.0);
        // In float (as the device reads them), kept inside the pixel by rounding down.
        auto inside = [](int cell, double offset) {
            const float f = float(cell) + float(offset);
            return double(std::min(f, std::nextafter(float(cell + 1), 0.0f)));
        };
        positions.emplace_back(inside(x, u), inside(y, v));
        ++m_used;
    }
    return positions;
}

}  // namespace pmcr
