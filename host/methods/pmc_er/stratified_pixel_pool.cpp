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

// The even bits of v packed together: bit 2i to bit i (the inverse of the bit interleave by
// masks and shifts, Warren, Hacker's Delight, sec. 7-2).
uint64_t compactEvenBits(uint64_t v) {
    v &= 0x5555555555555555ULL;
    v = (v | (v >> 1)) & 0x3333333333333333ULL;
    v = (v | (v >> 2)) & 0x0f0f0f0f0f0f0f0fULL;
    v = (v | (v >> 4)) & 0x00ff00ff00ff00ffULL;
    v = (v | (v >> 8)) & 0x0000ffff0000ffffULL;
    v = (v | (v >> 16)) & 0x00000000ffffffffULL;
    return v;
}

// Morton index -> (x, y) on a 2^bx by 2^by grid: bits interleaved x, y, x, y, ... from the
// lowest, the longer side's extra bits on top.
glm::ivec2 demorton(uint64_t code, int bx, int by) {
    const int m = std::min(bx, by);
    const uint64_t low = code & ((uint64_t(1) << (2 * m)) - 1);
    uint64_t x = compactEvenBits(low), y = compactEvenBits(low >> 1);
    const uint64_t high = code >> (2 * m);
    if (bx > by) x |= high << m;
    else y |= high << m;
    return {int(x), int(y)};
}

// The low `bits` bits of v in reverse order (Warren, Hacker's Delight, sec. 7-1: swap halves,
// then quarters, ...).
uint64_t reverseBits(uint64_t v, int bits) {
    if (bits == 0) return 0;
    v = ((v >> 1) & 0x5555555555555555ULL) | ((v & 0x5555555555555555ULL) << 1);
    v = ((v >> 2) & 0x3333333333333333ULL) | ((v & 0x3333333333333333ULL) << 2);
    v = ((v >> 4) & 0x0f0f0f0f0f0f0f0fULL) | ((v & 0x0f0f0f0f0f0f0f0fULL) << 4);
    v = ((v >> 8) & 0x00ff00ff00ff00ffULL) | ((v & 0x00ff00ff00ff00ffULL) << 8);
    v = ((v >> 16) & 0x0000ffff0000ffffULL) | ((v & 0x0000ffff0000ffffULL) << 16);
    v = (v >> 32) | (v << 32);
    return v >> (64 - bits);
}

}  // namespace

StratifiedPixelPool::StratifiedPixelPool(int width, int height, uint32_t rounds, uint32_t firstSample, Pcg32& rng,
                                         uint32_t lane, uint32_t lanes)
    : m_width(width), m_height(height), m_rounds(rounds), m_firstSample(firstSample), m_rng(rng.nextUint(), rng.nextUint()),
      m_lane(lane), m_lanes(lanes) {
    if (width < 1 || height < 1 || rounds < 1) throw Error("stratified pixel pool: empty");
    if (lanes < 1 || lane >= lanes) throw Error("stratified pixel pool: lane out of range");
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
        m_point = demorton(reverseBits(m_code, m_bitsX + m_bitsY), m_bitsX, m_bitsY);
        if (m_point.x < m_width && m_point.y < m_height) return true;
        ++m_code;
    }
}

std::vector<PoolSample> StratifiedPixelPool::next(uint32_t count) {
    std::vector<PoolSample> samples;
    samples.reserve(size_t(std::min<uint64_t>(count, remaining())));
    while (samples.size() < count && advance()) {
        ++m_code;
        if (m_seen++ % m_lanes != m_lane) continue;
        const int x = (m_point.x + m_shift.x) % m_width, y = (m_point.y + m_shift.y) % m_height;
        samples.push_back({uint32_t(y) * uint32_t(m_width) + uint32_t(x), m_firstSample + m_round});
        ++m_used;
    }
    return samples;
}

}  // namespace pmcr
