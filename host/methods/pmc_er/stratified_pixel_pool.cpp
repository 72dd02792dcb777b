#include "methods/pmc_er/stratified_pixel_pool.h"

#include <algorithm>

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

StratifiedPixelPool::StratifiedPixelPool(int width, int height, uint32_t rounds, uint32_t firstSample, Pcg32& rng)
    : m_width(width), m_height(height), m_rounds(rounds), m_firstSample(firstSample), m_rng(rng.nextUint(), rng.nextUint()) {
    if (width < 1 || height < 1 || rounds < 1) throw Error("stratified pixel pool: empty");
    m_bitsX = bitsFor(width);
    m_bitsY = bitsFor(height);
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

std::vector<PoolSample> StratifiedPixelPool::next(uint32_t count) {
    std::vector<PoolSample> samples;
    samples.reserve(size_t(std::min<uint64_t>(count, remaining())));
    while (samples.size() < count && advance()) {
        const glm::ivec2 c = demorton(reverseBits(m_code, m_bitsX + m_bitsY), m_bitsX, m_bitsY);
        ++m_code;
        const int x = (c.x + m_shift.x) % m_width, y = (c.y + m_shift.y) % m_height;
        samples.push_back({uint32_t(y) * uint32_t(m_width) + uint32_t(x), m_firstSample + m_round});
        ++m_used;
    }
    return samples;
}

}  // namespace pmcr
