#include "scene/tangents.h"

#include <algorithm>
#include <cmath>

namespace pmcr {

std::vector<glm::vec4> generateTangents(std::span<const gpu::Vertex> vertices,
                                        std::span<const glm::uvec3> triangles) {
    const size_t n = vertices.size();
    std::vector<glm::dvec3> tangent(n, glm::dvec3(0.0)), bitangent(n, glm::dvec3(0.0)),
        faceNormal(n, glm::dvec3(0.0));
    for (const glm::uvec3& t : triangles) {
        const gpu::Vertex* v[3] = {&vertices[t.x], &vertices[t.y], &vertices[t.z]};
        const glm::dvec3 e1 = glm::dvec3(v[1]->position - v[0]->position);
        const glm::dvec3 e2 = glm::dvec3(v[2]->position - v[0]->position);
        const glm::dvec2 d1(double(v[1]->u) - v[0]->u, double(v[1]->v) - v[0]->v);
        const glm::dvec2 d2(double(v[2]->u) - v[0]->u, double(v[2]->v) - v[0]->v);
        const double r = d1.x * d2.y - d2.x * d1.y;
        const glm::dvec3 ng = glm::cross(e1, e2);
        if (r == 0.0 || !std::isfinite(r) || glm::length(ng) == 0.0) continue;
        // p - p0 = e1 s + e2 t with (u, v) - (u0, v0) = d1 s + d2 t: dp/du and dp/dv.
        const glm::dvec3 dpdu = (e1 * d2.y - e2 * d1.y) / r;
        const glm::dvec3 dpdv = (e2 * d1.x - e1 * d2.x) / r;
        if (!(glm::length(dpdu) > 0.0) || !(glm::length(dpdv) > 0.0)) continue;
        const glm::dvec3 tu = glm::normalize(dpdu), tv = glm::normalize(dpdv);
        const uint32_t index[3] = {t.x, t.y, t.z};
        for (int c = 0; c < 3; ++c) {
            const glm::dvec3 a = glm::dvec3(v[(c + 1) % 3]->position - v[c]->position);
            const glm::dvec3 b = glm::dvec3(v[(c + 2) % 3]->position - v[c]->position);
            const double la = glm::length(a), lb = glm::length(b);
            if (la == 0.0 || lb == 0.0) continue;
            const double angle = std::acos(std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0));
            tangent[index[c]] += angle * tu;
            bitangent[index[c]] += angle * tv;
            faceNormal[index[c]] += angle * glm::normalize(ng);
        }
    }
    std::vector<glm::vec4> out(n, glm::vec4(0.0f));
    for (size_t i = 0; i < n; ++i) {
        glm::dvec3 N = glm::dvec3(vertices[i].normal);
        if (glm::length(N) == 0.0) N = faceNormal[i];
        if (!(glm::length(N) > 0.0)) continue;
        N = glm::normalize(N);
        glm::dvec3 T = tangent[i] - N * glm::dot(N, tangent[i]);
        if (!(glm::length(T) > 1e-12)) continue;
        T = glm::normalize(T);
        // cross(N, T) against dp/dv: opposite (the usual case, v down the image) gives w = +1.
        const double w = glm::dot(glm::cross(N, T), bitangent[i]) > 0.0 ? -1.0 : 1.0;
        out[i] = glm::vec4(glm::vec3(T), float(w));
    }
    return out;
}

}  // namespace pmcr
