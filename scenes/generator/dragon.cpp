#include "dragon.h"

#include <limits>

#include "core/error.h"
#include "source_glb.h"

namespace pmcr::scenegen {

ObjectDesc dragonObject(const SceneContext& context, int material) {
    const auto path = context.assets / "meshes/stanford_dragon_res2.glb";
    const SourceGlb source = readSourceGlb(path);
    if (source.primitives.size() != 1)
        fail(path.string(), "expected one primitive (the dragon)");
    Mesh mesh = source.primitives[0].mesh;
    mesh.name = "Dragon";
    mesh.normals.clear();

    constexpr double kScale = 10.0;
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const auto& p : mesh.positions) {
        lo = glm::min(lo, kScale * glm::dvec3(p));
        hi = glm::max(hi, kScale * glm::dvec3(p));
    }
    const glm::dvec3 offset(-0.5 * (lo.x + hi.x), -lo.y, -0.5 * (lo.z + hi.z));
    for (auto& p : mesh.positions)
        p = glm::vec3(kScale * glm::dvec3(p) + offset);
    return {std::move(mesh), material, kDragonUri};
}

}  // namespace pmcr::scenegen
