#include "scene/environment.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <numbers>

#include <stb_image.h>  // Radiance .hdr (the implementation is compiled in gltf_loader.cpp)

#include "core/decimal.h"
#include "core/error.h"
#include "core/paths.h"

namespace pmcr {

namespace {

// "R,G,B" as three decimal numbers (core/decimal.h: "0x10,1,1" is not 16,1,1), or false when
// `text` is not of that form.
bool parseTriple(const std::string& text, glm::vec3& out) {
    size_t at = 0;
    for (int i = 0; i < 3; ++i) {
        const size_t comma = i < 2 ? text.find(',', at) : text.size();
        if (comma == std::string::npos) return false;
        const std::string field = text.substr(at, comma - at);
        if (!isDecimalNumber(field)) return false;
        out[i] = float(std::strtod(field.c_str(), nullptr));
        at = comma + 1;
    }
    return true;
}

bool allFinite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// --env-scale as the user wrote it, near enough ("1e+30", not 31 digits).
std::string scaleText(float scale) {
    char text[32];
    std::snprintf(text, sizeof(text), "%g", double(scale));
    return text;
}

Image readRadianceHdr(const std::filesystem::path& path) {
    int w = 0, h = 0, channels = 0;
    std::unique_ptr<float, void (*)(void*)> data(
        stbi_loadf(path.string().c_str(), &w, &h, &channels, 3), stbi_image_free);
    if (!data) {
        if (!std::filesystem::exists(path)) fail(path.string(), "no such file");
        fail(path.string(), std::string("cannot read the Radiance HDR image: ") + stbi_failure_reason());
    }
    Image image(w, h);
    std::copy(data.get(), data.get() + image.rgb.size(), image.rgb.begin());
    return image;
}

}  // namespace

Environment loadEnvironment(const EnvironmentSpec& spec, const std::filesystem::path& folder) {
    Environment env;
    if (spec.value.empty()) return env;
    env.source = spec.value;
    if (!std::isfinite(spec.scale) || spec.scale < 0.0f) fail(spec.value, "--env-scale must be >= 0");
    env.scale = spec.scale;
    env.rotation = glm::radians(spec.rotateDegrees);
    glm::vec3 constant;
    if (parseTriple(spec.value, constant)) {
        if (!allFinite(constant) || glm::any(glm::lessThan(constant, glm::vec3(0.0f))))
            fail(spec.value, "environment radiance must be finite and >= 0");
        env.kind = gpu::ENV_CONSTANT;
        env.radiance = constant * spec.scale;
        if (!allFinite(env.radiance))
            fail(spec.value, "environment radiance overflows 32-bit floats when scaled by "
                             "--env-scale " + scaleText(spec.scale));
        return env;
    }
    const std::filesystem::path path(spec.value);
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".exr" && ext != ".pfm" && ext != ".hdr")
        fail(spec.value,
             "--env expects R,G,B (three decimal numbers) or an .exr, .pfm or .hdr image");
    if (!folder.empty() && !isInsideFolder(path, folder))
        fail(spec.value, "the environment image leaves the scene's folder (--restrict-paths)");
    env.image = ext == ".hdr" ? readRadianceHdr(path) : readHdr(path);
    if (env.image.width < 1 || env.image.height < 1) fail(spec.value, "empty image");
    if (uint64_t(env.image.width) * uint64_t(env.image.height) > (1u << 26))
        fail(spec.value, "environment image too large (more than 2^26 pixels)");
    float brightest = 0.0f;
    for (float v : env.image.rgb) {
        if (!std::isfinite(v) || v < 0.0f) fail(spec.value, "environment image has negative, NaN or infinite pixels");
        brightest = std::max(brightest, v);
    }
    // The kernels scale each pixel by --env-scale in 32-bit floats.
    if (!std::isfinite(brightest * spec.scale))
        fail(spec.value, "environment radiance overflows 32-bit floats when scaled by "
                         "--env-scale " + scaleText(spec.scale));
    env.kind = gpu::ENV_IMAGE;
    return env;
}

std::vector<gpu::Emitter> environmentAliasTable(const Environment& env) {
    if (env.kind != gpu::ENV_IMAGE) return {};
    const int w = env.image.width, h = env.image.height;
    std::vector<double> weight(size_t(w) * size_t(h));
    double total = 0.0;
    for (int y = 0; y < h; ++y) {
        const double sinTheta = std::sin(std::numbers::pi * (double(y) + 0.5) / double(h));
        for (int x = 0; x < w; ++x) {
            const double wgt = double(luminance(env.image.at(x, y))) * sinTheta;
            weight[size_t(y) * w + x] = wgt;
            total += wgt;
        }
    }
    // An all-black image is sampled uniformly: every sample then carries zero radiance.
    if (!(total > 0.0)) std::fill(weight.begin(), weight.end(), 1.0);
    std::vector<gpu::Emitter> table(weight.size());
    buildAliasTable(weight, table.data());
    for (size_t i = 0; i < table.size(); ++i) table[i].triangle = uint32_t(i);
    return table;
}

double environmentPower(const Environment& env, float sceneRadius) {
    // The integral of luminance over the sphere of directions.
    double integral = 0.0;
    if (env.kind == gpu::ENV_CONSTANT) {
        integral = 4.0 * std::numbers::pi * double(luminance(env.radiance));
    } else if (env.kind == gpu::ENV_IMAGE) {
        const int w = env.image.width, h = env.image.height;
        // Each pixel spans (2 pi / w) (pi / h) in (phi, theta), sin theta at its centre row.
        const double pixelArea = 2.0 * std::numbers::pi * std::numbers::pi / (double(w) * double(h));
        for (int y = 0; y < h; ++y) {
            const double sinTheta = std::sin(std::numbers::pi * (double(y) + 0.5) / double(h));
            for (int x = 0; x < w; ++x) integral += double(luminance(env.image.at(x, y))) * sinTheta * pixelArea;
        }
        integral *= double(env.scale);
    }
    const double r = std::max(double(sceneRadius), 1e-6);
    return std::numbers::pi * r * r * integral;
}

}  // namespace pmcr
