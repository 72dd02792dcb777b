// Numbers on the command line are decimal only (core/decimal.h, issue 42): `--env 0x10,1,1` was
// read as 16 by strtod.
#include <gtest/gtest.h>

#include "core/decimal.h"
#include "core/error.h"
#include "metrics/metrics.h"
#include "render/settings.h"

namespace pmcr {
namespace {

TEST(Decimal, Integers) {
    for (const char* ok : {"0", "12", "-3", "+7", "0010"}) EXPECT_TRUE(isDecimalInteger(ok)) << ok;
    for (const char* bad : {"", "-", "+", "0x10", "1e3", "1.0", " 1", "1 ", "1,2", "inf", "٣"})
        EXPECT_FALSE(isDecimalInteger(bad)) << bad;
}

TEST(Decimal, Numbers) {
    for (const char* ok : {"0", "12", "-0.5", "+.5", ".5", "3.", "1e-3", "2.5E+4", "7e0"})
        EXPECT_TRUE(isDecimalNumber(ok)) << ok;
    for (const char* bad : {"", ".", "-", "e3", "1e", "1e+", "0x10", "0X1p3", "inf", "-Infinity",
                            "nan", " 1", "1 ", "1,5", "1..2", "1.2.3", "1e3.5", "--1"})
        EXPECT_FALSE(isDecimalNumber(bad)) << bad;
}

TEST(Decimal, MethodOptionsAndListsAreDecimal) {
    RenderSettings s;
    s.options["n"] = "0x10";
    EXPECT_THROW(s.optionInt("n", 0), Error);
    EXPECT_THROW(s.optionDouble("n", 0.0), Error);
    s.options["n"] = "1e2";
    EXPECT_EQ(s.optionDouble("n", 0.0), 100.0);
    EXPECT_THROW(s.optionInt("n", 0), Error);
    EXPECT_THROW(parseNumberList("x", "5,0x10"), Error);
    EXPECT_THROW(parseNumberList("x", "5, 6"), Error);
    EXPECT_EQ(parseNumberList("x", "5/1e1").at(1), 10.0);
    EXPECT_THROW(parsePixelRect("--crop", "0,0,0x10,4"), Error);
    EXPECT_THROW(parsePixelRect("--crop", " 1,0,4,4"), Error);
    EXPECT_THROW(parsePixelRect("--crop", "1,0,4,4,"), Error);
    EXPECT_EQ(parsePixelRect("--crop", "1,2,3,4").height, 4);
}

}  // namespace
}  // namespace pmcr
