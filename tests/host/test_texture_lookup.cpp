// Host texture lookups (host/scene/texture_lookup.h), which must agree with the kernels'
// (tests/stat/test_textures.cpp renders through those): texel centres, bilinear blending, wrap
// modes and sRGB decoding; and the mean over a triangle that emitter power uses.
#include <gtest/gtest.h>

#include "scene/texture_lookup.h"

namespace pmcr {
namespace {

uint32_t rgba(uint32_t r, uint32_t g, uint32_t b, uint32_t a) { return r | g << 8 | b << 16 | a << 24; }

// 2 x 1: black, white (alpha 0 and 1).
Texture blackWhite(uint32_t wrap) {
    Texture t;
    t.width = 2;
    t.height = 1;
    t.rgba8 = {rgba(0, 0, 0, 0), rgba(255, 255, 255, 255)};
    t.wrap = wrap;
    return t;
}

TEST(TextureLookup, TexelCentresBlendsAndWraps) {
    const Texture repeat = blackWhite(gpu::WRAP_REPEAT);
    EXPECT_FLOAT_EQ(sampleTexture(repeat, {0.25f, 0.5f}, false).r, 0.0f);   // texel 0's centre
    EXPECT_FLOAT_EQ(sampleTexture(repeat, {0.75f, 0.5f}, false).r, 1.0f);   // texel 1's centre
    EXPECT_FLOAT_EQ(sampleTexture(repeat, {0.5f, 0.5f}, false).r, 0.5f);    // halfway
    EXPECT_FLOAT_EQ(sampleTexture(repeat, {0.5f, 0.5f}, false).a, 0.5f);    // alpha blends too
    EXPECT_FLOAT_EQ(sampleTexture(repeat, {1.0f, 0.5f}, false).r, 0.5f);    // wraps to texel 0
    EXPECT_FLOAT_EQ(sampleTexture(repeat, {1.25f, 0.5f}, false).r, 0.0f);
    const Texture clamp = blackWhite(gpu::WRAP_CLAMP);
    EXPECT_FLOAT_EQ(sampleTexture(clamp, {1.0f, 0.5f}, false).r, 1.0f);
    EXPECT_FLOAT_EQ(sampleTexture(clamp, {-3.0f, 0.5f}, false).r, 0.0f);
    const Texture mirror = blackWhite(gpu::WRAP_MIRROR);
    EXPECT_FLOAT_EQ(sampleTexture(mirror, {1.25f, 0.5f}, false).r, 1.0f);  // 1, 1, 0, 0, 1, ...
    // sRGB: decoded per texel, before blending; alpha stays linear.
    Texture grey;
    grey.width = grey.height = 1;
    grey.rgba8 = {rgba(128, 128, 128, 128)};
    EXPECT_NEAR(sampleTexture(grey, {0.3f, 0.7f}, true).r, 0.21586f, 1e-4f);
    EXPECT_NEAR(sampleTexture(grey, {0.3f, 0.7f}, true).a, 128.0f / 255.0f, 1e-6f);
}

TEST(TextureLookup, MeanOverTriangle) {
    Texture grey;
    grey.width = grey.height = 1;
    grey.rgba8 = {rgba(255, 64, 0, 255)};
    const glm::vec3 constant = meanOverTriangle(grey, {0, 0}, {3, 0}, {0, 5}, false);
    EXPECT_NEAR(constant.r, 1.0f, 1e-6f);
    EXPECT_NEAR(constant.g, 64.0f / 255.0f, 1e-6f);
    // A 2 x 1 black and white texture repeated many times over a large triangle: the mean tends
    // to the texture's, 1/2.
    const glm::vec3 tiled = meanOverTriangle(blackWhite(gpu::WRAP_REPEAT), {0, 0}, {37, 0}, {0, 41}, false);
    EXPECT_NEAR(tiled.r, 0.5f, 0.02f);
    // A triangle inside the white texel's half: white.
    const glm::vec3 inside = meanOverTriangle(blackWhite(gpu::WRAP_CLAMP), {0.8f, 0.1f}, {1.0f, 0.1f}, {0.8f, 0.9f}, false);
    EXPECT_NEAR(inside.r, 1.0f, 1e-6f);
}

}  // namespace
}  // namespace pmcr
