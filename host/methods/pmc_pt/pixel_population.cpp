#include "methods/pmc_pt/pixel_population.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "image/tvi.h"
#include "render/settings.h"

namespace pmcr {

double RunningStats::variance() const {
    if (count < 2) return 0.0;
    const double n = double(count);
    return std::max(0.0, (sumSq - sum * sum / n) / (n - 1.0));
}

glm::ivec2 samplePixelDisk(glm::ivec2 c, double r, int w, int h, Pcg32& rng) {
    const int R = int(std::floor(r));
    const int x0 = std::max(0, c.x - R), x1 = std::min(w - 1, c.x + R);
    const int y0 = std::max(0, c.y - R), y1 = std::min(h - 1, c.y + R);
    for (;;) {
        const glm::ivec2 p(x0 + int(rng.nextBelow(uint32_t(x1 - x0 + 1))),
                           y0 + int(rng.nextBelow(uint32_t(y1 - y0 + 1))));
        const int dx = p.x - c.x, dy = p.y - c.y;
        if (double(dx) * dx + double(dy) * dy <= r * r) return p;
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
    const char* expected = "--radii: expected 1 to 3 positive radii in pixels, e.g. 5,10,50";
    std::vector<double> radii;
    try {
        radii = parseNumberList("radii", text);
    } catch (const Error&) {
        throw Error(expected);
    }
    if (radii.empty() || radii.size() > size_t(kMaxPopulationRadii)) throw Error(expected);
    for (double r : radii)
        if (!(r > 0.0)) throw Error(expected);
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
    m.pixel = glm::ivec2(std::clamp(int(std::floor(position.x)), 0, m_width - 1),
                         std::clamp(int(std::floor(position.y)), 0, m_height - 1));
    const int k = components();
    for (int c = 0; c < k; ++c) m.alpha[size_t(c)] = 1.0 / double(k);
    return m;
}

void PixelPopulation::drawMutations(Pcg32& rng, std::vector<PositionDraw>& out,
                                    uint32_t mutations) const {
    const int k = components();
    const uint32_t tr = mutations > 0 ? mutations : m_settings.mutations;
    for (uint32_t i = 0; i < m_members.size(); ++i) {
        const PopulationMember& m = m_members[i];
        const double offset = rng.nextDouble();
        int c = 0;
        double below = 0.0;  // alpha CDF below component c
        for (uint32_t t = 0; t < tr; ++t) {
            // Choose the radius by alpha (eq. 4), systematically, then a uniform pixel of its disk.
            const double u = (double(t) + offset) / double(tr);
            while (c < k - 1 && u >= below + m.alpha[size_t(c)]) below += m.alpha[size_t(c++)];
            const glm::ivec2 p =
                samplePixelDisk(m.pixel, m_settings.radii[size_t(c)], m_width, m_height, rng);
            out.push_back({uint32_t(p.y) * uint32_t(m_width) + uint32_t(p.x), i, uint32_t(c)});
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

}  // namespace pmcr
