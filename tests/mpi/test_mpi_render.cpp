// `mpirun -n 2 pmcr render` against one rank at the same total samples (issue 25): the mean of
// independent two-rank renders passes the per-pixel z-test against independent one-rank renders
// for pt, PMC-IP (whose ranks adapt as one population) and ERPT (whose ranks share e_d). The
// renders run through mpirun and the CLI, as a user runs them, with the validation layer on;
// the one-rank side runs without mpirun, which the last test shows renders the same bits.
//
// 8 renders a side is few for a z-test (the t distribution's tails are heavier), so a method
// passes when 99% of the 1728 pixels do, not Mitsuba's 99.75%: a wrong reduction (summed
// images, unweighted shares, a rank's samples lost) fails nearly every pixel.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "image/image.h"
#include "statistics.h"
#include "test_util.h"

namespace pmcr::test {
namespace {

constexpr int kRenders = 8;
constexpr int kSpp = 16;

// Renders cornell-glass at 48x36 with `ranks` MPI ranks (0: without mpirun) and reads the image.
std::vector<float> render(int ranks, const std::string& method, uint32_t seed, const std::string& tag) {
    const std::filesystem::path out = tempDir("mpi-" + method + "-" + tag) / "image.pfm";
    std::string command;
    if (ranks > 0)
        command = std::string(PMCR_MPIEXEC) + " --allow-run-as-root --oversubscribe -n " + std::to_string(ranks) + " ";
    command += std::string(PMCR_EXE) + " render " + sourcePath("scenes/cornell-glass.glb").string() +
               " --method " + method + " --spp " + std::to_string(kSpp) + " --seed " + std::to_string(seed) +
               " --width 48 --height 36 --validate -q --no-png -o " + out.string();
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    return readHdr(out).rgb;
}

void expectTwoRanksMatchOne(const std::string& method) {
    ImageMoments two, one;
    for (int i = 0; i < kRenders; ++i) {
        two.add(render(2, method, 100 + uint32_t(i), "two"));
        one.add(render(0, method, 500 + uint32_t(i), "one"));
    }
    const PixelTestResult r =
        pixelZTest(two.mean(), two.variance(), two.count(), one.mean(), one.variance(), one.count());
    EXPECT_GE(r.passFraction, 0.99) << method << ": " << r.describe();
}

TEST(MpiRender, TwoRanksMatchOneRankPt) { expectTwoRanksMatchOne("pt"); }
TEST(MpiRender, TwoRanksMatchOneRankPmcIp) { expectTwoRanksMatchOne("pmc-ip"); }
TEST(MpiRender, TwoRanksMatchOneRankErpt) { expectTwoRanksMatchOne("erpt"); }

// One rank renders exactly what a run without MPI renders, bit for bit (the same seed, the same
// streams, the same arithmetic: every collective is the identity).
TEST(MpiRender, OneRankEqualsRenderWithoutMpi) {
    for (const std::string method : {"pt", "pmc-ip-hi", "pmc-pt", "erpt", "pmc-er"}) {
        const std::vector<float> plain = render(0, method, 7, "plain");
        const std::vector<float> one = render(1, method, 7, "one-rank");
        ASSERT_EQ(plain.size(), one.size());
        size_t differ = 0;
        for (size_t i = 0; i < plain.size(); ++i) differ += plain[i] != one[i];
        EXPECT_EQ(differ, 0u) << method;
    }
}

}  // namespace
}  // namespace pmcr::test
