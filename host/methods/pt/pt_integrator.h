// Path tracing (`pt`) and MIS direct lighting (`direct`): progressive passes of one sample per
// pixel, each pass split into dispatches over pixel ranges (or, on small images, several whole
// passes per dispatch). One writer per pixel per dispatch, adding its samples to the film one by
// one in pass order, makes the film sums independent of how the passes are split, so a fixed
// seed and sample count give the same image bit for bit on a given device.
// `pmc-hi` is the same loop with PMC-HI adaptive direct lighting
// (shaders/methods/pmc_hi/pmc_hi.comp) in place of MIS direct lighting.
#pragma once

#include "methods/pmc_hi/pmc_hi.h"
#include "render/baseline_options.h"
#include "render/integrator.h"
#include "render/method_info.h"

namespace pmcr {

// Points the work set of the per-camera-sample kernels (pt, direct, pmc_hi) in tile mode at
// `film`; their request and result lists, unused there, at the session's placeholder.
void bindTileWork(vk::DescriptorSet& work, const Film& film, const RenderSession& session);

// Items (tile pixels or requests) per invocation of a pt.comp or pt_record.comp dispatch of
// `items` items, each of `pathsPerItem` paths (a tile's passes), on `context`'s device
// (PtPush::itemsPerInvocation, paths in turn): on a CPU device, whose SIMD lanes would otherwise
// idle while the longest path of their vector ends, up to 32 paths per invocation while each
// CPU thread still gets several workgroups; 1 on a GPU.
uint32_t ptItemsPerInvocation(const vk::Context& context, uint32_t items,
                              uint32_t pathsPerItem = 1);

// The path-tracing kernel `name` ("pt" or "direct", under shaders/methods/pt/) for `scene`: the
// variant with punctual lights and the environment compiled in (NAME_all_lights) when the scene
// has them, else the one for emitters alone, which on lavapipe is faster (every branch of a
// kernel costs there, taken or not).
std::string pathTracingKernel(const GpuScene& scene, const std::string& name);

// Kernel `path` (under shaders/, without .comp), or its variant PATH_all_lights compiled with
// PMCR_OTHER_LIGHTS when `scene` has punctual lights or an environment: the choice
// pathTracingKernel makes, for every kernel that comes in the two variants.
std::string lightsKernelVariant(const GpuScene& scene, const std::string& path);

class PathTracer : public Integrator {
public:
    enum class Mode { Full, Direct, PmcHi };
    PathTracer(const RenderSettings& settings, Mode mode);
    RenderOutput render(RenderSession& session) override;

    static constexpr uint32_t kDefaultSpp = 64;
    uint32_t defaultSpp() const override { return kDefaultSpp; }

private:
    Mode m_mode;
    uint32_t m_lightSamples;
    PmcHiOptions m_hi;
    BaselineOptions m_baseline;  // --pixel-sampler (every mode), --mis (pt and direct)
};

// The registry entries (render/methods.cpp) of `pt`, `direct` and `pmc-hi` (this loop with
// PMC-HI direct lighting, methods/pmc_hi/pmc_hi.h).
MethodInfo ptMethod();
MethodInfo directMethod();
MethodInfo pmcHiMethod();

}  // namespace pmcr
