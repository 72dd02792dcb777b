#include "metrics/metrics.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/decimal.h"
#include "core/error.h"

namespace pmcr {

namespace {

std::string sizeText(const Image& image) {
    return std::to_string(image.width) + "x" + std::to_string(image.height);
}

std::string pixelText(size_t index, int width) {
    std::string text = std::to_string(index % size_t(width));
    text.append(", ").append(std::to_string(index / size_t(width)));
    return std::string("(").append(text).append(")");
}

// Checks what every metric needs of the two images; returns the region to measure.
PixelRect checkInputs(const Image& image, const Image& reference, const MetricOptions& o) {
    if (image.width != reference.width || image.height != reference.height)
        fail(o.imageName, "is " + sizeText(image) + " but the reference " + o.referenceName +
                              " is " + sizeText(reference) + "; compare images of the same size");
    if (image.pixelCount() == 0)
        fail(o.imageName, "empty image");
    for (size_t i = 0; i < image.rgb.size(); ++i) {
        if (!std::isfinite(image.rgb[i]))
            fail(o.imageName, "pixel " + pixelText(i / 3, image.width) +
                                  " is not finite; the error is undefined");
        const float r = reference.rgb[i];
        if (!std::isfinite(r) || r < 0.0f)
            fail(o.referenceName, "pixel " + pixelText(i / 3, image.width) + " is " +
                                      (r < 0.0f ? "negative" : "not finite") +
                                      "; a reference must be finite and non-negative");
    }
    PixelRect region{0, 0, image.width, image.height};
    if (o.cropped) {
        const PixelRect& c = o.crop;
        if (c.width <= 0 || c.height <= 0 || c.x < 0 || c.y < 0 ||
            int64_t(c.x) + c.width > image.width || int64_t(c.y) + c.height > image.height)
            fail(o.imageName,
                 "crop " + toString(c) + " is empty or outside the " + sizeText(image) + " image");
        region = c;
    }
    return region;
}

}  // namespace

PixelRect parsePixelRect(const std::string& option, const std::string& text) {
    PixelRect r;
    int* fields[4] = {&r.x, &r.y, &r.width, &r.height};
    size_t at = 0;
    for (int i = 0; i < 4; ++i) {
        // Each field decimal digits only (core/decimal.h), as every number on the command line.
        const size_t comma = i < 3 ? text.find(',', at) : text.size();
        const std::string field = comma == std::string::npos ? "" : text.substr(at, comma - at);
        errno = 0;
        const bool decimal = isDecimalInteger(field);
        const long long v = decimal ? std::strtoll(field.c_str(), nullptr, 10) : -1;
        if (!decimal || errno == ERANGE || v < 0 || v > (1 << 20))
            throw Error(option + ": expected x,y,width,height (four non-negative integers), got '" +
                        text + "'");
        *fields[i] = int(v);
        at = comma + 1;
    }
    if (r.width == 0 || r.height == 0)
        throw Error(option + ": empty rectangle '" + text + "'");
    return r;
}

std::string toString(const PixelRect& r) {
    return std::to_string(r.x) + "," + std::to_string(r.y) + "," + std::to_string(r.width) + "," +
           std::to_string(r.height);
}

double luminance709(const glm::vec3& rgb) {
    // Rec. ITU-R BT.709 relative luminance.
    return 0.2126 * double(rgb.r) + 0.7152 * double(rgb.g) + 0.0722 * double(rgb.b);
}

ErrorMetrics measureError(const Image& image, const Image& reference,
                          const MetricOptions& options) {
    ErrorMetrics m;
    m.region = checkInputs(image, reference, options);
    const PixelRect& r = m.region;
    double sumSq = 0.0, sumRel = 0.0, sumPerceptual = 0.0;
    glm::dvec3 sumSqRgb(0.0);
    for (int y = r.y; y < r.y + r.height; ++y) {
        for (int x = r.x; x < r.x + r.width; ++x) {
            const glm::vec3 v = image.at(x, y), ref = reference.at(x, y);
            const double yRef = luminance709(ref);
            const double e = luminance709(v) - yRef;
            sumSq += e * e;
            // Fan et al. sec. 4.4: e^2 / tvi(L) with L the reference's luminance.
            sumPerceptual += e * e / tvi(yRef, options.displayWhite);
            for (int c = 0; c < 3; ++c) {
                const double d = double(v[c]) - double(ref[c]);
                sumSqRgb[c] += d * d;
                // pbrt-v4 Image::MRSE.
                const double denominator = double(ref[c]) + kRelMseEpsilon;
                sumRel += d * d / (denominator * denominator);
            }
        }
    }
    const double n = double(r.width) * double(r.height);
    m.mse = sumSq / n;
    m.mseRgb = sumSqRgb / n;
    m.rmse = std::sqrt(m.mse);
    m.relmse = sumRel / (3.0 * n);
    m.pmse = sumPerceptual / n;
    return m;
}

double efficiency(double seconds, double err) {
    if (!(seconds > 0.0))
        return 0.0;
    if (err <= 0.0)
        return std::numeric_limits<double>::infinity();
    return 1.0 / (seconds * err);
}

std::vector<float> luminanceErrorMap(const Image& image, const Image& reference,
                                     const MetricOptions& options) {
    checkInputs(image, reference, options);
    std::vector<float> map(image.pixelCount());
    for (size_t i = 0; i < map.size(); ++i) {
        const glm::vec3 v(image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2]);
        const glm::vec3 ref(reference.rgb[3 * i], reference.rgb[3 * i + 1],
                            reference.rgb[3 * i + 2]);
        map[i] = float(std::abs(luminance709(v) - luminance709(ref)));
    }
    return map;
}

float quantile(std::vector<float> values, double q) {
    if (values.empty())
        return 0.0f;
    // Nearest rank (1-based): ceil(q n).
    const double rank = std::ceil(std::clamp(q, 0.0, 1.0) * double(values.size()));
    const size_t k = rank < 1.0 ? 0 : std::min(values.size() - 1, size_t(rank) - 1);
    std::nth_element(values.begin(), values.begin() + ptrdiff_t(k), values.end());
    return values[k];
}

}  // namespace pmcr
