// shaders/common/rng.glsl: the hashes and PCG streams equal a C++ reference bit for bit, and
// rngNext is uniform in 1D, in consecutive pairs and across neighbouring seeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "distribution_test.h"
#include "gpu_test.h"

namespace pmcr::test {
namespace {

struct RngPush {
    uint32_t mode;
    uint32_t count;
    uint32_t seed;
    uint32_t perStream;
};

// PCG-RXS-M-XS 32/32 (O'Neill 2014, sec. 6.3.4): LCG step with the multiplier and increment of
// Jarzynski and Olano 2020, then the output permutation of the new state.
uint32_t pcgPermute(uint32_t state) {
    const uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
uint32_t lcgStep(uint32_t state) {
    return state * 747796405u + 2891336453u;
}
uint32_t hashPcgReference(uint32_t v) {
    return pcgPermute(lcgStep(v));
}
uint32_t hashCombineReference(uint32_t a, uint32_t b) {
    return hashPcgReference(a ^ (hashPcgReference(b) + 0x9e3779b9u + (a << 6) + (a >> 2)));
}

class PcgReference {
public:
    explicit PcgReference(uint32_t seed) : m_state(hashPcgReference(seed)) {}
    uint32_t next() {
        m_state = lcgStep(m_state);
        return pcgPermute(m_state);
    }

private:
    uint32_t m_state;
};

class RngTest : public GpuTest {
protected:
    std::vector<uint32_t> streams(uint32_t mode, uint32_t streamCount, uint32_t perStream,
                                  uint32_t seed) {
        auto unused = zeros(16);
        auto out = zeros(size_t(streamCount) * perStream * 4, "rng words");
        run("tests/rng_test", RngPush{mode, streamCount, seed, perStream}, streamCount,
            {&unused, &out});
        return out.download<uint32_t>(size_t(streamCount) * perStream);
    }
};

TEST_F(RngTest, HashesMatchReference) {
    std::vector<glm::uvec4> inputs = {{0u, 0u, 0u, 0u},
                                      {1u, 2u, 3u, 0u},
                                      {0xffffffffu, 0xffffffffu, 0xffffffffu, 0u},
                                      {0x80000000u, 1u, 0x7fffffffu, 0u}};
    std::mt19937 gen(7);
    while (inputs.size() < 4096)
        inputs.push_back({gen(), gen(), gen(), 0u});
    const uint32_t n = uint32_t(inputs.size());
    auto in = storage(inputs, "hash inputs");
    auto out = zeros(n * 16, "hash outputs");
    run("tests/rng_test", RngPush{0, n, 0, 0}, n, {&in, &out});
    const auto words = out.download<uint32_t>(size_t(n) * 4);
    for (uint32_t i = 0; i < n; ++i) {
        const glm::uvec4 v = inputs[i];
        ASSERT_EQ(words[4 * i], hashPcgReference(v.x)) << "hashPcg(" << v.x << ")";
        ASSERT_EQ(words[4 * i + 1], hashCombineReference(v.x, v.y)) << "hashCombine " << i;
        ASSERT_EQ(words[4 * i + 2], hashCombineReference(hashCombineReference(v.x, v.y), v.z))
            << "hash3 " << i;
        ASSERT_EQ(words[4 * i + 3], hashPcgReference(v.x)) << "rngCreate " << i;
    }
}

TEST_F(RngTest, StreamsMatchReference) {
    const uint32_t streamCount = 4096, perStream = 16, seed = 12345;
    const auto uints = streams(1, streamCount, perStream, seed);
    const auto floats = streams(2, streamCount, perStream, seed);
    for (uint32_t s = 0; s < streamCount; ++s) {
        PcgReference reference(seed + s);
        for (uint32_t k = 0; k < perStream; ++k) {
            const uint32_t expected = reference.next();
            const size_t i = size_t(s) * perStream + k;
            ASSERT_EQ(uints[i], expected) << "stream " << s << " value " << k;
            // Top 24 bits, exactly: float(x >> 8) / 2^24.
            float value;
            std::memcpy(&value, &floats[i], 4);
            ASSERT_EQ(value, float(expected >> 8) / 16777216.0f)
                << "stream " << s << " value " << k;
            ASSERT_LT(value, 1.0f);
        }
    }
}

TEST_F(RngTest, UniformInOneAndTwoDimensions) {
    const uint32_t streamCount = 65536, perStream = 16;
    const auto bits = streams(2, streamCount, perStream, 0x5eed);
    std::vector<float> u(bits.size());
    std::memcpy(u.data(), bits.data(), bits.size() * 4);
    auto bin = [](float x, int n) { return std::min(int(x * n), n - 1); };

    const int n1 = 1000;
    std::vector<double> counts1(n1, 0.0);
    for (float x : u)
        counts1[size_t(bin(x, n1))] += 1.0;
    EXPECT_TRUE(chi2Passes(counts1, std::vector<double>(n1, double(u.size()) / n1), "rngNext 1D"));

    // Consecutive pairs of one stream, and the same draw of neighbouring seeds.
    const int n2 = 32;
    std::vector<double> pairs(n2 * n2, 0.0), neighbours(n2 * n2, 0.0);
    for (uint32_t s = 0; s < streamCount; ++s)
        for (uint32_t k = 0; k < perStream; k += 2) {
            const size_t i = size_t(s) * perStream + k;
            pairs[size_t(bin(u[i], n2) * n2 + bin(u[i + 1], n2))] += 1.0;
            if (s + 1 < streamCount)
                neighbours[size_t(bin(u[i], n2) * n2 + bin(u[i + perStream], n2))] += 1.0;
        }
    const double perCellPairs = double(streamCount) * perStream / 2 / (n2 * n2);
    EXPECT_TRUE(chi2Passes(pairs, std::vector<double>(n2 * n2, perCellPairs), "rngNext pairs"));
    const double perCellNeighbours = double(streamCount - 1) * perStream / 2 / (n2 * n2);
    EXPECT_TRUE(chi2Passes(neighbours, std::vector<double>(n2 * n2, perCellNeighbours),
                           "rngNext of neighbouring seeds"));
}

}  // namespace
}  // namespace pmcr::test
