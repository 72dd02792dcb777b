// A small, fast, seedable host random number generator: PCG32 (O'Neill 2014, pcg32_random_r,
// XSH RR output). The host's adaptive samplers (PMC-PT's population) draw from it, so a seed
// gives the same decisions, and the same image, on every run.
#pragma once

#include <cstdint>

namespace pmcr {

class Pcg32 {
public:
    explicit Pcg32(uint64_t seed = 0x853c49e6748fea9bULL, uint64_t stream = 0xda3e39cb94b95bdbULL) {
        m_inc = (stream << 1u) | 1u;
        m_state = 0;
        nextUint();
        m_state += seed;
        nextUint();
    }

    uint32_t nextUint() {
        const uint64_t old = m_state;
        m_state = old * 6364136223846793005ULL + m_inc;
        const uint32_t xorShifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        const uint32_t rot = uint32_t(old >> 59u);
        return (xorShifted >> rot) | (xorShifted << ((32u - rot) & 31u));
    }

    // Uniform in [0, 1) with 53 random bits.
    double nextDouble() {
        const uint64_t hi = nextUint() >> 5;  // 27 bits
        const uint64_t lo = nextUint() >> 6;  // 26 bits
        return double((hi << 26) | lo) * (1.0 / 9007199254740992.0);
    }

    // Uniform in [0, n) (Lemire's nearly divisionless method would be faster; n is small here).
    uint32_t nextBelow(uint32_t n) { return n <= 1 ? 0u : uint32_t(nextDouble() * double(n)); }

private:
    uint64_t m_state;
    uint64_t m_inc;
};

}  // namespace pmcr
