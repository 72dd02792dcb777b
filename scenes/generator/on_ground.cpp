#include "on_ground.h"

#include <cmath>
#include <cstring>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
// As built into pmcr_core (host/scene/gltf_loader.cpp): without the image writer.
#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>

#include "core/error.h"
#include "scene/gltf_loader.h"

namespace pmcr::scenegen {

namespace {

// Appends `bytes` to buffer 0 (4-byte aligned) and returns a buffer view of them.
int appendView(tinygltf::Model& m, const void* bytes, size_t size) {
    std::vector<unsigned char>& data = m.buffers[0].data;
    while (data.size() % 4 != 0) data.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = size;
    const auto* p = static_cast<const unsigned char*>(bytes);
    data.insert(data.end(), p, p + size);
    m.bufferViews.push_back(view);
    return int(m.bufferViews.size() - 1);
}

int appendAccessor(tinygltf::Model& m, int view, int componentType, int type, size_t count) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = componentType;
    a.type = type;
    a.count = count;
    m.accessors.push_back(a);
    return int(m.accessors.size() - 1);
}

}  // namespace

void placeOnGround(const std::filesystem::path& model, const std::filesystem::path& out,
                   const std::string& environment) {
    // The model's world-space bounds, as pmcr reads it (under a constant sky, so that a model
    // with no light of its own loads).
    const Scene scene = loadScene(model, EnvironmentSpec{"1,1,1"});

    tinygltf::TinyGLTF gltf;
    // Images are copied as encoded: not decoded here, and written back from their buffer views.
    gltf.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int,
                           const unsigned char*, int, void*) { return true; },
                        nullptr);
    tinygltf::Model m;
    std::string err, warn;
    if (!gltf.LoadBinaryFromFile(&m, &err, &warn, model.string()))
        fail(model.string(), "cannot read: " + err);
    if (m.buffers.size() != 1 || m.scenes.empty())
        fail(model.string(), "expected one buffer and a scene");
    for (const tinygltf::Image& image : m.images) {
        if (image.bufferView < 0) fail(model.string(), "expected images in buffer views");
    }

    // A ground square 20 times the model's extent, at its lowest point, facing +y.
    const glm::vec3 lo = scene.boundsMin, hi = scene.boundsMax;
    const glm::vec3 center = 0.5f * (lo + hi);
    const float extent = glm::length(hi - lo);
    const float half = 10.0f * extent;
    const float y = lo.y;
    const float positions[12] = {center.x - half, y, center.z - half, center.x - half, y, center.z + half,
                                 center.x + half, y, center.z + half, center.x + half, y, center.z - half};
    const float normals[12] = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
    const uint32_t indices[6] = {0, 1, 2, 0, 2, 3};
    const int position = appendAccessor(m, appendView(m, positions, sizeof(positions)),
                                        TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 4);
    m.accessors[size_t(position)].minValues = {center.x - half, y, center.z - half};
    m.accessors[size_t(position)].maxValues = {center.x + half, y, center.z + half};
    const int normal = appendAccessor(m, appendView(m, normals, sizeof(normals)),
                                      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 4);
    const int index = appendAccessor(m, appendView(m, indices, sizeof(indices)),
                                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, 6);
    m.buffers[0].uri.clear();

    tinygltf::Material ground;
    ground.name = "Ground (pmcr-scenegen)";
    ground.pbrMetallicRoughness.baseColorFactor = {0.5, 0.5, 0.5, 1.0};
    ground.pbrMetallicRoughness.metallicFactor = 0.0;
    ground.pbrMetallicRoughness.roughnessFactor = 1.0;
    m.materials.push_back(ground);
    tinygltf::Primitive primitive;
    primitive.attributes = {{"POSITION", position}, {"NORMAL", normal}};
    primitive.indices = index;
    primitive.material = int(m.materials.size() - 1);
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    tinygltf::Mesh mesh;
    mesh.name = "Ground";
    mesh.primitives.push_back(primitive);
    m.meshes.push_back(mesh);
    tinygltf::Node groundNode;
    groundNode.name = "Ground";
    groundNode.mesh = int(m.meshes.size() - 1);
    m.nodes.push_back(groundNode);
    const int scene0 = m.defaultScene >= 0 ? m.defaultScene : 0;
    m.scenes[size_t(scene0)].nodes.push_back(int(m.nodes.size() - 1));

    // A camera on the +z side, 20 degrees above the model's centre, framing its bounding sphere.
    tinygltf::Camera camera;
    camera.type = "perspective";
    camera.perspective.yfov = 0.6;
    camera.perspective.znear = 0.01 * extent;
    camera.perspective.zfar = 100.0 * extent;
    m.cameras.insert(m.cameras.begin(), camera);
    for (tinygltf::Node& n : m.nodes)
        if (n.camera >= 0) ++n.camera;
    const float radius = 0.5f * extent;
    const float distance = 1.1f * radius / std::sin(0.3f);
    const float elevation = glm::radians(20.0f);
    const glm::vec3 eye = center + distance * glm::vec3(0.0f, std::sin(elevation), std::cos(elevation));
    const glm::quat q = glm::quatLookAtRH(glm::normalize(center - eye), glm::vec3(0, 1, 0));
    tinygltf::Node cameraNode;
    cameraNode.name = "Camera (pmcr-scenegen)";
    cameraNode.camera = 0;
    cameraNode.translation = {eye.x, eye.y, eye.z};
    cameraNode.rotation = {q.x, q.y, q.z, q.w};
    m.nodes.push_back(cameraNode);
    // First in the scene, so that it is camera 0.
    auto& roots = m.scenes[size_t(scene0)].nodes;
    roots.insert(roots.begin(), int(m.nodes.size() - 1));

    tinygltf::Value::Object pmcr;
    pmcr["environment"] = tinygltf::Value(environment);
    pmcr["width"] = tinygltf::Value(320);
    pmcr["height"] = tinygltf::Value(240);
    tinygltf::Value::Object extras;
    extras["pmcr"] = tinygltf::Value(pmcr);
    m.extras = tinygltf::Value(extras);
    m.asset.generator = "pmcr-scenegen (" + model.filename().string() + " on a ground plane)";

    if (!gltf.WriteGltfSceneToFile(&m, out.string(), false, true, false, true))
        fail(out.string(), "cannot write");
}

}  // namespace pmcr::scenegen
