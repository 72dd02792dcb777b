// glTF's material textures (shaders/common/scene.glsl materialTextures). metallicRoughness: the
// factors times the texture's blue (metallic) and green (roughness) channels, read linearly; a
// texture of blue 0 and green 1 turns a rough metal into the Lambertian its factors then name,
// and renders bit for bit as that Lambertian does; a texture of blue 1 leaves the metal.
// baseColor: the factor times the texel decoded from sRGB renders as that colour untextured.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "gpu_test.h"
#include "render_test.h"
#include "scene_builder.h"

namespace pmcr::test {
namespace {

// A floor of `floor` under a small emitter, seen from above; textures[0] is one texel `rgba`
// (or the row `texels`, wrapped by `wrap`), read at `uv` everywhere.
Scene texturedFloor(gpu::Material floor, uint32_t rgba, std::vector<uint32_t> texels = {},
                    uint32_t wrap = 0, glm::vec2 uv = glm::vec2(0.0f)) {
    Scene s;
    s.path = "textured-floor.gltf";
    s.materials = {floor, testMaterial(glm::vec3(4.0f))};
    addTriangle(s, {-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, 0);
    addTriangle(s, {-2, 0, -2}, {2, 0, 2}, {2, 0, -2}, 0);
    addTriangle(s, {-0.3f, 1.5f, -0.3f}, {0.3f, 1.5f, 0.3f}, {-0.3f, 1.5f, 0.3f}, 1);  // facing down
    for (gpu::Vertex& v : s.vertices) {
        v.u = uv.x;
        v.v = uv.y;
    }
    Texture t;
    t.name = "test-texture";
    t.rgba8 = texels.empty() ? std::vector<uint32_t>{rgba} : texels;
    t.width = uint32_t(t.rgba8.size());
    t.height = 1;
    t.wrap = wrap;
    s.textures.push_back(t);
    Camera camera;
    camera.position = glm::vec3(0, 3, 3);
    camera.forward = glm::normalize(glm::vec3(0, -1, -1));
    camera.up = glm::normalize(glm::vec3(0, 1, -1));
    camera.right = glm::cross(camera.forward, camera.up);
    s.cameras.push_back(camera);
    finalizeScene(s);
    return s;
}

class MaterialTextures : public GpuTest {
protected:
    Image render(const Scene& scene) {
        RenderSettings s;
        s.method = "pt";
        s.spp = 8;
        s.width = 32;
        s.height = 24;
        return renderForTest(scene, s).output.image;
    }
};

TEST_F(MaterialTextures, MetallicRoughnessScalesTheFactorsByBlueAndGreen) {
    gpu::Material lambertian = testMaterial(glm::vec3(0.0f));  // metallic 0, roughness 1
    gpu::Material metal = lambertian;
    metal.metallic = 1.0f;
    metal.roughness = 1.0f;
    gpu::Material textured = metal;
    textured.flags |= 1u << gpu::MATERIAL_MR_TEXTURE_SHIFT;  // texture 0

    const uint32_t blue0green1 = 0xFF00FF00u;  // RGBA little-endian: R 0, G 255, B 0, A 255
    const uint32_t blue1green1 = 0xFFFFFF00u;  // B 255
    const Image plain = render(texturedFloor(lambertian, blue0green1));
    const Image unmetalled = render(texturedFloor(textured, blue0green1));
    EXPECT_EQ(plain.rgb, unmetalled.rgb) << "metallic 1 x blue 0 should be the Lambertian";
    const Image stillMetal = render(texturedFloor(textured, blue1green1));
    const Image metalImage = render(texturedFloor(metal, blue1green1));
    EXPECT_EQ(stillMetal.rgb, metalImage.rgb) << "metallic 1 x blue 1 should stay the metal";
    EXPECT_NE(metalImage.rgb, plain.rgb) << "the metal and the Lambertian should differ";
}

TEST_F(MaterialTextures, BaseColorTextureIsDecodedFromSrgb) {
    gpu::Material textured = testMaterial(glm::vec3(0.0f));
    textured.baseColor = glm::vec3(1.0f, 0.5f, 1.0f);
    textured.baseColorTexture = 0;
    const uint32_t r = 200, g = 128, b = 30;
    const uint32_t rgba = 0xFF000000u | (b << 16) | (g << 8) | r;
    auto decode = [](uint32_t c) {
        const double v = c / 255.0;
        return float(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
    };
    gpu::Material plain = testMaterial(glm::vec3(0.0f));
    plain.baseColor = glm::vec3(decode(r), 0.5f * decode(g), decode(b));
    const Image a = render(texturedFloor(textured, rgba));
    const Image e = render(texturedFloor(plain, rgba));
    double err = 0.0, norm = 0.0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        err += (a.rgb[i] - e.rgb[i]) * (a.rgb[i] - e.rgb[i]);
        norm += e.rgb[i] * e.rgb[i];
    }
    EXPECT_GT(norm, 0.0);
    EXPECT_LT(err, 1e-10 * norm) << "the same samples should differ by float rounding at most";
}

// A texture two texels wide (red, blue) read outside [0, 1]: at u = 5.25 REPEAT lands on red,
// at u = 5 CLAMP_TO_EDGE on blue, at u = 1.25 MIRRORED_REPEAT on blue (each exactly on a texel).
TEST_F(MaterialTextures, WrapModes) {
    const std::vector<uint32_t> redBlue = {0xFF0000FFu, 0xFFFF0000u};
    gpu::Material textured = testMaterial(glm::vec3(0.0f));
    textured.baseColor = glm::vec3(1.0f);
    textured.baseColorTexture = 0;
    gpu::Material red = testMaterial(glm::vec3(0.0f));
    red.baseColor = glm::vec3(1.0f, 0.0f, 0.0f);
    gpu::Material blue = red;
    blue.baseColor = glm::vec3(0.0f, 0.0f, 1.0f);
    auto close = [](const Image& a, const Image& e) {
        double err = 0.0, norm = 0.0;
        for (size_t i = 0; i < a.rgb.size(); ++i) {
            err += (a.rgb[i] - e.rgb[i]) * (a.rgb[i] - e.rgb[i]);
            norm += e.rgb[i] * e.rgb[i];
        }
        return norm > 0.0 && err < 1e-10 * norm;
    };
    EXPECT_TRUE(close(render(texturedFloor(textured, 0, redBlue, gpu::WRAP_REPEAT, {5.25f, 0.5f})),
                      render(texturedFloor(red, 0))))
        << "REPEAT";
    EXPECT_TRUE(close(render(texturedFloor(textured, 0, redBlue, gpu::WRAP_CLAMP, {5.0f, 0.5f})),
                      render(texturedFloor(blue, 0))))
        << "CLAMP_TO_EDGE";
    EXPECT_TRUE(close(render(texturedFloor(textured, 0, redBlue, gpu::WRAP_MIRROR, {1.25f, 0.5f})),
                      render(texturedFloor(blue, 0))))
        << "MIRRORED_REPEAT";
}

}  // namespace
}  // namespace pmcr::test
