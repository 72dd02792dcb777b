// Helpers for the shader tests of sampling routines (pbrt-v4 `bsdfs_test.cpp` and Mitsuba 3
// `chi2.py` habits): the suite-wide chi-square level, partitions of the sphere of directions
// graded towards where a density concentrates, and adaptive quadrature of a density (evaluated
// by a kernel) over their cells, for the expected counts.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace pmcr::test {

// Number of chi-square tests run through chi2Passes in pmcr_gpu_tests (rng 3, sampler 4, warps 8,
// GGX 20, BSDF 61, lights 5, environment 1, PMC-HI mixture 2, ERPT mutations 2, PMC-ER radius
// mixture 1, PSSMLT mutations 5, independent pixel samples 2): each runs at the Sidak level that
// keeps the whole suite's probability of rejecting a correct routine at 1%. Update it when
// adding tests.
constexpr int kSuiteChi2Tests = 114;
constexpr double kSuiteAlpha = 0.01;

// Pearson's test of observed against expected counts (pooling cells below 5 expected) at the
// suite's Sidak level; the message names `what` and the statistic.
::testing::AssertionResult chi2Passes(const std::vector<double>& observed,
                                      const std::vector<double>& expected, const std::string& what);

// `cells` equal intervals of [a, b].
std::vector<double> uniformBreaks(double a, double b, int cells);

// Breaks of [a, b] into `cells` intervals, half on each side of `focus`, whose widths grow
// geometrically away from it, the first being about `firstWidth` (uniform where that is wider
// than an equal split).
std::vector<double> gradedBreaks(double a, double focus, double b, int cells, double firstWidth);

// Cells of the sphere of directions (or of a part of it): products of an interval of
// z = cos(theta) and one of phi in [0, 2 pi). In (z, phi) the solid angle measure is dz dphi,
// so a cell's integral is a plain 2D integral.
class SphereGrid {
public:
    SphereGrid(std::vector<double> zBreaks, std::vector<double> phiBreaks);

    int cellCount() const { return int((m_z.size() - 1) * (m_phi.size() - 1)); }
    // The cell holding unit direction w, or -1 outside the grid.
    int cellOf(const glm::dvec3& w) const;
    // Histogram of directions over the cells; `outside` counts those in no cell.
    std::vector<double> histogram(const std::vector<glm::dvec3>& directions,
                                  double* outside = nullptr) const;

    // Cells sharing an edge with cell c (phi wraps around when the grid spans [0, 2 pi]) or,
    // in a ring around a pole, the pole.
    std::vector<int> neighbours(int c) const;
    // Corners of cell c in (z, phi).
    void bounds(int c, double& z0, double& z1, double& phi0, double& phi1) const;

private:
    std::vector<double> m_z;
    std::vector<double> m_phi;
};

glm::dvec3 directionFromZPhi(double z, double phi);

// Evaluates a density at a batch of unit directions (one kernel dispatch).
using DensityBatch = std::function<std::vector<double>(const std::vector<glm::vec3>&)>;

struct CellIntegrals {
    std::vector<double> value;  // integral of the density over each cell
    double error = 0.0;         // sum of the cells' error estimates
    long evaluations = 0;
    double total() const;
};

// Integral of `density` over each cell of `grid`: the midpoint rule on 2^L x 2^L sub-cells in
// (z, phi), raising L per cell from 2 until two successive levels differ by at most
// tolerance(value) or L reaches maxLevel; a cell found empty so far is refined further while a
// neighbour is not (support may end in a sliver along their common edge). The difference of the
// last two levels is the cell's error estimate (conservative for smooth densities, whose midpoint
// error falls 4x per level).
CellIntegrals integrateCells(const SphereGrid& grid, const DensityBatch& density,
                             const std::function<double(double)>& tolerance, int maxLevel = 7);

// Cells of a triangle in barycentrics (b1, b2): squares [i/n, (i+1)/n) x [j/n, (j+1)/n) with
// i + j < n - 1 and the half squares on the diagonal i + j = n - 1, indexed i n + j. A point
// outside the triangle gets an index whose cell has no area.
size_t barycentricCell(double b1, double b2, int n);
// Share of the triangle's area in each of the n^2 indices.
std::vector<double> barycentricCellAreas(int n);

// Expected counts n * integral for a chi-square test of `samples` over `grid`. A cell whose
// quadrature is zero although the density is positive at a sample inside it (a sliver of support
// between the quadrature points) gets a negligible count instead, so that only samples where the
// density really is zero fail the test outright.
std::vector<double> expectedCounts(const SphereGrid& grid, const CellIntegrals& integrals, double n,
                                   const std::vector<glm::dvec3>& samples,
                                   const DensityBatch& density);

// Tolerance for the expected counts of a chi-square test with n samples: errors well below the
// counts' own standard deviation (a tenth of it), and below 0.1 count in empty cells.
std::function<double(double)> countTolerance(double n);

}  // namespace pmcr::test
