#include "scene/texture_lookup.h"

#include <algorithm>
#include <cmath>

namespace pmcr {

namespace {

// Texel coordinate x of a texture n texels wide under wrap mode `mode` (glTF 2.0 sec. 3.8.4.3),
// as wrapTexel in shaders/common/scene.glsl.
int wrapTexel(float x, float n, uint32_t mode) {
    const float repeat = x - n * std::floor(x / n);
    const float period = x - 2.0f * n * std::floor(x / (2.0f * n));
    const float mirror = period < n ? period : 2.0f * n - 1.0f - period;
    return int(mode == gpu::WRAP_CLAMP ? std::clamp(x, 0.0f, n - 1.0f)
               : mode == gpu::WRAP_MIRROR ? mirror
                                          : repeat);
}

float srgbToLinear(float c) {  // IEC 61966-2-1
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

glm::vec4 texel(const Texture& t, float fx, float fy, bool srgb) {
    const int x = wrapTexel(fx, float(t.width), t.wrap & 3u);
    const int y = wrapTexel(fy, float(t.height), t.wrap >> 2);
    const uint32_t v = t.rgba8[size_t(y) * t.width + size_t(x)];
    glm::vec4 c(float(v & 255u), float((v >> 8) & 255u), float((v >> 16) & 255u), float(v >> 24));
    c /= 255.0f;
    if (srgb)
        for (int i = 0; i < 3; ++i) c[i] = srgbToLinear(c[i]);
    return c;
}

}  // namespace

glm::vec4 sampleTexture(const Texture& texture, glm::vec2 uv, bool srgb) {
    const glm::vec2 p = uv * glm::vec2(float(texture.width), float(texture.height)) - 0.5f;
    const float x = std::floor(p.x), y = std::floor(p.y);
    const glm::vec2 f = p - glm::vec2(x, y);
    const glm::vec4 t00 = texel(texture, x, y, srgb), t10 = texel(texture, x + 1.0f, y, srgb);
    const glm::vec4 t01 = texel(texture, x, y + 1.0f, srgb),
                    t11 = texel(texture, x + 1.0f, y + 1.0f, srgb);
    return glm::mix(glm::mix(t00, t10, f.x), glm::mix(t01, t11, f.x), f.y);
}

glm::vec3 meanOverTriangle(const Texture& texture, glm::vec2 uv0, glm::vec2 uv1, glm::vec2 uv2,
                           bool srgb) {
    const glm::vec2 size(float(texture.width), float(texture.height));
    const glm::vec2 a = (uv1 - uv0) * size, b = (uv2 - uv0) * size;
    const double texels = 0.5 * std::abs(double(a.x) * b.y - double(a.y) * b.x);
    const int k = int(std::clamp(std::ceil(std::sqrt(2.0 * texels)), 4.0, 64.0));
    // The k^2 sub-triangles of a regular subdivision have equal areas: k(k+1)/2 upright ones
    // with corners (i, j), (i+1, j), (i, j+1), and k(k-1)/2 inverted ones.
    glm::dvec3 sum(0.0);
    auto add = [&](double s, double t) {  // barycentrics (s, t) of uv1 and uv2
        const glm::vec2 uv = uv0 + float(s) * (uv1 - uv0) + float(t) * (uv2 - uv0);
        sum += glm::dvec3(glm::vec3(sampleTexture(texture, uv, srgb)));
    };
    for (int i = 0; i < k; ++i)
        for (int j = 0; i + j < k; ++j) {
            add((i + 1.0 / 3.0) / k, (j + 1.0 / 3.0) / k);
            if (i + j + 1 < k) add((i + 2.0 / 3.0) / k, (j + 2.0 / 3.0) / k);
        }
    return glm::vec3(sum / double(k * k));
}

}  // namespace pmcr
