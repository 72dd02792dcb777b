#include "render/stats.h"

#include <algorithm>
#include <fstream>

#include "core/error.h"
#include "image/image.h"
#include "vk/context.h"

namespace pmcr {

nlohmann::json renderStats(RenderSession& session, const RenderOutput& output,
                           const std::filesystem::path& scenePath, double renderSeconds,
                           double samplingSeconds) {
    const RenderSettings& s = session.settings();
    nlohmann::json j;
    j["pmcr_version"] = PMCR_VERSION;
    j["method"] = s.method;
    j["scene"] = scenePath.string();
    j["camera"] = s.camera;
    j["device"] = session.context().deviceName();
    j["device_type"] = session.context().deviceTypeName();
    j["width"] = session.width();
    j["height"] = session.height();
    j["seed"] = s.seed;
    j["max_depth"] = s.maxDepth;
    j["rr_depth"] = s.rrDepth;
    j["spp_requested"] = s.spp;
    j["time_limit_seconds"] = s.timeLimit;
    j["samples"] = output.cameraSamples;
    j["spp"] = output.samplesPerPixel;
    j["render_seconds"] = renderSeconds;
    j["sampling_seconds"] = samplingSeconds;
    j["bvh_build_seconds"] = session.scene().bvhBuildSeconds();
    j["triangles"] = session.scene().scene().triangles.size();
    j["bvh_nodes"] = session.scene().bvh().nodes().size();
    j["rays"] = session.counters().rays();
    j["rays_per_second"] = renderSeconds > 0.0 ? double(session.counters().rays()) / renderSeconds : 0.0;
    // Where the time went (docs/performance.md): building and compiling pipelines (outside the
    // clock), the pre-passes (on it), and how busy the device was while the clock ran.
    const double kernelSeconds = session.timer().totalMilliseconds() * 1e-3;
    j["pipeline_seconds"] = session.pipelineSeconds();
    j["prepass_seconds"] = session.prepassSeconds();
    j["device_busy"] = samplingSeconds > 0.0 ? kernelSeconds / samplingSeconds : 0.0;
    j["device_idle_seconds"] = std::max(0.0, samplingSeconds - session.deviceBusySeconds());
    j["queue_drains"] = session.queueDrains();
    j["rays_per_kernel_second"] = kernelSeconds > 0.0 ? double(session.counters().rays()) / kernelSeconds : 0.0;
    j["nan_samples_dropped"] = session.counters().nanDropped();
    j["interrupted"] = session.interrupted();
    j["options"] = s.options;
    nlohmann::json kernels = nlohmann::json::object();
    for (const auto& [name, total] : session.timer().totals())
        kernels[name] = {{"milliseconds", total.milliseconds}, {"dispatches", total.dispatches}};
    j["gpu_kernels"] = kernels;
    j["gpu_milliseconds"] = session.timer().totalMilliseconds();
    j["method_stats"] = output.methodStats;
    return j;
}

double statsNumber(const nlohmann::json& stats, const char* key) {
    const auto it = stats.find(key);
    return it != stats.end() && it->is_number() ? it->get<double>() : 0.0;
}

uint64_t statsCount(const nlohmann::json& stats, const char* key) {
    const auto it = stats.find(key);
    return it != stats.end() && it->is_number_unsigned() ? it->get<uint64_t>() : 0;
}

void StatsTotals::add(const nlohmann::json& stats) {
    rays += statsCount(stats, "rays");
    nanDropped += statsCount(stats, "nan_samples_dropped");
    gpuMilliseconds += statsNumber(stats, "gpu_milliseconds");
    const auto k = stats.find("gpu_kernels");
    if (k == stats.end() || !k->is_object()) return;
    for (const auto& [name, total] : k->items()) {
        auto& t = kernels[name];
        if (!t.is_object()) t = {{"milliseconds", 0.0}, {"dispatches", uint64_t(0)}};
        t["milliseconds"] = t.value("milliseconds", 0.0) + total.value("milliseconds", 0.0);
        t["dispatches"] = t.value("dispatches", uint64_t(0)) + total.value("dispatches", uint64_t(0));
    }
}

void StatsTotals::writeTo(nlohmann::json& stats, double renderSeconds) const {
    stats["rays"] = rays;
    stats["rays_per_second"] = renderSeconds > 0.0 ? double(rays) / renderSeconds : 0.0;
    stats["nan_samples_dropped"] = nanDropped;
    stats["gpu_milliseconds"] = gpuMilliseconds;
    stats["gpu_kernels"] = kernels;
}

std::filesystem::path statsPathFor(const std::filesystem::path& image) {
    std::filesystem::path p = image;
    return p.replace_extension(".json");
}

void writeJsonAtomically(const std::filesystem::path& path, const nlohmann::json& json) {
    writeFileAtomically(path, [&](const std::filesystem::path& tmp) {
        std::ofstream out(tmp);
        out << json.dump(2) << "\n";
        out.close();
        if (!out) throw Error(tmp.string() + ": write failed");
    });
}

}  // namespace pmcr
