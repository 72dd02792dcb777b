#include "mesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
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

void orientByNormals(Mesh& mesh) {
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::dvec3 n = glm::dvec3(mesh.normals[mesh.indices[3 * t]]) +
                             glm::dvec3(mesh.normals[mesh.indices[3 * t + 1]]) +
                             glm::dvec3(mesh.normals[mesh.indices[3 * t + 2]]);
        if (glm::dot(mesh.geometricNormal(t), n) < 0.0)
            flipTriangle(mesh, t);
    }
}

void append(Mesh& mesh, const Mesh& other) {
    const auto base = uint32_t(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), other.positions.begin(), other.positions.end());
    mesh.normals.insert(mesh.normals.end(), other.normals.begin(), other.normals.end());
    for (uint32_t i : other.indices)
        mesh.indices.push_back(base + i);
}

namespace {

// Two triangles for each of rows x columns grid cells; vertex (r, c) is first + r * columns + c.
// Columns wrap around; rows wrap too when wrapRows (rows vertex rows), else there are rows + 1.
void wrappedGrid(Mesh& mesh, uint32_t first, uint32_t rows, uint32_t columns, bool wrapRows) {
    for (uint32_t r = 0; r < rows; ++r) {
        const uint32_t r1 = wrapRows ? (r + 1) % rows : r + 1;
        for (uint32_t c = 0; c < columns; ++c) {
            const uint32_t c1 = (c + 1) % columns;
            const uint32_t a = first + r * columns + c, b = first + r * columns + c1;
            const uint32_t d = first + r1 * columns + c, e = first + r1 * columns + c1;
            mesh.indices.insert(mesh.indices.end(), {a, b, e, a, e, d});
        }
    }
}

}  // namespace

Mesh torus(std::string name, const glm::dvec3& center, double majorRadius, double minorRadius,
           int majorSegments, int minorSegments) {
    Mesh mesh;
    mesh.name = std::move(name);
    for (int i = 0; i < majorSegments; ++i) {
        const double phi = 2.0 * std::numbers::pi * i / majorSegments;
        for (int j = 0; j < minorSegments; ++j) {
            const double theta = 2.0 * std::numbers::pi * j / minorSegments;
            const glm::dvec3 n(std::cos(theta) * std::cos(phi), std::sin(theta),
                               std::cos(theta) * std::sin(phi));
            const glm::dvec3 ring(majorRadius * std::cos(phi), 0.0, majorRadius * std::sin(phi));
            mesh.positions.push_back(glm::vec3(center + ring + minorRadius * n));
            mesh.normals.push_back(glm::vec3(n));
        }
    }
    wrappedGrid(mesh, 0, uint32_t(majorSegments), uint32_t(minorSegments), true);
    orientByNormals(mesh);
    return mesh;
}

Mesh domeShell(std::string name, const glm::dvec3& center, double outerRadius, double innerRadius,
               int segments, int rings) {
    // Ring k (1..rings) of a hemisphere lies at polar angle k / rings * pi / 2; the last one is
    // the equator, computed with exact cos = 0 so that the shells and the base ring share its
    // vertex positions bit for bit (the mesh is then closed).
    auto direction = [&](int k, int j) {
        const double phi = 2.0 * std::numbers::pi * j / segments;
        const double theta = 0.5 * std::numbers::pi * k / rings;
        const double s = k == rings ? 1.0 : std::sin(theta);
        const double c = k == rings ? 0.0 : std::cos(theta);
        return glm::dvec3(s * std::cos(phi), c, s * std::sin(phi));
    };
    auto hemisphere = [&](double radius, bool inward) {
        Mesh part;
        part.positions.push_back(glm::vec3(center + glm::dvec3(0.0, radius, 0.0)));
        part.normals.push_back(glm::vec3(0.0f, inward ? -1.0f : 1.0f, 0.0f));
        for (int k = 1; k <= rings; ++k) {
            for (int j = 0; j < segments; ++j) {
                const glm::dvec3 d = direction(k, j);
                part.positions.push_back(glm::vec3(center + radius * d));
                part.normals.push_back(glm::vec3(inward ? -d : d));
            }
        }
        const auto n = uint32_t(segments);
        for (uint32_t j = 0; j < n; ++j)
            part.indices.insert(part.indices.end(), {0u, 1 + j, 1 + (j + 1) % n});
        wrappedGrid(part, 1, uint32_t(rings) - 1, n, false);
        orientByNormals(part);
        return part;
    };
    Mesh mesh = hemisphere(outerRadius, false);
    mesh.name = std::move(name);
    append(mesh, hemisphere(innerRadius, true));
    Mesh ring;
    for (double radius : {outerRadius, innerRadius}) {
        for (int j = 0; j < segments; ++j) {
            ring.positions.push_back(glm::vec3(center + radius * direction(rings, j)));
            ring.normals.push_back(glm::vec3(0.0f, -1.0f, 0.0f));
        }
    }
    wrappedGrid(ring, 0, 1, uint32_t(segments), false);
    orientByNormals(ring);
    append(mesh, ring);
    return mesh;
}

Mesh cylinderSide(std::string name, const glm::dvec3& base, double radius, double height,
                  int segments) {
    Mesh mesh;
    mesh.name = std::move(name);
    for (double y : {0.0, height}) {
        for (int j = 0; j < segments; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / segments;
            const glm::dvec3 n(std::cos(phi), 0.0, std::sin(phi));
            mesh.positions.push_back(glm::vec3(base + radius * n + glm::dvec3(0.0, y, 0.0)));
            mesh.normals.push_back(glm::vec3(n));
        }
    }
    wrappedGrid(mesh, 0, 1, uint32_t(segments), false);
    orientByNormals(mesh);
    return mesh;
}

Mesh coneSide(std::string name, const glm::dvec3& base, double bottomRadius, double topRadius,
              double height, int segments) {
    Mesh mesh;
    mesh.name = std::move(name);
    // The slant's outward normal at azimuth phi: (height cos phi, r0 - r1, height sin phi).
    const double slant = std::hypot(height, bottomRadius - topRadius);
    for (auto [y, radius] : {std::pair{0.0, bottomRadius}, std::pair{height, topRadius}}) {
        for (int j = 0; j < segments; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / segments;
            const glm::dvec3 out(std::cos(phi), 0.0, std::sin(phi));
            mesh.positions.push_back(glm::vec3(base + radius * out + glm::dvec3(0.0, y, 0.0)));
            mesh.normals.push_back(
                glm::vec3((height * out + glm::dvec3(0.0, bottomRadius - topRadius, 0.0)) / slant));
        }
    }
    wrappedGrid(mesh, 0, 1, uint32_t(segments), false);
    orientByNormals(mesh);
    return mesh;
}

Mesh box(std::string name, const glm::dvec3& lo, const glm::dvec3& hi) {
    // Two faces per axis, at lo and at hi; (u, v) walks around each face along the other two
    // axes. The winding is fixed afterwards.
    std::vector<glm::vec3> corners;
    for (int axis = 0; axis < 3; ++axis) {
        for (const glm::dvec3& side : {lo, hi}) {
            for (auto [u, v] :
                 {std::pair{0, 0}, std::pair{1, 0}, std::pair{1, 1}, std::pair{0, 1}}) {
                glm::dvec3 p = side;
                p[(axis + 1) % 3] = u ? hi[(axis + 1) % 3] : lo[(axis + 1) % 3];
                p[(axis + 2) % 3] = v ? hi[(axis + 2) % 3] : lo[(axis + 2) % 3];
                corners.push_back(glm::vec3(p));
            }
        }
    }
    Mesh mesh = quads(std::move(name), corners);
    orientTowards(mesh, 0.5 * (lo + hi), true);
    return mesh;
}

Mesh disk(std::string name, const glm::dvec3& center, double radius, int segments, bool up) {
    Mesh mesh;
    mesh.name = std::move(name);
    mesh.positions.push_back(glm::vec3(center));
    for (int j = 0; j < segments; ++j) {
        const double phi = 2.0 * std::numbers::pi * j / segments;
        mesh.positions.push_back(
            glm::vec3(center + radius * glm::dvec3(std::cos(phi), 0.0, std::sin(phi))));
    }
    const auto n = uint32_t(segments);
    for (uint32_t j = 0; j < n; ++j)
        mesh.indices.insert(mesh.indices.end(), {0u, 1 + j, 1 + (j + 1) % n});
    orientAlong(mesh, {0.0, up ? 1.0 : -1.0, 0.0});
    return mesh;
}

Mesh rectangle(std::string name, const glm::dvec3& center, const glm::dvec3& u,
               const glm::dvec3& v) {
    Mesh mesh =
        quads(std::move(name),
              {glm::vec3(center - 0.5 * u - 0.5 * v), glm::vec3(center + 0.5 * u - 0.5 * v),
               glm::vec3(center + 0.5 * u + 0.5 * v), glm::vec3(center - 0.5 * u + 0.5 * v)});
    orientAlong(mesh, glm::cross(u, v));
    return mesh;
}

Mesh tube(std::string name, const std::vector<glm::dvec3>& path, double radius, int sides) {
    Mesh mesh;
    mesh.name = std::move(name);
    // A frame carried along the path by projecting the previous side vector (no twist jumps).
    glm::dvec3 side(0.0);
    for (size_t i = 0; i < path.size(); ++i) {
        const glm::dvec3 tangent =
            glm::normalize(path[std::min(i + 1, path.size() - 1)] - path[i == 0 ? 0 : i - 1]);
        if (i == 0) {
            side = std::abs(tangent.y) < 0.9 ? glm::dvec3(0.0, 1.0, 0.0) : glm::dvec3(1.0, 0, 0);
        }
        side = glm::normalize(side - glm::dot(side, tangent) * tangent);
        const glm::dvec3 other = glm::cross(tangent, side);
        for (int j = 0; j < sides; ++j) {
            const double a = 2.0 * std::numbers::pi * j / sides;
            mesh.positions.push_back(
                glm::vec3(path[i] + radius * (std::cos(a) * side + std::sin(a) * other)));
        }
    }
    wrappedGrid(mesh, 0, uint32_t(path.size()) - 1, uint32_t(sides), false);
    // Face out of the tube: away from the middle of the path segment the triangle spans.
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const size_t ring =
            std::min({mesh.indices[3 * t], mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]}) /
            uint32_t(sides);
        const glm::dvec3 axis = 0.5 * (path[ring] + path[ring + 1]);
        if (glm::dot(mesh.geometricNormal(t), mesh.centroid(t) - axis) < 0.0)
            flipTriangle(mesh, t);
    }
    return mesh;
}

}  // namespace pmcr::scenegen
