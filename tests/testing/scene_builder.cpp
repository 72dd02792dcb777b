#include "scene_builder.h"

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

}  // namespace pmcr::test
