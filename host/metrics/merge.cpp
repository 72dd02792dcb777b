#include "metrics/merge.h"

#include <algorithm>
#include <fstream>
#include <set>
#include <string>

#include "core/error.h"
#include "core/log.h"
#include "render/stats.h"

namespace pmcr {

namespace {

// Settings two pieces must share for their images to estimate the same thing.
constexpr const char* kSameSettings[] = {"method", "camera", "max_depth", "rr_depth", "options"};

std::string jsonText(const nlohmann::json& j) {
    return j.is_null() ? "none" : j.dump();
}

double number(const RenderPiece& piece, const char* key) { return statsNumber(piece.stats, key); }

uint64_t count(const RenderPiece& piece, const char* key) { return statsCount(piece.stats, key); }

std::string sceneName(const nlohmann::json& stats) {
    const auto it = stats.find("scene");
    return it != stats.end() && it->is_string()
               ? std::filesystem::path(it->get<std::string>()).filename().string()
               : "";
}

}  // namespace

RenderPiece readRenderPiece(const std::filesystem::path& image) {
    RenderPiece piece;
    piece.path = image;
    piece.image = readHdr(image);
    const std::filesystem::path statsPath = statsPathFor(image);
    std::ifstream in(statsPath);
    if (!in)
        fail(statsPath.string(),
             "cannot read the stats of " + image.string() + " (needed for its sample count)");
    piece.stats = nlohmann::json::parse(in, nullptr, false);
    if (piece.stats.is_discarded() || !piece.stats.is_object())
        fail(statsPath.string(), "not a pmcr stats JSON object");
    const auto samples = piece.stats.find("samples");
    if (samples == piece.stats.end() || !samples->is_number_unsigned())
        fail(statsPath.string(), "no \"samples\" count");
    const auto width = piece.stats.find("width"), height = piece.stats.find("height");
    if (width == piece.stats.end() || height == piece.stats.end() || *width != piece.image.width ||
        *height != piece.image.height)
        fail(statsPath.string(), "its width and height do not match " + image.string());
    return piece;
}

std::vector<uint32_t> renderSeeds(const nlohmann::json& stats) {
    std::vector<uint32_t> seeds;
    if (auto it = stats.find("seeds"); it != stats.end() && it->is_array()) {
        for (const auto& s : *it)
            if (s.is_number_unsigned())
                seeds.push_back(s.get<uint32_t>());
    } else if (auto seed = stats.find("seed"); seed != stats.end() && seed->is_number_unsigned()) {
        seeds.push_back(seed->get<uint32_t>());
    }
    return seeds;
}

MergedRender mergeRenders(const std::vector<RenderPiece>& pieces) {
    if (pieces.size() < 2)
        throw Error("merge: give at least two images to merge");
    const RenderPiece& first = pieces.front();
    const std::string firstName = first.path.string();

    // Check every piece against the first before any arithmetic.
    std::set<uint32_t> seeds;
    uint64_t totalSamples = 0;
    for (const RenderPiece& p : pieces) {
        const std::string name = p.path.string();
        if (p.image.width != first.image.width || p.image.height != first.image.height)
            fail(name, "is " + std::to_string(p.image.width) + "x" +
                           std::to_string(p.image.height) + " but " + firstName + " is " +
                           std::to_string(first.image.width) + "x" +
                           std::to_string(first.image.height));
        if (sceneName(p.stats) != sceneName(first.stats))
            fail(name, "rendered from scene '" + sceneName(p.stats) + "', " + firstName +
                           " from '" + sceneName(first.stats) + "'");
        for (const char* key : kSameSettings) {
            const nlohmann::json a = p.stats.value(key, nlohmann::json()),
                                 b = first.stats.value(key, nlohmann::json());
            if (a != b)
                fail(name, std::string("rendered with ") + key + " " + jsonText(a) + ", " +
                               firstName + " with " + jsonText(b) +
                               "; merge only renders of the same method and settings");
        }
        const std::vector<uint32_t> pieceSeeds = renderSeeds(p.stats);
        if (pieceSeeds.empty())
            fail(statsPathFor(p.path).string(), "no \"seed\" recorded");
        for (uint32_t s : pieceSeeds)
            if (!seeds.insert(s).second)
                fail(name, "seed " + std::to_string(s) +
                               " is used by another piece too: the renders are not independent "
                               "(render each piece with its own --seed)");
        const uint64_t samples = count(p, "samples");
        if (samples == 0)
            fail(name, "has no samples (its stats record 0)");
        totalSamples += samples;
        if (p.stats.value("pmcr_version", "") != first.stats.value("pmcr_version", ""))
            log::warning(name + ": rendered by pmcr " + p.stats.value("pmcr_version", "?") + ", " +
                         firstName + " by " + first.stats.value("pmcr_version", "?"));
    }

    // The average weighted by sample counts, accumulated in double.
    std::vector<double> sum(first.image.rgb.size(), 0.0);
    for (const RenderPiece& p : pieces) {
        const double w = double(count(p, "samples")) / double(totalSamples);
        for (size_t i = 0; i < sum.size(); ++i)
            sum[i] += w * double(p.image.rgb[i]);
    }
    MergedRender merged;
    merged.image = Image(first.image.width, first.image.height);
    for (size_t i = 0; i < sum.size(); ++i)
        merged.image.rgb[i] = float(sum[i]);

    nlohmann::json& s = merged.stats;
    s = first.stats;
    double renderSeconds = 0.0, samplingSeconds = 0.0;
    StatsTotals totals;
    bool interrupted = false, allTimed = true, oneDevice = true;
    nlohmann::json from = nlohmann::json::array();
    for (const RenderPiece& p : pieces) {
        renderSeconds += number(p, "render_seconds");
        samplingSeconds += number(p, "sampling_seconds");
        allTimed = allTimed && p.stats.contains("sampling_seconds");
        oneDevice = oneDevice && p.stats.value("device", "") == first.stats.value("device", "");
        totals.add(p.stats);
        interrupted = interrupted || p.stats.value("interrupted", false);
        from.push_back({{"image", p.path.string()},
                        {"samples", count(p, "samples")},
                        {"seeds", renderSeeds(p.stats)},
                        {"render_seconds", number(p, "render_seconds")},
                        {"device", p.stats.value("device", "")},
                        {"method_stats", p.stats.value("method_stats", nlohmann::json::object())}});
    }
    const double pixels = double(first.image.pixelCount());
    s.erase("seed");
    s.erase("spp_requested");
    s.erase("time_limit_seconds");
    s.erase("method_stats");
    s["seeds"] = std::vector<uint32_t>(seeds.begin(), seeds.end());
    s["samples"] = totalSamples;
    s["spp"] = double(totalSamples) / pixels;
    s["render_seconds"] = renderSeconds;
    if (allTimed)
        s["sampling_seconds"] = samplingSeconds;
    else
        s.erase("sampling_seconds");
    if (!oneDevice)
        s["device"] = "several (see merged_from)";
    totals.writeTo(s, renderSeconds);
    s["interrupted"] = interrupted;
    s["merged_from"] = from;
    return merged;
}

}  // namespace pmcr
