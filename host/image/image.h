// A linear RGB float image and its file formats: OpenEXR (tinyexr, 32-bit float), PFM, and
// tonemapped 8-bit sRGB PNG (stb_image_write). Rows are stored top row first.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

namespace pmcr {

struct Image {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;  // 3 floats per pixel, row-major, top row first

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0.0f) {}
    glm::vec3 at(int x, int y) const {
        const float* p = &rgb[(size_t(y) * width + x) * 3];
        return {p[0], p[1], p[2]};
    }
    void set(int x, int y, const glm::vec3& v) {
        float* p = &rgb[(size_t(y) * width + x) * 3];
        p[0] = v.x;
        p[1] = v.y;
        p[2] = v.z;
    }
    size_t pixelCount() const { return size_t(width) * size_t(height); }
};

// Writes `path` atomically: `write` produces a temporary file beside it, which is renamed over
// `path` only once complete. On any failure the temporary is removed and pmcr::Error thrown.
void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path& tmp)>& write);

// HDR output by extension (.exr or .pfm), written atomically.
void writeHdr(const std::filesystem::path& path, const Image& image);
// HDR input (.exr or .pfm); throws pmcr::Error naming the file on any problem.
Image readHdr(const std::filesystem::path& path);

// 8-bit sRGB PNG of image * 2^exposure, clamped to [0,1], written atomically.
// NaN and infinite pixel components are written as 0.
void writePng(const std::filesystem::path& path, const Image& image, float exposure = 0.0f);

// The sRGB OETF (IEC 61966-2-1) for a linear value in [0,1].
float srgbEncode(float linear);
// The 8-bit sRGB pixels writePng stores: 3 bytes per pixel, top row first.
std::vector<uint8_t> toSrgb8(const Image& image, float exposure);

// The w x h rectangle of `image` whose top-left pixel is (x, y); throws pmcr::Error unless the
// rectangle is non-empty and lies inside the image.
Image crop(const Image& image, int x, int y, int w, int h);

}  // namespace pmcr
