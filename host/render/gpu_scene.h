// The scene on the device: BVH built on the host, every scene buffer uploaded once, and the
// scene descriptor set (set 0) that every kernel binds.
#pragma once

#include <memory>

#include "scene/bvh.h"
#include "scene/scene.h"
#include "shared/host_device.h"
#include "vk/buffer.h"
#include "vk/pipeline.h"

namespace pmcr {

class GpuScene {
public:
    // Builds the BVH and uploads everything; `camera` indexes scene.cameras, width/height set
    // the raster. Fails with the scene's file name when it exceeds the device's buffer limits.
    GpuScene(vk::Context& context, const vk::PipelineLayout& layout, const Scene& scene,
             int camera, int width, int height);

    const vk::DescriptorSet& descriptorSet() const { return *m_set; }
    const gpu::SceneInfo& info() const { return m_info; }
    const Scene& scene() const { return m_scene; }
    const Bvh& bvh() const { return m_bvh; }
    const LightGroupTable& lightGroups() const { return m_lightGroups; }
    double bvhBuildSeconds() const { return m_bvhSeconds; }
    // gpu::SCENE_FEATURE_* bits the kernels are specialized for (sceneFeatures).
    uint32_t features() const { return m_features; }

private:
    const Scene& m_scene;
    Bvh m_bvh;
    LightGroupTable m_lightGroups;
    gpu::SceneInfo m_info{};
    double m_bvhSeconds = 0.0;
    uint32_t m_features = 0;
    vk::Buffer m_infoBuffer;
    vk::Buffer m_vertices;
    vk::Buffer m_triangles;
    vk::Buffer m_bvhTexels;
    vk::Buffer m_materials;
    vk::Buffer m_lightGroupBuffer;
    vk::Buffer m_lightEmitterBuffer;
    vk::Buffer m_triangleLightBuffer;
    vk::Buffer m_textureInfos;
    vk::Buffer m_texels;
    vk::Buffer m_envTexels;
    vk::Buffer m_envAlias;
    vk::Buffer m_punctualLights;
    vk::Buffer m_punctualAlias;
    vk::Buffer m_tangents;
    vk::Buffer m_triangleEmission;
    std::unique_ptr<vk::DescriptorSet> m_set;
};

// The SceneInfo (camera and constants) for a scene, camera index and raster size.
gpu::SceneInfo makeSceneInfo(const Scene& scene, int camera, int width, int height);

}  // namespace pmcr
