// `pmcr bench`: several methods on one scene, each for the same render time (and/or the same
// sample budget), measured against one reference with the papers' metrics (metrics/metrics.h).
// The methods run one after the other in this process on one device, so the device is set up
// once and every method sees the same machine.
//
// Time is the render clock (RenderSession::startClock): from a method's first sample to its end,
// without the scene upload, BVH build and kernel compilation (the same for every method, paid
// once per scene and device in an application) and without the convergence snapshots. Each run's
// wall time is recorded beside it in results.json.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "image/image.h"
#include "metrics/metrics.h"
#include "render/settings.h"
#include "scene/scene.h"

namespace pmcr {

namespace vk {
class Context;
}

// One entry of --methods: "direct" or "direct:light-samples=4" (options separated by ':').
struct BenchMethod {
    std::string label;  // as given
    std::string method;
    std::map<std::string, std::string> options;
};

// Parses a comma-separated method list; throws pmcr::Error naming `option` for an unknown
// method, a malformed or unknown option, or a label given twice. Methods that are not
// implemented yet are accepted (the bench reports them as such).
std::vector<BenchMethod> parseBenchMethods(const std::string& option, const std::string& text);

struct BenchOptions {
    std::vector<BenchMethod> methods;
    RenderSettings base;  // size, seed, depths, camera, timeLimit and/or spp (the budget), quiet
    std::optional<std::filesystem::path> reference;  // else render one with pt:
    uint32_t referenceSpp = 0;                       //   this many samples per pixel
    std::optional<float> exposure;                   // PNG exposure (EV); default: see autoExposure
    std::vector<PixelRect> crops;                    // the papers' zoomed regions
    double displayWhite = kDefaultDisplayWhite;
    int snapshots = 8;  // convergence points per run before the last: budget / 2^k, k = 1..n
};

struct ConvergencePoint {
    double seconds = 0.0;
    double spp = 0.0;
    double mse = 0.0;
    double pmse = 0.0;
};

struct BenchRun {
    BenchMethod method;
    bool implemented = true;
    std::string plannedIn;  // for a method not implemented yet
    double seconds = 0.0;   // the render clock
    double wallSeconds = 0.0;
    uint64_t samples = 0;
    double spp = 0.0;
    ErrorMetrics error;
    std::vector<ErrorMetrics> cropErrors;  // one per BenchOptions::crops
    double eff = 0.0, peff = 0.0;
    double effRatio = 0.0, peffRatio = 0.0;  // to the first implemented method
    std::vector<ConvergencePoint> convergence;
    Image image;
    std::vector<std::pair<std::string, Image>> diagnostics;
    nlohmann::json stats;
};

struct BenchReport {
    BenchOptions options;  // options.base with the image size resolved
    std::filesystem::path scene;
    std::string device;
    int width = 0, height = 0;
    Image reference;
    // Where the reference came from: "path", "rendered_by_bench", "method", "spp", "seeds",
    // and "notes" (warnings about it, also shown in the report).
    nlohmann::json referenceInfo;
    nlohmann::json referenceStats;  // when rendered by the bench
    std::vector<BenchRun> runs;
    float exposure = 0.0f;
    float errorScale = 1.0f;  // |Y - Y_ref| shown as full scale in every error image
    bool interrupted = false;
};

// The exposure that maps the reference's mean luminance to 18% grey: log2(0.18 / mean); 0 for a
// black reference.
float autoExposure(const Image& reference);

// Checks the options and loads the reference before any device work: throws pmcr::Error for bad
// input (a reference of the wrong size or sharing the bench's seed, a crop outside the image, a
// bad method option). Returns the report to run, with the image size resolved
// (report.options.base).
BenchReport prepareBench(const Scene& scene, const BenchOptions& options);

// Renders the reference (without --reference), then each method, and measures them. Stops early
// with report.interrupted set when the user interrupts a render.
void runBench(vk::Context& context, const Scene& scene, BenchReport& report);

}  // namespace pmcr
