// `pmcr merge` (metrics/merge.h) on small synthetic pieces written to disk with their stats.
#include <gtest/gtest.h>

#include "core/error.h"
#include "metrics/merge.h"
#include "render/stats.h"
#include "test_util.h"

namespace pmcr {
namespace {

nlohmann::json pieceStats(uint32_t seed, uint64_t samples, int width, int height) {
    return {{"pmcr_version", "test"},
            {"method", "pt"},
            {"scene", "scenes/box.glb"},
            {"camera", 0},
            {"max_depth", 16},
            {"rr_depth", 3},
            {"options", nlohmann::json::object()},
            {"seed", seed},
            {"samples", samples},
            {"width", width},
            {"height", height},
            {"render_seconds", 2.0},
            {"sampling_seconds", 1.5},
            {"rays", 100},
            {"nan_samples_dropped", 1},
            {"gpu_kernels", {{"pt", {{"milliseconds", 10.0}, {"dispatches", 2}}}}},
            {"gpu_milliseconds", 10.0}};
}

std::filesystem::path writePiece(const std::filesystem::path& dir, const std::string& name,
                                 const Image& image, const nlohmann::json& stats) {
    const auto path = dir / (name + ".exr");
    writeHdr(path, image);
    writeJsonAtomically(statsPathFor(path), stats);
    return path;
}

Image filled(int width, int height, float base) {
    Image image(width, height);
    for (size_t i = 0; i < image.rgb.size(); ++i)
        image.rgb[i] = base + 0.125f * float(i);
    return image;
}

std::string mergeError(const std::vector<std::filesystem::path>& paths) {
    try {
        std::vector<RenderPiece> pieces;
        for (const auto& p : paths)
            pieces.push_back(readRenderPiece(p));
        mergeRenders(pieces);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

// Pieces of 1 and 3 samples per pixel: weights 1/4 and 3/4, counts and times summed.
TEST(Merge, WeightsBySampleCounts) {
    const auto dir = test::tempDir("merge-weights");
    const Image a = filled(2, 1, 1.0f), b = filled(2, 1, 5.0f);
    const auto pa = writePiece(dir, "a", a, pieceStats(1, 2, 2, 1));
    const auto pb = writePiece(dir, "b", b, pieceStats(2, 6, 2, 1));
    const MergedRender m = mergeRenders({readRenderPiece(pa), readRenderPiece(pb)});
    ASSERT_EQ(m.image.rgb.size(), a.rgb.size());
    for (size_t i = 0; i < a.rgb.size(); ++i)
        EXPECT_FLOAT_EQ(m.image.rgb[i], 0.25f * a.rgb[i] + 0.75f * b.rgb[i]) << i;
    EXPECT_EQ(m.stats["samples"], 8u);
    EXPECT_DOUBLE_EQ(m.stats["spp"].get<double>(), 4.0);
    EXPECT_DOUBLE_EQ(m.stats["render_seconds"].get<double>(), 4.0);
    EXPECT_DOUBLE_EQ(m.stats["sampling_seconds"].get<double>(), 3.0);
    EXPECT_EQ(m.stats["rays"], 200u);
    EXPECT_EQ(m.stats["nan_samples_dropped"], 2u);
    EXPECT_EQ(m.stats["gpu_kernels"]["pt"]["dispatches"], 4u);
    EXPECT_EQ(m.stats["seeds"], nlohmann::json({1, 2}));
    EXPECT_FALSE(m.stats.contains("seed"));
    ASSERT_EQ(m.stats["merged_from"].size(), 2u);
    EXPECT_EQ(m.stats["merged_from"][1]["samples"], 6u);
}

// A merged render merges again: its seeds and total sample count carry over.
TEST(Merge, MergedPiecesMergeAgain) {
    const auto dir = test::tempDir("merge-nested");
    const Image a = filled(1, 1, 1.0f), b = filled(1, 1, 2.0f), c = filled(1, 1, 6.0f);
    const auto pa = writePiece(dir, "a", a, pieceStats(1, 1, 1, 1));
    const auto pb = writePiece(dir, "b", b, pieceStats(2, 1, 1, 1));
    const auto pc = writePiece(dir, "c", c, pieceStats(3, 2, 1, 1));
    const MergedRender ab = mergeRenders({readRenderPiece(pa), readRenderPiece(pb)});
    const auto pab = writePiece(dir, "ab", ab.image, ab.stats);
    const MergedRender abc = mergeRenders({readRenderPiece(pab), readRenderPiece(pc)});
    // (1 * a + 1 * b + 2 * c) / 4, whichever way it is merged.
    for (size_t i = 0; i < 3; ++i)
        EXPECT_FLOAT_EQ(abc.image.rgb[i], (a.rgb[i] + b.rgb[i] + 2.0f * c.rgb[i]) / 4.0f);
    EXPECT_EQ(abc.stats["seeds"], nlohmann::json({1, 2, 3}));
    EXPECT_EQ(abc.stats["samples"], 4u);
    // The merged piece still carries seed 1: merging it with a again is refused.
    EXPECT_NE(mergeError({pab, pa}).find("seed 1"), std::string::npos);
}

TEST(Merge, RefusesPiecesThatAreNotIndependentRendersOfTheSameThing) {
    const auto dir = test::tempDir("merge-refuse");
    const auto a = writePiece(dir, "a", filled(2, 2, 1.0f), pieceStats(1, 4, 2, 2));
    const auto sameSeed = writePiece(dir, "same-seed", filled(2, 2, 1.0f), pieceStats(1, 4, 2, 2));
    auto directStats = pieceStats(2, 4, 2, 2);
    directStats["method"] = "direct";
    const auto direct = writePiece(dir, "direct", filled(2, 2, 1.0f), directStats);
    auto depthStats = pieceStats(3, 4, 2, 2);
    depthStats["max_depth"] = 4;
    const auto depth = writePiece(dir, "depth", filled(2, 2, 1.0f), depthStats);
    auto sceneStats = pieceStats(4, 4, 2, 2);
    sceneStats["scene"] = "scenes/other.glb";
    const auto scene = writePiece(dir, "scene", filled(2, 2, 1.0f), sceneStats);
    const auto small = writePiece(dir, "small", filled(1, 1, 1.0f), pieceStats(5, 4, 1, 1));
    const auto empty = writePiece(dir, "empty", filled(2, 2, 1.0f), pieceStats(6, 0, 2, 2));
    writeHdr(dir / "nostats.exr", filled(2, 2, 1.0f));

    const std::string seed = mergeError({a, sameSeed});
    EXPECT_NE(seed.find("same-seed.exr: seed 1"), std::string::npos) << seed;
    EXPECT_NE(mergeError({a, direct}).find("direct.exr: rendered with method \"direct\""),
              std::string::npos)
        << mergeError({a, direct});
    EXPECT_NE(mergeError({a, depth}).find("max_depth 4"), std::string::npos);
    EXPECT_NE(mergeError({a, scene}).find("other.glb"), std::string::npos);
    EXPECT_NE(mergeError({a, small}).find("small.exr: is 1x1"), std::string::npos);
    EXPECT_NE(mergeError({a, empty}).find("no samples"), std::string::npos);
    const std::string noStats = mergeError({a, dir / "nostats.exr"});
    EXPECT_NE(noStats.find("nostats.json: cannot read"), std::string::npos) << noStats;
    EXPECT_NE(mergeError({a}).find("at least two"), std::string::npos);
    for (const auto& message : {seed, noStats})
        EXPECT_EQ(message.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace pmcr
