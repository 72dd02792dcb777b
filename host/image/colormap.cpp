#include "image/colormap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>

#include "core/error.h"

namespace pmcr {

namespace {

// matplotlib's viridis (van der Walt & Smith, 2015) sampled at nine evenly spaced points, as
// 8-bit sRGB (the palette viridis(9) of the R package viridisLite).
constexpr std::array<uint32_t, 9> kViridis = {0x440154, 0x472D7B, 0x3B528B, 0x2C728E, 0x21908C,
                                              0x27AD81, 0x5DC863, 0xAADC32, 0xFDE725};

glm::vec3 controlPoint(size_t i) {
    const uint32_t c = kViridis[i];
    return glm::vec3(float((c >> 16) & 0xff), float((c >> 8) & 0xff), float(c & 0xff)) / 255.0f;
}

// Inverse of the sRGB OETF, IEC 61966-2-1:1999 section 5.2.
float srgbDecode(float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

}  // namespace

glm::vec3 viridis(float t) {
    t = t > 0.0f ? std::min(t, 1.0f) : 0.0f;
    // Interpolate linearly in sRGB between control points, then convert to linear RGB.
    const float u = t * float(kViridis.size() - 1);
    const size_t i = std::min(size_t(u), kViridis.size() - 2);
    const glm::vec3 srgb = glm::mix(controlPoint(i), controlPoint(i + 1), u - float(i));
    return {srgbDecode(srgb.r), srgbDecode(srgb.g), srgbDecode(srgb.b)};
}

Image falseColor(const std::vector<float>& values, int width, int height, float maxValue) {
    if (width < 0 || height < 0 || values.size() != size_t(width) * size_t(height)) {
        throw Error("falseColor: " + std::to_string(values.size()) + " values for a " +
                    std::to_string(width) + "x" + std::to_string(height) + " image");
    }
    if (!(maxValue > 0.0f) || !std::isfinite(maxValue)) {
        throw Error("falseColor: maximum value " + std::to_string(maxValue) +
                    " is not positive and finite");
    }
    Image image(width, height);
    for (size_t i = 0; i < values.size(); ++i) {
        const glm::vec3 c = viridis(values[i] / maxValue);
        image.rgb[3 * i + 0] = c.r;
        image.rgb[3 * i + 1] = c.g;
        image.rgb[3 * i + 2] = c.b;
    }
    return image;
}

}  // namespace pmcr
