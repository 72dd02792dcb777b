#include "methods/pmc_hi/pmc_hi.h"

#include <algorithm>
#include <string>

#include "core/error.h"

namespace pmcr {

std::vector<MethodOption> pmcHiMethodOptions() {
    return {
        {"population-per-component", "2", "population N = this x components (BSDF, lights, cone)"},
        {"initial-population-per-component", "same",
         "the first iteration's population per component (same: --population-per-component)"},
        {"iterations", "2", "PMC iterations per direct-lighting estimate"},
        {"cone-initial", "0.2", "cone weight after the first iteration (the others scaled by 1 - it)"},
        {"max-light-components", "4",
         "one component per light up to this many lights (at most 8; 7 with an environment), else one for all"},
        {"alpha-floor", "0.05", "defensive floor of the BSDF and light weights (keeps it unbiased)"},
        {"adapt-rate", "1",
         "how far each iteration moves the weights to eq. 9's (1: all the way, the paper)"},
        {"initial-alpha", "paper",
         "the first iteration's weights without feedback: paper (BSDF and lights equal, the lights' "
         "share split by power) or BSDF,LIGHT...[,ENV] (one per light component, then the environment's "
         "if the scene has one; ',' or '/' between; floored, normalised)"},
        {"rao-blackwell", "on",
         "weights f / K with the full mixture; off: f / h_k of the sample's own component (sec. 7), "
         "which misses the light outside a component's support",
         true},
    };
}

PmcHiOptions parsePmcHiOptions(const RenderSettings& settings, const std::string& iterationsOption) {
    PmcHiOptions o;
    const int population = settings.optionInt("population-per-component", 2);
    if (population < 1 || population > int(gpu::PMC_HI_MAX_POPULATION_PER_COMPONENT))
        throw Error("--population-per-component: expected 1.." +
                    std::to_string(gpu::PMC_HI_MAX_POPULATION_PER_COMPONENT));
    const std::string initial = settings.optionString("initial-population-per-component", "same");
    const int initialPopulation =
        initial == "same" ? population : settings.optionInt("initial-population-per-component", population);
    if (initialPopulation < 1 || initialPopulation > int(gpu::PMC_HI_MAX_POPULATION_PER_COMPONENT))
        throw Error("--initial-population-per-component: expected 1.." +
                    std::to_string(gpu::PMC_HI_MAX_POPULATION_PER_COMPONENT) + " or same");
    const int iterations = settings.optionInt(iterationsOption, 2);
    if (iterations < 1 || iterations > int(gpu::PMC_HI_MAX_ITERATIONS))
        throw Error("--" + iterationsOption + ": expected 1.." + std::to_string(gpu::PMC_HI_MAX_ITERATIONS));
    const double cone = settings.optionDouble("cone-initial", 0.2);
    if (!(cone >= 0.0 && cone < 1.0)) throw Error("--cone-initial: expected 0 <= value < 1");
    const double floor = settings.optionDouble("alpha-floor", 0.05);
    if (!(floor > 0.0 && floor <= 0.5)) throw Error("--alpha-floor: expected 0 < value <= 0.5");
    const int maxLights = settings.optionInt("max-light-components", 4);
    if (maxLights < 1 || maxLights > int(gpu::PMC_HI_MAX_LIGHTS))
        throw Error("--max-light-components: expected 1.." + std::to_string(gpu::PMC_HI_MAX_LIGHTS));
    o.params.populationPerComponent = uint32_t(population);
    o.params.initialPopulationPerComponent = uint32_t(initialPopulation);
    o.params.iterations = uint32_t(iterations);
    o.params.coneInitial = float(cone);
    o.params.alphaFloor = float(floor);
    const double rate = settings.optionDouble("adapt-rate", 1.0);
    if (!(rate > 0.0 && rate <= 1.0)) throw Error("--adapt-rate: expected 0 < rate <= 1");
    o.params.adaptRate = float(rate);
    o.params.flags = settings.optionBool("rao-blackwell", true) ? gpu::PMC_HI_FLAG_RAO_BLACKWELL : 0u;
    o.maxLightComponents = uint32_t(maxLights);
    if (settings.optionString("initial-alpha", "paper") != "paper") {
        o.initialAlpha = settings.optionNumbers("initial-alpha", "paper");
        for (double v : o.initialAlpha)
            if (!(v >= 0.0 && v <= 1e6))
                throw Error("--initial-alpha: expected paper or non-negative weights BSDF,LIGHT..., got '" +
                            settings.optionString("initial-alpha", "") + "'");
    }
    return o;
}

gpu::PmcHiParams pmcHiParamsForScene(const PmcHiOptions& options, const GpuScene& scene) {
    return pmcHiParamsFor(options, uint32_t(scene.lightGroups().lights.size()),
                          scene.info().envKind != gpu::ENV_NONE);
}

gpu::PmcHiParams pmcHiParamsFor(const PmcHiOptions& options, uint32_t lights, bool environment) {
    gpu::PmcHiParams p = options.params;
    // The environment's slot follows the lights' and takes one of theirs (pmc_hi_types.h);
    // punctual lights take none.
    if (environment) p.flags |= gpu::PMC_HI_FLAG_ENVIRONMENT;
    const uint32_t maxLights = std::min(options.maxLightComponents, gpu::PMC_HI_MAX_LIGHTS - (environment ? 1u : 0u));
    const bool shared = lights > maxLights;
    p.sharedLight = shared ? 1u : 0u;
    p.lightComponents = shared ? 1u : lights;
    if (!options.initialAlpha.empty()) {
        // The BSDF's weight, then one per light component (slots PMC_HI_BSDF, PMC_HI_LIGHT + l),
        // then the environment's.
        const size_t expected = 1 + p.lightComponents + (environment ? 1 : 0);
        if (options.initialAlpha.size() != expected)
            throw Error("--initial-alpha: this scene has " + std::to_string(expected) +
                        " components to weigh (the BSDF, then " +
                        (shared ? std::string("one shared light component")
                                : std::to_string(p.lightComponents) + " lights") +
                        (environment ? ", then the environment" : "") + "), got " +
                        std::to_string(options.initialAlpha.size()) + " weights");
        p.initialAlpha[gpu::PMC_HI_BSDF] = float(options.initialAlpha[0]);
        for (uint32_t l = 0; l < p.lightComponents; ++l)
            p.initialAlpha[gpu::PMC_HI_LIGHT + l] = float(options.initialAlpha[1 + l]);
        if (environment)
            p.initialAlpha[gpu::PMC_HI_LIGHT + p.lightComponents] =
                float(options.initialAlpha[1 + p.lightComponents]);
        p.flags |= gpu::PMC_HI_FLAG_INITIAL_ALPHA;
    }
    return p;
}

uint32_t pmcHiComponents(const gpu::PmcHiParams& params) {
    const bool environment = (params.flags & gpu::PMC_HI_FLAG_ENVIRONMENT) != 0u;
    return gpu::PMC_HI_LIGHT + params.lightComponents + (environment ? 1u : 0u);
}

std::string pmcHiKernel(const GpuScene& scene) {
    const bool otherLights = scene.info().envKind != gpu::ENV_NONE || scene.info().punctualCount > 0;
    return std::string("methods/pmc_hi/pmc_hi") + (otherLights ? "_all_lights" : "");
}

void addPmcHiOutputs(RenderOutput& out, const gpu::PmcHiParams& params, const GpuScene& scene,
                     const std::vector<float>& alphaSums, int width, int height) {
    const uint32_t components = pmcHiComponents(params);
    const bool shared = params.sharedLight != 0u;
    const bool environment = (params.flags & gpu::PMC_HI_FLAG_ENVIRONMENT) != 0u;
    out.methodStats["lights"] = scene.lightGroups().lights.size();
    out.methodStats["light_components"] = params.lightComponents;
    out.methodStats["shared_light_component"] = params.sharedLight;
    out.methodStats["environment_component"] = environment;
    out.methodStats["punctual_lights"] = scene.info().punctualCount;
    out.methodStats["population"] = params.populationPerComponent * components;
    out.methodStats["pmc_hi_iterations"] = params.iterations;
    out.methodStats["samples_per_estimate"] =
        (params.initialPopulationPerComponent + params.populationPerComponent * (params.iterations - 1)) *
        components;
    out.methodStats["rao_blackwell"] = (params.flags & gpu::PMC_HI_FLAG_RAO_BLACKWELL) != 0u;

    auto map = [&](uint32_t slot) {
        Image image(width, height);
        for (int p = 0; p < width * height; ++p) {
            const float* a = &alphaSums[size_t(p) * gpu::PMC_HI_ALPHA_STRIDE];
            const float count = a[gpu::PMC_HI_MAX_COMPONENTS];
            image.set(p % width, p / width, glm::vec3(count > 0.0f ? a[slot] / count : 0.0f));
        }
        return image;
    };
    out.diagnostics.emplace_back("alpha-brdf", map(gpu::PMC_HI_BSDF));
    for (uint32_t l = 0; l < params.lightComponents; ++l)
        out.diagnostics.emplace_back(shared ? std::string("alpha-light") : "alpha-light" + std::to_string(l),
                                     map(gpu::PMC_HI_LIGHT + l));
    if (environment) out.diagnostics.emplace_back("alpha-env", map(gpu::PMC_HI_LIGHT + params.lightComponents));
    out.diagnostics.emplace_back("alpha-cone", map(gpu::PMC_HI_CONE));
}

}  // namespace pmcr
