#include "render/baseline_options.h"

#include "core/error.h"
#include "shared/host_device.h"

namespace pmcr {

uint32_t BaselineOptions::kernelOptions() const {
    uint32_t bits = 0;
    if (pixelSampler == PixelSampler::Independent) bits |= gpu::KERNEL_OPTION_INDEPENDENT_PIXELS;
    if (mis == MisHeuristic::Balance) bits |= gpu::KERNEL_OPTION_BALANCE_HEURISTIC;
    return bits;
}

MethodOption pixelSamplerOption() {
    MethodOption o{"pixel-sampler", "stratified",
                   "where a camera sample lands in its pixel: stratified ((0,2)-sequence) or "
                   "independent (uniform, no stratification)"};
    o.paperBaseline =
        "independent: the uniform image-plane sampling of the PMC-IP and PMC-PT papers";
    return o;
}

MethodOption misOption() {
    MethodOption o{"mis", "power",
                   "MIS weights of light and BSDF samples: power (beta = 2) or balance heuristic"};
    o.paperBaseline =
        "balance: Veach's balance heuristic, a reading of the PMC-HI paper's unspecified MIS";
    return o;
}

BaselineOptions parseBaselineOptions(const RenderSettings& settings) {
    BaselineOptions b;
    const std::string sampler = settings.optionString("pixel-sampler", "stratified");
    if (sampler == "independent") b.pixelSampler = PixelSampler::Independent;
    else if (sampler != "stratified")
        throw Error("--pixel-sampler: expected stratified or independent, got '" + sampler + "'");
    const std::string mis = settings.optionString("mis", "power");
    if (mis == "balance") b.mis = MisHeuristic::Balance;
    else if (mis != "power") throw Error("--mis: expected power or balance, got '" + mis + "'");
    return b;
}

}  // namespace pmcr
