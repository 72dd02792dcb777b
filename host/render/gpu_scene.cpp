#include "render/gpu_scene.h"

#include <chrono>

#include "core/error.h"
#include "scene/environment.h"
#include "scene/light_choice.h"

namespace pmcr {

gpu::SceneInfo makeSceneInfo(const Scene& scene, int camera, int width, int height) {
    if (camera < 0 || camera >= int(scene.cameras.size()))
        fail(scene.path.string(), "--camera " + std::to_string(camera) + " out of range (the scene has " +
                                      std::to_string(scene.cameras.size()) + " camera(s))");
    const Camera& c = scene.cameras[size_t(camera)];
    gpu::SceneInfo info{};
    info.cameraPosition = c.position;
    info.tanHalfFovY = std::tan(0.5f * c.yfov);
    info.cameraRight = c.right;
    info.aspect = float(width) / float(height);
    info.cameraUp = c.up;
    info.width = uint32_t(width);
    info.cameraForward = c.forward;
    info.height = uint32_t(height);
    info.sceneCenter = 0.5f * (scene.boundsMin + scene.boundsMax);
    info.sceneRadius = 0.5f * glm::length(scene.boundsMax - scene.boundsMin);
    info.triangleCount = uint32_t(scene.triangles.size());
    return info;
}

GpuScene::GpuScene(vk::Context& context, const vk::PipelineLayout& layout, const Scene& scene,
                   int camera, int width, int height)
    : m_scene(scene) {
    m_info = makeSceneInfo(scene, camera, width, height);
    m_features = sceneFeatures(scene);
    auto start = std::chrono::steady_clock::now();
    m_bvh = Bvh::build(scene);
    m_bvhSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    m_lightGroups = buildLightGroups(scene);
    m_info.lightCount = uint32_t(m_lightGroups.lights.size());
    m_info.nodeCount = uint32_t(m_bvh.nodes().size());
    // The group of all emitters is buildEmitters' table, so its power is the emitters' total.
    m_info.totalEmitterPower = m_lightGroups.allEmitters.power;

    // The environment and the punctual lights, and how light sampling picks among all lights.
    const Environment& env = scene.environment;
    m_info.envKind = env.kind;
    m_info.envRadiance = env.kind == gpu::ENV_CONSTANT ? env.radiance : glm::vec3(env.scale);
    m_info.envRotation = env.rotation;
    m_info.envWidth = uint32_t(env.image.width);
    m_info.envHeight = uint32_t(env.image.height);
    m_info.punctualCount = uint32_t(scene.punctualLights.size());
    const LightChoice choice = chooseLights(scene, m_info.totalEmitterPower, m_info.sceneRadius);
    m_info.envSelectPmf = choice.envPmf;
    m_info.punctualSelectPmf = choice.punctualPmf;
    std::vector<glm::vec4> envTexels;
    for (int y = 0; y < env.image.height; ++y)
        for (int x = 0; x < env.image.width; ++x) envTexels.emplace_back(env.image.at(x, y), 0.0f);

    std::vector<gpu::TextureInfo> textureInfos;
    std::vector<uint32_t> texels;
    for (const Texture& t : scene.textures) {
        textureInfos.push_back({uint32_t(texels.size()), t.width, t.height, t.wrap});
        texels.insert(texels.end(), t.rgba8.begin(), t.rgba8.end());
    }

    // The read-only tables the kernels fetch as 16-byte uint texels (shaders/common/scene.glsl).
    auto uintTexels = [&](const auto& values, const char* name) {
        return vk::Buffer::texels(context, values, VK_FORMAT_R32G32B32A32_UINT, name);
    };
    try {
        m_infoBuffer = vk::Buffer(context, sizeof(gpu::SceneInfo), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                  "scene info");
        m_infoBuffer.upload(&m_info, sizeof(m_info));
        m_vertices = vk::Buffer::texels(context, scene.vertices, VK_FORMAT_R32G32B32A32_SFLOAT,
                                        "vertex buffer");
        m_triangles = uintTexels(scene.triangles, "triangle buffer");
        m_bvhTexels = uintTexels(m_bvh.deviceTexels(), "BVH texel buffer");
        m_materials = uintTexels(scene.materials, "material buffer");
        m_lightGroupBuffer = uintTexels(m_lightGroups.deviceGroups(), "light group buffer");
        m_lightEmitterBuffer = uintTexels(m_lightGroups.emitters, "light group emitter buffer");
        m_triangleLightBuffer =
            vk::Buffer::storage(context, m_lightGroups.triangleLight, "triangle light buffer");
        m_textureInfos = uintTexels(textureInfos, "texture table");
        // Four RGBA8 texels to each 16-byte texel (shaders/common/scene.glsl texelAt).
        std::vector<glm::uvec4> packed((texels.size() + 3) / 4, glm::uvec4(0));
        for (size_t i = 0; i < texels.size(); ++i) packed[i / 4][int(i % 4)] = texels[i];
        m_texels = uintTexels(packed, "texture buffer");
        m_envTexels = vk::Buffer::texels(context, envTexels, VK_FORMAT_R32G32B32A32_SFLOAT,
                                         "environment texels");
        m_envAlias = uintTexels(environmentAliasTable(env), "environment alias table");
        m_punctualLights = uintTexels(scene.punctualLights, "punctual light buffer");
        m_punctualAlias = uintTexels(choice.punctualTable, "punctual light alias table");
        // Per-vertex tangents and per-triangle emitter luminance (four to a texel), or one
        // placeholder texel for scenes that do not use them.
        std::vector<glm::vec4> tangents = scene.tangents;
        if (tangents.empty()) tangents.emplace_back(0.0f);
        m_tangents = vk::Buffer::texels(context, tangents, VK_FORMAT_R32G32B32A32_SFLOAT, "tangents");
        std::vector<glm::vec4> emission((scene.triangleEmission.size() + 3) / 4 + 1, glm::vec4(0.0f));
        for (size_t i = 0; i < scene.triangleEmission.size(); ++i)
            emission[i / 4][int(i % 4)] = scene.triangleEmission[i];
        m_triangleEmission = vk::Buffer::texels(context, emission, VK_FORMAT_R32G32B32A32_SFLOAT,
                                                "triangle emission");
    } catch (const Error& e) {
        fail(scene.path.string(), std::string("scene too large for the device: ") + e.what());
    }

    m_set = std::make_unique<vk::DescriptorSet>(layout, vk::DescriptorSet::Kind::Scene, "scene");
    m_set->bind(gpu::BINDING_SCENE_INFO, m_infoBuffer);
    m_set->bind(gpu::BINDING_VERTICES, m_vertices);
    m_set->bind(gpu::BINDING_TRIANGLES, m_triangles);
    m_set->bind(gpu::BINDING_BVH, m_bvhTexels);
    m_set->bind(gpu::BINDING_MATERIALS, m_materials);
    m_set->bind(gpu::BINDING_LIGHT_GROUPS, m_lightGroupBuffer);
    m_set->bind(gpu::BINDING_LIGHT_EMITTERS, m_lightEmitterBuffer);
    m_set->bind(gpu::BINDING_TRIANGLE_LIGHTS, m_triangleLightBuffer);
    m_set->bind(gpu::BINDING_TEXTURE_INFOS, m_textureInfos);
    m_set->bind(gpu::BINDING_TEXELS, m_texels);
    m_set->bind(gpu::BINDING_ENV_TEXELS, m_envTexels);
    m_set->bind(gpu::BINDING_ENV_ALIAS, m_envAlias);
    m_set->bind(gpu::BINDING_PUNCTUAL_LIGHTS, m_punctualLights);
    m_set->bind(gpu::BINDING_PUNCTUAL_ALIAS, m_punctualAlias);
    m_set->bind(gpu::BINDING_TANGENTS, m_tangents);
    m_set->bind(gpu::BINDING_TRIANGLE_EMISSION, m_triangleEmission);
}

}  // namespace pmcr
