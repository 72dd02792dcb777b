#include "render/image_plane_sampler.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "image/tvi.h"
#include "scene/scene.h"

namespace pmcr {

std::vector<double> pmcIpMixtureWeights(const std::vector<double>& alphaPrime, double epsilon) {
    const double pixels = double(alphaPrime.size());
    double total = 0.0;
    for (double a : alphaPrime) total += std::max(a, 0.0);
    std::vector<double> alpha(alphaPrime.size(), 1.0 / pixels);
    if (!(total > 0.0) || !std::isfinite(total)) return alpha;
    // PMC-IP sec. 4.2: alpha = epsilon + (1 - epsilon) alpha' / sum alpha', with epsilon shared
    // over the P pixels so that the mixture weights sum to one.
    for (size_t i = 0; i < alpha.size(); ++i)
        alpha[i] = epsilon / pixels + (1.0 - epsilon) * std::max(alphaPrime[i], 0.0) / total;
    return alpha;
}

std::vector<double> dmsExpectedCounts(const std::vector<double>& alpha, uint64_t total,
                                      uint32_t minPerComponent) {
    const uint64_t reserved = uint64_t(minPerComponent) * alpha.size();
    if (total < reserved) throw Error("deterministic mixture sampling: fewer samples than the minimum");
    const double adaptive = double(total - reserved);
    std::vector<double> expected(alpha.size());
    for (size_t k = 0; k < alpha.size(); ++k) expected[k] = double(minPerComponent) + adaptive * alpha[k];
    return expected;
}

std::vector<uint32_t> dmsAllocate(const std::vector<double>& alpha, uint64_t total,
                                  uint32_t minPerComponent, double u) {
    const std::vector<double> expected = dmsExpectedCounts(alpha, total, minPerComponent);
    std::vector<uint32_t> counts(alpha.size());
    std::vector<double> fraction(alpha.size());
    uint64_t assigned = 0;
    double fractionSum = 0.0;
    // The deterministic part: floor(n'_k) samples from component k.
    for (size_t k = 0; k < alpha.size(); ++k) {
        const double whole = std::floor(expected[k]);
        counts[k] = uint32_t(whole);
        assigned += counts[k];
        fraction[k] = expected[k] - whole;
        fractionSum += fraction[k];
    }
    if (assigned > total) throw Error("deterministic mixture sampling: weights sum above one");
    const uint64_t residual = total - assigned;
    if (residual == 0) return counts;
    // The residual: one systematic pass over the fractions, scaled so they sum to the residual
    // exactly (they do up to rounding); the k-th pick falls where the running sum passes u + k.
    const double scale = fractionSum > 0.0 ? double(residual) / fractionSum : 0.0;
    double cumulative = 0.0;
    uint64_t picked = 0;
    size_t lastWithFraction = 0;
    for (size_t k = 0; k < alpha.size() && picked < residual; ++k) {
        if (fraction[k] > 0.0) lastWithFraction = k;
        cumulative += fraction[k] * scale;
        while (picked < residual && u + double(picked) < cumulative) {
            counts[k] += 1;
            ++picked;
        }
    }
    // Rounding can leave the last pick (u + residual - 1 just below the total) unmade; it
    // belongs to the last component whose interval ends at the total.
    if (picked < residual) counts[lastWithFraction] += uint32_t(residual - picked);
    return counts;
}

ImagePlaneSampler::ImagePlaneSampler(int width, int height, const ImagePlaneOptions& options)
    : m_width(width), m_height(height), m_options(options) {
    const size_t n = size_t(width) * size_t(height);
    if (options.initialSpp < 2) throw Error("PMC-IP: the first iteration needs at least 2 spp");
    if (!(options.samplesPerIteration >= double(options.minSamples)) || !(options.samplesPerIteration > 0.0))
        throw Error("PMC-IP: samples per iteration below the per-pixel minimum");
    m_alpha.assign(n, 1.0 / double(n));
    m_iterSum.assign(n, glm::dvec3(0.0));
    m_iterCount.assign(n, 0);
    m_estimateSum.assign(n, glm::dvec3(0.0));
    m_weightSum.assign(n, 0.0);
    m_weightSqOverN.assign(n, 0.0);
    m_lumSum.assign(n, 0.0);
    m_lumSqSum.assign(n, 0.0);
    m_count.assign(n, 0);
}

std::vector<double> ImagePlaneSampler::perceptualVariance() const {
    std::vector<double> result(m_count.size(), 0.0);
    for (size_t i = 0; i < result.size(); ++i) {
        const double n = double(m_count[i]);
        if (n < 2.0) continue;
        const double mean = m_lumSum[i] / n;
        const double sampleVariance = std::max(0.0, (m_lumSqSum[i] - n * mean * mean) / (n - 1.0));
        const double level = m_weightSum[i] > 0.0 ? luminance(glm::vec3(m_estimateSum[i] / m_weightSum[i]))
                                                  : mean;
        // PMC-IP sec. 4.2: alpha' = sigma-bar^2 / tvi(L).
        result[i] = sampleVariance / n / tvi(level, m_options.displayWhite);
    }
    return result;
}

const std::vector<uint32_t>& ImagePlaneSampler::allocate(double u) {
    const size_t n = m_count.size();
    if (m_iteration == 0) {
        m_iterationBudget = double(m_options.initialSpp);
        m_allocated.assign(n, m_options.initialSpp);
        m_expected.assign(n, double(m_options.initialSpp));
    } else {
        m_iterationBudget = m_options.samplesPerIteration;
        m_alpha = pmcIpMixtureWeights(perceptualVariance(), m_options.epsilon);
        const uint64_t total = uint64_t(std::llround(m_options.samplesPerIteration * double(n)));
        m_expected = dmsExpectedCounts(m_alpha, total, m_options.minSamples);
        m_allocated = dmsAllocate(m_alpha, total, m_options.minSamples, u);
    }
    std::fill(m_iterSum.begin(), m_iterSum.end(), glm::dvec3(0.0));
    std::fill(m_iterCount.begin(), m_iterCount.end(), 0u);
    return m_allocated;
}

void ImagePlaneSampler::addSample(uint32_t pixel, const glm::vec3& radiance) {
    m_iterSum[pixel] += glm::dvec3(radiance);
    m_iterCount[pixel] += 1;
    const double y = luminance(radiance);
    m_lumSum[pixel] += y;
    m_lumSqSum[pixel] += y * y;
    m_count[pixel] += 1;
    ++m_samplesTaken;
}

void ImagePlaneSampler::finishIteration() {
    const double weight = m_iterationBudget;
    for (size_t i = 0; i < m_count.size(); ++i) {
        if (m_iterCount[i] != m_allocated[i]) continue;  // not finished: this iteration is skipped
        // Where DMS guarantees a sample, the iteration's mean; where the pixel may get none,
        // eq. 3's S / m (see the header).
        const bool guaranteed = std::floor(m_expected[i]) >= 1.0;
        const double divisor = guaranteed ? double(m_iterCount[i]) : m_expected[i];
        if (!(divisor > 0.0)) continue;
        m_estimateSum[i] += weight * m_iterSum[i] / divisor;
        m_weightSum[i] += weight;
        m_weightSqOverN[i] += weight * weight / divisor;
    }
    ++m_iteration;
}

Image ImagePlaneSampler::image() const {
    Image img(m_width, m_height);
    for (size_t i = 0; i < m_count.size(); ++i) {
        if (m_weightSum[i] <= 0.0) continue;
        const glm::dvec3 v = m_estimateSum[i] / m_weightSum[i];
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
        if (n < 2.0 || m_weightSum[i] <= 0.0) continue;
        const double mean = m_lumSum[i] / n;
        const double sampleVariance = std::max(0.0, (m_lumSqSum[i] - n * mean * mean) / (n - 1.0));
        // Var(sum_t c_t M_t) with c_t = w_t / sum w and Var(M_t) ~ s^2 / n_t.
        const double v = sampleVariance * m_weightSqOverN[i] / (m_weightSum[i] * m_weightSum[i]);
        for (int c = 0; c < 3; ++c) img.rgb[3 * i + c] = float(v);
    }
    return img;
}

}  // namespace pmcr
