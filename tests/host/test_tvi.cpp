// tvi against values computed by hand from Ferwerda et al. 1996's formulas (see image/tvi.h).
#include <gtest/gtest.h>

#include <cmath>

#include "image/tvi.h"

namespace pmcr {
namespace {

double log10Of(double x) { return std::log10(x); }

TEST(Tvi, PhotopicBranchesAtKnownPoints) {
    EXPECT_NEAR(log10Of(tviPhotopic(1e-3)), -0.72, 1e-12);          // log La = -3: floor
    EXPECT_NEAR(log10Of(tviPhotopic(1.0)), std::pow(0.65, 2.7) - 0.72, 1e-12);  // -0.40749
    EXPECT_NEAR(log10Of(tviPhotopic(1.0)), -0.40749, 1e-4);
    EXPECT_NEAR(log10Of(tviPhotopic(100.0)), 2.0 - 1.255, 1e-12);  // log La = 2: Weber
    EXPECT_NEAR(tviPhotopic(100.0), 5.5590, 1e-3);
}

TEST(Tvi, ScotopicBranchesAtKnownPoints) {
    EXPECT_NEAR(log10Of(tviScotopic(1e-5)), -2.86, 1e-12);
    EXPECT_NEAR(log10Of(tviScotopic(1e-2)), std::pow(0.405 * -2.0 + 1.6, 2.18) - 2.86, 1e-12);
    EXPECT_NEAR(log10Of(tviScotopic(1e-2)), -2.2619, 1e-3);
    EXPECT_NEAR(log10Of(tviScotopic(1.0)), -0.395, 1e-12);
}

TEST(Tvi, TheMoreSensitiveSystemWins) {
    EXPECT_DOUBLE_EQ(tviCdM2(100.0), tviPhotopic(100.0));  // daylight: cones
    EXPECT_DOUBLE_EQ(tviCdM2(1e-2), tviScotopic(1e-2));    // dim: rods
}

// Ferwerda's fits are piecewise: the rod curve steps down by 0.012 in log10 (2.8%) where its
// middle branch meets the Weber branch (log La = -1.44). Elsewhere the threshold never decreases.
TEST(Tvi, BranchesAreNearlyContinuousAndIncreasing) {
    double previous = 0.0;
    for (double logLa = -6.0; logLa <= 5.0; logLa += 0.01) {
        const double t = tviCdM2(std::pow(10.0, logLa));
        EXPECT_GE(t, previous * (1.0 - 0.03)) << "log La = " << logLa;
        previous = t;
    }
}

TEST(Tvi, PixelUnitsScaleByTheDisplayWhite) {
    // Pixel luminance 1 = 100 cd/m^2 by default.
    EXPECT_NEAR(tvi(1.0), tviCdM2(100.0) / 100.0, 1e-15);
    EXPECT_NEAR(tvi(0.5, 200.0), tviCdM2(100.0) / 200.0, 1e-15);
    EXPECT_GT(tvi(0.0), 0.0);  // black pixels get the darkest threshold, not zero
}

}  // namespace
}  // namespace pmcr
