#include "bench/bench.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>

#include "core/error.h"
#include "core/log.h"
#include "metrics/merge.h"
#include "render/methods.h"
#include "render/renderer.h"
#include "render/stats.h"
#include "vk/context.h"

namespace pmcr {

namespace {

// The reference the bench renders itself uses this seed offset from the methods' seed, so that
// no method is measured against its own samples.
constexpr uint32_t kReferenceSeedOffset = 0x9e3779b9u;

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    size_t start = 0;
    while (true) {
        const size_t end = text.find(separator, start);
        parts.push_back(text.substr(start, end - start));
        if (end == std::string::npos)
            return parts;
        start = end + 1;
    }
}

std::string sizeText(int width, int height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

// Render-clock times (or sample counts) budget / 2^k for k = n..1, ascending.
std::vector<double> halvings(double budget, int n) {
    std::vector<double> points;
    for (int k = n; k >= 1; --k)
        points.push_back(budget / std::pow(2.0, k));
    return points;
}

// Reads the reference and what its stats JSON (if any) says about it; checks it can serve.
void loadReference(BenchReport& report, RenderSettings& base, const Scene& scene,
                   const std::filesystem::path& path) {
    const std::string name = path.string();
    report.reference = readHdr(path);
    if (base.width == 0 && base.height == 0) {
        base.width = report.reference.width;
        base.height = report.reference.height;
    } else {
        resolveImageSize(scene, base);
        if (base.width != report.reference.width || base.height != report.reference.height)
            fail(name, "is " + sizeText(report.reference.width, report.reference.height) +
                           " but the bench renders " + sizeText(base.width, base.height) +
                           " (--width/--height)");
    }
    nlohmann::json& info = report.referenceInfo;
    info = {{"path", name}, {"rendered_by_bench", false}, {"notes", nlohmann::json::array()}};
    const std::filesystem::path statsPath = statsPathFor(path);
    std::error_code ec;
    if (!std::filesystem::exists(statsPath, ec)) {
        info["notes"].push_back(
            "no stats JSON beside the reference: its method, samples and "
            "seeds are unknown, and its independence from the methods' "
            "samples cannot be checked");
        return;
    }
    std::ifstream in(statsPath);
    const nlohmann::json stats = nlohmann::json::parse(in, nullptr, false);
    if (stats.is_discarded() || !stats.is_object())
        fail(statsPath.string(), "not a pmcr stats JSON object");
    const std::vector<uint32_t> seeds = renderSeeds(stats);
    if (std::find(seeds.begin(), seeds.end(), base.seed) != seeds.end())
        fail(name, "was rendered with seed " + std::to_string(base.seed) +
                       ", the seed of this bench: the methods would share its samples; give the "
                       "bench another --seed");
    info["method"] = stats.value("method", "");
    info["spp"] = stats.value("spp", 0.0);
    info["seeds"] = seeds;
    auto note = [&](const std::string& text) {
        info["notes"].push_back(text);
        log::warning(name + ": " + text);
    };
    const std::string refScene =
        std::filesystem::path(stats.value("scene", "")).filename().string();
    if (refScene != scene.path.filename().string())
        note("rendered from '" + refScene + "', not " + scene.path.filename().string());
    const std::pair<const char*, uint32_t> depths[] = {{"max_depth", base.maxDepth},
                                                       {"rr_depth", base.rrDepth}};
    for (const auto& [key, value] : depths)
        if (stats.contains(key) && stats[key] != value)
            note(std::string("rendered with ") + key + " " + stats[key].dump() +
                 ", the bench uses " + std::to_string(value) +
                 ": the errors include the difference");
    if (stats.contains("camera") && stats["camera"] != base.camera)
        note("rendered from camera " + stats["camera"].dump() + ", the bench uses " +
             std::to_string(base.camera));
}

void renderReference(BenchReport& report, vk::Context& context, const Scene& scene,
                     const RenderSettings& base, uint32_t spp) {
    RenderSettings s = base;
    s.method = "pt";
    s.options.clear();
    s.spp = spp;
    s.timeLimit = 0.0;
    s.seed = base.seed + kReferenceSeedOffset;
    s.snapshotSeconds.clear();
    s.snapshotSpp.clear();
    if (!s.quiet)
        log::info("bench: rendering the reference (pt, " + std::to_string(spp) + " spp, seed " +
                  std::to_string(s.seed) + ")");
    RenderResult r = renderScene(context, scene, s);
    if (r.interrupted) {
        report.interrupted = true;
        return;
    }
    report.reference = std::move(r.output.image);
    report.referenceStats = r.stats;
    report.referenceInfo = {
        {"path", "reference.exr"},
        {"rendered_by_bench", true},
        {"method", "pt"},
        {"spp", r.output.samplesPerPixel},
        {"seeds", {s.seed}},
        {"render_seconds", r.seconds},
        {"notes", nlohmann::json::array({"rendered by this bench with pt and a seed of its own "
                                         "(the methods use seed " +
                                         std::to_string(base.seed) +
                                         "); a pt reference converges slowly in caustics, so "
                                         "its own noise adds to every method's Err"})}};
}

MetricOptions metricOptions(const BenchOptions& o) {
    MetricOptions m;
    m.displayWhite = o.displayWhite;
    m.referenceName = o.reference ? o.reference->string() : "reference.exr";
    return m;
}

void checkCrops(const std::vector<PixelRect>& crops, int width, int height) {
    for (const PixelRect& c : crops)
        if (int64_t(c.x) + c.width > width || int64_t(c.y) + c.height > height)
            throw Error("--crop " + toString(c) + ": outside the " + sizeText(width, height) +
                        " image");
}

}  // namespace

std::vector<BenchMethod> parseBenchMethods(const std::string& option, const std::string& text) {
    std::vector<BenchMethod> list;
    std::set<std::string> labels;
    for (const std::string& item : split(text, ',')) {
        if (item.empty())
            throw Error(option + ": empty method name in '" + text + "'");
        const std::vector<std::string> parts = split(item, ':');
        BenchMethod m;
        m.label = item;
        m.method = parts[0];
        const MethodInfo* info = findMethod(m.method);
        if (!info)
            throw Error(option + ": unknown method '" + m.method + "' (see pmcr render --help)");
        for (size_t i = 1; i < parts.size(); ++i) {
            const size_t eq = parts[i].find('=');
            if (eq == std::string::npos || eq == 0)
                throw Error(option + ": expected METHOD:OPTION=VALUE, got '" + item + "'");
            const std::string name = parts[i].substr(0, eq);
            const bool known = std::any_of(info->options.begin(), info->options.end(),
                                           [&](const MethodOption& o) { return o.name == name; });
            if (!known)
                throw Error(option + ": unknown option '" + name + "' for method " + m.method);
            m.options[name] = parts[i].substr(eq + 1);
        }
        if (!labels.insert(m.label).second)
            throw Error(option + ": '" + m.label + "' is given twice");
        list.push_back(std::move(m));
    }
    return list;
}

float autoExposure(const Image& reference) {
    double sum = 0.0;
    for (size_t i = 0; i < reference.pixelCount(); ++i)
        sum += luminance709(
            glm::vec3(reference.rgb[3 * i], reference.rgb[3 * i + 1], reference.rgb[3 * i + 2]));
    const double mean = reference.pixelCount() > 0 ? sum / double(reference.pixelCount()) : 0.0;
    return mean > 0.0 && std::isfinite(mean) ? float(std::log2(0.18 / mean)) : 0.0f;
}

BenchReport prepareBench(const Scene& scene, const BenchOptions& options) {
    if (options.methods.empty())
        throw Error("bench: no methods (--methods)");
    if (options.base.timeLimit <= 0.0 && options.base.spp == 0)
        throw Error("bench: give a budget: --time SECONDS and/or --budget-spp N");
    if (!options.reference && options.referenceSpp == 0)
        throw Error("bench: give --reference REF.exr, or --reference-spp N to render one");
    BenchReport report;
    report.options = options;
    report.scene = scene.path;
    RenderSettings& base = report.options.base;
    if (options.reference)
        loadReference(report, base, scene, *options.reference);
    else
        resolveImageSize(scene, base);
    checkCrops(options.crops, base.width, base.height);
    // Options of the implemented methods, values included (creating an integrator parses them).
    for (const BenchMethod& m : options.methods) {
        const MethodInfo* info = findMethod(m.method);
        if (!info || !info->create)
            continue;
        RenderSettings s = base;
        s.method = m.method;
        s.options = m.options;
        validateMethodOptions(s);
        info->create(s);
    }
    report.width = base.width;
    report.height = base.height;
    return report;
}

void runBench(vk::Context& context, const Scene& scene, BenchReport& report) {
    const BenchOptions& options = report.options;
    const RenderSettings& base = options.base;
    report.device = context.deviceName();
    if (!options.reference) {
        renderReference(report, context, scene, base, options.referenceSpp);
        if (report.interrupted)
            return;
    }
    report.exposure = options.exposure ? *options.exposure : autoExposure(report.reference);

    const size_t count = options.methods.size();
    for (size_t i = 0; i < count; ++i) {
        BenchRun run;
        run.method = options.methods[i];
        const MethodInfo* info = findMethod(run.method.method);
        if (!info || !info->create) {
            run.implemented = false;
            run.plannedIn = info ? info->plannedIn : "";
            report.runs.push_back(std::move(run));
            continue;
        }
        RenderSettings s = base;
        s.method = run.method.method;
        s.options = run.method.options;
        if (s.timeLimit > 0.0)
            s.snapshotSeconds = halvings(s.timeLimit, options.snapshots);
        if (s.spp > 0)
            s.snapshotSpp = halvings(double(s.spp), options.snapshots);
        if (!s.quiet)
            log::info("bench: " + run.method.label + " (" + std::to_string(i + 1) + "/" +
                      std::to_string(count) + ")");
        RenderResult r = renderScene(context, scene, s);
        if (r.interrupted) {
            report.interrupted = true;
            return;
        }
        MetricOptions m = metricOptions(options);
        m.imageName = run.method.label;
        run.seconds = r.samplingSeconds;
        run.wallSeconds = r.seconds;
        run.samples = r.output.cameraSamples;
        run.spp = r.output.samplesPerPixel;
        run.error = measureError(r.output.image, report.reference, m);
        for (const PixelRect& crop : options.crops) {
            MetricOptions c = m;
            c.cropped = true;
            c.crop = crop;
            run.cropErrors.push_back(measureError(r.output.image, report.reference, c));
        }
        run.eff = efficiency(run.seconds, run.error.mse);
        run.peff = efficiency(run.seconds, run.error.pmse);
        for (const Snapshot& snap : r.snapshots) {
            const ErrorMetrics e = measureError(snap.image, report.reference, m);
            run.convergence.push_back({snap.seconds, snap.samplesPerPixel, e.mse, e.pmse});
        }
        run.convergence.push_back({run.seconds, run.spp, run.error.mse, run.error.pmse});
        run.image = std::move(r.output.image);
        run.diagnostics = std::move(r.output.diagnostics);
        run.stats = std::move(r.stats);
        report.runs.push_back(std::move(run));
    }

    // Ratios to the first method that ran (the papers' baseline column).
    const BenchRun* baseline = nullptr;
    for (const BenchRun& run : report.runs)
        if (run.implemented && !baseline)
            baseline = &run;
    for (BenchRun& run : report.runs) {
        if (!run.implemented || !baseline)
            continue;
        run.effRatio = baseline->eff > 0.0 ? run.eff / baseline->eff : 0.0;
        run.peffRatio = baseline->peff > 0.0 ? run.peff / baseline->peff : 0.0;
    }

    // One error scale for all error images: the largest 99th percentile of |Y - Y_ref|.
    float scale = 0.0f, largest = 0.0f;
    for (const BenchRun& run : report.runs) {
        if (!run.implemented)
            continue;
        const std::vector<float> map = luminanceErrorMap(run.image, report.reference);
        scale = std::max(scale, quantile(map, 0.99));
        largest = std::max(largest, *std::max_element(map.begin(), map.end()));
    }
    report.errorScale = scale > 0.0f ? scale : largest > 0.0f ? largest : 1.0f;
}

}  // namespace pmcr
