// chooseLights (host/scene/light_choice.h): each choice half by power, half uniform; without
// emitters the environment and punctual lights take all of u.
#include <gtest/gtest.h>

#include <cmath>

#include "scene/environment.h"
#include "scene/light_choice.h"

namespace pmcr::test {
namespace {

gpu::PunctualLight light(uint32_t type, float intensity) {
    gpu::PunctualLight l{};
    l.type = type;
    l.direction = glm::vec3(0, -1, 0);
    l.intensity = glm::vec3(intensity);
    l.cosInner = 1.0f;
    l.cosOuter = 1.0f;
    return l;
}

TEST(LightChoice, NoOtherLightsLeaveEverythingToTheEmitters) {
    const LightChoice c = chooseLights(Scene{}, 5.0, 1.0f);
    EXPECT_EQ(c.envPmf, 0.0f);
    EXPECT_EQ(c.punctualPmf, 0.0f);
    EXPECT_TRUE(c.punctualTable.empty());
}

TEST(LightChoice, HalfByPowerHalfUniform) {
    Scene s;
    s.environment = loadEnvironment({"1,1,1"});
    const float radius = 2.0f;
    const double envPower = environmentPower(s.environment, radius);
    const double emitterPower = 3.0 * envPower;
    const LightChoice c = chooseLights(s, emitterPower, radius);
    EXPECT_NEAR(c.envPmf, 0.5 * 0.25 + 0.5 / 2.0, 1e-6);
    EXPECT_EQ(c.punctualPmf, 0.0f);
}

// A directional light's power grows with the scene (pi R^2 E): a lamp beside it still gets at
// least half its uniform share, and the table's pmfs are the half-and-half mix.
TEST(LightChoice, ADirectionalLightDoesNotStarveALamp) {
    Scene s;
    s.punctualLights = {light(gpu::PUNCTUAL_DIRECTIONAL, 1.0f), light(gpu::PUNCTUAL_POINT, 1.0f)};
    const float radius = 1000.0f;
    const LightChoice c = chooseLights(s, 1.0, radius);
    ASSERT_EQ(c.punctualTable.size(), 2u);
    const double sun = punctualLightPower(s.punctualLights[0], radius);
    const double lamp = punctualLightPower(s.punctualLights[1], radius);
    EXPECT_NEAR(c.punctualTable[1].pmf, 0.5 * lamp / (sun + lamp) + 0.25, 1e-6);
    EXPECT_GE(c.punctualTable[1].pmf, 0.25f);
    EXPECT_GE(c.punctualPmf, 0.25f);  // against the emitters' 1 W
    EXPECT_EQ(c.punctualTable[0].triangle, 0u);
    EXPECT_EQ(c.punctualTable[1].triangle, 1u);
}

TEST(LightChoice, WithoutEmittersTheOtherLightsTakeAllOfU) {
    Scene s;
    s.environment = loadEnvironment({"0.3,0.2,0.1"});
    s.punctualLights = {light(gpu::PUNCTUAL_SPOT, 7.0f)};
    const LightChoice c = chooseLights(s, 0.0, 3.0f);
    EXPECT_EQ(c.envPmf + c.punctualPmf, 1.0f);
    s.punctualLights.clear();
    EXPECT_EQ(chooseLights(s, 0.0, 3.0f).envPmf, 1.0f);
}

}  // namespace
}  // namespace pmcr::test
