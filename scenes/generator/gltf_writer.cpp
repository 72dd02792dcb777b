#include "gltf_writer.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <set>

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>
#include <stb_image_write.h>  // implemented in host/image/image.cpp

#include "core/error.h"

namespace pmcr::scenegen {

namespace {

using Json = nlohmann::ordered_json;

// glTF 2.0 enumerations (specification section 5).
constexpr int kFloat = 5126;
constexpr int kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;

Json vec3Json(const glm::dvec3& v) {
    return Json::array({v.x, v.y, v.z});
}

// Accumulates the binary buffers and the accessors / buffer views that describe them. Buffer 0
// is the scene's own (the GLB BIN chunk, or <name>.bin); shared meshes get buffers of their own.
class BufferBuilder {
public:
    BufferBuilder() : m_buffers(1) {}

    int addBuffer() {
        m_buffers.emplace_back();
        return int(m_buffers.size()) - 1;
    }

    // One tightly packed buffer view (byteStride omitted) and one accessor over all of it.
    int addVec3(int buffer, const std::vector<glm::vec3>& data, bool withBounds) {
        Json accessor = {{"bufferView", addView(buffer, data.data(),
                                                data.size() * sizeof(glm::vec3), kArrayBuffer)},
                         {"componentType", kFloat},
                         {"count", data.size()},
                         {"type", "VEC3"}};
        if (withBounds) {
            glm::vec3 lo(std::numeric_limits<float>::max());
            glm::vec3 hi(-std::numeric_limits<float>::max());
            for (const auto& p : data) {
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
            // Exact float values, so that min/max equal the data bit for bit (section 3.6.2.5).
            accessor["min"] = vec3Json(glm::dvec3(lo));
            accessor["max"] = vec3Json(glm::dvec3(hi));
        }
        m_accessors.push_back(std::move(accessor));
        return int(m_accessors.size()) - 1;
    }

    int addVec2(int buffer, const std::vector<glm::vec2>& data) {
        m_accessors.push_back({{"bufferView", addView(buffer, data.data(),
                                                      data.size() * sizeof(glm::vec2), kArrayBuffer)},
                               {"componentType", kFloat},
                               {"count", data.size()},
                               {"type", "VEC2"}});
        return int(m_accessors.size()) - 1;
    }

    // A buffer view of raw bytes (an embedded image: no target, section 3.6.2.4).
    int addBytes(int buffer, const std::vector<uint8_t>& data) {
        return addView(buffer, data.data(), data.size(), 0);
    }

    int addIndices(int buffer, const std::vector<uint32_t>& data) {
        m_accessors.push_back(
            {{"bufferView",
              addView(buffer, data.data(), data.size() * sizeof(uint32_t), kElementArrayBuffer)},
             {"componentType", kUnsignedInt},
             {"count", data.size()},
             {"type", "SCALAR"}});
        return int(m_accessors.size()) - 1;
    }

    const std::vector<uint8_t>& bytes(int buffer) const { return m_buffers[size_t(buffer)]; }
    size_t bufferCount() const { return m_buffers.size(); }
    Json& accessors() { return m_accessors; }
    Json& bufferViews() { return m_views; }

private:
    int addView(int buffer, const void* data, size_t size, int target) {
        // Every view starts on a 4-byte boundary (section 3.6.2.4: offsets are multiples of the
        // component size).
        std::vector<uint8_t>& bytes = m_buffers[size_t(buffer)];
        bytes.resize((bytes.size() + 3) & ~size_t(3), 0);
        const size_t offset = bytes.size();
        bytes.resize(offset + size);
        std::memcpy(bytes.data() + offset, data, size);
        m_views.push_back({{"buffer", buffer}, {"byteOffset", offset}, {"byteLength", size}});
        if (target != 0) m_views.back()["target"] = target;
        return int(m_views.size()) - 1;
    }

    std::vector<std::vector<uint8_t>> m_buffers;
    Json m_accessors = Json::array();
    Json m_views = Json::array();
};

Json materialJson(const MaterialDesc& m, std::set<std::string>& extensionsUsed) {
    Json pbr = {{"baseColorFactor", {m.baseColor.x, m.baseColor.y, m.baseColor.z, m.alpha}},
                {"metallicFactor", m.metallic},
                {"roughnessFactor", m.roughness}};
    if (m.baseColorTexture >= 0) pbr["baseColorTexture"] = {{"index", m.baseColorTexture}};
    Json json = {{"name", m.name}, {"pbrMetallicRoughness", pbr}};
    if (m.blend) {
        json["alphaMode"] = "BLEND";
        json["doubleSided"] = true;
    }
    Json extensions = Json::object();
    // emissiveFactor is limited to [0, 1]; larger radiance goes into
    // KHR_materials_emissive_strength (emission = emissiveFactor * emissiveStrength).
    const double peak = std::max({m.emission.x, m.emission.y, m.emission.z});
    if (peak > 0.0) {
        const double strength = std::max(peak, 1.0);
        json["emissiveFactor"] = vec3Json(m.emission / strength);
        if (strength > 1.0) {
            extensions["KHR_materials_emissive_strength"] = {{"emissiveStrength", strength}};
        }
    }
    if (m.transmission > 0.0) {
        extensions["KHR_materials_transmission"] = {{"transmissionFactor", m.transmission}};
        extensions["KHR_materials_ior"] = {{"ior", m.ior}};
        // A volume (thicknessFactor > 0) makes the mesh a solid refracting body rather than a
        // thin-walled surface.
        if (!m.thinWalled) extensions["KHR_materials_volume"] = {{"thicknessFactor", 1.0}};
    }
    if (m.specular >= 0.0) {
        extensions["KHR_materials_specular"] = {{"specularFactor", m.specular},
                                                {"specularColorFactor", vec3Json(m.specularColor)}};
    }
    if (m.clearcoat > 0.0) {
        extensions["KHR_materials_clearcoat"] = {{"clearcoatFactor", m.clearcoat},
                                                 {"clearcoatRoughnessFactor", m.clearcoatRoughness}};
    }
    if (m.sheenColor != glm::dvec3(0.0)) {
        extensions["KHR_materials_sheen"] = {{"sheenColorFactor", vec3Json(m.sheenColor)},
                                             {"sheenRoughnessFactor", m.sheenRoughness}};
    }
    if (!extensions.empty()) {
        for (const auto& item : extensions.items())
            extensionsUsed.insert(item.key());
        json["extensions"] = std::move(extensions);
    }
    return json;
}

// The camera node's rotation: glTF cameras look down their local -Z with +Y up (section 3.10).
Json cameraNode(const CameraDesc& c, int cameraIndex) {
    Json node = {{"name", c.name}, {"camera", cameraIndex}};
    const glm::dvec3 forward = glm::normalize(c.forward);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, c.up));
    const glm::dvec3 up = glm::cross(right, forward);
    const glm::dquat q = glm::quat_cast(glm::dmat3(right, up, -forward));
    if (std::abs(std::abs(q.w) - 1.0) > 1e-12)
        node["rotation"] = {q.x, q.y, q.z, q.w};
    if (c.position != glm::dvec3(0.0))
        node["translation"] = vec3Json(c.position);
    return node;
}

// Little-endian, as GLB stores its header words (section 4.4.2).
void putU32(uint8_t* at, uint32_t v) {
    for (int i = 0; i < 4; ++i)
        at[i] = uint8_t(v >> (8 * i));
}

void writeFile(const std::filesystem::path& path, const void* data, size_t size) {
    std::ofstream stream(path, std::ios::binary | std::ios::trunc);
    if (!stream)
        fail(path.string(), "cannot open for writing");
    stream.write(static_cast<const char*>(data), std::streamsize(size));
    if (!stream)
        fail(path.string(), "write failed");
}

// GLB container: 12-byte header, JSON chunk padded with spaces, BIN chunk padded with zeros,
// both to 4-byte multiples (section 4.4).
void writeGlbFile(const std::filesystem::path& path, const Json& root,
                  const std::vector<uint8_t>& buffer) {
    std::string jsonText = root.dump();
    jsonText.resize((jsonText.size() + 3) & ~size_t(3), ' ');
    std::vector<uint8_t> bin = buffer;
    bin.resize((bin.size() + 3) & ~size_t(3), 0);
    const size_t total = 12 + 8 + jsonText.size() + 8 + bin.size();
    if (total > std::numeric_limits<uint32_t>::max())
        fail(path.string(), "scene too large for a .glb");

    std::vector<uint8_t> out(total);
    putU32(&out[0], 0x46546C67u);  // "glTF"
    putU32(&out[4], 2u);
    putU32(&out[8], uint32_t(total));
    putU32(&out[12], uint32_t(jsonText.size()));
    putU32(&out[16], 0x4E4F534Au);  // "JSON"
    std::memcpy(&out[20], jsonText.data(), jsonText.size());
    const size_t binAt = 20 + jsonText.size();
    putU32(&out[binAt], uint32_t(bin.size()));
    putU32(&out[binAt + 4], 0x004E4942u);  // "BIN\0"
    std::memcpy(&out[binAt + 8], bin.data(), bin.size());
    writeFile(path, out.data(), out.size());
}

}  // namespace

std::filesystem::path writeScene(const SceneDesc& scene, const std::filesystem::path& dir) {
    bool external = false;
    for (const auto& object : scene.objects)
        external = external || !object.sharedUri.empty();
    const std::filesystem::path path = dir / (scene.name + (external ? ".gltf" : ".glb"));
    const std::string file = path.string();
    BufferBuilder buffer;
    std::set<std::string> extensionsUsed;

    Json materials = Json::array();
    for (const auto& m : scene.materials)
        materials.push_back(materialJson(m, extensionsUsed));

    // A shared mesh's buffer and its primitive's attributes and indices, per file.
    struct Shared {
        int buffer;
        Json attributes;
        int indices;
    };
    std::map<std::string, Shared> shared;
    Json meshes = Json::array();
    Json nodes = Json::array();
    for (const auto& object : scene.objects) {
        const Mesh& mesh = object.mesh;
        if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) {
            fail(file, "mesh '" + mesh.name + "' has no complete triangles");
        }
        if (object.material < 0 || object.material >= int(scene.materials.size())) {
            fail(file, "mesh '" + mesh.name + "' names a material that does not exist");
        }
        auto addMesh = [&](int target) {
            Json attributes = {{"POSITION", buffer.addVec3(target, mesh.positions, true)}};
            if (!mesh.normals.empty())
                attributes["NORMAL"] = buffer.addVec3(target, mesh.normals, false);
            if (!mesh.uvs.empty()) attributes["TEXCOORD_0"] = buffer.addVec2(target, mesh.uvs);
            return Shared{target, attributes, buffer.addIndices(target, mesh.indices)};
        };
        Shared data;
        if (object.sharedUri.empty()) {
            data = addMesh(0);
        } else {
            auto found = shared.find(object.sharedUri);
            if (found == shared.end())
                found = shared.emplace(object.sharedUri, addMesh(buffer.addBuffer())).first;
            data = found->second;
        }
        Json primitive = {{"attributes", data.attributes},
                          {"indices", data.indices},
                          {"material", object.material}};
        meshes.push_back({{"name", mesh.name}, {"primitives", Json::array({primitive})}});
        nodes.push_back({{"name", mesh.name}, {"mesh", int(meshes.size()) - 1}});
    }
    nodes.push_back(cameraNode(scene.camera, 0));
    // Textures: PNG images in the scene's own buffer, the default sampler (bilinear, repeat).
    Json images = Json::array(), textures = Json::array();
    for (const TextureDesc& t : scene.textures) {
        if (t.width <= 0 || t.height <= 0 || t.rgba.size() != size_t(t.width) * t.height * 4)
            fail(file, "texture '" + t.name + "' has the wrong number of texels");
        std::vector<uint8_t> png;
        auto append = [](void* context, void* data, int size) {
            auto* out = static_cast<std::vector<uint8_t>*>(context);
            out->insert(out->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
        };
        if (!stbi_write_png_to_func(append, &png, t.width, t.height, 4, t.rgba.data(), t.width * 4))
            fail(file, "cannot encode texture '" + t.name + "'");
        images.push_back({{"name", t.name}, {"bufferView", buffer.addBytes(0, png)}, {"mimeType", "image/png"}});
        textures.push_back({{"source", int(images.size()) - 1}});
    }
    if (buffer.bytes(0).empty())
        fail(file, "the scene has no geometry of its own");

    Json sceneNodes = Json::array();
    for (size_t i = 0; i < nodes.size(); ++i)
        sceneNodes.push_back(i);

    Json asset = {{"version", "2.0"}, {"generator", "pmcr-scenegen"}};
    if (!scene.copyright.empty())
        asset["copyright"] = scene.copyright;
    Json root = {{"asset", asset}};
    if (!extensionsUsed.empty())
        root["extensionsUsed"] = extensionsUsed;
    root["scene"] = 0;
    root["scenes"] = Json::array({{{"name", scene.name}, {"nodes", sceneNodes}}});
    root["nodes"] = std::move(nodes);
    root["meshes"] = std::move(meshes);
    root["materials"] = std::move(materials);
    if (!textures.empty()) {
        root["textures"] = std::move(textures);
        root["images"] = std::move(images);
    }
    // No aspectRatio: the viewport's aspect ratio is used (section 5.13), so --width/--height
    // can change the image shape without distortion.
    root["cameras"] = Json::array(
        {{{"name", scene.camera.name},
          {"type", "perspective"},
          {"perspective", {{"yfov", scene.camera.yfov}, {"znear", scene.camera.znear}}}}});
    root["accessors"] = std::move(buffer.accessors());
    root["bufferViews"] = std::move(buffer.bufferViews());
    Json pmcr = {{"width", scene.width}, {"height", scene.height}};
    if (scene.paperWidth > 0 && scene.paperHeight > 0) {
        pmcr["paper_width"] = scene.paperWidth;
        pmcr["paper_height"] = scene.paperHeight;
    }
    if (!scene.environment.empty()) pmcr["environment"] = scene.environment;

    if (!external) {
        root["buffers"] = Json::array({{{"byteLength", buffer.bytes(0).size()}}});
        root["extras"] = {{"pmcr", pmcr}};
        writeGlbFile(path, root, buffer.bytes(0));
        return path;
    }

    // .gltf: buffer 0 in <name>.bin beside it, each shared mesh in its own file (uris are
    // relative to the .gltf, section 3.6.1.1).
    std::vector<std::string> uris(buffer.bufferCount());
    uris[0] = scene.name + ".bin";
    for (const auto& [uri, data] : shared)
        uris[size_t(data.buffer)] = uri;
    Json buffers = Json::array();
    for (size_t b = 0; b < uris.size(); ++b) {
        buffers.push_back({{"uri", uris[b]}, {"byteLength", buffer.bytes(int(b)).size()}});
        const std::filesystem::path target = dir / uris[b];
        std::error_code ec;
        std::filesystem::create_directories(target.parent_path(), ec);
        if (ec)
            fail(target.parent_path().string(), "cannot create directory: " + ec.message());
        writeFile(target, buffer.bytes(int(b)).data(), buffer.bytes(int(b)).size());
    }
    root["buffers"] = std::move(buffers);
    root["extras"] = {{"pmcr", pmcr}};
    const std::string text = root.dump(1) + "\n";
    writeFile(path, text.data(), text.size());
    return path;
}

}  // namespace pmcr::scenegen
