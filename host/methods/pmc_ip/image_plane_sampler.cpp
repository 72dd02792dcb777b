#include "methods/pmc_ip/image_plane_sampler.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/parallel.h"
#include "image/tvi.h"
#include "scene/scene.h"

namespace pmcr {

namespace {

// The mean of v over the neighbours of (x, y) within `radius` (a square, the pixel itself
// excluded) inside the image, and how many there are.
std::pair<double, int> neighbourMean(const std::vector<double>& v, int width, int height, int x, int y,
                                     int radius) {
    double sum = 0.0;
    int n = 0;
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
            sum += v[size_t(ny) * width + nx];
            ++n;
        }
    return {n > 0 ? sum / n : 0.0, n};
}

double sampleVariance(double sum, double sumSq, double n) {
    if (n < 2.0) return 0.0;
    const double mean = sum / n;
    return std::max(0.0, (sumSq - n * mean * mean) / (n - 1.0));
}

}  // namespace

std::vector<double> neighbourMixtureWeights(const std::vector<double>& v, int width, int height,
                                            double epsilon, int radius) {
    const size_t pixels = size_t(width) * size_t(height);
    constexpr size_t kRowsPerBlock = 8;  // the rows of the image go to the cores in these blocks
    // a_j = mean of v over j's neighbours, alpha'_j = sqrt(a_j), Z = sum alpha'.
    std::vector<double> mean(pixels), count(pixels), alphaPrime(pixels);
    parallelFor(size_t(height), kRowsPerBlock, [&](size_t y0, size_t y1) {
        for (int y = int(y0); y < int(y1); ++y)
            for (int x = 0; x < width; ++x) {
                const size_t j = size_t(y) * width + x;
                const auto [m, n] = neighbourMean(v, width, height, x, y, radius);
                mean[j] = m;
                count[j] = n;
                alphaPrime[j] = std::sqrt(std::max(0.0, m));
            }
    });
    const double z = parallelSum(pixels, kRowsPerBlock * size_t(width), [&](size_t j) { return alphaPrime[j]; });
    std::vector<double> alpha(pixels);
    parallelFor(size_t(height), kRowsPerBlock, [&](size_t y0, size_t y1) {
        for (int y = int(y0); y < int(y1); ++y)
            for (int x = 0; x < width; ++x) {
                const size_t i = size_t(y) * width + x;
                // Z_-i: the neighbours j of i (those whose means include v_i) without v_i.
                double zWithout = z;
                for (int dy = -radius; dy <= radius; ++dy)
                    for (int dx = -radius; dx <= radius; ++dx) {
                        const int nx = x + dx, ny = y + dy;
                        if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
                        const size_t j = size_t(ny) * width + nx;
                        zWithout -= alphaPrime[j] - std::sqrt(std::max(0.0, mean[j] - v[i] / count[j]));
                    }
                // PMC-IP sec. 4.2 with the leave-one-out weight (see the header).
                alpha[i] = zWithout > 0.0 ? epsilon / double(pixels) + (1.0 - epsilon) * alphaPrime[i] / zWithout
                                          : 1.0 / double(pixels);
            }
    });
    return alpha;
}

std::vector<uint32_t> dmsRound(const std::vector<double>& expected, double u) {
    std::vector<uint32_t> counts(expected.size());
    std::vector<double> fraction(expected.size());
    for (size_t k = 0; k < expected.size(); ++k) {
        const double whole = std::floor(std::max(0.0, expected[k]));
        counts[k] = uint32_t(whole);
        fraction[k] = std::max(0.0, expected[k]) - whole;
    }
    // One systematic pass: the k-th extra sample goes where the running sum of the fractions
    // passes u + k, so component k gets one with probability exactly its fraction.
    double cumulative = 0.0;
    uint64_t picked = 0;
    for (size_t k = 0; k < fraction.size(); ++k) {
        cumulative += fraction[k];
        while (u + double(picked) < cumulative) {
            counts[k] += 1;
            ++picked;
        }
    }
    return counts;
}

ImagePlaneSampler::ImagePlaneSampler(int width, int height, const ImagePlaneOptions& options)
    : m_width(width), m_height(height), m_options(options) {
    const size_t n = size_t(width) * size_t(height);
    if (options.initialSpp < 2) throw Error("PMC-IP: the first iteration needs at least 2 spp");
    if (options.radius < 1) throw Error("PMC-IP: the variance neighbourhood needs a radius of at least 1");
    if (!(options.samplesPerIteration >= double(options.minSamples)) || !(options.samplesPerIteration > 0.0))
        throw Error("PMC-IP: samples per iteration below the per-pixel minimum");
    m_alpha.assign(n, 1.0 / double(n));
    m_sum.assign(n, glm::dvec3(0.0));
    m_count.assign(n, 0);
    m_scheduled.assign(n, 0);
    m_lumSum.assign(n, 0.0);
    m_lumSqSum.assign(n, 0.0);
    m_pilotLumSum.assign(n, 0.0);
    m_pilotLumSqSum.assign(n, 0.0);
    m_pilotCount.assign(n, 0);
}

std::vector<double> ImagePlaneSampler::pilotPerceptualVariance() const {
    const size_t pixels = m_count.size();
    // The pilot moments [sum, sum of squares, count] per pixel: this process's, or every
    // process's with a pilot reduction.
    std::vector<double> moments(3 * pixels);
    for (size_t i = 0; i < pixels; ++i) {
        moments[3 * i + 0] = m_pilotLumSum[i];
        moments[3 * i + 1] = m_pilotLumSqSum[i];
        moments[3 * i + 2] = double(m_pilotCount[i]);
    }
    if (m_sumPilots) m_sumPilots(moments);
    std::vector<double> v(pixels, 0.0);
    parallelFor(pixels, 16384, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            const double sum = moments[3 * i], sumSq = moments[3 * i + 1], n = moments[3 * i + 2];
            if (n < 2.0) continue;
            v[i] = sampleVariance(sum, sumSq, n) / tvi(sum / n, m_options.displayWhite);
        }
    });
    return v;
}

const std::vector<uint32_t>& ImagePlaneSampler::allocate(double u, double spp) {
    const size_t n = m_count.size();
    m_sequenceStart = m_scheduled;
    if (m_allocations++ == 0) {
        m_allocated.assign(n, m_options.initialSpp);
        for (size_t i = 0; i < n; ++i) m_scheduled[i] += m_allocated[i];
        return m_allocated;
    }
    m_alpha = neighbourMixtureWeights(pilotPerceptualVariance(), m_width, m_height, m_options.epsilon,
                                     m_options.radius);
    // N = spp * P: the pilot samples per pixel, the rest by alpha.
    m_iterationPilots = std::min<uint32_t>(m_options.minSamples, uint32_t(std::max(0.0, std::floor(spp))));
    const double adaptive = std::max(0.0, spp - double(m_iterationPilots)) * double(n);
    std::vector<double> expected(n);
    for (size_t i = 0; i < n; ++i) expected[i] = double(m_iterationPilots) + adaptive * m_alpha[i];
    m_allocated = dmsRound(expected, u);
    for (size_t i = 0; i < n; ++i) m_scheduled[i] += m_allocated[i];
    return m_allocated;
}

void ImagePlaneSampler::addResult(uint32_t pixel, bool pilot, const glm::vec3& radiance) {
    addPixelResult(pixel, pilot, radiance);
    ++m_samplesTaken;
}

void ImagePlaneSampler::addPixelResult(uint32_t pixel, bool pilot, const glm::vec3& radiance) {
    const double y = luminance(radiance);
    m_sum[pixel] += glm::dvec3(radiance);
    m_count[pixel] += 1;
    m_lumSum[pixel] += y;
    m_lumSqSum[pixel] += y * y;
    if (pilot) {
        m_pilotLumSum[pixel] += y;
        m_pilotLumSqSum[pixel] += y * y;
        m_pilotCount[pixel] += 1;
    }
}

Image ImagePlaneSampler::image() const {
    Image img(m_width, m_height);
    for (size_t i = 0; i < m_count.size(); ++i) {
        if (m_count[i] == 0) continue;
        const glm::dvec3 v = m_sum[i] / double(m_count[i]);
        img.rgb[3 * i + 0] = float(v.x);
        img.rgb[3 * i + 1] = float(v.y);
        img.rgb[3 * i + 2] = float(v.z);
    }
    return img;
}

Image ImagePlaneSampler::alphaImage() const {
    Image img(m_width, m_height);
    const double pixels = double(m_alpha.size());
    for (size_t i = 0; i < m_alpha.size(); ++i)
        for (int c = 0; c < 3; ++c) img.rgb[3 * i + c] = float(m_alpha[i] * pixels);
    return img;
}

Image ImagePlaneSampler::sampleCountImage() const {
    Image img(m_width, m_height);
    for (size_t i = 0; i < m_count.size(); ++i)
        for (int c = 0; c < 3; ++c) img.rgb[3 * i + c] = float(m_count[i]);
    return img;
}

Image ImagePlaneSampler::varianceImage() const {
    Image img(m_width, m_height);
    for (size_t i = 0; i < m_count.size(); ++i) {
        const double n = double(m_count[i]);
        const float v = float(sampleVariance(m_lumSum[i], m_lumSqSum[i], n) / std::max(n, 1.0));
        for (int c = 0; c < 3; ++c) img.rgb[3 * i + c] = v;
    }
    return img;
}

}  // namespace pmcr
