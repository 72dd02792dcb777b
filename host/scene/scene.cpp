#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <map>
#include <tuple>
#include <string>
#include <vector>

#include <glm/gtc/constants.hpp>

#include "core/error.h"
#include "core/log.h"
#include "scene/environment.h"
#include "scene/texture_lookup.h"

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

// Whether material m has a GGX lobe (shaders/common/bsdf.glsl makeBsdf): its alpha = roughness^2
// is not below SMOOTH_ALPHA (or a texture may make it so) and it has a conductor, glass, or
// coated base part (the base is Lambertian alone at roughness 1), or a rough clear coat.
bool hasGlossyLobe(const gpu::Material& m) {
    if (m.metallicRoughnessTexture != 0) return true;
    // A rough clear coat (KHR_materials_clearcoat), or one a texture may make rough.
    if (m.clearcoat > 0.0f && (m.clearcoatRoughnessTexture != 0 ||
                               m.clearcoatRoughness * m.clearcoatRoughness >= gpu::SMOOTH_ALPHA))
        return true;
    if (m.roughness * m.roughness < gpu::SMOOTH_ALPHA) return false;
    return m.metallic > 0.0f || m.transmission > 0.0f || m.roughness < 1.0f;
}

}  // namespace

float luminance(const glm::vec3& rgb) {
    // Rec. ITU-R BT.709 relative luminance.
    return 0.2126f * rgb.r + 0.7152f * rgb.g + 0.0722f * rgb.b;
}

float emitterLuminance(const Scene& scene, uint32_t triangle) {
    if (!scene.triangleEmission.empty()) return scene.triangleEmission[triangle];
    return luminance(scene.materials[scene.triangles[triangle].material].emission);
}

float emitterPower(const Scene& scene, uint32_t triangle) {
    const gpu::Triangle& t = scene.triangles[triangle];
    const gpu::Material& m = scene.materials[t.material];
    const float sides = (m.flags & gpu::MATERIAL_DOUBLE_SIDED) ? 2.0f : 1.0f;
    // Power of a diffuse area light, Phi = pi * A * L per emitting side (pbrt-v4,
    // DiffuseAreaLight::Phi), with L reduced to its luminance (its mean over a textured one).
    return triangleArea(scene, t) * emitterLuminance(scene, triangle) * glm::pi<float>() * sides;
}

uint32_t sceneFeatures(const Scene& scene) {
    uint32_t features = 0;
    bool glossy = false, transmission = false, blend = false, thin = false, specular = false,
         clearcoat = false, sheen = false, clearcoatNormals = false;
    for (const gpu::Material& m : scene.materials) {
        blend = blend || (m.flags & gpu::MATERIAL_BLEND) != 0;
        thin = thin || ((m.flags & gpu::MATERIAL_THIN_WALLED) != 0 && m.transmission > 0.0f);
        specular = specular || (m.flags & gpu::MATERIAL_SPECULAR) != 0;
        clearcoat = clearcoat || m.clearcoat > 0.0f;
        sheen = sheen || m.sheenColor != glm::vec3(0.0f);
        if (m.normalTexture != 0) features |= gpu::SCENE_FEATURE_NORMAL_MAPS;
        // A coat whose normal may not be the shading normal (shaders/common/bsdf.glsl
        // clearcoatNormal): its own normal map, or the material's that the coat does not take.
        clearcoatNormals = clearcoatNormals || (m.clearcoat > 0.0f && (m.clearcoatNormalTexture != 0 ||
                                                                       m.normalTexture != 0));
        if (m.alphaCutoff > 0.0f) features |= gpu::SCENE_FEATURE_ALPHA_MASKS;
        if (m.absorption != glm::vec3(0.0f)) features |= gpu::SCENE_FEATURE_ABSORPTION;
        if (hasGlossyLobe(m)) glossy = true;
        if (m.transmission > 0.0f) transmission = true;
    }
    if (!glossy) features |= gpu::SCENE_FEATURE_NO_GLOSSY;
    if (!transmission) features |= gpu::SCENE_FEATURE_NO_TRANSMISSION;
    if (!blend) features |= gpu::SCENE_FEATURE_NO_BLEND;
    if (!thin) features |= gpu::SCENE_FEATURE_NO_THIN;
    if (!specular) features |= gpu::SCENE_FEATURE_NO_SPECULAR;
    if (!clearcoat) features |= gpu::SCENE_FEATURE_NO_CLEARCOAT;
    if (!sheen) features |= gpu::SCENE_FEATURE_NO_SHEEN;
    if (!clearcoatNormals) features |= gpu::SCENE_FEATURE_NO_CLEARCOAT_NORMALS;
    if (!scene.triangleEmission.empty()) features |= gpu::SCENE_FEATURE_EMISSIVE_TEXTURES;
    if (scene.tangents.size() != scene.vertices.size()) {
        // No normal map is read: every coat normal is the interpolated one, the shading normal.
        features &= ~gpu::SCENE_FEATURE_NORMAL_MAPS;
        features |= gpu::SCENE_FEATURE_NO_CLEARCOAT_NORMALS;
    }
    return features;
}

// Vose's alias method (Vose 1991, "A linear algorithm for generating random numbers with a
// given distribution"): pair each under-full slot with an over-full donor.
double buildAliasTable(const std::vector<double>& power, gpu::Emitter* table) {
    const size_t n = power.size();
    double total = 0.0;
    for (double p : power)
        total += p;
    std::vector<double> scaled(n);
    std::vector<uint32_t> small, large;
    for (size_t i = 0; i < n; ++i) {
        table[i].pmf = float(power[i] / total);
        scaled[i] = power[i] / total * double(n);
        (scaled[i] < 1.0 ? small : large).push_back(uint32_t(i));
    }
    while (!small.empty() && !large.empty()) {
        const uint32_t s = small.back();
        small.pop_back();
        const uint32_t l = large.back();
        table[s].aliasThreshold = float(scaled[s]);
        table[s].alias = l;
        scaled[l] = (scaled[l] + scaled[s]) - 1.0;
        if (scaled[l] < 1.0) {
            large.pop_back();
            small.push_back(l);
        }
    }
    // Slots left in either list are full up to rounding: they always keep themselves.
    for (const auto* rest : {&small, &large}) {
        for (uint32_t i : *rest) {
            table[i].aliasThreshold = 1.0f;
            table[i].alias = i;
        }
    }
    return total;
}

double punctualLightPower(const gpu::PunctualLight& light, float sceneRadius) {
    const double pi = std::numbers::pi;
    const double I = luminance(light.intensity);
    switch (light.type) {
        case gpu::PUNCTUAL_POINT:
            return 4.0 * pi * I;
        case gpu::PUNCTUAL_SPOT:  // the cone's solid angle, the smooth falloff counted as half
            return 2.0 * pi * I * (1.0 - 0.5 * (double(light.cosInner) + double(light.cosOuter)));
        default:
            return pi * double(sceneRadius) * double(sceneRadius) * I;
    }
}

namespace {

// Union-find with path halving.
uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

}  // namespace

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
    if (power.empty())
        return table;
    table.totalPower = float(buildAliasTable(power, table.emitters.data()));
    return table;
}

LightGroupTable buildLightGroups(const Scene& scene) {
    LightGroupTable out;
    out.triangleLight.assign(scene.triangles.size(), gpu::LIGHT_NONE);
    std::vector<uint32_t> emissive;
    std::vector<double> power;
    for (uint32_t t = 0; t < scene.triangles.size(); ++t) {
        const float p = emitterPower(scene, t);
        if (p > 0.0f && std::isfinite(p)) {
            emissive.push_back(t);
            power.push_back(p);
        }
    }
    // Union emitters that share a vertex position (meshes often duplicate vertices per face).
    const size_t n = emissive.size();
    std::vector<uint32_t> parent(n);
    for (size_t i = 0; i < n; ++i)
        parent[i] = uint32_t(i);
    std::map<std::tuple<float, float, float>, uint32_t> owner;
    for (size_t i = 0; i < n; ++i) {
        const gpu::Triangle& tri = scene.triangles[emissive[i]];
        for (uint32_t v : {tri.i0, tri.i1, tri.i2}) {
            const glm::vec3& p = scene.vertices[v].position;
            auto [it, inserted] = owner.try_emplace({p.x, p.y, p.z}, uint32_t(i));
            if (!inserted) parent[findRoot(parent, uint32_t(i))] = findRoot(parent, it->second);
        }
    }
    // Number the lights by their first triangle; list each light's emitters in scene order.
    std::vector<uint32_t> lightOfRoot(n, gpu::LIGHT_NONE);
    std::vector<std::vector<uint32_t>> members;
    for (size_t i = 0; i < n; ++i) {
        const uint32_t root = findRoot(parent, uint32_t(i));
        if (lightOfRoot[root] == gpu::LIGHT_NONE) {
            lightOfRoot[root] = uint32_t(members.size());
            members.emplace_back();
        }
        members[lightOfRoot[root]].push_back(uint32_t(i));
    }
    for (uint32_t l = 0; l < members.size(); ++l) {
        gpu::LightGroup group{};
        group.firstEmitter = uint32_t(out.emitters.size());
        group.emitterCount = uint32_t(members[l].size());
        std::vector<double> groupPower;
        for (uint32_t i : members[l]) {
            out.emitters.push_back({emissive[i], 0.0f, 1.0f, 0u});
            groupPower.push_back(power[i]);
            out.triangleLight[emissive[i]] = l;
        }
        group.power = float(buildAliasTable(groupPower, out.emitters.data() + group.firstEmitter));
        out.lights.push_back(group);
    }
    // The group of all emitters is buildEmitters' table (its aliases are relative to its start,
    // like a group's), the one light sampling uses (shaders/common/lights.glsl sampleLight).
    const EmitterTable all = buildEmitters(scene);
    out.allEmitters.firstEmitter = uint32_t(out.emitters.size());
    out.allEmitters.emitterCount = uint32_t(all.emitters.size());
    out.allEmitters.power = all.totalPower;
    out.emitters.insert(out.emitters.end(), all.emitters.begin(), all.emitters.end());
    return out;
}

std::vector<gpu::LightGroup> LightGroupTable::deviceGroups() const {
    std::vector<gpu::LightGroup> groups = lights;
    groups.push_back(allEmitters);
    return groups;
}

namespace {

std::string materialLabel(const Scene& scene, size_t m) {
    const std::string index = "material " + std::to_string(m);
    if (m >= scene.materialNames.size() || scene.materialNames[m].empty() ||
        scene.materialNames[m] == index)
        return index;
    return index + " ('" + scene.materialNames[m] + "')";
}

std::string punctualLabel(const Scene& scene, size_t i) {
    if (i < scene.punctualLightNames.size() && !scene.punctualLightNames[i].empty())
        return scene.punctualLightNames[i];
    return "punctual light " + std::to_string(i);
}

std::string powerText(double power) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.3g", power);
    return text;
}

// The lights as the device will sum and sample them, in 32-bit floats (buildEmitters,
// chooseLights, the kernels): a light whose power overflows renders black or as NaN samples
// that are dropped (a point light of intensity 3e38: 4 pi I is infinite), so it is refused by
// name; and a scene whose lights together have no power (--env 0,0,0 or --env-scale 0 as its only
// light, an emitter whose texture is black) can only render black, so it is refused like a scene
// without light. A directional light's and the environment's power grow with the scene's radius
// R (pi R^2 times their irradiance): they are checked at max(R, 1), so that whether a light
// overflows does not depend on the scene's units.
void checkLightPower(const Scene& scene) {
    const std::string file = scene.path.string();
    const double largest = double(std::numeric_limits<float>::max());
    const float radius = std::max(0.5f * glm::length(scene.boundsMax - scene.boundsMin), 1.0f);
    double total = 0.0;
    for (uint32_t t = 0; t < scene.triangles.size(); ++t) {
        const float power = emitterPower(scene, t);
        if (!std::isfinite(power)) {
            fail(file, materialLabel(scene, scene.triangles[t].material) +
                           ": the power of its triangle " + std::to_string(t) +
                           " overflows 32-bit floats");
        }
        total += double(power);
    }
    if (total > largest) fail(file, "the emitters' total power overflows 32-bit floats");
    for (size_t i = 0; i < scene.punctualLights.size(); ++i) {
        const gpu::PunctualLight& light = scene.punctualLights[i];
        const double power = punctualLightPower(light, radius);
        if (!std::isfinite(luminance(light.intensity)) || !(power <= largest)) {
            fail(file, punctualLabel(scene, i) + ": its power overflows 32-bit floats (intensity " +
                           powerText(double(luminance(light.intensity))) + ")");
        }
        total += power;
    }
    if (scene.environment.kind != gpu::ENV_NONE) {
        const double power = environmentPower(scene.environment, radius);
        if (!(power <= largest)) {
            fail(file, "environment '" + scene.environment.source +
                           "': its power overflows 32-bit floats (" + powerText(power) +
                           " at radius " + powerText(radius) + ")");
        }
        total += power;
    }
    if (!(total <= largest)) fail(file, "the lights' total power overflows 32-bit floats");
    if (total == 0.0) {
        fail(file, "no light: its emitters, punctual lights and environment together have zero "
                   "power (a black --env, --env-scale 0 or black emission)");
    }
}

}  // namespace

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
            fail(file, materialLabel(scene, m) + " has a negative or non-finite emission");
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

    // Emitters with an emissiveTexture: light selection by the power of the textured emission,
    // averaged over each triangle (the kernels sample a point uniformly in its area).
    scene.triangleEmission.clear();
    bool emissiveTextures = false;
    for (const gpu::Material& m : scene.materials) {
        if (m.emissiveTexture > scene.textures.size()) {
            fail(file, "a material's emissiveTexture is out of range");
        }
        emissiveTextures |= m.emissiveTexture != 0 && luminance(m.emission) > 0.0f;
    }
    if (emissiveTextures) {
        scene.triangleEmission.resize(scene.triangles.size());
        for (size_t i = 0; i < scene.triangles.size(); ++i) {
            const gpu::Triangle& t = scene.triangles[i];
            const gpu::Material& m = scene.materials[t.material];
            glm::vec3 mean(1.0f);
            if (m.emissiveTexture != 0 && luminance(m.emission) > 0.0f) {
                auto uv = [&](uint32_t v) { return glm::vec2(scene.vertices[v].u, scene.vertices[v].v); };
                mean = meanOverTriangle(scene.textures[m.emissiveTexture - 1], uv(t.i0), uv(t.i1),
                                        uv(t.i2), true);
            }
            scene.triangleEmission[i] = luminance(m.emission * mean);
        }
    }

    bool anyEmitter = false;
    for (const gpu::Triangle& t : scene.triangles) {
        if (luminance(scene.materials[t.material].emission) > 0.0f) {
            anyEmitter = true;
            break;
        }
    }
    if (!anyEmitter && scene.punctualLights.empty() && scene.environment.kind == gpu::ENV_NONE) {
        fail(file, "no emitters: the scene has no emissive triangles and no punctual lights "
                   "(light it with --env R,G,B or --env FILE, an environment light)");
    }

    scene.boundsMin = glm::vec3(INFINITY);
    scene.boundsMax = glm::vec3(-INFINITY);
    for (const gpu::Triangle& t : scene.triangles) {
        for (uint32_t i : {t.i0, t.i1, t.i2}) {
            scene.boundsMin = glm::min(scene.boundsMin, scene.vertices[i].position);
            scene.boundsMax = glm::max(scene.boundsMax, scene.vertices[i].position);
        }
    }
    checkLightPower(scene);
}

}  // namespace pmcr
