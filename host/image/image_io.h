// In-memory codecs behind readHdr/writeHdr: OpenEXR (through tinyexr) and PFM. `name` is the
// file the bytes come from or go to; every error is a one-line pmcr::Error naming it.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "image/image.h"

namespace pmcr {

// Single-part scanline OpenEXR, 32-bit float R, G, B channels, ZIP compression (lossless).
std::vector<uint8_t> encodeExr(const Image& image, const std::string& name);
// Any single-part (scanline or tiled) OpenEXR with half, float or uint R, G, B channels; other
// channels (A included) are ignored. Tiled files give their first level.
Image decodeExr(std::span<const uint8_t> bytes, const std::string& name);

// "PF" colour PFM, little-endian (negative scale), rows bottom to top.
std::vector<uint8_t> encodePfm(const Image& image, const std::string& name);
// "PF" colour or "Pf" greyscale PFM of either byte order; pixels are multiplied by |scale|
// when it is not 1.
Image decodePfm(std::span<const uint8_t> bytes, const std::string& name);

}  // namespace pmcr
