// KHR_materials_volume absorption (Beer-Lambert inside dielectrics; shaders/common/shading.glsl
// segmentTransmittance) against its analytic answer: an emitter of radiance 1 seen through a
// slab of index-matched glass (ior 1: no refraction, no reflection) of thickness 1 and
// absorption sigma. A camera ray crossing the slab at angle theta to its normal travels
// 1 / cos(theta) inside, so the pixel is exp(-sigma / cos(theta)), channel by channel, with no
// noise. pt must match per pixel; erpt and pmc-er, which re-evaluate the paths they perturb,
// must keep the image's mean.
#include <gtest/gtest.h>

#include <cmath>

#include "gpu_test.h"
#include "render_test.h"
#include "scene_builder.h"

namespace pmcr::test {
namespace {

const glm::vec3 kSigma(0.1f, 0.4f, 0.8f);

// Axis-aligned box [lo, hi] with outward-facing triangles.
void addBox(Scene& s, glm::vec3 lo, glm::vec3 hi, uint32_t material) {
    const glm::vec3 c = 0.5f * (lo + hi);
    auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 d, glm::vec3 e) {
        auto outward = [&](glm::vec3 p, glm::vec3 q, glm::vec3 r) {
            if (glm::dot(glm::cross(q - p, r - p), (p + q + r) / 3.0f - c) < 0.0f) std::swap(q, r);
            addTriangle(s, p, q, r, material);
        };
        outward(a, b, d);
        outward(a, d, e);
    };
    const glm::vec3 p[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                            {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
    quad(p[0], p[1], p[2], p[3]);
    quad(p[4], p[5], p[6], p[7]);
    quad(p[0], p[1], p[5], p[4]);
    quad(p[3], p[2], p[6], p[7]);
    quad(p[0], p[3], p[7], p[4]);
    quad(p[1], p[2], p[6], p[5]);
}

Scene slabScene() {
    Scene s;
    s.path = "absorbing-slab.gltf";
    gpu::Material glass = testMaterial(glm::vec3(0.0f));
    glass.baseColor = glm::vec3(1.0f);
    glass.roughness = 0.0f;
    glass.transmission = 1.0f;
    glass.ior = 1.0f;
    glass.absorption = kSigma;
    s.materials = {glass, testMaterial(glm::vec3(1.0f))};
    addBox(s, {-10, -10, -1}, {10, 10, 0}, 0);
    addTriangle(s, {-20, -20, -3}, {20, -20, -3}, {20, 20, -3}, 1);  // facing +z
    addTriangle(s, {-20, -20, -3}, {20, 20, -3}, {-20, 20, -3}, 1);
    Camera camera;
    camera.position = glm::vec3(0, 0, 5);
    camera.yfov = 0.6f;
    s.cameras.push_back(camera);
    finalizeScene(s);
    return s;
}

// exp(-sigma / cos(theta)) for the camera ray through the centre of pixel (x, y).
glm::vec3 expected(int x, int y, int width, int height, float yfov) {
    const float t = std::tan(0.5f * yfov), aspect = float(width) / float(height);
    const glm::vec3 d = glm::normalize(glm::vec3((2.0f * (x + 0.5f) / width - 1.0f) * t * aspect,
                                                 (1.0f - 2.0f * (y + 0.5f) / height) * t, -1.0f));
    return glm::exp(-kSigma / std::abs(d.z));
}

class Absorption : public GpuTest {};

TEST_F(Absorption, SlabMatchesBeerLambert) {
    const Scene scene = slabScene();
    ASSERT_EQ(sceneFeatures(scene) & ~gpu::SCENE_FEATURES_LACKS, gpu::SCENE_FEATURE_ABSORPTION);
    RenderSettings s;
    s.width = 24;
    s.height = 16;
    s.spp = 4;
    s.method = "pt";
    const Image pt = renderForTest(scene, s).output.image;
    glm::dvec3 meanExpected(0.0);
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            const glm::vec3 e = expected(x, y, s.width, s.height, 0.6f);
            meanExpected += glm::dvec3(e) / double(s.width * s.height);
            for (int c = 0; c < 3; ++c) {
                // Within a pixel 1 / cos(theta) varies by less than 0.3%.
                ASSERT_NEAR(pt.rgb[3 * (size_t(y) * s.width + x) + c], e[c], 3e-3 * e[c])
                    << "pixel " << x << ", " << y << " channel " << c;
            }
        }
    // Energy redistribution deposits the seed paths' luminance in the colour of the path it
    // holds, P / lum(P): the image's colour (its channels over its luminance) tests P's
    // absorption closely, while its level carries the noise of the chain counts (about 6% here).
    for (const char* method : {"erpt", "pmc-er"}) {
        s.method = method;
        s.spp = 16;
        const glm::dvec3 mean = imageMean(renderForTest(scene, s).output.image);
        const double lum = luminance(glm::vec3(mean)), lumExpected = luminance(glm::vec3(meanExpected));
        EXPECT_NEAR(lum, lumExpected, 0.3 * lumExpected) << method;
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(mean[c] / lum, meanExpected[c] / lumExpected, 0.01 * meanExpected[c] / lumExpected)
                << method << " channel " << c;
        }
    }
}

}  // namespace
}  // namespace pmcr::test
