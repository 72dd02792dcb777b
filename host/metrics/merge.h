// `pmcr merge`: building one render from independent pieces (a long reference rendered in parts,
// on several machines or after an interruption). Each piece is an image with its stats JSON
// beside it (render/stats.h); the merged image is the average of the pieces weighted by their
// sample counts, w_i = n_i / sum_j n_j.
//
// For the per-pixel-average estimators (pt, direct, PMC-IP) a piece's image is the mean of its
// n_i samples per pixel, so the weighted average is exactly the mean of all samples. For the
// splatting methods (erpt, pmc-er) a piece is an unbiased estimate whose variance falls as 1/n_i
// with n_i its path-traced seed samples, so the same weights are the right ones for them too.
//
// Merging is refused unless the pieces are renders of the same scene and camera by the same
// method with the same settings, with different seeds: pieces that share a seed are not
// independent, and averaging them would claim samples the image does not have.
#pragma once

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "image/image.h"

namespace pmcr {

struct RenderPiece {
    std::filesystem::path path;  // the image file
    Image image;
    nlohmann::json stats;  // its stats JSON
};

// Reads an image and the stats JSON beside it; throws pmcr::Error naming the file at fault.
RenderPiece readRenderPiece(const std::filesystem::path& image);

// The seeds a render used: its "seed", or for a merged render its "seeds".
std::vector<uint32_t> renderSeeds(const nlohmann::json& stats);

struct MergedRender {
    Image image;
    nlohmann::json stats;  // the first piece's, with counts and times summed, "seeds" and
                           // "merged_from" (one entry per piece) added and "seed" removed
};

// Throws pmcr::Error naming the piece at fault when the pieces cannot be merged (fewer than two,
// different sizes, scenes, methods or settings, a shared seed, no samples).
MergedRender mergeRenders(const std::vector<RenderPiece>& pieces);

}  // namespace pmcr
