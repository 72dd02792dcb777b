// The render options a kernel is specialized for: specialization constant 1, which the host sets
// to KERNEL_OPTION_* bits (shared/render_types.h) when it creates the pipeline (vk::Kernel,
// RenderSession::kernel). They select the papers' weaker baselines (--pixel-sampler independent,
// --mis balance; host/render/baseline_options.h). The driver folds the code of an option that is
// off away, so the default kernels run the code they ran before the options existed.
#ifndef PMCR_KERNEL_OPTIONS_GLSL
#define PMCR_KERNEL_OPTIONS_GLSL

layout(constant_id = 1) const uint kKernelOptions = 0u;

// Camera samples land uniformly in their pixel, independently of the pixel's other samples.
bool independentPixelSamples() { return (kKernelOptions & KERNEL_OPTION_INDEPENDENT_PIXELS) != 0u; }
// Light and BSDF samples are weighed by the balance heuristic instead of the power heuristic.
bool balanceHeuristicMis() { return (kKernelOptions & KERNEL_OPTION_BALANCE_HEURISTIC) != 0u; }

#endif
