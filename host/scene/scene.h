// The scene on the host: flattened world-space triangles, materials, textures and cameras,
// as produced by the glTF loader and consumed by the BVH builder and the GPU upload.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "image/image.h"
#include "shared/host_device.h"

namespace pmcr {

// A pinhole camera in world space. forward/up/right are orthonormal, right = cross(forward, up).
struct Camera {
    std::string name;
    glm::vec3 position{0.0f};
    glm::vec3 forward{0.0f, 0.0f, -1.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    glm::vec3 right{1.0f, 0.0f, 0.0f};
    float yfov = 0.8f;    // vertical field of view, radians
    float aspect = 0.0f;  // width / height from the file; 0 when the file does not say
};

// An 8-bit texture, RGBA packed little-endian (R in the low byte): colour textures
// (baseColorTexture, emissiveTexture) hold sRGB-encoded values, data textures (metallicRoughness,
// normal) linear ones. Sampled as the kernels do by host/scene/texture_lookup.h.
struct Texture {
    std::string name;
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<uint32_t> rgba8;
    uint32_t wrap = 0;  // gpu::TextureInfo::wrap: its sampler's wrap modes
};

// The environment light (--env; host/scene/environment.h): radiance arriving from infinitely
// far, a constant or an equirectangular (latitude-longitude) image with +y up, rotated about +y.
struct Environment {
    std::string source;            // what --env named, for messages; empty: no environment
    uint32_t kind = gpu::ENV_NONE;
    glm::vec3 radiance{0.0f};      // ENV_CONSTANT: the radiance, scale applied
    Image image;                   // ENV_IMAGE: RGB radiance, scale not applied
    float scale = 1.0f;
    float rotation = 0.0f;         // radians about +y
};

struct Scene {
    std::filesystem::path path;            // the file it was loaded from
    std::vector<gpu::Vertex> vertices;     // world space
    std::vector<gpu::Triangle> triangles;  // all triangles, world space, front face = CCW winding
    std::vector<gpu::Material> materials;
    std::vector<std::string> materialNames;
    std::vector<Texture> textures;
    std::vector<Camera> cameras;           // cameras in node order; never empty after loading
    int defaultWidth = 0;                  // image size the scene asks for (extras), 0 = pmcr default
    int defaultHeight = 0;
    int paperWidth = 0;                    // size the paper rendered it at (extras; --paper-size)
    int paperHeight = 0;
    glm::vec3 boundsMin{0.0f};
    glm::vec3 boundsMax{0.0f};
    Environment environment;               // set before finalizeScene (loadScene's EnvironmentSpec)
    std::vector<gpu::PunctualLight> punctualLights;  // KHR_lights_punctual, world space
    std::vector<std::string> punctualLightNames;     // for messages ("light 2 ('sun')"); may be empty
    // Per vertex, for normal maps: the tangent (world space) and the bitangent's sign in w
    // (glTF TANGENT, or generated: host/scene/tangents.h). Empty when no material has a
    // normalTexture.
    std::vector<glm::vec4> tangents;
    // Per triangle, the luminance of its mean emitted radiance (emission times the mean of its
    // emissiveTexture over the triangle), set by finalizeScene when an emitter has an
    // emissiveTexture; empty otherwise (the emission is then the material's alone).
    std::vector<float> triangleEmission;
};

// The gpu::SCENE_FEATURE_* bits the scene uses: the kernels are specialized for them.
uint32_t sceneFeatures(const Scene& scene);

// Emitters: every triangle whose material has non-zero emission, in a Walker alias table over
// emitted power (area * luminance(Le) * pi * sides), and the total power.
struct EmitterTable {
    std::vector<gpu::Emitter> emitters;
    float totalPower = 0.0f;
};
EmitterTable buildEmitters(const Scene& scene);

// Fills pmf, aliasThreshold and alias of `table` (one entry per element of `power`, alias
// indices relative to the table's start; `triangle` is left to the caller) and returns the
// total power: a Walker alias table (shaders/common/scene.glsl aliasTableTriangle).
double buildAliasTable(const std::vector<double>& power, gpu::Emitter* table);

// Lights as the adaptive direct-lighting sampler (PMC-HI) sees them: the emitters grouped into
// connected components (triangles sharing a vertex position, union-find), each with an alias
// table over its own triangles' power; and, per scene triangle, its light (gpu::LIGHT_NONE when
// it does not emit). Lights are numbered by their first triangle in scene order.
struct LightGroupTable {
    std::vector<gpu::LightGroup> lights;
    gpu::LightGroup allEmitters{};        // every emitter (buildEmitters' table): light sampling
    std::vector<gpu::Emitter> emitters;   // alias tables, one range per light, then allEmitters'
    std::vector<uint32_t> triangleLight;  // one per scene triangle
    // The groups as the device has them: the lights, then allEmitters (index lights.size()).
    std::vector<gpu::LightGroup> deviceGroups() const;
};
LightGroupTable buildLightGroups(const Scene& scene);

// Power of a punctual light, its intensity reduced to luminance (pbrt-v4 PointLight, SpotLight
// and DistantLight::Phi; a directional light's through the scene's bounding disk of radius
// sceneRadius): light sampling picks the lights in proportion to it.
double punctualLightPower(const gpu::PunctualLight& light, float sceneRadius);

// Power of an emitter triangle, area * luminance of its mean emission * pi * sides, and the
// luminance it uses (the material's emission, or scene.triangleEmission with emissive
// textures). The kernels compute the same for MIS: shaders/common/lights.glsl.
float emitterPower(const Scene& scene, uint32_t triangle);
float emitterLuminance(const Scene& scene, uint32_t triangle);

// Recomputes bounds; throws pmcr::Error naming scene.path for NaN/Inf positions, no triangles
// or no light (no emitters, punctual lights or environment, or all of them together of zero
// power, e.g. --env 0,0,0 or --env-scale 0 as the only light), and naming the light whose power
// overflows 32-bit floats (the device's; at the scene's radius and at least at radius 1), or
// when their total does; drops zero-area triangles with one warning; computes
// triangleEmission for emissive textures.
void finalizeScene(Scene& scene);

float luminance(const glm::vec3& rgb);  // Rec. 709 / sRGB primaries

}  // namespace pmcr
