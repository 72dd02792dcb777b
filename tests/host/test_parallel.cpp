// core/parallel.h: the host's work spread over the cores gives one thread's result.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "core/parallel.h"

namespace pmcr {
namespace {

// Every item's elements in item order, whatever the blocks: items contribute 0 to 3 elements
// (many contribute none, as paths with no stored photon or photons that are not caustic).
TEST(Parallel, ConcatIsOneThreadsConcatenation) {
    const size_t count = 100003;  // not a multiple of the block
    auto sizeOf = [](size_t i) -> size_t { return (i * 7919u) % 4u == 3u ? 0 : (i * 7919u) % 4u; };
    std::vector<uint32_t> expected;
    for (size_t i = 0; i < count; ++i)
        for (size_t k = 0; k < sizeOf(i); ++k) expected.push_back(uint32_t(i * 4 + k));
    for (size_t block : {size_t(1000), size_t(8192), size_t(1) << 20}) {
        std::vector<uint32_t> got;
        parallelConcat(count, block, got, sizeOf, [&](size_t i, uint32_t* out) {
            for (size_t k = 0; k < sizeOf(i); ++k) *out++ = uint32_t(i * 4 + k);
            return out;
        });
        EXPECT_EQ(got, expected) << "block " << block;
    }
}

// Each block summed in order, then the blocks in order: the same bits for any thread count.
TEST(Parallel, SumAddsBlocksInOrder) {
    const size_t count = 50001, block = 4096;
    auto term = [](size_t i) { return 1.0 / double(i + 1); };
    double expected = 0.0;
    for (size_t b = 0; b < count; b += block) {
        double s = 0.0;
        for (size_t i = b; i < std::min(count, b + block); ++i) s += term(i);
        expected += s;
    }
    EXPECT_EQ(parallelSum(count, block, term), expected);
}

}  // namespace
}  // namespace pmcr
