#include "scene/light_choice.h"

#include "scene/environment.h"

namespace pmcr {

namespace {

// Half of each probability from `power`, half uniform over its entries.
std::vector<double> halfPowerHalfUniform(std::vector<double> power) {
    double total = 0.0;
    for (double p : power) total += p;
    for (double& p : power) p = 0.5 * (total > 0.0 ? p / total : 0.0) + 0.5 / double(power.size());
    return power;
}

}  // namespace

LightChoice chooseLights(const Scene& scene, double emitterPower, float sceneRadius) {
    LightChoice c;
    const bool env = scene.environment.kind != gpu::ENV_NONE;
    const bool punctual = !scene.punctualLights.empty();
    if (!env && !punctual) return c;

    double punctualPower = 0.0;
    if (punctual) {
        std::vector<double> power;
        for (const gpu::PunctualLight& light : scene.punctualLights)
            power.push_back(punctualLightPower(light, sceneRadius));
        for (double p : power) punctualPower += p;
        c.punctualTable.resize(power.size());
        buildAliasTable(halfPowerHalfUniform(power), c.punctualTable.data());
        for (size_t i = 0; i < c.punctualTable.size(); ++i) c.punctualTable[i].triangle = uint32_t(i);
    }
    // The kinds present, in the order of their intervals of u: environment, punctual, emitters.
    std::vector<double> kinds;
    if (env) kinds.push_back(environmentPower(scene.environment, sceneRadius));
    if (punctual) kinds.push_back(punctualPower);
    if (emitterPower > 0.0) kinds.push_back(emitterPower);
    const std::vector<double> pmf = halfPowerHalfUniform(kinds);
    if (env) c.envPmf = float(pmf[0]);
    if (punctual) c.punctualPmf = float(pmf[env ? 1 : 0]);
    // Without emitters nothing is left for them: rounding must not leave a sliver of u.
    if (!(emitterPower > 0.0)) {
        if (punctual) c.punctualPmf = 1.0f - c.envPmf;
        else c.envPmf = 1.0f;
    }
    return c;
}

}  // namespace pmcr
