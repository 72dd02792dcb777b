// Statistical tests for sampling routines and renderers (pbrt-v4 `bsdfs_test.cpp`, Mitsuba 3
// `chi2.py` and `test_renders.py` habits).
#pragma once

#include <string>
#include <vector>

namespace pmcr::test {

// Regularised lower incomplete gamma P(a, x) (series for x < a + 1, continued fraction beyond).
double incompleteGammaP(double a, double x);
// Upper tail of the chi-square distribution with `dof` degrees of freedom.
double chi2Survival(double statistic, double dof);
// Standard normal CDF.
double normalCdf(double x);

// Significance level per test so that `tests` independent tests together reject a true null
// hypothesis with probability alpha (Sidak correction).
double sidakLevel(double alpha, int tests);

struct Chi2Result {
    double statistic = 0.0;
    int dof = 0;
    double pValue = 1.0;
    std::string describe() const;
};

// Pearson's chi-square test of observed counts against expected counts. Cells with expected
// count below `minExpected` are pooled (sorted by expectation, merged until the pool reaches it),
// as pbrt-v4 and Mitsuba do.
Chi2Result chi2Test(const std::vector<double>& observed, const std::vector<double>& expected,
                    double minExpected = 5.0);

// Mitsuba-style per-pixel test of a method's mean image against a reference: each pixel's mean
// over n independent renders and its sample variance, against the reference value and its
// variance (per render of the reference: pass 0 for an exact reference), Welch's t-test
// approximated by a z-test; a pixel passes when its two-sided p-value exceeds the Sidak level for
// `alpha` over all pixels. Returns the fraction of pixels that pass (per channel: all three).
struct PixelTestResult {
    double passFraction = 0.0;
    int failing = 0;
    int pixels = 0;
    double worstZ = 0.0;
    std::vector<std::string> failures;  // the first few failing pixels, described
    std::string describe() const;
};
PixelTestResult pixelZTest(const std::vector<float>& mean, const std::vector<float>& variance,
                           int renders, const std::vector<float>& reference,
                           const std::vector<float>& referenceVariance, int referenceRenders,
                           double alpha = 0.01);

// Accumulates independent images (RGB floats) into per-pixel mean and unbiased sample variance.
class ImageMoments {
public:
    void add(const std::vector<float>& image);
    int count() const { return m_count; }
    std::vector<float> mean() const;
    std::vector<float> variance() const;  // of one image, n - 1 in the denominator

private:
    int m_count = 0;
    std::vector<double> m_sum;
    std::vector<double> m_sumSq;
};

}  // namespace pmcr::test
