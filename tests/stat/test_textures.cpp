// glTF's material textures (shaders/common/scene.glsl materialTextures). metallicRoughness: the
// factors times the texture's blue (metallic) and green (roughness) channels, read linearly; a
// texture of blue 0 and green 1 turns a rough metal into the Lambertian its factors then name,
// and renders bit for bit as that Lambertian does; a texture of blue 1 leaves the metal.
// baseColor: the factor times the texel decoded from sRGB renders as that colour untextured.
// normalTexture: a floor whose map tilts the normal renders as the floor whose vertex normals
// are that tilted normal. alphaMode MASK: a card whose alpha is 0 (everywhere, or where its
// uvs fall) is invisible to camera and shadow rays, one whose alpha is 1 is the opaque card.
// emissiveTexture: emitters textured black and white render as emitters of those emissions
// (light selection by the textured power included).
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
    textured.metallicRoughnessTexture = 1;  // texture 0

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

double relativeError(const Image& a, const Image& e) {
    double err = 0.0, norm = 0.0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        err += (a.rgb[i] - e.rgb[i]) * (a.rgb[i] - e.rgb[i]);
        norm += e.rgb[i] * e.rgb[i];
    }
    return norm > 0.0 ? std::sqrt(err / norm) : 1.0;
}

// The floor's tangent is +x with sign +1, its normal +y, so B = cross(N, T) = -z: a texel
// (x, y, z) in [-1, 1] maps to the world normal (x s, z, -y s) for normalScale s.
TEST_F(MaterialTextures, NormalMapTiltsTheShadingNormal) {
    const uint32_t r = 200, g = 90, b = 220;
    const uint32_t texel = 0xFF000000u | (b << 16) | (g << 8) | r;
    for (float scale : {1.0f, 0.5f}) {
        gpu::Material mapped = testMaterial(glm::vec3(0.0f));
        mapped.normalTexture = 1;  // texture 0
        mapped.normalScale = scale;
        Scene withMap = texturedFloor(mapped, texel);
        withMap.tangents.assign(withMap.vertices.size(), glm::vec4(1, 0, 0, 1));
        ASSERT_EQ(sceneFeatures(withMap) & gpu::SCENE_FEATURE_NORMAL_MAPS, gpu::SCENE_FEATURE_NORMAL_MAPS);
        const glm::vec3 t = glm::vec3(r, g, b) / 255.0f * 2.0f - 1.0f;
        const glm::vec3 n = glm::normalize(glm::vec3(t.x * scale, t.z, -t.y * scale));
        Scene tilted = texturedFloor(testMaterial(glm::vec3(0.0f)), texel);
        for (size_t i = 0; i < 6; ++i) tilted.vertices[i].normal = n;  // the floor's vertices
        const Image a = render(withMap), e = render(tilted);
        EXPECT_LT(relativeError(a, e), 1e-4) << "scale " << scale;
        EXPECT_GT(relativeError(e, render(texturedFloor(testMaterial(glm::vec3(0.0f)), texel))), 0.01)
            << "the tilt should show";
    }
}

// KHR_materials_clearcoat's clearcoatNormalTexture (read with its scale): a rough coat whose
// texture is the base's normalTexture renders as that coat over vertex normals tilted alike (the
// coat's own normal, shaders/common/bsdf.glsl clearcoatNormal, then is the shading normal); over
// a normal map without a texture of its own the coat keeps the interpolated normal (the
// extension's fallback) and renders otherwise; a coat texture alone tilts the coat alone.
TEST_F(MaterialTextures, ClearcoatNormalTextureTiltsTheCoat) {
    const uint32_t r = 200, g = 90, b = 220;
    const uint32_t texel = 0xFF000000u | (b << 16) | (g << 8) | r;
    const float scale = 0.5f;
    gpu::Material coated = testMaterial(glm::vec3(0.0f));
    coated.clearcoat = 1.0f;
    coated.clearcoatRoughness = 0.3f;
    gpu::Material both = coated;
    both.normalTexture = 1;  // texture 0
    both.normalScale = scale;
    both.clearcoatNormalTexture = 1;
    both.clearcoatNormalScale = scale;
    auto mapped = [&](const gpu::Material& m) {
        Scene s = texturedFloor(m, texel);
        s.tangents.assign(s.vertices.size(), glm::vec4(1, 0, 0, 1));
        return s;
    };
    const Scene withMaps = mapped(both);
    ASSERT_EQ(sceneFeatures(withMaps) & gpu::SCENE_FEATURE_NO_CLEARCOAT_NORMALS, 0u);
    // The floor's world normal for the texel (NormalMapTiltsTheShadingNormal).
    const glm::vec3 t = glm::vec3(r, g, b) / 255.0f * 2.0f - 1.0f;
    const glm::vec3 n = glm::normalize(glm::vec3(t.x * scale, t.z, -t.y * scale));
    Scene tilted = texturedFloor(coated, texel);
    for (size_t i = 0; i < 6; ++i) tilted.vertices[i].normal = n;  // the floor's vertices
    ASSERT_NE(sceneFeatures(tilted) & gpu::SCENE_FEATURE_NO_CLEARCOAT_NORMALS, 0u);
    const Image e = render(tilted);
    EXPECT_LT(relativeError(render(withMaps), e), 1e-4);

    gpu::Material baseOnly = both;
    baseOnly.clearcoatNormalTexture = 0;
    EXPECT_GT(relativeError(render(mapped(baseOnly)), e), 0.01)
        << "the coat should keep the interpolated normal under a normal map";
    gpu::Material coatOnly = both;
    coatOnly.normalTexture = 0;
    const Image c = render(mapped(coatOnly));
    EXPECT_GT(relativeError(c, render(texturedFloor(coated, texel))), 0.01) << "the coat's tilt should show";
    EXPECT_GT(relativeError(c, e), 0.01) << "the base should keep its normal";
}

// A unit card at height 0.5 between the floor and the light, textured by a two-texel row
// (alpha 0, alpha 255) read at u (CLAMP_TO_EDGE: u 0 is the first texel, 1 the second).
Scene cardOverFloor(bool masked, float u, bool withCard = true) {
    gpu::Material card = testMaterial(glm::vec3(0.0f));
    card.baseColor = glm::vec3(0.9f, 0.2f, 0.2f);
    card.baseColorTexture = 0;
    if (masked) card.alphaCutoff = 0.5f;
    Scene s = texturedFloor(testMaterial(glm::vec3(0.0f)), 0, {0x00FFFFFFu, 0xFFFFFFFFu}, gpu::WRAP_CLAMP);
    if (withCard) {
        s.materials.push_back(card);
        const uint32_t m = uint32_t(s.materials.size() - 1);
        addTriangle(s, {-0.5f, 0.5f, -0.5f}, {-0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, m);
        addTriangle(s, {-0.5f, 0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, -0.5f}, m);
        for (size_t i = s.vertices.size() - 6; i < s.vertices.size(); ++i) s.vertices[i].u = u;
    }
    finalizeScene(s);
    return s;
}

TEST_F(MaterialTextures, AlphaMaskCutsCameraAndShadowRays) {
    ASSERT_EQ(sceneFeatures(cardOverFloor(true, 0.0f)) & ~gpu::SCENE_FEATURES_LACKS,
              gpu::SCENE_FEATURE_ALPHA_MASKS);
    const Image noCard = render(cardOverFloor(false, 0.0f, false));
    const Image opaqueCard = render(cardOverFloor(false, 0.0f));
    ASSERT_GT(relativeError(opaqueCard, noCard), 0.05) << "the card should show";
    EXPECT_LT(relativeError(render(cardOverFloor(true, 0.0f)), noCard), 1e-4) << "alpha 0: cut";
    EXPECT_LT(relativeError(render(cardOverFloor(true, 1.0f)), opaqueCard), 1e-4) << "alpha 1: kept";
}

// KHR_materials_transmission's transmissionTexture: the factor times the texel's red channel.
TEST_F(MaterialTextures, TransmissionTextureScalesTheFactor) {
    gpu::Material glass = testMaterial(glm::vec3(0.0f));
    glass.baseColor = glm::vec3(0.9f);
    glass.roughness = 0.3f;
    glass.transmission = 1.0f;
    gpu::Material textured = glass;
    textured.transmissionTexture = 1;  // texture 0
    gpu::Material opaque = glass;
    opaque.transmission = 0.0f;
    const uint32_t red0 = 0xFFFFFF00u, red1 = 0xFF0000FFu;
    const Image plainGlass = render(texturedFloor(glass, red1));
    ASSERT_GT(relativeError(render(texturedFloor(opaque, red1)), plainGlass), 0.05);
    EXPECT_LT(relativeError(render(texturedFloor(textured, red1)), plainGlass), 1e-4) << "red 1";
    EXPECT_LT(relativeError(render(texturedFloor(textured, red0)), render(texturedFloor(opaque, red0))), 1e-4)
        << "red 0";
}

// Two emitter triangles side by side, each reading one texel of a black and white row
// (CLAMP_TO_EDGE, u = 0 and u = 1) times emission 6: as a black and a white emitter of 6.
TEST_F(MaterialTextures, EmissiveTextureScalesEmission) {
    auto scene = [](bool textured) {
        Scene s = texturedFloor(testMaterial(glm::vec3(0.0f)), 0, {0xFF000000u, 0xFFFFFFFFu}, gpu::WRAP_CLAMP);
        s.triangles.pop_back();  // the untextured emitter
        gpu::Material glow = testMaterial(glm::vec3(6.0f));
        if (textured) {
            glow.emissiveTexture = 1;
            s.materials.push_back(glow);
        } else {
            s.materials.push_back(testMaterial(glm::vec3(0.0f)));
            s.materials.push_back(glow);
        }
        const uint32_t dark = 2, bright = textured ? 2 : 3;
        addTriangle(s, {-0.6f, 1.5f, -0.3f}, {0.0f, 1.5f, 0.3f}, {-0.6f, 1.5f, 0.3f}, dark);
        addTriangle(s, {0.0f, 1.5f, -0.3f}, {0.6f, 1.5f, 0.3f}, {0.0f, 1.5f, 0.3f}, bright);
        for (size_t i = s.vertices.size() - 3; i < s.vertices.size(); ++i) s.vertices[i].u = 1.0f;
        finalizeScene(s);
        return s;
    };
    const Scene textured = scene(true);
    ASSERT_EQ(sceneFeatures(textured) & ~gpu::SCENE_FEATURES_LACKS, gpu::SCENE_FEATURE_EMISSIVE_TEXTURES);
    EXPECT_FLOAT_EQ(textured.triangleEmission[textured.triangles.size() - 2], 0.0f);
    EXPECT_NEAR(textured.triangleEmission.back(), 6.0f, 1e-5f);
    EXPECT_LT(relativeError(render(textured), render(scene(false))), 1e-4);
}

}  // namespace
}  // namespace pmcr::test
