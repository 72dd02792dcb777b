#include "mesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace pmcr::scenegen {

glm::dvec3 Mesh::geometricNormal(size_t triangle) const {
    const glm::dvec3 p0 = positions[indices[3 * triangle]];
    const glm::dvec3 p1 = positions[indices[3 * triangle + 1]];
    const glm::dvec3 p2 = positions[indices[3 * triangle + 2]];
    return glm::cross(p1 - p0, p2 - p0);
}

glm::dvec3 Mesh::centroid(size_t triangle) const {
    const glm::dvec3 p0 = positions[indices[3 * triangle]];
    const glm::dvec3 p1 = positions[indices[3 * triangle + 1]];
    const glm::dvec3 p2 = positions[indices[3 * triangle + 2]];
    return (p0 + p1 + p2) / 3.0;
}

Mesh quads(std::string name, const std::vector<glm::vec3>& corners) {
    Mesh mesh;
    mesh.name = std::move(name);
    mesh.positions = corners;
    for (uint32_t q = 0; q + 3 < corners.size(); q += 4) {
        mesh.indices.insert(mesh.indices.end(), {q, q + 1, q + 2, q, q + 2, q + 3});
    }
    return mesh;
}

namespace {

void flipTriangle(Mesh& mesh, size_t triangle) {
    std::swap(mesh.indices[3 * triangle + 1], mesh.indices[3 * triangle + 2]);
}

}  // namespace

Mesh icosphere(std::string name, const glm::dvec3& center, double radius, int subdivisions,
               bool smooth, bool inward) {
    // Icosahedron: the cyclic permutations of (0, +-1, +-phi); edges have length 2.
    const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<glm::dvec3> dirs;
    for (double a : {-1.0, 1.0}) {
        for (double b : {-phi, phi}) {
            dirs.push_back({0.0, a, b});
            dirs.push_back({a, b, 0.0});
            dirs.push_back({b, 0.0, a});
        }
    }
    // Its faces are the vertex triples at mutual distance 2, wound counter-clockwise seen from
    // outside.
    auto isEdge = [&](size_t i, size_t j) {
        return std::abs(glm::length(dirs[i] - dirs[j]) - 2.0) < 1e-9;
    };
    std::vector<uint32_t> tris;
    for (uint32_t i = 0; i < dirs.size(); ++i) {
        for (uint32_t j = i + 1; j < dirs.size(); ++j) {
            for (uint32_t k = j + 1; k < dirs.size(); ++k) {
                if (!isEdge(i, j) || !isEdge(j, k) || !isEdge(i, k))
                    continue;
                const glm::dvec3 n = glm::cross(dirs[j] - dirs[i], dirs[k] - dirs[i]);
                if (glm::dot(n, dirs[i] + dirs[j] + dirs[k]) > 0.0) {
                    tris.insert(tris.end(), {i, j, k});
                } else {
                    tris.insert(tris.end(), {i, k, j});
                }
            }
        }
    }
    for (auto& d : dirs)
        d = glm::normalize(d);

    // Loop-style 1-to-4 split; new vertices are edge midpoints pushed onto the unit sphere.
    for (int level = 0; level < subdivisions; ++level) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            const auto key = std::minmax(a, b);
            auto [it, inserted] = midpoints.try_emplace(key, uint32_t(dirs.size()));
            if (inserted)
                dirs.push_back(glm::normalize(dirs[a] + dirs[b]));
            return it->second;
        };
        std::vector<uint32_t> next;
        next.reserve(tris.size() * 4);
        for (size_t t = 0; t < tris.size(); t += 3) {
            const uint32_t a = tris[t], b = tris[t + 1], c = tris[t + 2];
            const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        tris = std::move(next);
    }

    Mesh mesh;
    mesh.name = std::move(name);
    mesh.indices = std::move(tris);
    mesh.positions.reserve(dirs.size());
    for (const auto& d : dirs)
        mesh.positions.push_back(glm::vec3(center + radius * d));
    if (smooth) {
        for (const auto& d : dirs)
            mesh.normals.push_back(glm::vec3(inward ? -d : d));
    }
    if (inward) {
        for (size_t t = 0; t < mesh.triangleCount(); ++t)
            flipTriangle(mesh, t);
    }
    return mesh;
}

void orientTowards(Mesh& mesh, const glm::dvec3& point, bool away) {
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const double side = glm::dot(mesh.geometricNormal(t), point - mesh.centroid(t));
        if (away ? side > 0.0 : side < 0.0)
            flipTriangle(mesh, t);
    }
}

void orientAlong(Mesh& mesh, const glm::dvec3& direction) {
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        if (glm::dot(mesh.geometricNormal(t), direction) < 0.0)
            flipTriangle(mesh, t);
    }
}

}  // namespace pmcr::scenegen
