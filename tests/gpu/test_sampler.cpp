// shaders/common/sampler.glsl: the Sobol and scrambling building blocks equal straightforward
// C++ references, every aligned block of 2^k samples of a pixel is a (0,k,2)-net in every
// dimension pair (a (0,k)-net in 1D), pixels and dimensions are decorrelated, and an independent
// draw in place of the first pair leaves the others as they were.
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

struct SamplerPush {
    uint32_t mode;
    uint32_t count;
    uint32_t seed;
    uint32_t dimensions;
    uint32_t samplesPerPixel;
    uint32_t pixelBase;
    uint32_t pixelStride;
    uint32_t sampleBase;
};

uint32_t reverseBits(uint32_t x) {
    uint32_t r = 0;
    for (int k = 0; k < 32; ++k)
        r |= ((x >> k) & 1u) << (31 - k);
    return r;
}

// Sobol dimension 1 by the definition: XOR of the direction numbers of the index's set bits,
// v_1 = 2^31, v_{k+1} = v_k xor (v_k >> 1) (Joe and Kuo 2008, dimension 2 of their tables).
uint32_t sobolSecondDimensionReference(uint32_t index) {
    uint32_t v = 1u << 31, x = 0;
    for (int k = 0; k < 32; ++k, v ^= v >> 1)
        if ((index >> k) & 1u)
            x ^= v;
    return x;
}

uint32_t laineKarrasReference(uint32_t x, uint32_t seed) {
    x += seed;
    for (uint32_t c : {0x6c50b47cu, 0xb82f1e52u, 0xc7afe638u, 0x8d22f6e6u})
        x ^= x * c;
    return x;
}

uint32_t nestedUniformScrambleReference(uint32_t x, uint32_t seed) {
    return reverseBits(laineKarrasReference(reverseBits(x), seed));
}

class SamplerTest : public GpuTest {
protected:
    // Floats written by modes 1, 2 and 3: (pixels * spp) invocations of `dimensions` draws.
    std::vector<float> draw(uint32_t mode, uint32_t pixels, uint32_t spp, uint32_t dimensions,
                            uint32_t pixelBase, uint32_t pixelStride, uint32_t seed) {
        const uint32_t n = pixels * spp;
        const size_t words = size_t(n) * dimensions * (mode == 2 ? 1 : 2);
        auto unused = zeros(16);
        auto out = zeros(words * 4, "sampler draws");
        run("tests/sampler_test",
            SamplerPush{mode, n, seed, dimensions, spp, pixelBase, pixelStride, 0}, n,
            {&unused, &out});
        std::vector<float> values(words);
        out.download(values.data(), words * 4);
        return values;
    }
};

TEST_F(SamplerTest, BuildingBlocksMatchReferences) {
    std::vector<glm::uvec4> inputs;
    std::mt19937 gen(11);
    for (uint32_t i = 0; i < 65536; ++i)
        inputs.push_back({i, gen(), 0u, 0u});
    for (uint32_t i = 0; i < 4096; ++i)
        inputs.push_back({gen(), gen(), 0u, 0u});
    // Pairs that agree in bits 0..k: Laine-Karras output bit k depends only on those.
    const uint32_t firstPair = uint32_t(inputs.size());
    for (uint32_t i = 0; i < 4096; ++i) {
        const uint32_t x = gen(), seed = gen(), k = i % 31;
        const uint32_t high = ~0u << (k + 1);
        inputs.push_back({x, seed, k, 0u});
        inputs.push_back({(x & ~high) | (gen() & high), seed, k, 0u});
    }
    const uint32_t n = uint32_t(inputs.size());
    auto in = storage(inputs, "sampler inputs");
    auto out = zeros(size_t(n) * 16, "sampler outputs");
    run("tests/sampler_test", SamplerPush{0, n, 0, 0, 1, 0, 0, 0}, n, {&in, &out});
    const auto words = out.download<uint32_t>(size_t(n) * 4);
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t x = inputs[i].x, seed = inputs[i].y;
        ASSERT_EQ(words[4 * i], sobolSecondDimensionReference(x)) << "sobol index " << x;
        ASSERT_EQ(words[4 * i + 1], laineKarrasReference(x, seed)) << "laineKarras " << i;
        ASSERT_EQ(words[4 * i + 2], nestedUniformScrambleReference(x, seed)) << "scramble " << i;
    }
    for (uint32_t i = firstPair; i < n; i += 2) {
        const uint32_t low = ~(~0u << (inputs[i].z + 1));
        ASSERT_EQ(words[4 * i + 1] & low, words[4 * (i + 1) + 1] & low)
            << "bits <= " << inputs[i].z;
    }
}

// True when points[first .. first + 2^k) (2D, stride 2) put exactly one point in every elementary
// interval of area 2^-k: for each split k = a + b, cells of 2^-a by 2^-b.
bool isNet2D(const std::vector<float>& xy, size_t first, size_t stride, int k, std::string& why) {
    const size_t count = size_t(1) << k;
    std::vector<char> seen(count);
    for (int a = 0; a <= k; ++a) {
        std::fill(seen.begin(), seen.end(), 0);
        for (size_t p = 0; p < count; ++p) {
            const float x = xy[(first + p) * stride], y = xy[(first + p) * stride + 1];
            const size_t cell =
                (size_t(x * float(1u << a)) << (k - a)) + size_t(y * float(1u << (k - a)));
            if (cell >= count || seen[cell]++) {
                why = "two points in an interval of 2^-" + std::to_string(a) + " x 2^-" +
                      std::to_string(k - a);
                return false;
            }
        }
    }
    return true;
}

TEST_F(SamplerTest, AlignedBlocksAreZeroKTwoNets) {
    const uint32_t pixels = 4, spp = 2048, dimensions = 6, pixelBase = 3, pixelStride = 1000;
    const auto xy = draw(1, pixels, spp, dimensions, pixelBase, pixelStride, 7);
    const auto x1 = draw(2, pixels, spp, dimensions, pixelBase, pixelStride, 7);
    for (uint32_t p = 0; p < pixels; ++p)
        for (uint32_t d = 0; d < dimensions; ++d) {
            // View of pixel p, dimension d: point s at (p * spp + s) * dimensions + d.
            std::vector<float> pts(2 * spp), line(spp);
            for (uint32_t s = 0; s < spp; ++s) {
                const size_t slot = (size_t(p) * spp + s) * dimensions + d;
                pts[2 * s] = xy[2 * slot];
                pts[2 * s + 1] = xy[2 * slot + 1];
                line[s] = x1[slot];
                ASSERT_EQ(line[s], pts[2 * s]) << "samplerGet1D is samplerGet2D's x";
            }
            for (int k = 0; k <= 11; ++k)
                for (size_t first = 0; first < spp; first += size_t(1) << k) {
                    std::string why;
                    ASSERT_TRUE(isNet2D(pts, first, 2, k, why))
                        << "pixel " << pixelBase + p * pixelStride << " pair " << d << " samples ["
                        << first << ", " << first + (size_t(1) << k) << "): " << why;
                    std::vector<char> seen(size_t(1) << k);
                    for (size_t s = first; s < first + (size_t(1) << k); ++s)
                        ASSERT_FALSE(seen[size_t(line[s] * float(1u << k))]++)
                            << "1D: pixel " << p << " dimension " << d << " k " << k;
                }
        }
}

TEST_F(SamplerTest, PixelsAndDimensionsAreDecorrelated) {
    const int bins = 16;
    auto cell = [&](float a, float b) {
        return size_t(std::min(int(a * bins), bins - 1) * bins + std::min(int(b * bins), bins - 1));
    };
    auto uniform = [&](double n) { return std::vector<double>(bins * bins, n / (bins * bins)); };

    // One sample in each of 65536 consecutive pixels, two dimension pairs.
    const uint32_t pixels = 65536;
    const auto one = draw(1, pixels, 1, 2, 0, 1, 3);
    std::vector<double> neighbours(bins * bins, 0.0), dims(bins * bins, 0.0);
    for (uint32_t p = 0; p < pixels; ++p) {
        const size_t slot = size_t(p) * 2;
        if (p + 1 < pixels)
            neighbours[cell(one[2 * slot], one[2 * (slot + 2)])] += 1.0;
        dims[cell(one[2 * slot], one[2 * (slot + 1)])] += 1.0;
    }
    EXPECT_TRUE(chi2Passes(neighbours, uniform(pixels - 1), "x of neighbouring pixels"));
    EXPECT_TRUE(chi2Passes(dims, uniform(pixels), "x of pairs 0 and 1, one sample per pixel"));

    // 256 samples in each of 256 pixels: padded pairs are shuffled independently per pixel.
    const auto many = draw(1, 256, 256, 2, 100, 7, 3);
    std::vector<double> xs(bins * bins, 0.0), ys(bins * bins, 0.0);
    for (size_t i = 0; i < 65536; ++i) {
        xs[cell(many[4 * i], many[4 * i + 2])] += 1.0;
        ys[cell(many[4 * i + 1], many[4 * i + 3])] += 1.0;
    }
    EXPECT_TRUE(chi2Passes(xs, uniform(65536), "x of pairs 0 and 1 within pixels"));
    EXPECT_TRUE(chi2Passes(ys, uniform(65536), "y of pairs 0 and 1 within pixels"));
}

// samplerGetIndependent2D (the pixel sampler `independent`, tests/gpu/test_pixel_sampler.cpp)
// takes the first pair's place: its points are not the sequence's, and every later pair is drawn
// as without it, so only the raster position of a path changes.
TEST_F(SamplerTest, IndependentFirstPairKeepsTheOtherPairs) {
    const uint32_t pixels = 64, spp = 16, dimensions = 4;
    const auto sequence = draw(1, pixels, spp, dimensions, 5, 3, 9);
    const auto independent = draw(3, pixels, spp, dimensions, 5, 3, 9);
    size_t differ = 0;
    for (size_t slot = 0; slot < size_t(pixels) * spp * dimensions; ++slot) {
        if (slot % dimensions == 0) {
            differ += sequence[2 * slot] != independent[2 * slot];
            continue;
        }
        ASSERT_EQ(sequence[2 * slot], independent[2 * slot]) << "slot " << slot;
        ASSERT_EQ(sequence[2 * slot + 1], independent[2 * slot + 1]) << "slot " << slot;
    }
    EXPECT_GT(differ, size_t(pixels) * spp * 99 / 100);
}

}  // namespace
}  // namespace pmcr::test
