#include "render/gpu_scene.h"

#include <chrono>

#include "core/error.h"
#include "scene/environment.h"

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
    auto start = std::chrono::steady_clock::now();
    m_bvh = Bvh::build(scene);
    m_bvhSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    m_lightGroups = buildLightGroups(scene);
    m_info.lightCount = uint32_t(m_lightGroups.lights.size());
    m_info.nodeCount = uint32_t(m_bvh.nodes().size());
    // The group of all emitters is buildEmitters' table, so its power is the emitters' total.
    m_info.totalEmitterPower = m_lightGroups.allEmitters.power;

    // The environment and the punctual lights. Light sampling picks the environment, a punctual
    // light or an emitter triangle in proportion to their power (lights.glsl).
    const Environment& env = scene.environment;
    m_info.envKind = env.kind;
    m_info.envRadiance = env.kind == gpu::ENV_CONSTANT ? env.radiance : glm::vec3(env.scale);
    m_info.envRotation = env.rotation;
    m_info.envWidth = uint32_t(env.image.width);
    m_info.envHeight = uint32_t(env.image.height);
    // Power alone can starve a light: a directional light's power grows with the scene's area
    // (pi R^2 E), so in a large scene a nearby point light would be picked once in thousands of
    // samples. So each choice (between the kinds present, and between punctual lights) takes
    // half its probability from power and half uniformly: still unbiased (every light keeps a
    // positive probability, which the kernels divide by), and no light below a quarter of its
    // uniform share. Among emitter triangles the choice stays by power, as before.
    auto defensive = [](std::vector<double> power) {
        double total = 0.0;
        for (double p : power) total += p;
        for (double& p : power) p = 0.5 * (total > 0.0 ? p / total : 0.0) + 0.5 / double(power.size());
        return power;
    };
    m_info.punctualCount = uint32_t(scene.punctualLights.size());
    std::vector<double> punctualPower;
    for (const gpu::PunctualLight& light : scene.punctualLights)
        punctualPower.push_back(punctualLightPower(light, m_info.sceneRadius));
    std::vector<gpu::Emitter> punctualAlias(punctualPower.size());
    double totalPunctual = 0.0;
    for (double p : punctualPower) totalPunctual += p;
    if (!punctualPower.empty()) buildAliasTable(defensive(punctualPower), punctualAlias.data());
    for (size_t i = 0; i < punctualAlias.size(); ++i) punctualAlias[i].triangle = uint32_t(i);
    m_info.envSelectPmf = 0.0f;
    m_info.punctualSelectPmf = 0.0f;
    if (env.kind != gpu::ENV_NONE || !scene.punctualLights.empty()) {
        // The kinds present: environment, punctual lights, emitter triangles.
        std::vector<double> kindPower;
        std::vector<int> kind;
        if (env.kind != gpu::ENV_NONE) {
            kindPower.push_back(environmentPower(env, m_info.sceneRadius));
            kind.push_back(0);
        }
        if (!scene.punctualLights.empty()) {
            kindPower.push_back(totalPunctual);
            kind.push_back(1);
        }
        if (m_info.totalEmitterPower > 0.0f) {
            kindPower.push_back(m_info.totalEmitterPower);
            kind.push_back(2);
        }
        const std::vector<double> pmf = defensive(kindPower);
        for (size_t i = 0; i < kind.size(); ++i) {
            if (kind[i] == 0) m_info.envSelectPmf = float(pmf[i]);
            if (kind[i] == 1) m_info.punctualSelectPmf = float(pmf[i]);
        }
        // Without emitters nothing is left for them (rounding must not leave a sliver).
        if (!(m_info.totalEmitterPower > 0.0f)) {
            if (scene.punctualLights.empty()) m_info.envSelectPmf = 1.0f;
            else m_info.punctualSelectPmf = 1.0f - m_info.envSelectPmf;
        }
    }
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
        m_punctualAlias = uintTexels(punctualAlias, "punctual light alias table");
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
}

}  // namespace pmcr
