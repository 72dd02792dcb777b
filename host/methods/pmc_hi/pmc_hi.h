// PMC-HI (Fan, Lai, Chenney and Dyer, sec. 5) on the host: its method options, the per-scene
// kernel parameters (one light component per light up to --max-light-components, else one
// shared by all, and one for the environment when the scene has one), the kernel variant, and
// the diagnostics (the figure 7 alpha maps). Used by `pmc-hi`
// (methods/pt/pt_integrator.h) and `pmc-ip-hi` (methods/pmc_ip/pmc_ip_integrator.h); the sampler
// itself is shaders/methods/pmc_hi/pmc_hi.glsl.
#pragma once

#include <string>
#include <vector>

#include "render/gpu_scene.h"
#include "render/method_info.h"
#include "render/session.h"
#include "shared/host_device.h"

namespace pmcr {

struct PmcHiOptions {
    gpu::PmcHiParams params{};  // lightComponents, sharedLight, the environment: see pmcHiParamsForScene
    uint32_t maxLightComponents = 4;
    std::vector<double> initialAlpha;  // --initial-alpha: empty for the paper's
};

// The options of both PMC-HI methods, for the registry.
std::vector<MethodOption> pmcHiMethodOptions();
// Parses them; throws pmcr::Error for a bad value. `iterationsOption` names PMC-HI's iteration
// count (pmc-ip-hi calls it hi-iterations, its --iterations being PMC-IP's).
PmcHiOptions parsePmcHiOptions(const RenderSettings& settings,
                               const std::string& iterationsOption = "iterations");
// The parameters for a scene: its lights (connected emitters) as components, or one shared,
// and its environment as one more (PMC_HI_FLAG_ENVIRONMENT).
gpu::PmcHiParams pmcHiParamsForScene(const PmcHiOptions& options, const GpuScene& scene);
// The same for `lights` lights (connected emitter groups) and an environment or none.
gpu::PmcHiParams pmcHiParamsFor(const PmcHiOptions& options, uint32_t lights, bool environment);
// The mixture's slots in use (m): BSDF, cone, the light components and the environment's.
uint32_t pmcHiComponents(const gpu::PmcHiParams& params);

// The PMC-HI kernel for `scene`: pmc_hi_all_lights (the environment as a component, punctual
// lights by their own next-event estimate) when the scene has either, else pmc_hi, which leaves
// them out and is faster on lavapipe (every branch of a kernel costs there, taken or not).
std::string pmcHiKernel(const GpuScene& scene);

// Adds the figure 7 maps ("alpha-brdf", "alpha-light0", ..., "alpha-env" with an environment,
// "alpha-cone": per pixel the mean
// final alpha of its first-hit estimates) from per-pixel sums laid out as pmc_hi.comp writes
// them (PMC_HI_ALPHA_STRIDE floats per pixel, the count last), and the method stats.
void addPmcHiOutputs(RenderOutput& out, const gpu::PmcHiParams& params, const GpuScene& scene,
                     const std::vector<float>& alphaSums, int width, int height);

}  // namespace pmcr
