#include "render/distributed.h"

#include <algorithm>
#include <cstdlib>
#include <thread>

#include "core/error.h"
#include "render/stats.h"
#include "vk/context.h"

namespace pmcr {

namespace {

// MurmurHash3's 32-bit finaliser: a bijection of uint32 with fmix32(0) = 0.
uint32_t fmix32(uint32_t h) {
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return h;
}

// Diagnostics that count things per pixel (samples, chains, proposals...) add up over the
// ranks; the variance of the weighted image is sum w_r^2 v_r; the rest (alpha maps, strategy
// images) are weighted like the image.
double diagnosticWeight(const std::string& suffix, double w) {
    static const char* const counts[] = {"samples", "chains", "proposals", "accepted", "mutations"};
    for (const char* c : counts)
        if (suffix == c) return 1.0;
    if (suffix == "variance") return w * w;
    return w;
}

void append(std::vector<double>& out, const Image& image, double w) {
    for (float v : image.rgb) out.push_back(w * double(v));
}

size_t unpack(const std::vector<double>& in, size_t at, Image& image) {
    for (float& v : image.rgb) v = float(in[at++]);
    return at;
}

}  // namespace

uint32_t rankSeed(uint32_t seed, int rank) { return seed ^ fmix32(uint32_t(rank)); }

RenderSettings rankSettings(const RenderSettings& settings, uint32_t defaultSpp, const Communicator& comm) {
    RenderSettings s = settings;
    if (!comm.distributed()) return s;
    const uint32_t ranks = uint32_t(comm.size()), rank = uint32_t(comm.rank());
    s.seed = rankSeed(settings.seed, comm.rank());
    if (settings.spp > 0 || settings.timeLimit <= 0.0) {
        const uint32_t total = settings.spp > 0 ? settings.spp : defaultSpp;
        if (total < ranks)
            throw Error("--spp " + std::to_string(total) + " is fewer samples per pixel than the " +
                        std::to_string(ranks) + " ranks (--spp is the total over the ranks)");
        s.spp = total / ranks + (rank < total % ranks ? 1 : 0);
    }
    return s;
}

std::string chooseRankDevice(RenderSettings& settings, const Communicator& comm) {
    std::string line;
    if (comm.localSize() > 1 && !std::getenv("LP_NUM_THREADS")) {
        // Lavapipe reads this when its device is created: the cores split between the ranks.
        const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
        const unsigned threads = std::max(1u, cores / unsigned(comm.localSize()));
        setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 0);
        line = "LP_NUM_THREADS=" + std::to_string(threads) + " (" + std::to_string(comm.localSize()) +
               " ranks on this machine's " + std::to_string(cores) + " cores)";
    }
    if (!comm.distributed() || !settings.device.empty()) return line;
    std::vector<uint32_t> gpus;
    for (const vk::DeviceDescription& d : vk::Context::listDevices())
        if (d.missing.empty() && d.type != "CPU") gpus.push_back(d.index);
    if (!gpus.empty()) {
        settings.device = std::to_string(gpus[size_t(comm.localRank()) % gpus.size()]);
        line += std::string(line.empty() ? "" : "; ") + "device " + settings.device + " (local rank " +
                std::to_string(comm.localRank()) + " of " + std::to_string(gpus.size()) + " GPUs)";
    }
    return line;
}

void onEveryRank(Communicator& comm, const std::function<void()>& stage) {
    if (!comm.distributed()) {
        stage();
        return;
    }
    std::string error;
    try {
        stage();
    } catch (const std::exception& e) {
        error = e.what()[0] ? e.what() : "failed";
    }
    if (!comm.anyTrue(!error.empty())) return;
    const std::vector<std::string> errors = comm.gatherToRoot(error);
    for (size_t r = 0; r < errors.size(); ++r)
        if (!errors[r].empty()) throw Error(r == 0 ? errors[r] : "rank " + std::to_string(r) + ": " + errors[r]);
    throw Error(error.empty() ? "another rank failed" : error);  // ranks > 0: not printed
}

RenderResult reduceRenderResults(RenderResult mine, const RenderSettings& requested, Communicator& comm) {
    if (!comm.distributed()) return mine;
    RenderOutput& out = mine.output;
    std::vector<uint64_t> samples{out.cameraSamples};
    comm.allReduceSum(samples);
    const uint64_t total = samples[0];
    // A rank interrupted before its first sample weighs nothing; all of them: equal weights.
    const double w = total > 0 ? double(out.cameraSamples) / double(total) : 1.0 / double(comm.size());

    // The image and the diagnostics, in one reduction (every rank ran the same method, so they
    // hold the same images in the same order).
    std::vector<double> sum;
    append(sum, out.image, w);
    for (const auto& [suffix, image] : out.diagnostics) append(sum, image, diagnosticWeight(suffix, w));
    comm.allReduceSum(sum);
    size_t at = unpack(sum, 0, out.image);
    for (auto& [suffix, image] : out.diagnostics) at = unpack(sum, at, image);
    out.cameraSamples = total;
    out.samplesPerPixel = double(total) / double(out.image.pixelCount());
    mine.interrupted = comm.anyTrue(mine.interrupted);

    const std::vector<std::string> texts = comm.gatherToRoot(mine.stats.dump());
    if (comm.rank() != 0) return mine;
    nlohmann::json& s = mine.stats;
    StatsTotals totals;
    double renderSeconds = 0.0, samplingSeconds = 0.0;
    bool oneDevice = true;
    nlohmann::json perRank = nlohmann::json::array();
    for (size_t r = 0; r < texts.size(); ++r) {
        const nlohmann::json j = nlohmann::json::parse(texts[r]);
        totals.add(j);
        // The ranks run side by side: the render takes as long as the slowest.
        renderSeconds = std::max(renderSeconds, statsNumber(j, "render_seconds"));
        samplingSeconds = std::max(samplingSeconds, statsNumber(j, "sampling_seconds"));
        oneDevice = oneDevice && j.value("device", "") == s.value("device", "");
        perRank.push_back({{"rank", r},
                           {"device", j.value("device", "")},
                           {"seed", j.value("seed", 0u)},
                           {"samples", statsCount(j, "samples")},
                           {"spp", statsNumber(j, "spp")},
                           {"render_seconds", statsNumber(j, "render_seconds")},
                           {"sampling_seconds", statsNumber(j, "sampling_seconds")},
                           {"rays", statsCount(j, "rays")},
                           {"interrupted", j.value("interrupted", false)},
                           {"method_stats", j.value("method_stats", nlohmann::json::object())}});
    }
    s["ranks"] = comm.size();
    s["rank_stats"] = perRank;
    s["seed"] = requested.seed;
    s["spp_requested"] = requested.spp;
    s["samples"] = total;
    s["spp"] = out.samplesPerPixel;
    s["render_seconds"] = renderSeconds;
    s["sampling_seconds"] = samplingSeconds;
    totals.writeTo(s, renderSeconds);
    s["interrupted"] = mine.interrupted;
    if (!oneDevice) s["device"] = "several (see rank_stats)";
    mine.seconds = renderSeconds;
    mine.samplingSeconds = samplingSeconds;
    return mine;
}

}  // namespace pmcr
