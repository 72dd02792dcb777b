// Lavapipe's loop limit, measured (Mesa 22.3.6, LLVM 15, Debian bookworm):
//
//   gallivm keeps ONE loop-iteration budget of 65535 (LP_MAX_TGSI_LOOP_ITERATIONS) per shader
//   invocation, shared by every loop the invocation runs, nested or sequential, `for` or
//   `while (true)`. When it runs out, every loop exits at its next iteration as if its condition
//   were false — silently. Measured: one loop of 100000 stops at 65534-65535 (a few iterations go to the shader's other loops); two sequential loops of
//   40000 give 40000 and 25534; nested 1000 x 100 gives 64249; a while(true) loop of 100000
//   stops at 65531. Invocations do not share the budget: 128 invocations of a workgroup each
//   complete 60000 iterations.
//
// What pmcr does about it: every kernel keeps each invocation's total loop iterations per
// dispatch far below 65535. BVH traversal takes tens to a few hundred iterations per ray (one per
// interior node or triangle tested), a camera sample at most 2 * (max depth + 1) rays, an
// invocation of pt or pt_record at most 64 camera samples (64 passes of one pixel, or up to 32
// pixels or requests in turn; methods/pt/pt_integrator.h), and
// Markov-chain kernels advance a bounded number of mutations per dispatch. A traversal cut short would be silent (the kernels do not
// count truncated traversals); tests/gpu/test_bvh_traversal.cpp checks that GPU traversals of
// the default scene and of the 200k-triangle dragon give the host's hits. Real GPUs have no
// such limit.
#include <gtest/gtest.h>

#include "gpu_test.h"

namespace pmcr::test {
namespace {

constexpr uint32_t kMesaBudget = 65535;

struct LoopPush {
    uint32_t a;
    uint32_t b;
    uint32_t mode;
};

class LoopLimits : public GpuTest {
protected:
    std::vector<uint32_t> run(LoopPush push, uint32_t invocations = 1) {
        auto ones = storage(std::vector<uint32_t>(8, 1u), "ones");
        auto out = zeros((3 + invocations) * sizeof(uint32_t), "loop counts");
        GpuTest::run("tests/loop_limit_test", push, invocations, {&ones, &out});
        return out.download<uint32_t>(3 + invocations);
    }
};

// The property pmcr relies on: an invocation may run tens of thousands of loop iterations in
// total, independently of the other invocations of its workgroup.
TEST_F(LoopLimits, EachInvocationHasItsOwnBudget) {
    auto counts = run({60000, 0, 5}, 128);
    for (uint32_t i = 0; i < 128; ++i) ASSERT_EQ(counts[3 + i], 60000u) << "invocation " << i;
}

// Either no limit at all (GPUs, newer Mesa) or Mesa's shared per-invocation budget; any other
// behaviour would invalidate the budget rules above.
TEST_F(LoopLimits, DriverHasNoLimitOrMesasSharedBudget) {
    auto single = run({100000, 0, 0});
    auto sequential = run({40000, 40000, 1});
    auto nested = run({3, 70000, 2});
    auto whileLoop = run({100000, 0, 3});
    const bool unlimited = single[0] == 100000 && sequential[0] + sequential[1] == 80000 &&
                           nested[1] == 210000 && whileLoop[0] == 100000;
    if (unlimited) {
        RecordProperty("loop_limit", "none");
        return;
    }
    RecordProperty("loop_limit", "shared budget of 65535 per invocation");
    EXPECT_NEAR(double(single[0]), double(kMesaBudget), 8.0);
    EXPECT_EQ(sequential[0], 40000u);
    EXPECT_NEAR(double(sequential[0] + sequential[1]), double(kMesaBudget), 8.0);
    EXPECT_LT(nested[1], kMesaBudget);
    EXPECT_GT(nested[1], kMesaBudget - 16);
    EXPECT_NEAR(double(whileLoop[0]), double(kMesaBudget), 8.0);
}

}  // namespace
}  // namespace pmcr::test
