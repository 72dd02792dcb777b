// The white furnace of every BSDF (issue 22's "every BSDF energy-conserving"): a convex sphere
// under a constant environment L, seen by pt with Russian roulette and a deep path limit. A BSDF
// that conserves energy returns L along every camera ray, sphere or background: the Lambertian
// of albedo 1 (also tests/stat/test_environment_render.cpp), the perfect mirror (Schlick F0 = 1)
// and smooth glass (Fresnel reflection and refraction, the eta^2 of radiance in and out of the
// sphere cancelling). Single-scattering microfacet models lose the energy of their masked
// paths, so rough conductors, rough glass and the coated plastic may only stay at or below L.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "gpu_test.h"
#include "render_test.h"
#include "scene/environment.h"
#include "scene_builder.h"

namespace pmcr::test {
namespace {

constexpr double kSky = 0.7;

Scene furnaceSphere(const gpu::Material& material) {
    Scene s;
    s.path = "furnace-sphere-under-sky.gltf";
    s.materials = {material};
    addSphere(s, glm::vec3(0.0f), 1.0f, 24, 48, 0);
    Camera camera;
    camera.position = glm::vec3(0, 0, 3);
    camera.yfov = 0.8f;
    s.cameras.push_back(camera);
    s.environment = loadEnvironment({std::to_string(kSky) + "," + std::to_string(kSky) + "," +
                                     std::to_string(kSky)});
    finalizeScene(s);
    return s;
}

gpu::Material material(float metallic, float roughness, float transmission) {
    gpu::Material m = testMaterial(glm::vec3(0.0f));
    m.baseColor = glm::vec3(1.0f);
    m.metallic = metallic;
    m.roughness = roughness;
    m.transmission = transmission;
    m.ior = 1.5f;
    return m;
}

class EnvironmentFurnace : public GpuTest {
protected:
    MeanEstimate furnace(const gpu::Material& m) {
        RenderSettings s;
        s.method = "pt";
        s.spp = 8;
        // Deep: the flat facets tilt the surface enough for total internal reflection to trap
        // some rays in the glass for tens of bounces (at 64 the glass loses 0.4%, 10 sigma).
        s.maxDepth = 1000;
        s.rrDepth = 8;
        s.width = 24;
        s.height = 24;
        return meanOverRenders(furnaceSphere(m), s, 8, 301);
    }
};

TEST_F(EnvironmentFurnace, EnergyConservingBsdfsReturnTheSky) {
    const std::pair<const char*, gpu::Material> cases[] = {
        {"mirror", material(1.0f, 0.0f, 0.0f)},
        {"smooth glass", material(0.0f, 0.0f, 1.0f)},
        {"half mirror, half glass", material(0.5f, 0.0f, 1.0f)},
    };
    for (const auto& [name, m] : cases) {
        const MeanEstimate e = furnace(m);
        EXPECT_NEAR(e.mean, kSky, 5.0 * e.standardError + 1e-4) << name << " (standard error " << e.standardError << ")";
    }
}

TEST_F(EnvironmentFurnace, MicrofacetBsdfsStayAtOrBelowTheSky) {
    const std::pair<const char*, gpu::Material> cases[] = {
        {"rough conductor", material(1.0f, 0.5f, 0.0f)},
        {"rough glass", material(0.0f, 0.4f, 1.0f)},
        {"plastic", material(0.0f, 0.3f, 0.0f)},
    };
    for (const auto& [name, m] : cases) {
        const MeanEstimate e = furnace(m);
        EXPECT_LE(e.mean, kSky + 5.0 * e.standardError + 1e-4) << name;
        EXPECT_GT(e.mean, 0.5 * kSky) << name << ": loses more than a single-scattering model does";
    }
}

}  // namespace
}  // namespace pmcr::test
