#include "scene_builder.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <utility>

namespace pmcr::test {

gpu::Material testMaterial(const glm::vec3& emission, bool doubleSided, float roughness) {
    gpu::Material m{};
    m.baseColor = glm::vec3(0.5f);
    m.baseColorTexture = -1;
    m.emission = emission;
    m.flags = doubleSided ? gpu::MATERIAL_DOUBLE_SIDED : 0u;
    m.roughness = roughness;
    m.ior = 1.5f;
    return m;
}

void addTriangle(Scene& scene, const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
                 uint32_t material) {
    const uint32_t base = uint32_t(scene.vertices.size());
    for (const glm::vec3& p : {p0, p1, p2}) {
        gpu::Vertex v{};
        v.position = p;
        scene.vertices.push_back(v);
    }
    scene.triangles.push_back({base, base + 1, base + 2, material});
}

Texture normalTexel(const std::string& name, const glm::vec3& n) {
    const glm::vec3 stored = (glm::normalize(n) + 1.0f) * 0.5f;
    auto byte = [](float v) { return uint32_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    Texture t;
    t.name = name;
    t.rgba8 = {0xFF000000u | (byte(stored.z) << 16) | (byte(stored.y) << 8) | byte(stored.x)};
    t.width = 1;
    t.height = 1;
    return t;
}

void setPlanarTangents(Scene& scene) {
    scene.tangents.assign(scene.vertices.size(), glm::vec4(1, 0, 0, 1));
    for (const gpu::Triangle& t : scene.triangles) {
        const glm::vec3 p0 = scene.vertices[t.i0].position, p1 = scene.vertices[t.i1].position,
                        p2 = scene.vertices[t.i2].position;
        const glm::vec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
        const glm::vec3 helper = std::abs(n.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
        const glm::vec4 tangent(glm::normalize(glm::cross(n, helper)), 1.0f);
        for (uint32_t i : {t.i0, t.i1, t.i2}) scene.tangents[i] = tangent;
    }
}

void addSphere(Scene& scene, const glm::vec3& center, float radius, int rings, int segments,
               uint32_t material) {
    auto point = [&](int i, int j) {
        const double theta = std::numbers::pi * i / rings, phi = 2.0 * std::numbers::pi * j / segments;
        return center + radius * glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                           std::sin(theta) * std::sin(phi));
    };
    auto outward = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
        if (glm::dot(glm::cross(b - a, c - a), a + b + c - 3.0f * center) < 0.0f) std::swap(b, c);
        addTriangle(scene, a, b, c, material);
    };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const glm::vec3 p00 = point(i, j), p01 = point(i, j + 1), p10 = point(i + 1, j),
                            p11 = point(i + 1, j + 1);
            if (i > 0) outward(p00, p10, p01);
            if (i < rings - 1) outward(p01, p10, p11);
        }
}

Environment randomSkyImage(uint32_t seed, float blackFraction, const glm::vec3& scale, int width,
                           int height) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Environment env;
    env.source = "random-sky.exr";
    env.kind = gpu::ENV_IMAGE;
    env.image = Image(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            if (blackFraction > 0.0f && u(rng) < blackFraction) {
                env.image.set(x, y, glm::vec3(0.0f));
                continue;
            }
            const float b = u(rng), g = u(rng), r = u(rng);
            env.image.set(x, y, glm::vec3(r, g, b) * scale);
        }
    return env;
}

gpu::PunctualLight punctualLight(uint32_t type, const glm::vec3& position, const glm::vec3& direction,
                                 const glm::vec3& intensity, float inner, float outer) {
    gpu::PunctualLight l{};
    l.type = type;
    l.position = position;
    l.direction = glm::normalize(direction);
    l.intensity = intensity;
    l.cosInner = std::cos(inner);
    l.cosOuter = std::cos(outer);
    return l;
}

}  // namespace pmcr::test
