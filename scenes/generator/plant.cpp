#include "plant.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace pmcr::scenegen {

namespace {

// PCG32 (O'Neill 2014, pcg32 "XSH RR"): defined bit for bit, unlike std:: distributions.
class Pcg32 {
public:
    explicit Pcg32(uint64_t seed) {
        next();
        m_state += seed;
        next();
    }
    uint32_t next() {
        const uint64_t old = m_state;
        m_state = old * 6364136223846793005ull + 1442695040888963407ull;
        const auto xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        const auto rot = uint32_t(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }
    // Uniform in [lo, hi).
    double uniform(double lo, double hi) { return lo + (hi - lo) * (next() * 0x1p-32); }

private:
    uint64_t m_state = 0;
};

// A leaflet from `base` along unit `dir`, `length` long and `width` wide, with its flat side
// facing roughly `up`: a hexagon B-L1-L2-T-R2-R1 fanned from B, its two halves folded up along
// the midrib.
void addLeaflet(Mesh& leaves, const glm::dvec3& base, const glm::dvec3& dir, const glm::dvec3& up,
                double length, double width) {
    const glm::dvec3 across = glm::normalize(glm::cross(dir, up));
    const glm::dvec3 normal = glm::cross(across, dir);
    const double fold = 0.25 * width;
    auto edge = [&](double along, double halfWidth, double side) {
        return base + along * length * dir + side * halfWidth * width * across +
               fold * halfWidth * 2.0 * normal;
    };
    const glm::dvec3 points[6] = {base,
                                  edge(0.3, 0.5, 1.0),
                                  edge(0.65, 0.35, 1.0),
                                  base + length * dir,
                                  edge(0.65, 0.35, -1.0),
                                  edge(0.3, 0.5, -1.0)};
    const auto first = uint32_t(leaves.positions.size());
    for (const auto& p : points)
        leaves.positions.push_back(glm::vec3(p));
    for (uint32_t k = 1; k < 5; ++k)
        leaves.indices.insert(leaves.indices.end(), {first, first + k, first + k + 1});
}

}  // namespace

Plant makePlant(const glm::dvec3& base, uint64_t seed) {
    Pcg32 rng(seed);
    Plant plant;
    plant.stems.name = "PlantStems";
    plant.leaves.name = "PlantLeaves";

    // The stem: slightly leaning, 0.45 tall.
    const glm::dvec3 top = base + glm::dvec3(0.03, 0.45, -0.02);
    append(plant.stems,
           tube("", {base, 0.5 * (base + top) + glm::dvec3(0.01, 0, 0), top}, 0.02, 6));

    // Fronds leave the upper stem at golden-angle steps, rise and arch over under a constant
    // "gravity" bend; leaflet pairs shrink towards both ends of each frond.
    constexpr int kFronds = 14;
    constexpr int kSteps = 16;
    constexpr int kPairs = 13;
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (int f = 0; f < kFronds; ++f) {
        const double t = double(f) / (kFronds - 1);
        const glm::dvec3 start = base + (0.55 + 0.45 * t) * (top - base);
        const double azimuth = f * golden + rng.uniform(-0.2, 0.2);
        const double elevation =
            (75.0 - 35.0 * t + rng.uniform(-8.0, 8.0)) * std::numbers::pi / 180;
        const double length = rng.uniform(0.8, 1.1);
        const double bend = rng.uniform(2.2, 3.0);  // downward turn per unit length, radians
        const glm::dvec3 outward(std::cos(azimuth), 0.0, std::sin(azimuth));

        std::vector<glm::dvec3> path{start};
        std::vector<glm::dvec3> tangents;
        glm::dvec3 p = start;
        for (int s = 0; s < kSteps; ++s) {
            const double a = elevation - bend * length * (s + 0.5) / kSteps;
            const glm::dvec3 d = std::cos(a) * outward + glm::dvec3(0.0, std::sin(a), 0.0);
            p += (length / kSteps) * d;
            path.push_back(p);
            tangents.push_back(d);
        }
        append(plant.stems, tube("", path, 0.006, 5));

        for (int k = 0; k < kPairs; ++k) {
            const double u = 0.15 + 0.8 * k / (kPairs - 1);  // position along the frond
            const int step = std::min(kSteps - 1, int(u * kSteps));
            const glm::dvec3 at =
                path[size_t(step)] +
                (u * kSteps - step) * (path[size_t(step) + 1] - path[size_t(step)]);
            const glm::dvec3 along = tangents[size_t(step)];
            const glm::dvec3 side = glm::normalize(glm::cross(along, glm::dvec3(0, 1, 0)));
            const glm::dvec3 up = glm::normalize(glm::cross(side, along));
            const double size = 0.22 * std::sin(std::numbers::pi * (0.15 + 0.8 * u));
            for (double s : {-1.0, 1.0}) {
                // Leaflets point forward along the frond and droop a little.
                glm::dvec3 dir = s * side * 0.8 + along * 0.6 - up * rng.uniform(0.05, 0.3);
                dir = glm::normalize(dir);
                addLeaflet(plant.leaves, at, dir, up, size * rng.uniform(0.85, 1.1), 0.3 * size);
            }
        }
    }
    orientAlong(plant.leaves, {0.0, 1.0, 0.0});
    return plant;
}

}  // namespace pmcr::scenegen
