#include "statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace pmcr::test {

double incompleteGammaP(double a, double x) {
    if (x <= 0.0) return 0.0;
    const double logPrefix = a * std::log(x) - x - std::lgamma(a);
    if (x < a + 1.0) {
        // Series: P = e^-x x^a / Gamma(a+1) * sum x^n / ((a+1)...(a+n)).
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < 1000; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::abs(term) < std::abs(sum) * 1e-15) break;
        }
        return std::min(1.0, sum * std::exp(logPrefix));
    }
    // Continued fraction for Q = 1 - P (modified Lentz).
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 1000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < 1e-15) break;
    }
    return std::max(0.0, 1.0 - std::exp(logPrefix) * h);
}

double chi2Survival(double statistic, double dof) {
    if (dof <= 0) return 1.0;
    return 1.0 - incompleteGammaP(0.5 * dof, 0.5 * statistic);
}

double normalCdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

double sidakLevel(double alpha, int tests) {
    return 1.0 - std::pow(1.0 - alpha, 1.0 / std::max(tests, 1));
}

std::string Chi2Result::describe() const {
    std::ostringstream s;
    s << "chi2 = " << statistic << ", dof = " << dof << ", p = " << pValue;
    return s.str();
}

Chi2Result chi2Test(const std::vector<double>& observed, const std::vector<double>& expected,
                    double minExpected) {
    if (observed.size() != expected.size()) throw std::invalid_argument("chi2Test: size mismatch");
    std::vector<size_t> order(observed.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
    Chi2Result r;
    double pooledObserved = 0.0, pooledExpected = 0.0;
    int cells = 0;
    for (size_t k : order) {
        if (expected[k] <= 0.0) {
            // A sample where the density is zero is an outright failure.
            if (observed[k] > 0.0) {
                r.statistic = std::numeric_limits<double>::infinity();
                r.pValue = 0.0;
                return r;
            }
            continue;
        }
        if (expected[k] < minExpected || pooledExpected > 0.0) {
            pooledObserved += observed[k];
            pooledExpected += expected[k];
            if (pooledExpected >= minExpected) {
                r.statistic += (pooledObserved - pooledExpected) * (pooledObserved - pooledExpected) / pooledExpected;
                ++cells;
                pooledObserved = pooledExpected = 0.0;
            }
            continue;
        }
        r.statistic += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
        ++cells;
    }
    if (pooledExpected > 0.0) {
        r.statistic += (pooledObserved - pooledExpected) * (pooledObserved - pooledExpected) / pooledExpected;
        ++cells;
    }
    r.dof = cells - 1;
    r.pValue = chi2Survival(r.statistic, r.dof);
    return r;
}

std::string PixelTestResult::describe() const {
    std::ostringstream s;
    s << failing << " of " << pixels << " pixels fail (pass fraction " << passFraction
      << ", worst |z| " << worstZ << ")";
    for (const auto& f : failures) s << "; " << f;
    return s.str();
}

PixelTestResult pixelZTest(const std::vector<float>& mean, const std::vector<float>& variance,
                           int renders, const std::vector<float>& reference,
                           const std::vector<float>& referenceVariance, int referenceRenders,
                           double alpha) {
    PixelTestResult r;
    r.pixels = int(mean.size() / 3);
    const double level = sidakLevel(alpha, r.pixels);
    for (int p = 0; p < r.pixels; ++p) {
        bool pass = true;
        for (int c = 0; c < 3; ++c) {
            const size_t i = size_t(3 * p + c);
            double var = variance[i] / renders;
            if (!referenceVariance.empty() && referenceRenders > 0)
                var += referenceVariance[i] / referenceRenders;
            const double diff = double(mean[i]) - double(reference[i]);
            if (var <= 0.0) {
                // Both exact (e.g. a black pixel): they must agree to float precision.
                if (std::abs(diff) > 1e-6 * std::max(1.0, std::abs(double(reference[i])))) pass = false;
                continue;
            }
            const double z = diff / std::sqrt(var);
            r.worstZ = std::max(r.worstZ, std::abs(z));
            const double pValue = 2.0 * (1.0 - normalCdf(std::abs(z)));
            if (pValue < level) {
                pass = false;
                if (r.failures.size() < 8) {
                    std::ostringstream f;
                    f << "pixel " << p << " channel " << c << ": " << mean[i] << " vs " << reference[i]
                      << " (z " << z << ")";
                    r.failures.push_back(f.str());
                }
            }
        }
        if (!pass) ++r.failing;
    }
    r.passFraction = r.pixels > 0 ? 1.0 - double(r.failing) / r.pixels : 0.0;
    return r;
}

void ImageMoments::add(const std::vector<float>& image) {
    if (m_sum.empty()) {
        m_sum.assign(image.size(), 0.0);
        m_sumSq.assign(image.size(), 0.0);
    }
    if (image.size() != m_sum.size()) throw std::invalid_argument("ImageMoments: size mismatch");
    for (size_t i = 0; i < image.size(); ++i) {
        m_sum[i] += image[i];
        m_sumSq[i] += double(image[i]) * image[i];
    }
    ++m_count;
}

std::vector<float> ImageMoments::mean() const {
    std::vector<float> m(m_sum.size());
    for (size_t i = 0; i < m.size(); ++i) m[i] = float(m_sum[i] / m_count);
    return m;
}

std::vector<float> ImageMoments::variance() const {
    std::vector<float> v(m_sum.size(), 0.0f);
    if (m_count < 2) return v;
    for (size_t i = 0; i < v.size(); ++i) {
        const double mean = m_sum[i] / m_count;
        v[i] = float(std::max(0.0, (m_sumSq[i] - m_count * mean * mean) / (m_count - 1)));
    }
    return v;
}

}  // namespace pmcr::test
