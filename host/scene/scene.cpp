#include "scene/scene.h"

#include <cmath>
#include <string>
#include <vector>

#include <glm/gtc/constants.hpp>

#include "core/error.h"
#include "core/log.h"

namespace pmcr {

namespace {

float triangleArea(const Scene& scene, const gpu::Triangle& t) {
    const glm::vec3& p0 = scene.vertices[t.i0].position;
    const glm::vec3& p1 = scene.vertices[t.i1].position;
    const glm::vec3& p2 = scene.vertices[t.i2].position;
    return 0.5f * glm::length(glm::cross(p1 - p0, p2 - p0));
}

bool isFinite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

float luminance(const glm::vec3& rgb) {
    // Rec. ITU-R BT.709 relative luminance.
    return 0.2126f * rgb.r + 0.7152f * rgb.g + 0.0722f * rgb.b;
}

float emitterPower(const Scene& scene, uint32_t triangle) {
    const gpu::Triangle& t = scene.triangles[triangle];
    const gpu::Material& m = scene.materials[t.material];
    const float sides = (m.flags & gpu::MATERIAL_DOUBLE_SIDED) ? 2.0f : 1.0f;
    // Power of a diffuse area light, Phi = pi * A * L per emitting side (pbrt-v4,
    // DiffuseAreaLight::Phi), with L reduced to its luminance.
    return triangleArea(scene, t) * luminance(m.emission) * glm::pi<float>() * sides;
}

EmitterTable buildEmitters(const Scene& scene) {
    EmitterTable table;
    std::vector<double> power;
    for (uint32_t t = 0; t < scene.triangles.size(); ++t) {
        const float p = emitterPower(scene, t);
        if (p > 0.0f && std::isfinite(p)) {
            table.emitters.push_back({t, 0.0f, 1.0f, uint32_t(power.size())});
            power.push_back(p);
        }
    }
    const size_t n = power.size();
    if (n == 0)
        return table;
    double total = 0.0;
    for (double p : power)
        total += p;
    table.totalPower = float(total);

    // Vose's alias method (Vose 1991, "A linear algorithm for generating random numbers with a
    // given distribution"): pair each under-full slot with an over-full donor.
    std::vector<double> scaled(n);
    std::vector<uint32_t> small, large;
    for (size_t i = 0; i < n; ++i) {
        table.emitters[i].pmf = float(power[i] / total);
        scaled[i] = power[i] / total * double(n);
        (scaled[i] < 1.0 ? small : large).push_back(uint32_t(i));
    }
    while (!small.empty() && !large.empty()) {
        const uint32_t s = small.back();
        small.pop_back();
        const uint32_t l = large.back();
        table.emitters[s].aliasThreshold = float(scaled[s]);
        table.emitters[s].alias = l;
        scaled[l] = (scaled[l] + scaled[s]) - 1.0;
        if (scaled[l] < 1.0) {
            large.pop_back();
            small.push_back(l);
        }
    }
    // Slots left in either list are full up to rounding: they always keep themselves.
    for (const auto* rest : {&small, &large}) {
        for (uint32_t i : *rest) {
            table.emitters[i].aliasThreshold = 1.0f;
            table.emitters[i].alias = i;
        }
    }
    return table;
}

void finalizeScene(Scene& scene) {
    const std::string file = scene.path.string();
    for (size_t i = 0; i < scene.vertices.size(); ++i) {
        if (!isFinite(scene.vertices[i].position)) {
            fail(file, "vertex " + std::to_string(i) + " has a non-finite (NaN or Inf) position");
        }
    }
    for (size_t m = 0; m < scene.materials.size(); ++m) {
        const glm::vec3& e = scene.materials[m].emission;
        if (!isFinite(e) || e.r < 0.0f || e.g < 0.0f || e.b < 0.0f) {
            fail(file, "material " + std::to_string(m) + " has a negative or non-finite emission");
        }
    }
    const size_t vertexCount = scene.vertices.size();
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const gpu::Triangle& t = scene.triangles[i];
        if (t.i0 >= vertexCount || t.i1 >= vertexCount || t.i2 >= vertexCount) {
            fail(file, "triangle " + std::to_string(i) + " references a vertex out of range");
        }
        if (t.material >= scene.materials.size()) {
            fail(file, "triangle " + std::to_string(i) + " references material " +
                           std::to_string(t.material) + " out of range");
        }
    }

    // Drop triangles without a usable area (zero, NaN or overflowing to Inf).
    const size_t loaded = scene.triangles.size();
    std::vector<gpu::Triangle> kept;
    kept.reserve(loaded);
    for (const gpu::Triangle& t : scene.triangles) {
        const float area = triangleArea(scene, t);
        if (area > 0.0f && std::isfinite(area))
            kept.push_back(t);
    }
    const size_t dropped = loaded - kept.size();
    if (kept.empty()) {
        if (dropped > 0) {
            fail(file, "no triangles left: all " + std::to_string(dropped) +
                           " triangles are degenerate (zero area)");
        }
        fail(file, "no triangles: the scene has no triangle geometry");
    }
    if (dropped > 0) {
        log::warning(file + ": dropped " + std::to_string(dropped) + " of " +
                     std::to_string(loaded) + " triangles with zero area");
    }
    scene.triangles = std::move(kept);

    bool anyEmitter = false;
    for (const gpu::Triangle& t : scene.triangles) {
        if (luminance(scene.materials[t.material].emission) > 0.0f) {
            anyEmitter = true;
            break;
        }
    }
    if (!anyEmitter) {
        fail(file,
             "no emitters: the scene has no emissive triangles (pmcr renders only area lights)");
    }

    scene.boundsMin = glm::vec3(INFINITY);
    scene.boundsMax = glm::vec3(-INFINITY);
    for (const gpu::Triangle& t : scene.triangles) {
        for (uint32_t i : {t.i0, t.i1, t.i2}) {
            scene.boundsMin = glm::min(scene.boundsMin, scene.vertices[i].position);
            scene.boundsMax = glm::max(scene.boundsMax, scene.vertices[i].position);
        }
    }
}

}  // namespace pmcr
