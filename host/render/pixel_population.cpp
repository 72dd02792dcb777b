#include "render/pixel_population.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "core/error.h"
#include "image/tvi.h"

namespace pmcr {

double RunningStats::variance() const {
    if (count < 2) return 0.0;
    const double n = double(count);
    return std::max(0.0, (sumSq - sum * sum / n) / (n - 1.0));
}

namespace {

// Integral of sqrt(r^2 - x^2) dx from -r to x (the area under a half circle's top).
double halfChordArea(double x, double r) {
    const double t = std::clamp(x / r, -1.0, 1.0);
    const double xc = t * r;
    return 0.5 * (xc * std::sqrt(std::max(0.0, r * r - xc * xc)) + r * r * std::asin(t)) +
           0.25 * std::numbers::pi * r * r;
}

double chordIntegral(double x0, double x1, double r) {
    return x1 > x0 ? halfChordArea(x1, r) - halfChordArea(x0, r) : 0.0;
}

// Area of the disk of radius r at the origin intersected with the quadrant x <= a, y <= b:
// the integral over x <= a of the part of the chord [-h(x), h(x)], h = sqrt(r^2 - x^2), below b.
double diskQuadrantArea(double a, double b, double r) {
    a = std::clamp(a, -r, r);
    if (b >= r) return 2.0 * chordIntegral(-r, a, r);
    if (b <= -r) return 0.0;
    const double s = std::sqrt(r * r - b * b);
    double area = 0.0;
    // |x| < s: the chord crosses y = b, so b + h(x) of it lies below.
    const double hi = std::min(a, s);
    if (hi > -s) area += b * (hi + s) + chordIntegral(-s, hi, r);
    // |x| >= s: the whole chord lies below b when b >= 0, none of it when b < 0.
    if (b >= 0.0) area += 2.0 * (chordIntegral(-r, std::min(a, -s), r) + chordIntegral(s, a, r));
    return area;
}

}  // namespace

double diskRectangleArea(glm::dvec2 c, double r, double w, double h) {
    const double x0 = -c.x, x1 = w - c.x, y0 = -c.y, y1 = h - c.y;
    const double area = diskQuadrantArea(x1, y1, r) - diskQuadrantArea(x0, y1, r) -
                        diskQuadrantArea(x1, y0, r) + diskQuadrantArea(x0, y0, r);
    return std::max(0.0, area);
}

glm::dvec2 sampleDiskInImage(glm::dvec2 c, double r, double w, double h, Pcg32& rng) {
    const glm::dvec2 lo(std::max(0.0, c.x - r), std::max(0.0, c.y - r));
    const glm::dvec2 hi(std::min(w, c.x + r), std::min(h, c.y + r));
    for (;;) {
        const glm::dvec2 p(lo.x + rng.nextDouble() * (hi.x - lo.x),
                           lo.y + rng.nextDouble() * (hi.y - lo.y));
        const glm::dvec2 d = p - c;
        if (d.x * d.x + d.y * d.y < r * r && p.x < w && p.y < h) return p;
    }
}

std::array<double, kMaxPopulationRadii> mixtureWeights(
    const std::array<double, kMaxPopulationRadii>& prime, int components, double epsilon,
    const std::array<double, kMaxPopulationRadii>& current) {
    double sum = 0.0;
    for (int k = 0; k < components; ++k) sum += prime[size_t(k)];
    if (!(sum > 0.0) || !std::isfinite(sum)) return current;
    // alpha_k = eps + (1 - eps) alpha'_k / sum alpha', normalised to sum to one.
    const double norm = double(components) * epsilon + (1.0 - epsilon);
    std::array<double, kMaxPopulationRadii> alpha{};
    for (int k = 0; k < components; ++k)
        alpha[size_t(k)] = (epsilon + (1.0 - epsilon) * prime[size_t(k)] / sum) / norm;
    return alpha;
}

std::array<double, kMaxPopulationRadii> adaptAlpha(
    const std::array<RunningStats, kMaxPopulationRadii>& tagged, int components, double epsilon,
    const std::array<double, kMaxPopulationRadii>& current) {
    // PMC-PT sec. 4.3.3: alpha'_k = 1 / sigma^2_k, or 0 if sigma_k = 0.
    std::array<double, kMaxPopulationRadii> prime{};
    for (int k = 0; k < components; ++k) {
        const double v = tagged[size_t(k)].variance();
        prime[size_t(k)] = v > 0.0 ? 1.0 / v : 0.0;
    }
    return mixtureWeights(prime, components, epsilon, current);
}

std::vector<double> parseRadii(const std::string& text) {
    // Commas or slashes (`pmcr bench --methods` splits methods at commas).
    std::string list = text;
    std::replace(list.begin(), list.end(), '/', ',');
    std::vector<double> radii;
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ',')) {
        char* end = nullptr;
        const double r = std::strtod(item.c_str(), &end);
        if (item.empty() || *end != '\0' || !(r > 0.0) || !std::isfinite(r))
            throw Error("--radii: expected 1 to 3 positive radii in pixels, e.g. 5,10,50");
        radii.push_back(r);
    }
    if (radii.empty() || radii.size() > size_t(kMaxPopulationRadii))
        throw Error("--radii: expected 1 to 3 positive radii in pixels, e.g. 5,10,50");
    return radii;
}

std::vector<glm::dvec2> PositionPool::next(uint32_t count, Pcg32& rng) {
    // R2: x_n = frac(n / g, n / g^2), g the plastic number (root of g^3 = g + 1).
    constexpr double g = 1.32471795724474602596;
    constexpr double a1 = 1.0 / g, a2 = 1.0 / (g * g);
    const double shiftX = rng.nextDouble(), shiftY = rng.nextDouble();
    std::vector<glm::dvec2> positions(count);
    for (uint32_t i = 0; i < count; ++i, ++m_index) {
        const double n = double(m_index);
        double u = std::fmod(0.5 + a1 * n + shiftX, 1.0);
        double v = std::fmod(0.5 + a2 * n + shiftY, 1.0);
        positions[i] = glm::dvec2(u * m_width, v * m_height);
        // Keep rounding from reaching the far edge.
        positions[i].x = std::min(positions[i].x, std::nextafter(double(m_width), 0.0));
        positions[i].y = std::min(positions[i].y, std::nextafter(double(m_height), 0.0));
    }
    return positions;
}

void PixelImportance::update(const std::vector<RunningStats>& pixelLuminance,
                             const std::vector<double>& estimateLuminance) {
    m_cdf.resize(pixelLuminance.size());
    double total = 0.0;
    for (size_t p = 0; p < pixelLuminance.size(); ++p) {
        // beta'_ij = sigma^2_ij / tvi(I_ij) (PMC-PT sec. 4.3.2).
        const double v = pixelLuminance[p].variance();
        if (v > 0.0 && std::isfinite(v)) total += v / tvi(estimateLuminance[p]);
        m_cdf[p] = total;
    }
    m_total = total;
}

double PixelImportance::probability(uint32_t pixel) const {
    if (empty()) return 0.0;
    const double below = pixel > 0 ? m_cdf[pixel - 1] : 0.0;
    return (m_cdf[pixel] - below) / m_total;
}

uint32_t PixelImportance::samplePixel(double u) const {
    const double target = u * m_total;
    auto it = std::upper_bound(m_cdf.begin(), m_cdf.end(), target);
    if (it == m_cdf.end()) --it;
    // Skip pixels of zero weight that share the running sum (upper_bound lands past them).
    return uint32_t(it - m_cdf.begin());
}

RunningStats PopulationMember::all() const {
    RunningStats s;
    for (const auto& t : tagged) s.merge(t);
    return s;
}

PixelPopulation::PixelPopulation(const PopulationSettings& settings, int width, int height,
                                 Pcg32& rng)
    : m_settings(settings), m_width(width), m_height(height) {
    // A jittered grid of gx x gy cells with about one cell per member, cells taken in a random
    // order (so the members past gx gy, if any, land anywhere).
    const uint32_t n = settings.size;
    const double aspect = double(width) / double(height);
    const int gx = std::max(1, int(std::lround(std::sqrt(double(n) * aspect))));
    const int gy = std::max(1, int(std::lround(double(n) / double(gx))));
    std::vector<uint32_t> cells(size_t(gx) * size_t(gy));
    for (uint32_t c = 0; c < cells.size(); ++c) cells[c] = c;
    for (size_t i = cells.size(); i > 1; --i) std::swap(cells[i - 1], cells[rng.nextBelow(uint32_t(i))]);
    m_members.reserve(n);
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t c = cells[i % cells.size()];
        const double cx = double(c % uint32_t(gx)), cy = double(c / uint32_t(gx));
        glm::dvec2 p((cx + rng.nextDouble()) * width / gx, (cy + rng.nextDouble()) * height / gy);
        p.x = std::min(p.x, std::nextafter(double(width), 0.0));
        p.y = std::min(p.y, std::nextafter(double(height), 0.0));
        m_members.push_back(makeMember(p));
    }
}

PopulationMember PixelPopulation::makeMember(glm::dvec2 position) const {
    PopulationMember m;
    m.position = position;
    const int k = components();
    for (int c = 0; c < k; ++c) {
        m.alpha[size_t(c)] = 1.0 / double(k);
        m.area[size_t(c)] =
            diskRectangleArea(position, m_settings.radii[size_t(c)], m_width, m_height);
    }
    return m;
}

void PixelPopulation::drawMutations(Pcg32& rng, std::vector<PositionDraw>& out) const {
    const int k = components();
    for (uint32_t i = 0; i < m_members.size(); ++i) {
        const PopulationMember& m = m_members[i];
        for (uint32_t t = 0; t < m_settings.mutations; ++t) {
            // Choose the radius by alpha (eq. 4), then a uniform point of its disk.
            double u = rng.nextDouble();
            int c = 0;
            while (c < k - 1 && u >= m.alpha[size_t(c)]) u -= m.alpha[size_t(c++)];
            const glm::dvec2 p = sampleDiskInImage(m.position, m_settings.radii[size_t(c)],
                                                   m_width, m_height, rng);
            out.push_back({p, i, uint32_t(c)});
        }
    }
}

void PixelPopulation::record(const PositionDraw& draw, double luminance) {
    if (draw.member == PositionDraw::kPool || !std::isfinite(luminance)) return;
    m_members[draw.member].tagged[draw.component].add(luminance);
}

void PixelPopulation::endStep() {
    for (auto& m : m_members) ++m.stepsUsed;
}

void PixelPopulation::adapt() {
    for (auto& m : m_members)
        m.alpha = adaptAlpha(m.tagged, components(), m_settings.epsilon, m.alpha);
}

uint32_t PixelPopulation::replacementsPerStep() const {
    const double r = std::round(m_settings.resampleRate * double(m_members.size()));
    return uint32_t(std::clamp(r, 0.0, double(m_members.size())));
}

uint32_t PixelPopulation::poolReplacementsPerStep(bool importanceAvailable) const {
    const uint32_t r = replacementsPerStep();
    return importanceAvailable ? r - r / 2 : r;
}

ResampleCounts PixelPopulation::resample(Pcg32& rng, const std::vector<glm::dvec2>& poolPositions,
                                         const PixelImportance& importance) {
    ResampleCounts counts;
    const uint32_t n = uint32_t(m_members.size());
    const uint32_t replace = replacementsPerStep();
    if (replace == 0) return counts;
    // Survival keys (Efraimidis and Spirakis 2006): keeping the n - replace largest of
    // log(u) / w_i draws the survivors without replacement with probability ∝ w_i;
    // w_i = sigma^2_i / N_used (PMC-PT sec. 4.3.1).
    struct Key {
        double key;
        double tie;
        uint32_t member;
    };
    std::vector<Key> keys(n);
    for (uint32_t i = 0; i < n; ++i) {
        const PopulationMember& m = m_members[i];
        const double w = m.all().variance() / double(std::max<uint32_t>(m.stepsUsed, 1));
        const double u = rng.nextDouble();
        const double key = w > 0.0 && std::isfinite(w) ? std::log1p(-u) / w
                                                       : -std::numeric_limits<double>::infinity();
        keys[i] = {key, rng.nextDouble(), i};
    }
    std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
        return a.key != b.key ? a.key < b.key : a.tie < b.tie;
    });
    // Eliminated members, in member order (so the replacements' order does not depend on the sort).
    std::vector<uint32_t> eliminated(replace);
    for (uint32_t r = 0; r < replace; ++r) eliminated[r] = keys[r].member;
    std::sort(eliminated.begin(), eliminated.end());
    counts.eliminated = replace;

    const uint32_t fromPool = std::min<uint32_t>(poolReplacementsPerStep(!importance.empty()),
                                                 uint32_t(poolPositions.size()));
    for (uint32_t r = 0; r < replace; ++r) {
        glm::dvec2 p;
        if (r < fromPool) {
            p = poolPositions[r];
            ++counts.fromPool;
        } else if (!importance.empty()) {
            // A pixel drawn ∝ beta, its centre jittered by up to one pixel each way.
            const uint32_t pixel = importance.samplePixel(rng.nextDouble());
            p = glm::dvec2(double(pixel % uint32_t(m_width)) + 0.5 + (2.0 * rng.nextDouble() - 1.0),
                           double(pixel / uint32_t(m_width)) + 0.5 + (2.0 * rng.nextDouble() - 1.0));
            p.x = std::clamp(p.x, 0.0, std::nextafter(double(m_width), 0.0));
            p.y = std::clamp(p.y, 0.0, std::nextafter(double(m_height), 0.0));
            ++counts.fromImportance;
        } else {
            p = glm::dvec2(rng.nextDouble() * m_width, rng.nextDouble() * m_height);
            ++counts.fromPool;
        }
        m_members[eliminated[r]] = makeMember(p);
    }
    return counts;
}

ProposalDensity::ProposalDensity(const PixelPopulation& population, uint32_t poolDraws) {
    const double w = population.width(), h = population.height();
    m_uniform = double(poolDraws) / (w * h);
    const auto& radii = population.settings().radii;
    m_components = population.components();
    for (int c = 0; c < m_components; ++c) m_radiusSq[size_t(c)] = radii[size_t(c)] * radii[size_t(c)];
    m_cell = std::max(1.0, *std::max_element(radii.begin(), radii.end()));
    m_cellsX = std::max(1, int(std::ceil(w / m_cell)));
    m_cellsY = std::max(1, int(std::ceil(h / m_cell)));
    const auto& members = population.members();
    const double tr = population.settings().mutations;
    std::vector<uint32_t> cellOf(members.size());
    m_cellStart.assign(size_t(m_cellsX) * size_t(m_cellsY) + 1, 0);
    for (size_t i = 0; i < members.size(); ++i) {
        const int cx = std::min(m_cellsX - 1, int(members[i].position.x / m_cell));
        const int cy = std::min(m_cellsY - 1, int(members[i].position.y / m_cell));
        cellOf[i] = uint32_t(cy * m_cellsX + cx);
        ++m_cellStart[cellOf[i] + 1];
    }
    for (size_t c = 1; c < m_cellStart.size(); ++c) m_cellStart[c] += m_cellStart[c - 1];
    m_x.resize(members.size());
    m_y.resize(members.size());
    for (auto& w : m_weight) w.assign(members.size(), 0.0);
    std::vector<uint32_t> fill(m_cellStart.begin(), m_cellStart.end() - 1);
    for (size_t i = 0; i < members.size(); ++i) {
        const auto& m = members[i];
        const uint32_t e = fill[cellOf[i]]++;
        m_x[e] = m.position.x;
        m_y[e] = m.position.y;
        for (int c = 0; c < m_components; ++c)
            m_weight[size_t(c)][e] =
                m.area[size_t(c)] > 0.0 ? tr * m.alpha[size_t(c)] / m.area[size_t(c)] : 0.0;
    }
}

double ProposalDensity::operator()(glm::dvec2 x) const {
    const int cx = std::min(m_cellsX - 1, int(x.x / m_cell));
    const int cy = std::min(m_cellsY - 1, int(x.y / m_cell));
    const int x0 = std::max(0, cx - 1), x1 = std::min(m_cellsX - 1, cx + 1);
    double q = m_uniform;
    for (int y = std::max(0, cy - 1); y <= std::min(m_cellsY - 1, cy + 1); ++y) {
        // Cells x0..x1 of a row are contiguous in m_entries.
        const size_t row = size_t(y) * size_t(m_cellsX);
        const uint32_t begin = m_cellStart[row + size_t(x0)], end = m_cellStart[row + size_t(x1) + 1];
        const double r0 = m_radiusSq[0], r1 = m_radiusSq[1], r2 = m_radiusSq[2];
        const double *px = m_x.data(), *py = m_y.data();
        const double *w0 = m_weight[0].data(), *w1 = m_weight[1].data(), *w2 = m_weight[2].data();
        for (uint32_t j = begin; j < end; ++j) {
            const double dx = x.x - px[j], dy = x.y - py[j];
            const double d2 = dx * dx + dy * dy;
            q += (d2 < r0 ? w0[j] : 0.0) + (d2 < r1 ? w1[j] : 0.0) + (d2 < r2 ? w2[j] : 0.0);
        }
    }
    return q;
}

}  // namespace pmcr
