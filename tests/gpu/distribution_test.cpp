#include "distribution_test.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "statistics.h"

namespace pmcr::test {

::testing::AssertionResult chi2Passes(const std::vector<double>& observed,
                                      const std::vector<double>& expected,
                                      const std::string& what) {
    const Chi2Result r = chi2Test(observed, expected);
    const double level = sidakLevel(kSuiteAlpha, kSuiteChi2Tests);
    if (r.dof > 0 && r.pValue >= level)
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << what << ": " << r.describe() << " (level " << level
                                         << (r.dof > 0 ? ")" : ", no degrees of freedom)");
}

std::vector<double> uniformBreaks(double a, double b, int cells) {
    std::vector<double> breaks(size_t(cells) + 1);
    for (int k = 0; k <= cells; ++k)
        breaks[size_t(k)] = a + (b - a) * k / cells;
    breaks.back() = b;
    return breaks;
}

namespace {

// Breaks of [0, length] in n cells with widths growing by e^(kappa / n) per cell, the first
// about `first`: x_k = length (e^(kappa k / n) - 1) / (e^kappa - 1).
std::vector<double> geometricSide(double length, int n, double first) {
    std::vector<double> x(size_t(n) + 1);
    auto firstWidth = [&](double kappa) {
        return kappa < 1e-9 ? length / n : length * std::expm1(kappa / n) / std::expm1(kappa);
    };
    double kappa = 0.0;
    if (first < length / n) {
        // The first width falls monotonically with kappa: bisect.
        double lo = 0.0, hi = 1.0;
        while (firstWidth(hi) > first && hi < 500.0)
            hi *= 2.0;
        for (int i = 0; i < 100; ++i) {
            const double mid = 0.5 * (lo + hi);
            (firstWidth(mid) > first ? lo : hi) = mid;
        }
        kappa = hi;
    }
    for (int k = 0; k <= n; ++k)
        x[size_t(k)] =
            kappa < 1e-9 ? length * k / n : length * std::expm1(kappa * k / n) / std::expm1(kappa);
    x.back() = length;
    return x;
}

}  // namespace

std::vector<double> gradedBreaks(double a, double focus, double b, int cells, double firstWidth) {
    focus = std::clamp(focus, a, b);
    const int below = focus > a ? (focus < b ? cells / 2 : cells) : 0;
    const int above = cells - below;
    std::vector<double> breaks;
    if (below > 0) {
        auto side = geometricSide(focus - a, below, firstWidth);
        for (auto it = side.rbegin(); it != side.rend(); ++it)
            breaks.push_back(focus - *it);
        breaks.front() = a;
    }
    if (above > 0) {
        auto side = geometricSide(b - focus, above, firstWidth);
        for (size_t k = breaks.empty() ? 0 : 1; k < side.size(); ++k)
            breaks.push_back(focus + side[k]);
        breaks.back() = b;
    }
    return breaks;
}

SphereGrid::SphereGrid(std::vector<double> zBreaks, std::vector<double> phiBreaks)
    : m_z(std::move(zBreaks)), m_phi(std::move(phiBreaks)) {}

int SphereGrid::cellOf(const glm::dvec3& w) const {
    const double z = std::clamp(w.z, -1.0, 1.0);
    double phi = std::atan2(w.y, w.x);
    if (phi < 0.0)
        phi += 2.0 * std::numbers::pi;
    if (z < m_z.front() || z > m_z.back() || phi < m_phi.front() || phi > m_phi.back())
        return -1;
    auto index = [](const std::vector<double>& breaks, double x) {
        const auto it = std::upper_bound(breaks.begin(), breaks.end(), x);
        return std::clamp(int(it - breaks.begin()) - 1, 0, int(breaks.size()) - 2);
    };
    return index(m_z, z) * int(m_phi.size() - 1) + index(m_phi, phi);
}

std::vector<double> SphereGrid::histogram(const std::vector<glm::dvec3>& directions,
                                          double* outside) const {
    std::vector<double> counts(size_t(cellCount()), 0.0);
    double out = 0.0;
    for (const glm::dvec3& w : directions) {
        const int c = cellOf(w);
        if (c < 0)
            out += 1.0;
        else
            counts[size_t(c)] += 1.0;
    }
    if (outside)
        *outside = out;
    return counts;
}

void SphereGrid::bounds(int c, double& z0, double& z1, double& phi0, double& phi1) const {
    const int nPhi = int(m_phi.size() - 1);
    const size_t iz = size_t(c / nPhi), ip = size_t(c % nPhi);
    z0 = m_z[iz];
    z1 = m_z[iz + 1];
    phi0 = m_phi[ip];
    phi1 = m_phi[ip + 1];
}

glm::dvec3 directionFromZPhi(double z, double phi) {
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

double CellIntegrals::total() const {
    double sum = 0.0;
    for (double v : value)
        sum += v;
    return sum;
}

std::vector<int> SphereGrid::neighbours(int c) const {
    const int nz = int(m_z.size() - 1), nPhi = int(m_phi.size() - 1);
    const int iz = c / nPhi, ip = c % nPhi;
    const bool wraps = m_phi.front() == 0.0 && m_phi.back() >= 2.0 * std::numbers::pi - 1e-12;
    std::vector<int> result;
    if (iz > 0)
        result.push_back(c - nPhi);
    if (iz + 1 < nz)
        result.push_back(c + nPhi);
    if (ip > 0 || wraps)
        result.push_back(iz * nPhi + (ip + nPhi - 1) % nPhi);
    if (ip + 1 < nPhi || wraps)
        result.push_back(iz * nPhi + (ip + 1) % nPhi);
    // The cells of a ring around a pole all meet at the pole.
    if ((iz == 0 && m_z.front() == -1.0) || (iz == nz - 1 && m_z.back() == 1.0))
        for (int j = 0; j < nPhi; ++j)
            if (j != ip)
                result.push_back(iz * nPhi + j);
    return result;
}

CellIntegrals integrateCells(const SphereGrid& grid, const DensityBatch& density,
                             const std::function<double(double)>& tolerance, int maxLevel) {
    // A cell where every point so far was zero may still hold a sliver of support along an edge
    // it shares with a cell that has some: such cells are refined up to this level (sub-cells of
    // 1/32 of theirs) before their zero is accepted.
    const int zeroMaxLevel = std::min(maxLevel, 5);
    CellIntegrals result;
    const int cells = grid.cellCount();
    result.value.assign(size_t(cells), 0.0);
    std::vector<double> previous(size_t(cells), 0.0);
    std::vector<int> active(static_cast<size_t>(cells));
    for (int c = 0; c < cells; ++c)
        active[size_t(c)] = c;
    for (int level = 1; level <= maxLevel && !active.empty(); ++level) {
        const int n = 1 << level;
        std::vector<glm::vec3> points;
        points.reserve(active.size() * size_t(n * n));
        for (int c : active) {
            double z0, z1, p0, p1;
            grid.bounds(c, z0, z1, p0, p1);
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j)
                    points.push_back(glm::vec3(directionFromZPhi(z0 + (z1 - z0) * (i + 0.5) / n,
                                                                 p0 + (p1 - p0) * (j + 0.5) / n)));
        }
        const std::vector<double> values = density(points);
        result.evaluations += long(points.size());
        for (size_t a = 0; a < active.size(); ++a) {
            const int c = active[a];
            double z0, z1, p0, p1;
            grid.bounds(c, z0, z1, p0, p1);
            double sum = 0.0;
            for (int k = 0; k < n * n; ++k)
                sum += values[a * size_t(n * n) + size_t(k)];
            previous[size_t(c)] = result.value[size_t(c)];
            result.value[size_t(c)] = sum * (z1 - z0) * (p1 - p0) / (n * n);
        }
        if (level == 1)
            continue;
        std::vector<int> next;
        for (int c : active) {
            const double estimate = result.value[size_t(c)];
            const double change = std::abs(estimate - previous[size_t(c)]);
            bool done = level == maxLevel;
            if (estimate == 0.0 && previous[size_t(c)] == 0.0) {
                bool nextToSupport = false;
                for (int d : grid.neighbours(c))
                    nextToSupport |= result.value[size_t(d)] > 0.0;
                done |= !nextToSupport || level >= zeroMaxLevel;
            } else {
                done |= change <= tolerance(estimate);
            }
            if (done)
                result.error += change;
            else
                next.push_back(c);
        }
        active = std::move(next);
    }
    return result;
}

size_t barycentricCell(double b1, double b2, int n) {
    const int i = std::clamp(int(std::floor(b1 * n)), 0, n - 1);
    const int j = std::clamp(int(std::floor(b2 * n)), 0, n - 1);
    return size_t(i * n + j);
}

std::vector<double> barycentricCellAreas(int n) {
    std::vector<double> share(size_t(n * n), 0.0);
    for (int i = 0; i < n; ++i)
        for (int j = 0; i + j < n; ++j)
            share[size_t(i * n + j)] = (i + j < n - 1 ? 2.0 : 1.0) / (n * n);
    return share;
}

std::vector<double> expectedCounts(const SphereGrid& grid, const CellIntegrals& integrals, double n,
                                   const std::vector<glm::dvec3>& samples,
                                   const DensityBatch& density) {
    std::vector<double> expected(integrals.value);
    for (double& e : expected)
        e *= n;
    std::vector<glm::vec3> suspects;
    std::vector<int> cells;
    for (const glm::dvec3& w : samples) {
        const int c = grid.cellOf(w);
        if (c >= 0 && expected[size_t(c)] <= 0.0) {
            suspects.push_back(glm::vec3(w));
            cells.push_back(c);
        }
    }
    if (suspects.empty())
        return expected;
    const std::vector<double> values = density(suspects);
    for (size_t i = 0; i < suspects.size(); ++i)
        if (values[i] > 0.0)
            expected[size_t(cells[i])] = 1e-6;
    return expected;
}

std::function<double(double)> countTolerance(double n) {
    return [n](double integral) { return 0.1 * std::sqrt(std::max(integral, 1.0 / n) / n); };
}

}  // namespace pmcr::test
