// Rendering under an environment light (--env) or punctual lights (KHR_lights_punctual) against
// analytic answers, for every method that takes them:
//  - a white Lambertian sphere under a constant environment L (a furnace): every pixel, sphere
//    or background, sees L, whatever the depth (a convex object's reflected rays escape);
//  - a large white Lambertian floor under a random environment image, seen from above: every
//    pixel sees (1 / pi) * the integral over the upper hemisphere of L cos(theta), a sum over
//    the image's upper rows in closed form (the image is constant over a pixel), and the same
//    whatever the rotation about +y. Light sampling (the pixel table), BSDF sampling and their
//    MIS weights must then add up to it exactly;
//  - the same floor under a point, a spot and a directional light: each pixel sees
//    (1 / pi) * sum of I cos(theta) / d^2 (the spot's times its falloff) and E cos(theta), which
//    the test integrates over each pixel's footprint on the host.
// pmc-hi and pmc-ip-hi take the environment as one more component of their mixture and the
// punctual lights by a next-event estimate beside it (docs/methods/pmc-hi.md), and must give the
// same answers.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "gpu_test.h"
#include "render_test.h"
#include "scene/environment.h"
#include "scene_builder.h"

namespace pmcr::test {
namespace {

gpu::Material whiteLambertian() {
    gpu::Material m = testMaterial(glm::vec3(0.0f));
    m.baseColor = glm::vec3(1.0f);
    return m;
}

// A UV sphere of radius 1 at the origin, seen from +z.
Scene sphereScene(Environment env) {
    Scene s;
    s.path = "environment-sphere.gltf";
    s.materials = {whiteLambertian()};
    addSphere(s, glm::vec3(0.0f), 1.0f, 16, 32, 0);
    Camera camera;
    camera.position = glm::vec3(0, 0, 4);
    s.cameras.push_back(camera);
    s.environment = std::move(env);
    finalizeScene(s);
    return s;
}

// A 200 x 200 white floor facing +y, seen straight down from `height` above it, lit by `env`
// and `punctualLights`.
Scene floorScene(Environment env, std::vector<gpu::PunctualLight> punctualLights = {},
                 float height = 1.0f, float yfov = 0.6f) {
    Scene s;
    s.path = "environment-floor.gltf";
    s.materials = {whiteLambertian()};
    addTriangle(s, {-100, 0, -100}, {-100, 0, 100}, {100, 0, 100}, 0);
    addTriangle(s, {-100, 0, -100}, {100, 0, 100}, {100, 0, -100}, 0);
    Camera camera;
    camera.position = glm::vec3(0, height, 0);
    camera.forward = glm::vec3(0, -1, 0);
    camera.up = glm::vec3(0, 0, -1);
    camera.right = glm::cross(camera.forward, camera.up);
    camera.yfov = yfov;
    s.cameras.push_back(camera);
    s.environment = std::move(env);
    s.punctualLights = std::move(punctualLights);
    finalizeScene(s);
    return s;
}

Environment randomSky(float rotationDegrees) {
    Environment env = randomSkyImage(17, 0.2f, glm::vec3(1.0f, 2.0f, 1.0f));
    env.image.set(5, 2, glm::vec3(30.0f, 60.0f, 20.0f));  // a sun
    env.scale = 0.8f;
    env.rotation = glm::radians(rotationDegrees);
    return env;
}

// (1 / pi) * integral over the upper hemisphere of L_green cos(theta): row y spans
// theta in [pi y / h, pi (y + 1) / h] and phi in 2 pi / w per pixel, and
// integral cos sin dtheta = (sin^2 theta1 - sin^2 theta0) / 2.
double floorAnswer(const Environment& env) {
    const int w = env.image.width, h = env.image.height;
    double sum = 0.0;
    for (int y = 0; y < h / 2; ++y) {
        const double s0 = std::sin(std::numbers::pi * y / h), s1 = std::sin(std::numbers::pi * (y + 1) / h);
        const double rowWeight = (2.0 * std::numbers::pi / w) * 0.5 * (s1 * s1 - s0 * s0);
        for (int x = 0; x < w; ++x) sum += double(env.image.at(x, y).y) * rowWeight;
    }
    return sum * env.scale / std::numbers::pi;
}

class EnvironmentRender : public GpuTest {
protected:
    // The image mean over 16 renders must match `expected` within 5 standard errors.
    void expectMean(const Scene& scene, RenderSettings s, double expected, const std::string& what) {
        s.width = 24;
        s.height = 24;
        const MeanEstimate m = meanOverRenders(scene, s, 16, 101);
        EXPECT_NEAR(m.mean, expected, 5.0 * m.standardError + 1e-4 * expected)
            << what << ": mean " << m.mean << ", expected " << expected << " (standard error "
            << m.standardError << ")";
    }
};

RenderSettings method(const std::string& name, uint32_t spp, uint32_t maxDepth = 16) {
    RenderSettings s;
    s.method = name;
    s.spp = spp;
    s.maxDepth = maxDepth;
    return s;
}

// pmc-ip-hi with a short image-plane schedule: 2 samples per pixel, then 1 per iteration.
RenderSettings pmcIpHi(uint32_t spp) {
    RenderSettings s = method("pmc-ip-hi", spp);
    s.options["initial-spp"] = "2";
    s.options["spp-per-iteration"] = "1";
    return s;
}

TEST_F(EnvironmentRender, WhiteSphereUnderConstantSky) {
    const Scene scene = sphereScene(loadEnvironment({"0.7,0.7,0.7"}));
    expectMean(scene, method("pt", 8, 1), 0.7, "pt depth 1");
    expectMean(scene, method("pt", 8, 5), 0.7, "pt depth 5");
    expectMean(scene, method("direct", 8), 0.7, "direct");
    RenderSettings ip = method("pmc-ip", 16, 4);
    expectMean(scene, ip, 0.7, "pmc-ip");
    expectMean(scene, method("pmc-ip-direct", 16), 0.7, "pmc-ip-direct");
    expectMean(scene, method("pmc-pt", 16, 4), 0.7, "pmc-pt");
    expectMean(scene, method("pmc-hi", 4), 0.7, "pmc-hi");
    expectMean(scene, pmcIpHi(4), 0.7, "pmc-ip-hi");
}

TEST_F(EnvironmentRender, WhiteFloorUnderImageSky) {
    for (const float rotation : {0.0f, 130.0f}) {
        SCOPED_TRACE(rotation);
        const Scene scene = floorScene(randomSky(rotation));
        const double expected = floorAnswer(scene.environment);
        expectMean(scene, method("pt", 8, 1), expected, "pt depth 1");
        expectMean(scene, method("pt", 8, 3), expected, "pt depth 3");
        RenderSettings direct = method("direct", 8);
        direct.options["light-samples"] = "2";
        expectMean(scene, direct, expected, "direct");
        expectMean(scene, method("pmc-ip", 16, 2), expected, "pmc-ip");
        expectMean(scene, method("pmc-hi", 4), expected, "pmc-hi");
        expectMean(scene, pmcIpHi(4), expected, "pmc-ip-hi");
    }
}


// Radiance of the white floor at x (green): (1 / pi) * irradiance from the lights.
double floorRadiance(const std::vector<gpu::PunctualLight>& lights, const glm::dvec3& x) {
    double E = 0.0;
    for (const gpu::PunctualLight& l : lights) {
        if (l.type == gpu::PUNCTUAL_DIRECTIONAL) {
            E += l.intensity.y * std::max(0.0, -double(l.direction.y));
            continue;
        }
        const glm::dvec3 toLight = glm::dvec3(l.position) - x;
        const double d2 = glm::dot(toLight, toLight);
        const glm::dvec3 wi = toLight / std::sqrt(d2);
        double falloff = 1.0;
        if (l.type == gpu::PUNCTUAL_SPOT) {
            const double t = std::clamp((glm::dot(-wi, glm::dvec3(l.direction)) - l.cosOuter) /
                                            std::max(1e-3, double(l.cosInner) - double(l.cosOuter)),
                                        0.0, 1.0);
            falloff = t * t;
        }
        E += l.intensity.y * falloff * std::max(0.0, wi.y) / d2;
    }
    return E / std::numbers::pi;
}

// The image mean of `scene` (a camera looking at the floor y = 0) as the average over every
// pixel of the floor radiance seen through it, n x n points per pixel.
double floorImageMean(const Scene& scene, int width, int height, int n) {
    const Camera& c = scene.cameras[0];
    const double t = std::tan(0.5 * c.yfov), aspect = double(width) / height;
    double sum = 0.0;
    for (int py = 0; py < height; ++py)
        for (int px = 0; px < width; ++px)
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    const double rx = px + (i + 0.5) / n, ry = py + (j + 0.5) / n;
                    const glm::dvec3 d = glm::dvec3(c.forward) +
                                         ((2.0 * rx / width - 1.0) * t * aspect) * glm::dvec3(c.right) +
                                         ((1.0 - 2.0 * ry / height) * t) * glm::dvec3(c.up);
                    const glm::dvec3 x = glm::dvec3(c.position) + d * (-double(c.position.y) / d.y);
                    sum += floorRadiance(scene.punctualLights, x);
                }
    return sum / (double(width) * height * n * n);
}

TEST_F(EnvironmentRender, WhiteFloorUnderPunctualLights) {
    const Scene scene = floorScene(
        Environment{},
        {punctualLight(gpu::PUNCTUAL_POINT, {0.5f, 1.0f, 0.3f}, {0, -1, 0}, {2.0f, 3.0f, 1.0f}),
         punctualLight(gpu::PUNCTUAL_SPOT, {-0.6f, 1.2f, 0.0f}, {0.2f, -1, 0}, {4.0f, 5.0f, 4.0f}, 0.2f, 0.5f),
         punctualLight(gpu::PUNCTUAL_DIRECTIONAL, {0, 0, 0}, {0.3f, -1, 0.2f}, {0.5f, 0.4f, 0.5f})},
        2.0f, 1.2f);
    const double expected = floorImageMean(scene, 24, 24, 16);
    expectMean(scene, method("pt", 8, 1), expected, "pt depth 1");
    expectMean(scene, method("pt", 8, 3), expected, "pt depth 3");
    expectMean(scene, method("direct", 8), expected, "direct");
    expectMean(scene, method("pmc-ip", 16, 2), expected, "pmc-ip");
    expectMean(scene, method("pmc-pt", 16, 2), expected, "pmc-pt");
    expectMean(scene, method("pmc-hi", 4), expected, "pmc-hi");
    expectMean(scene, pmcIpHi(4), expected, "pmc-ip-hi");
}

// A point light and an environment together, with an emitter: light selection across the
// three kinds must still add up (the floor's answer is the sum of each alone).
TEST_F(EnvironmentRender, AllLightKindsTogether) {
    const Scene scene = floorScene(loadEnvironment({"0.3,0.6,0.9"}),
                                   {punctualLight(gpu::PUNCTUAL_POINT, {0.2f, 1.5f, -0.1f}, {0, -1, 0}, {1, 2, 3})});
    // A constant sky of radiance L over a white floor gives L; the point light adds its part.
    const double expected = 0.6 + floorImageMean(scene, 24, 24, 16);
    expectMean(scene, method("pt", 8, 2), expected, "pt");
    expectMean(scene, method("direct", 8), expected, "direct");
    expectMean(scene, method("pmc-hi", 4), expected, "pmc-hi");
    expectMean(scene, pmcIpHi(4), expected, "pmc-ip-hi");
}

}  // namespace
}  // namespace pmcr::test
