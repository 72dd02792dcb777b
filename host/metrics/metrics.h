// Error and efficiency metrics of an image against a reference, as the papers report them
// (Lai et al., "Photorealistic Image Rendering with Population Monte Carlo Energy
// Redistribution", results section; Fan et al., "Population Monte Carlo Samplers for Rendering",
// sec. 4.4):
//
//   Err    = mean over pixels of e^2, e = Y - Y_ref, the difference in luminance (Rec. 709 Y, the
//            papers' "intensity") between the image and the reference: the luminance MSE
//   MSE_c  = the same per channel c in {R, G, B}
//   RMSE   = sqrt(Err)
//   relMSE = mean over pixels and channels of (v - r)^2 / (r + 0.01)^2: pbrt-v4's MRSE
//            (Image::MRSE, `imgtool diff --metric MRSE`), with pbrt-v4's epsilon 0.01
//   P-Err  = mean over pixels of e^2 / tvi(Y_ref): the perceptual Err of Fan et al. sec. 4.4, e
//            the luminance difference, tvi Ferwerda et al. 1996's threshold (image/tvi.h) in pixel
//            units, pixel luminance 1 read as `displayWhite` cd/m^2
//   Eff    = 1 / (T * Err), P-Eff = 1 / (T * P-Err), T the render time in seconds: how much
//            longer one method needs to reach another's error (Pharr and Humphreys 2004)
//
// Fan et al. write the perceptual Err as a sum over pixels; pmcr reports means (as Lai et al. do
// for Err), so that a figure does not depend on the image size. Ratios between methods on the
// same image are the same either way.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "image/image.h"
#include "image/tvi.h"

namespace pmcr {

// A rectangle of pixels: top-left corner (x, y), size width x height.
struct PixelRect {
    int x = 0;
    int y = 0;
    int width = 0;
    int height = 0;
    bool operator==(const PixelRect&) const = default;
};

// "x,y,w,h" -> PixelRect; throws pmcr::Error naming `option` unless four integers with w, h > 0.
PixelRect parsePixelRect(const std::string& option, const std::string& text);
std::string toString(const PixelRect& rect);  // "x,y,w,h"

// relMSE's epsilon (pbrt-v4 Image::MRSE).
constexpr double kRelMseEpsilon = 0.01;

struct ErrorMetrics {
    PixelRect region;        // the pixels measured (the whole image unless cropped)
    double mse = 0.0;        // Err: luminance MSE
    glm::dvec3 mseRgb{0.0};  // per-channel MSE
    double rmse = 0.0;
    double relmse = 0.0;
    double pmse = 0.0;  // P-Err
};

struct MetricOptions {
    bool cropped = false;
    PixelRect crop;                              // used when `cropped`
    double displayWhite = kDefaultDisplayWhite;  // cd/m^2 of pixel luminance 1 (image/tvi.h)
    std::string imageName = "image";             // file names for error messages
    std::string referenceName = "reference";
};

// Rec. ITU-R BT.709 relative luminance (as pmcr::luminance in scene/scene.h), in double.
double luminance709(const glm::vec3& rgb);

// Throws pmcr::Error naming the files when the sizes differ or the crop is outside the image,
// when the image has a non-finite value, or when the reference has a negative or non-finite value
// (a reference is a converged render: finite and non-negative).
ErrorMetrics measureError(const Image& image, const Image& reference,
                          const MetricOptions& options = {});

// Eff = 1 / (T * err); +infinity for a zero error, 0 when T is not positive.
double efficiency(double seconds, double err);

// Per-pixel luminance error |Y - Y_ref| over the whole image (for error images); the inputs are
// checked as by measureError.
std::vector<float> luminanceErrorMap(const Image& image, const Image& reference,
                                     const MetricOptions& options = {});

// The q-quantile (q in [0, 1]) of `values` (nearest rank; 0 for no values).
float quantile(std::vector<float> values, double q);

}  // namespace pmcr
