// Error and efficiency metrics (metrics/metrics.h) against values computed by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "metrics/metrics.h"

namespace pmcr {
namespace {

Image greyImage(const std::vector<float>& values, int width) {
    Image image(width, int(values.size()) / width);
    for (size_t i = 0; i < values.size(); ++i)
        image.rgb[3 * i] = image.rgb[3 * i + 1] = image.rgb[3 * i + 2] = values[i];
    return image;
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

// Grey pixels: luminance = value (the Rec. 709 weights sum to 1). Reference luminances 1 and
// 0.01 at the default display white (100 cd/m^2) adapt to 100 and 1 cd/m^2, where Ferwerda's
// thresholds are closed forms: 10^(2 - 1.255) (cones, Weber branch) and 10^(0.65^2.7 - 0.72)
// (cones, middle branch; below the rods' 10^-0.395).
TEST(Metrics, ErrRelMseAndPerceptualErrByHand) {
    const Image reference = greyImage({1.0f, 0.01f}, 2);
    const Image image = greyImage({1.1f, 0.02f}, 2);
    const ErrorMetrics m = measureError(image, reference);
    const double e0 = double(1.1f) - 1.0, e1 = double(0.02f) - double(0.01f);
    EXPECT_NEAR(m.mse, (0.01 + 1e-4) / 2.0, 1e-8);
    EXPECT_NEAR(m.mse, (e0 * e0 + e1 * e1) / 2.0, 1e-12);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(m.mseRgb[c], m.mse, 1e-12);
    EXPECT_NEAR(m.rmse, std::sqrt(0.00505), 1e-7);
    // relMSE: (v - r)^2 / (r + 0.01)^2, the same in each channel.
    EXPECT_NEAR(m.relmse, (0.01 / (1.01 * 1.01) + 1e-4 / (0.02 * 0.02)) / 2.0, 1e-6);
    const double tvi1 = std::pow(10.0, 2.0 - 1.255) / 100.0;                   // 0.0555904
    const double tvi001 = std::pow(10.0, std::pow(0.65, 2.7) - 0.72) / 100.0;  // 0.0039130
    EXPECT_NEAR(tvi1, 0.0555904, 1e-6);
    EXPECT_NEAR(tvi001, 0.0039130, 1e-6);
    EXPECT_NEAR(m.pmse, (0.01 / tvi1 + 1e-4 / tvi001) / 2.0, 1e-5);
    EXPECT_EQ(m.region, (PixelRect{0, 0, 2, 1}));
}

TEST(Metrics, PerceptualErrFollowsTheDisplayWhite) {
    const Image reference = greyImage({1.0f}, 1);
    const Image image = greyImage({1.5f}, 1);
    MetricOptions options;
    options.displayWhite = 1000.0;  // 1000 cd/m^2: Weber branch, threshold 10^(3 - 1.255) / 1000
    const double expected = 0.25 / (std::pow(10.0, 3.0 - 1.255) / 1000.0);
    EXPECT_NEAR(measureError(image, reference, options).pmse, expected, 1e-9 * expected);
    // Same error on a darker reference is more visible: a larger P-Err.
    EXPECT_GT(measureError(greyImage({0.6f}, 1), greyImage({0.1f}, 1)).pmse,
              measureError(image, reference).pmse);
}

TEST(Metrics, ErrIsLuminanceAndChannelsAreSeparate) {
    Image reference(1, 1), image(1, 1);
    image.set(0, 0, {1.0f, 0.0f, 0.0f});
    const ErrorMetrics m = measureError(image, reference);
    EXPECT_NEAR(m.mse, 0.2126 * 0.2126, 1e-12);
    EXPECT_DOUBLE_EQ(m.mseRgb.r, 1.0);
    EXPECT_DOUBLE_EQ(m.mseRgb.g, 0.0);
    EXPECT_DOUBLE_EQ(m.mseRgb.b, 0.0);
    EXPECT_NEAR(m.relmse, (1.0 / (0.01 * 0.01)) / 3.0, 1e-6);
}

TEST(Metrics, CropMeasuresOnlyTheRectangle) {
    const Image reference = greyImage({0, 0, 0, 0, 0, 0}, 3);
    const Image image = greyImage({5, 1, 7, 9, 2, 9}, 3);
    MetricOptions options;
    options.cropped = true;
    options.crop = {1, 0, 1, 2};  // the middle column: errors 1 and 2
    const ErrorMetrics m = measureError(image, reference, options);
    EXPECT_NEAR(m.mse, (1.0 + 4.0) / 2.0, 1e-12);
    EXPECT_EQ(m.region, (PixelRect{1, 0, 1, 2}));
}

TEST(Metrics, BadInputIsOneLineNamingTheFiles) {
    MetricOptions names;
    names.imageName = "a.exr";
    names.referenceName = "ref.exr";
    const std::string size = errorOf([&] { measureError(Image(4, 4), Image(2, 2), names); });
    EXPECT_NE(size.find("a.exr"), std::string::npos) << size;
    EXPECT_NE(size.find("ref.exr"), std::string::npos) << size;
    EXPECT_NE(size.find("4x4"), std::string::npos) << size;
    EXPECT_EQ(size.find('\n'), std::string::npos);

    Image nan(2, 2);
    nan.rgb[4] = std::numeric_limits<float>::quiet_NaN();
    const std::string notFinite = errorOf([&] { measureError(nan, Image(2, 2), names); });
    EXPECT_NE(notFinite.find("a.exr: pixel (1, 0)"), std::string::npos) << notFinite;

    Image negative(2, 2);
    negative.rgb[0] = -1.0f;
    const std::string badReference = errorOf([&] { measureError(Image(2, 2), negative, names); });
    EXPECT_NE(badReference.find("ref.exr: pixel (0, 0) is negative"), std::string::npos)
        << badReference;

    names.cropped = true;
    names.crop = {1, 1, 4, 1};
    EXPECT_NE(errorOf([&] { measureError(Image(2, 2), Image(2, 2), names); }).find("outside"),
              std::string::npos);
}

TEST(Metrics, EfficiencyAndRatios) {
    EXPECT_DOUBLE_EQ(efficiency(2.0, 0.25), 2.0);  // 1 / (2 * 0.25)
    EXPECT_DOUBLE_EQ(efficiency(4.0, 0.05), 5.0);
    // Eff ratio of the second method to the first: half the error in twice the time is no gain,
    // a fifth of the error in twice the time is 2.5 times as efficient.
    EXPECT_DOUBLE_EQ(efficiency(4.0, 0.125) / efficiency(2.0, 0.25), 1.0);
    EXPECT_DOUBLE_EQ(efficiency(4.0, 0.05) / efficiency(2.0, 0.25), 2.5);
    EXPECT_EQ(efficiency(0.0, 0.1), 0.0);
    EXPECT_TRUE(std::isinf(efficiency(1.0, 0.0)));
}

TEST(Metrics, PixelRectParsing) {
    EXPECT_EQ(parsePixelRect("--crop", "1,2,3,4"), (PixelRect{1, 2, 3, 4}));
    EXPECT_EQ(toString(PixelRect{1, 2, 3, 4}), "1,2,3,4");
    for (const char* bad :
         {"1,2,3", "1,2,3,4,5", "a,b,c,d", "1,2,0,4", "-1,2,3,4", "", "1,2,3,4x"}) {
        const std::string message = errorOf([&] { parsePixelRect("--crop", bad); });
        EXPECT_EQ(message.rfind("--crop: ", 0), 0u) << bad << " -> " << message;
    }
}

TEST(Metrics, QuantileIsTheNearestRank) {
    std::vector<float> values;
    for (int i = 100; i >= 1; --i)
        values.push_back(float(i));
    EXPECT_EQ(quantile(values, 0.99), 99.0f);
    EXPECT_EQ(quantile(values, 1.0), 100.0f);
    EXPECT_EQ(quantile(values, 0.0), 1.0f);
    EXPECT_EQ(quantile({}, 0.5), 0.0f);
}

TEST(Metrics, LuminanceErrorMap) {
    const auto map = luminanceErrorMap(greyImage({1, 2}, 2), greyImage({2, 2}, 2));
    ASSERT_EQ(map.size(), 2u);
    EXPECT_FLOAT_EQ(map[0], 1.0f);
    EXPECT_FLOAT_EQ(map[1], 0.0f);
}

}  // namespace
}  // namespace pmcr
