#include "cli/compare_command.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "image/colormap.h"
#include "metrics/metrics.h"
#include "render/stats.h"

namespace pmcr::cli {

namespace {

namespace fs = std::filesystem;

nlohmann::json finiteOrNull(double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

// The render time recorded beside an image: its stats' "sampling_seconds" (the render clock),
// else "render_seconds". Sets `source` to the stats file when found.
std::optional<double> recordedTime(const fs::path& image, std::string& source) {
    const fs::path statsPath = statsPathFor(image);
    std::error_code ec;
    if (!fs::exists(statsPath, ec))
        return std::nullopt;
    std::ifstream in(statsPath);
    const nlohmann::json stats = nlohmann::json::parse(in, nullptr, false);
    if (stats.is_discarded() || !stats.is_object())
        fail(statsPath.string(), "not a pmcr stats JSON object (or give --time)");
    for (const char* key : {"sampling_seconds", "render_seconds"}) {
        if (auto it = stats.find(key);
            it != stats.end() && it->is_number() && it->get<double>() > 0.0) {
            source = statsPath.string() + " " + key;
            return it->get<double>();
        }
    }
    return std::nullopt;
}

}  // namespace

void printCompareHelp() {
    std::printf(
        "usage: pmcr compare IMAGE REFERENCE [options]\n"
        "\n"
        "Measures IMAGE against REFERENCE (EXR or PFM, the same size) with the papers' metrics:\n"
        "  Err     luminance MSE: mean over pixels of e^2, e = Y - Y_ref (Rec. 709 luminance)\n"
        "  MSE RGB the same per channel\n"
        "  RMSE    sqrt(Err)\n"
        "  relMSE  mean over pixels and channels of (v - r)^2 / (r + 0.01)^2 (pbrt-v4's MRSE)\n"
        "  P-Err   mean of e^2 / tvi(Y_ref), Fan et al.'s perceptual Err with Ferwerda et al.\n"
        "          1996's threshold-versus-intensity\n"
        "  Eff     1 / (T Err) and P-Eff 1 / (T P-Err), when the render time T is known\n"
        "\n"
        "options:\n"
        "  --time SECONDS       render time T (default: \"sampling_seconds\" from the stats JSON\n"
        "                       beside IMAGE, else its \"render_seconds\"; none: no Eff)\n"
        "  --crop x,y,w,h       measure only this rectangle (top-left x, y; width, height)\n"
        "  --error-image FILE   write |e| in false colour (viridis) as a PNG (of the crop, if "
        "any)\n"
        "  --error-max V        |e| shown as full scale (default: the 99th percentile)\n"
        "  --display-white CD   cd/m^2 that pixel luminance 1 stands for in tvi (default %g)\n"
        "  --json               print one JSON object: mse, mse_rgb, rmse, relmse, pmse, region,\n"
        "                       display_white and, with a time, time, eff, peff\n",
        kDefaultDisplayWhite);
}

int runCompare(Args& args) {
    std::vector<fs::path> files;
    MetricOptions options;
    std::optional<double> time;
    std::optional<fs::path> errorImage;
    std::optional<double> errorMax;
    bool json = false;
    while (!args.done()) {
        const std::string a = args.next();
        if (a == "--time")
            time = parseDouble(a, args.value(a), 1e-9, 1e9);
        else if (a == "--crop") {
            options.cropped = true;
            options.crop = parsePixelRect(a, args.value(a));
        } else if (a == "--error-image")
            errorImage = args.value(a);
        else if (a == "--error-max")
            errorMax = parseDouble(a, args.value(a), 1e-30, 1e30);
        else if (a == "--display-white")
            options.displayWhite = parseDouble(a, args.value(a), 1e-6, 1e9);
        else if (a == "--json")
            json = true;
        else if (a.rfind("-", 0) == 0 && a.size() > 1)
            throw Error(a + ": unknown option for compare");
        else
            files.emplace_back(a);
    }
    if (files.size() != 2)
        throw Error("compare: expected IMAGE REFERENCE, got " + std::to_string(files.size()) +
                    " file(s) (see pmcr compare --help)");
    if (errorImage && errorImage->extension() != ".png")
        fail(errorImage->string(), "--error-image must end in .png");
    const Image image = readHdr(files[0]);
    const Image reference = readHdr(files[1]);
    options.imageName = files[0].string();
    options.referenceName = files[1].string();
    const ErrorMetrics m = measureError(image, reference, options);
    std::string timeSource = "--time";
    if (!time)
        time = recordedTime(files[0], timeSource);

    if (errorImage) {
        const PixelRect& r = m.region;
        const Image a = crop(image, r.x, r.y, r.width, r.height);
        const Image b = crop(reference, r.x, r.y, r.width, r.height);
        MetricOptions names = options;
        names.cropped = false;
        const std::vector<float> map = luminanceErrorMap(a, b, names);
        float scale = errorMax ? float(*errorMax) : quantile(map, 0.99);
        if (!(scale > 0.0f))
            scale = 1.0f;
        writePng(*errorImage, falseColor(map, r.width, r.height, scale));
    }

    if (json) {
        nlohmann::json j = {{"image", files[0].string()},
                            {"reference", files[1].string()},
                            {"region",
                             {{"x", m.region.x},
                              {"y", m.region.y},
                              {"width", m.region.width},
                              {"height", m.region.height}}},
                            {"mse", m.mse},
                            {"mse_rgb", {m.mseRgb.r, m.mseRgb.g, m.mseRgb.b}},
                            {"rmse", m.rmse},
                            {"relmse", m.relmse},
                            {"pmse", m.pmse},
                            {"display_white", options.displayWhite}};
        if (time) {
            j["time"] = *time;
            j["time_source"] = timeSource;
            j["eff"] = finiteOrNull(efficiency(*time, m.mse));
            j["peff"] = finiteOrNull(efficiency(*time, m.pmse));
        }
        std::printf("%s\n", j.dump(2).c_str());
        return 0;
    }
    std::printf("image       %s\n", files[0].string().c_str());
    std::printf("reference   %s\n", files[1].string().c_str());
    std::printf("region      %dx%d at (%d, %d)%s\n", m.region.width, m.region.height, m.region.x,
                m.region.y, options.cropped ? "" : " (whole image)");
    std::printf("Err         %.6e  (luminance MSE)\n", m.mse);
    std::printf("MSE R G B   %.6e %.6e %.6e\n", m.mseRgb.r, m.mseRgb.g, m.mseRgb.b);
    std::printf("RMSE        %.6e\n", m.rmse);
    std::printf("relMSE      %.6e\n", m.relmse);
    std::printf("P-Err       %.6e  (display white %g cd/m^2)\n", m.pmse, options.displayWhite);
    if (time) {
        std::printf("time        %.4g s  (%s)\n", *time, timeSource.c_str());
        std::printf("Eff         %.6g\n", efficiency(*time, m.mse));
        std::printf("P-Eff       %.6g\n", efficiency(*time, m.pmse));
    } else {
        std::printf("time        unknown (no stats JSON beside the image; give --time for Eff)\n");
    }
    if (errorImage)
        std::printf("wrote       %s\n", errorImage->string().c_str());
    return 0;
}

}  // namespace pmcr::cli
