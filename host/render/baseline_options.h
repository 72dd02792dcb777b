// The papers' own baselines as options (issue 26): pmcr's baselines are stronger than the
// papers' (stratified pixel samples, MIS with the power heuristic), so a reader can ask for the
// weaker ones to reproduce a paper under its own conditions.
//   --pixel-sampler stratified|independent: where a camera sample lands in its pixel, the
//     pixel's (0,2)-sequence (default) or a point uniform in the pixel and independent of the
//     pixel's other samples (the "uniform" image-plane sampling PMC-IP and PMC-PT compare with);
//   --mis power|balance: the MIS weights of light and BSDF samples, the power heuristic
//     (default) or the balance heuristic.
// Both specialize the kernels (KERNEL_OPTION_*, shared/render_types.h;
// shaders/common/kernel_options.glsl): the default kernels are the code they were before the
// options existed, so the defaults give the same images bit for bit. A method offers an option
// by listing it among its MethodOptions; any other method rejects it as an unknown option.
// docs/paper-baselines.md says which paper each reproduces and where the papers are silent.
#pragma once

#include <cstdint>

#include "render/method_info.h"
#include "render/settings.h"

namespace pmcr {

enum class PixelSampler { Stratified, Independent };
enum class MisHeuristic { Power, Balance };

struct BaselineOptions {
    PixelSampler pixelSampler = PixelSampler::Stratified;
    MisHeuristic mis = MisHeuristic::Power;

    // The gpu::KERNEL_OPTION_* bits the kernels are specialized for (RenderSession::kernel).
    uint32_t kernelOptions() const;
};

// The registry entries of the two options (MethodInfo::options), labelled as paper baselines.
MethodOption pixelSamplerOption();
MethodOption misOption();

// --pixel-sampler and --mis from `settings` (defaults where absent); throws pmcr::Error, one
// line naming the option, on any other value.
BaselineOptions parseBaselineOptions(const RenderSettings& settings);

}  // namespace pmcr
