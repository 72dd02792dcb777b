// Lavapipe's loop limits. Mesa's gallivm used to end every loop after 65535 iterations
// (LP_MAX_TGSI_LOOP_ITERATIONS), silently. pmcr's kernels never rely on long loops: BVH
// traversal is bounded by its node count, paths by --max-depth, Markov chains advance a bounded
// number of steps per dispatch. This test records what the driver in use actually does; see the
// finding in the comment at the end of the file.
#include <gtest/gtest.h>

#include "gpu_test.h"

namespace pmcr::test {
namespace {

struct LoopPush {
    uint32_t iterations;
    uint32_t outer;
};

class LoopLimits : public GpuTest {
protected:
    std::vector<uint32_t> run(uint32_t iterations, uint32_t outer) {
        auto ones = storage(std::vector<uint32_t>(8, 1u), "ones");
        auto out = zeros(3 * sizeof(uint32_t), "loop counts");
        GpuTest::run("tests/loop_limit_test", LoopPush{iterations, outer}, 1, {&ones, &out});
        return out.download<uint32_t>(3);
    }
};

TEST_F(LoopLimits, LoopsRunPast65535Iterations) {
    const uint32_t n = 200000;
    auto counts = run(n, 1);
    EXPECT_EQ(counts[0], n) << "for loop capped on " << context().deviceName();
    EXPECT_EQ(counts[2], n) << "while loop capped on " << context().deviceName();
}

TEST_F(LoopLimits, NestedLoopsRunTheirFullProduct) {
    auto counts = run(70000, 3);
    EXPECT_EQ(counts[1], 210000u) << "nested loops capped on " << context().deviceName();
}

}  // namespace
}  // namespace pmcr::test
