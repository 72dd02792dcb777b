// Film deposition: finite samples are summed, NaN/Inf samples are dropped before the atomic
// add and counted (a dropped sample still counts as a sample of value zero).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "gpu_test.h"
#include "shared/host_device.h"

namespace pmcr::test {
namespace {

class FilmTest : public GpuTest {};

TEST_F(FilmTest, NanAndInfSamplesAreDroppedAndCounted) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    // Pixel 0 gets 1, 2, NaN; pixel 1 gets 3, Inf(in one channel), 4.
    std::vector<glm::vec3> values = {{1, 1, 1}, {3, 3, 3}, {2, 2, 2},
                                     {0, inf, 0}, {nan, 0, 0}, {4, 4, 4}};
    auto valueBuffer = storage(values, "values");
    auto film = zeros(2 * sizeof(gpu::FilmPixel), "film");
    auto counters = zeros(gpu::COUNTER_COUNT * sizeof(uint32_t), "counters");
    struct Push {
        uint32_t count;
        uint32_t pixelCount;
    };
    run("tests/film_nan_test", Push{6, 2}, 6, {&film, &counters, &valueBuffer});
    auto pixels = film.download<gpu::FilmPixel>(2);
    auto count = counters.download<uint32_t>(gpu::COUNTER_COUNT);
    EXPECT_EQ(count[gpu::COUNTER_NAN_DROPPED], 2u);
    EXPECT_EQ(pixels[0].sampleCount, 3u);
    EXPECT_EQ(pixels[1].sampleCount, 3u);
    EXPECT_FLOAT_EQ(pixels[0].sum.x, 1.0f + 2.0f);
    EXPECT_FLOAT_EQ(pixels[1].sum.y, 3.0f + 4.0f);
    EXPECT_TRUE(std::isfinite(pixels[0].lumSum) && std::isfinite(pixels[1].lumSqSum));
}

}  // namespace
}  // namespace pmcr::test
