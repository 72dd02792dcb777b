#include "scene/gltf_loader.h"

// The project's one tinygltf/stb_image implementation unit (stb_image_write's implementation
// lives in the image I/O). Images are decoded here, only those a material uses.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define STB_IMAGE_IMPLEMENTATION
#define STBI_MAX_DIMENSIONS 16384
#include <tiny_gltf.h>

#include <algorithm>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "core/error.h"
#include "core/log.h"
#include "core/paths.h"
#include "scene/tangents.h"

namespace pmcr {

namespace {

namespace fs = std::filesystem;

constexpr uint64_t kMaxFileBytes = uint64_t(UINT32_MAX);  // tinygltf takes 32-bit sizes
constexpr size_t kMaxJsonDepth = 256;             // tinygltf converts extras/extensions recursively
constexpr size_t kMaxVertices = size_t(1) << 26;  // 2 GiB of vertices: bounds instancing bombs
constexpr size_t kMaxTriangles = size_t(1) << 26;
constexpr size_t kMaxZeroAccessorCount = size_t(1) << 24;  // accessors without a buffer view
constexpr int kMaxImageDimension = 16384;
constexpr size_t kMaxMessage = 300;

const std::set<std::string> kSupportedExtensions = {"KHR_materials_emissive_strength",
                                                    "KHR_materials_transmission",
                                                    "KHR_materials_ior", "KHR_materials_volume",
                                                    "KHR_materials_specular", "KHR_materials_clearcoat",
                                                    "KHR_materials_sheen",
                                                    "KHR_lights_punctual", "KHR_texture_transform",
                                                    "KHR_xmp"};  // metadata (authorship, licence)

// tinygltf's (possibly multi-line, possibly data-URI-sized) messages as one short line.
std::string oneLine(const std::string& text) {
    std::string out;
    bool pendingSeparator = false;
    for (char c : text) {
        if (c == '\n' || c == '\r') {
            pendingSeparator = !out.empty();
            continue;
        }
        if (pendingSeparator) {
            out += "; ";
            pendingSeparator = false;
        }
        out += (c == '\t') ? ' ' : c;
        if (out.size() > kMaxMessage) {
            out.resize(kMaxMessage);
            return out + "...";
        }
    }
    return out;
}

std::string inQuotes(const std::string& name) {
    std::string out(1, '\'');
    out += oneLine(name);
    out += '\'';
    return out;
}

// Deepest nesting of JSON arrays/objects (string contents skipped).
size_t jsonNestingDepth(const char* text, size_t size) {
    size_t depth = 0, deepest = 0;
    bool inString = false;
    for (size_t i = 0; i < size; ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\') {
                ++i;
            } else if (c == '"') {
                inString = false;
            }
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

// What tinygltf's filesystem callbacks see: the folder it joins relative uris to and, under
// --restrict-paths, the first uri refused for leaving the scene's folder.
struct ResourceAccess {
    std::string baseDir;
    bool restrictPaths = false;
    std::string refused;
};

// Filesystem callbacks for tinygltf: resources are regular files beside the scene file only
// (tinygltf would also look in the working directory and expand paths with wordexp); with
// --restrict-paths, only inside the scene's folder. A refused uri is remembered, so that the
// error names it instead of tinygltf's "file not found".
bool resourceExists(const std::string& path, void* user) {
    ResourceAccess& access = *static_cast<ResourceAccess*>(user);
    if (path.rfind(access.baseDir, 0) != 0)
        return false;
    if (access.restrictPaths && !isInsideFolder(path, access.baseDir)) {
        if (access.refused.empty()) {
            std::string uri = path.substr(access.baseDir.size());
            access.refused = uri.empty() || uri[0] != '/' ? uri : uri.substr(1);
        }
        return false;
    }
    std::error_code ec;
    return fs::is_regular_file(path, ec);
}

std::string expandResourcePath(const std::string& path, void*) {
    return path;
}

bool readResource(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                  void*) {
    std::error_code ec;
    const uint64_t size = fs::file_size(path, ec);
    if (ec || !fs::is_regular_file(path, ec) || size > kMaxFileBytes) {
        if (err)
            *err = "not a readable regular file below 4 GiB";
        return false;
    }
    std::ifstream in(path, std::ios::binary);
    out->resize(size);
    if (!in || !in.read(reinterpret_cast<char*>(out->data()), std::streamsize(size))) {
        if (err)
            *err = "read error";
        return false;
    }
    return true;
}

bool writeResource(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err)
        *err = "pmcr never writes glTF resources";
    return false;
}

// tinygltf image callback: keeps a URI image's encoded bytes; decodeImage decodes the images
// materials use. For buffer-view images tinygltf passes an unchecked range: those bytes are
// read later through a validated view instead.
bool keepEncodedImage(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
    if (image->bufferView < 0 && bytes != nullptr && size > 0) {
        image->image.assign(bytes, bytes + size);
    }
    image->as_is = true;
    return true;
}

std::string decodeFailure() {
    const char* reason = stbi_failure_reason();
    return reason ? reason : "unsupported image";
}

size_t componentSize(int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return 4;
        default:
            return 0;
    }
}

int componentCount(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return 1;
        case TINYGLTF_TYPE_VEC2:
            return 2;
        case TINYGLTF_TYPE_VEC3:
            return 3;
        case TINYGLTF_TYPE_VEC4:
            return 4;
        default:
            return 0;  // matrices: never vertex data pmcr reads
    }
}

// An accessor's elements, validated to lie inside their buffer.
struct AccessorData {
    const uint8_t* data = nullptr;
    size_t stride = 0;
    size_t count = 0;
    int componentType = 0;
    std::vector<uint8_t> dense;  // owns the elements of sparse or view-less accessors

    const uint8_t* element(size_t i) const {
        return (dense.empty() ? data : dense.data()) + i * stride;
    }
    glm::vec3 vec3(size_t i) const {
        float v[3];
        std::memcpy(v, element(i), sizeof(v));
        return {v[0], v[1], v[2]};
    }
    glm::vec4 vec4(size_t i) const {
        float v[4];
        std::memcpy(v, element(i), sizeof(v));
        return {v[0], v[1], v[2], v[3]};
    }
    glm::vec2 texcoord(size_t i) const {
        const uint8_t* p = element(i);
        if (componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
            float v[2];
            std::memcpy(v, p, sizeof(v));
            return {v[0], v[1]};
        }
        if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
            return glm::vec2(p[0], p[1]) / 255.0f;
        }
        uint16_t v[2];
        std::memcpy(v, p, sizeof(v));
        return glm::vec2(v[0], v[1]) / 65535.0f;
    }
    uint32_t index(size_t i) const { return readUnsigned(element(i), componentType); }

    static uint32_t readUnsigned(const uint8_t* p, int componentType) {
        if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE)
            return p[0];
        if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
            uint16_t v;
            std::memcpy(&v, p, sizeof(v));
            return v;
        }
        uint32_t v;
        std::memcpy(&v, p, sizeof(v));
        return v;
    }
};

bool isUnsignedIndexType(int componentType) {
    return componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
           componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
           componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

class GltfLoader {
public:
    GltfLoader(const fs::path& path, EnvironmentSpec environment, const SceneLoadOptions& options)
        : m_path(path), m_file(path.string()), m_environment(std::move(environment)),
          m_options(options) {}
    Scene load();

private:
    [[noreturn]] void error(const std::string& message) const { fail(m_file, message); }
    void warnOnce(const std::string& message);
    void ignoreFor(const std::string& kind, const std::string& material);

    void parse();
    void parseGlb(tinygltf::TinyGLTF& gltf, const std::vector<unsigned char>& bytes,
                  const std::string& baseDir, std::string& err, std::string& warn);
    void checkExtensions();
    void readExtras();

    void convertMaterials();
    gpu::Material convertMaterial(int index);
    int convertTexture(const tinygltf::TextureInfo& info, const std::string& label, const char* what);
    Texture decodeImage(int index);
    uint32_t defaultMaterial();

    void traverseScene();
    glm::dmat4 localTransform(int node) const;
    void addCamera(int node, const glm::dmat4& world);
    void addLight(int node, const tinygltf::Value& extension, const glm::dmat4& world);
    void addPrimitive(int mesh, int primitive, const glm::dmat4& world);

    const tinygltf::BufferView& checkedView(int index, const std::string& user) const;
    AccessorData readAccessor(int index, const std::string& role) const;
    void applySparse(const tinygltf::Accessor& accessor, size_t elementSize,
                     const std::string& label, AccessorData& data) const;

    std::string nodeLabel(int node) const;
    std::string meshLabel(int mesh) const;
    std::string materialLabel(int material) const;

    fs::path m_path;
    std::string m_file;
    tinygltf::Model m_model;
    Scene m_scene;
    EnvironmentSpec m_environment;  // --env; else extras.pmcr.environment
    SceneLoadOptions m_options;
    std::set<std::string> m_warned;
    std::map<std::string, std::vector<std::string>> m_ignored;  // kind -> material labels
    std::vector<int> m_textureSlot;  // glTF texture -> Scene::textures index, -1 if unused
    std::vector<int> m_texCoordSet;  // per material: TEXCOORD_n its textures read
    std::vector<glm::dmat3> m_uvTransform;  // per material: KHR_texture_transform of those uvs
    std::vector<bool> m_invisible;  // per material: cut away entirely by its alpha (no texture)
    int m_defaultMaterial = -1;
};

void GltfLoader::warnOnce(const std::string& message) {
    if (m_warned.insert(message).second)
        log::warning(m_file + ": " + message);
}

void GltfLoader::ignoreFor(const std::string& kind, const std::string& material) {
    std::vector<std::string>& materials = m_ignored[kind];
    if (std::find(materials.begin(), materials.end(), material) == materials.end()) {
        materials.push_back(material);
    }
}

std::string GltfLoader::nodeLabel(int node) const {
    const std::string& name = m_model.nodes[size_t(node)].name;
    return "node " + std::to_string(node) + (name.empty() ? "" : " (" + inQuotes(name) + ")");
}

std::string GltfLoader::meshLabel(int mesh) const {
    const std::string& name = m_model.meshes[size_t(mesh)].name;
    return name.empty() ? "mesh " + std::to_string(mesh) : "mesh " + inQuotes(name);
}

std::string GltfLoader::materialLabel(int material) const {
    const std::string& name = m_model.materials[size_t(material)].name;
    return name.empty() ? "material " + std::to_string(material) : "material " + inQuotes(name);
}

Scene GltfLoader::load() {
    parse();
    checkExtensions();
    m_scene.path = m_path;
    readExtras();
    // Under --restrict-paths the environment image, from --env or the file's extras, must lie
    // in the scene's folder too.
    const fs::path folder = m_path.parent_path().empty() ? fs::path(".") : m_path.parent_path();
    m_scene.environment =
        loadEnvironment(m_environment, m_options.restrictPaths ? folder : fs::path());
    convertMaterials();
    traverseScene();
    for (const auto& [kind, materials] : m_ignored) {
        std::string list = inQuotes(materials[0]);
        for (size_t i = 1; i < std::min<size_t>(materials.size(), 3); ++i) {
            list += ", " + inQuotes(materials[i]);
        }
        if (materials.size() > 3)
            list += " and " + std::to_string(materials.size() - 3) + " more";
        log::warning(m_file + ": " + kind + " (" + list + ")");
    }

    finalizeScene(m_scene);

    if (m_scene.cameras.empty()) {
        log::warning(m_file + ": no perspective camera: using a default camera on +Z");
        // Frame the bounding sphere in the vertical field of view.
        Camera camera;
        camera.name = "default";
        camera.yfov = 0.8f;
        const glm::vec3 center = 0.5f * (m_scene.boundsMin + m_scene.boundsMax);
        const float radius = 0.5f * glm::length(m_scene.boundsMax - m_scene.boundsMin);
        camera.position = center + glm::vec3(0.0f, 0.0f, radius / std::sin(0.5f * camera.yfov));
        m_scene.cameras.push_back(camera);
    }
    return std::move(m_scene);
}

void GltfLoader::parse() {
    std::string extension = m_path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (extension != ".gltf" && extension != ".glb") {
        error("unsupported scene format '" + extension + "' (pmcr loads .gltf and .glb)");
    }

    std::error_code ec;
    const fs::file_status status = fs::status(m_path, ec);
    if (!fs::exists(status))
        error("cannot open: no such file");
    if (!fs::is_regular_file(status))
        error("cannot open: not a regular file");
    const uint64_t size = fs::file_size(m_path, ec);
    if (ec)
        error("cannot open: " + ec.message());
    if (size > kMaxFileBytes)
        error("file too large (" + std::to_string(size) + " bytes)");
    std::vector<unsigned char> bytes(size);
    std::ifstream in(m_path, std::ios::binary);
    if (!in || !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size))) {
        error("cannot read the file");
    }

    tinygltf::TinyGLTF gltf;
    ResourceAccess access;
    access.baseDir = m_path.parent_path().string();
    if (access.baseDir.empty())
        access.baseDir = ".";
    access.restrictPaths = m_options.restrictPaths;
    const std::string& baseDir = access.baseDir;
    gltf.SetFsCallbacks(
        {&resourceExists, &expandResourcePath, &readResource, &writeResource, &access});
    gltf.SetImageLoader(&keepEncodedImage, nullptr);

    std::string err, warn;
    if (extension == ".glb") {
        parseGlb(gltf, bytes, baseDir, err, warn);
    } else {
        if (jsonNestingDepth(reinterpret_cast<const char*>(bytes.data()), bytes.size()) >
            kMaxJsonDepth) {
            error("JSON nested more than " + std::to_string(kMaxJsonDepth) + " levels deep");
        }
        bool ok = false;
        try {
            ok = gltf.LoadASCIIFromString(&m_model, &err, &warn,
                                          reinterpret_cast<const char*>(bytes.data()),
                                          unsigned(bytes.size()), baseDir);
        } catch (const std::exception& e) {
            error("invalid glTF: " + oneLine(e.what()));
        }
        if (!ok && err.empty())
            err = "tinygltf rejected the file";
    }
    if (!access.refused.empty())
        error("uri " + inQuotes(access.refused) + " leaves the scene's folder (--restrict-paths)");
    if (!warn.empty())
        log::warning(m_file + ": " + oneLine(warn));
    if (!err.empty()) {
        if (err.rfind("[json.exception", 0) == 0)
            error("not valid JSON: " + oneLine(err));
        error("invalid glTF: " + oneLine(err));
    }
    if (m_model.asset.version.rfind("2.", 0) != 0) {
        error("glTF version " + inQuotes(m_model.asset.version) + " is not supported (need 2.x)");
    }
}

// GLB container (glTF 2.0 §4.4), checked in full before tinygltf reads it: tinygltf 2.7 reads
// past the end of a truncated BIN chunk.
void GltfLoader::parseGlb(tinygltf::TinyGLTF& gltf, const std::vector<unsigned char>& bytes,
                          const std::string& baseDir, std::string& err, std::string& warn) {
    auto u32 = [&](size_t offset) {
        uint32_t v;
        std::memcpy(&v, bytes.data() + offset, 4);
        return v;
    };
    const size_t size = bytes.size();
    if (size < 12 || std::memcmp(bytes.data(), "glTF", 4) != 0) {
        error("not a GLB file (no 'glTF' header; truncated or wrong format)");
    }
    if (u32(4) != 2)
        error("GLB container version " + std::to_string(u32(4)) + " is not supported");
    const uint64_t length = u32(8);
    if (length > size) {
        error("truncated GLB: the header says " + std::to_string(length) + " bytes, the file has " +
              std::to_string(size));
    }
    if (length < 20)
        error("truncated GLB: no JSON chunk");
    const uint64_t jsonLength = u32(12);
    if (u32(16) != 0x4E4F534Au)
        error("GLB: the first chunk is not JSON");
    if (jsonLength < 4 || 20 + jsonLength > length) {
        error("truncated GLB: the JSON chunk (" + std::to_string(jsonLength) +
              " bytes) does not fit in the file");
    }
    if (jsonLength % 4 != 0)
        error("GLB: JSON chunk length is not a multiple of 4");
    const uint64_t binStart = 20 + jsonLength;
    if (binStart < length) {
        if (binStart + 8 > length)
            error("truncated GLB: incomplete BIN chunk header");
        const uint64_t binLength = u32(binStart);
        if (u32(binStart + 4) != 0x004E4942u)
            error("GLB: the second chunk is not BIN");
        if (binStart + 8 + binLength > length) {
            error("truncated GLB: the BIN chunk (" + std::to_string(binLength) +
                  " bytes) does not fit in the file");
        }
        if (binLength < 4 || binLength % 4 != 0) {
            error("GLB: BIN chunk length " + std::to_string(binLength) +
                  " is not a positive multiple of 4");
        }
        if (binStart + 8 + binLength != length) {
            error("GLB: unexpected data after the BIN chunk");
        }
    }
    if (jsonNestingDepth(reinterpret_cast<const char*>(bytes.data() + 20), jsonLength) >
        kMaxJsonDepth) {
        error("JSON nested more than " + std::to_string(kMaxJsonDepth) + " levels deep");
    }
    // Only a container that holds together has bytes "after" it: a header length of 0 or one
    // short of its chunks is an error above, not this warning.
    if (length < size)
        warnOnce("ignoring " + std::to_string(size - length) + " bytes after the GLB");
    bool ok = false;
    try {
        ok = gltf.LoadBinaryFromMemory(&m_model, &err, &warn, bytes.data(), unsigned(length),
                                       baseDir);
    } catch (const std::exception& e) {
        error("invalid glTF: " + oneLine(e.what()));
    }
    if (!ok && err.empty())
        err = "tinygltf rejected the file";
}

void GltfLoader::checkExtensions() {
    for (const std::string& name : m_model.extensionsRequired) {
        if (!kSupportedExtensions.count(name)) {
            error("required extension " + inQuotes(name) + " is not supported");
        }
    }
    for (const std::string& name : m_model.extensionsUsed) {
        if (kSupportedExtensions.count(name))
            continue;
        warnOnce("extension " + inQuotes(name) + " is not supported and is ignored");
    }
}

void GltfLoader::readExtras() {
    const tinygltf::Value& extras = m_model.extras;
    if (!extras.IsObject() || !extras.Has("pmcr"))
        return;
    const tinygltf::Value& pmcr = extras.Get("pmcr");
    if (!pmcr.IsObject())
        error("extras.pmcr must be an object");
    auto dimension = [&](const char* key) {
        if (!pmcr.Has(key))
            return 0;
        const tinygltf::Value& v = pmcr.Get(key);
        const double d = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
        if (!(d >= 1.0 && d <= kMaxImageDimension && d == std::floor(d))) {
            error(std::string("extras.pmcr.") + key + " must be an integer in [1, " +
                  std::to_string(kMaxImageDimension) + "]");
        }
        return int(d);
    };
    m_scene.defaultWidth = dimension("width");
    m_scene.defaultHeight = dimension("height");
    if ((m_scene.defaultWidth == 0) != (m_scene.defaultHeight == 0)) {
        error("extras.pmcr needs both width and height");
    }
    m_scene.paperWidth = dimension("paper_width");
    m_scene.paperHeight = dimension("paper_height");
    if ((m_scene.paperWidth == 0) != (m_scene.paperHeight == 0)) {
        error("extras.pmcr needs both paper_width and paper_height");
    }
    // The environment the scene is made for (an image beside it), unless --env names one.
    if (pmcr.Has("environment") && m_environment.value.empty()) {
        const tinygltf::Value& env = pmcr.Get("environment");
        if (!env.IsString() || env.Get<std::string>().empty())
            error("extras.pmcr.environment must be a file name");
        m_environment.value = (m_path.parent_path() / env.Get<std::string>()).string();
    }
}

// ---------------------------------------------------------------------------------------------
// Materials and textures

void GltfLoader::convertMaterials() {
    m_textureSlot.assign(m_model.textures.size(), -1);
    m_texCoordSet.assign(m_model.materials.size(), -1);
    m_uvTransform.assign(m_model.materials.size(), glm::dmat3(1.0));
    m_invisible.assign(m_model.materials.size(), false);
    for (int i = 0; i < int(m_model.materials.size()); ++i) {
        m_scene.materials.push_back(convertMaterial(i));
        const std::string& name = m_model.materials[size_t(i)].name;
        m_scene.materialNames.push_back(name.empty() ? "material " + std::to_string(i) : name);
    }
}

uint32_t GltfLoader::defaultMaterial() {
    if (m_defaultMaterial < 0) {
        // glTF 2.0 §3.9.6: the default material is metallic-roughness with every factor at its
        // default (baseColor 1, metallic 1, roughness 1).
        gpu::Material m{};
        m.baseColor = glm::vec3(1.0f);
        m.baseColorTexture = -1;
        m.metallic = 1.0f;
        m.roughness = 1.0f;
        m.ior = 1.5f;
        m_defaultMaterial = int(m_scene.materials.size());
        m_scene.materials.push_back(m);
        m_scene.materialNames.push_back("default material");
    }
    return uint32_t(m_defaultMaterial);
}

gpu::Material GltfLoader::convertMaterial(int index) {
    const tinygltf::Material& src = m_model.materials[size_t(index)];
    const std::string label = materialLabel(index);
    const std::string name = src.name.empty() ? "material " + std::to_string(index) : src.name;
    auto number = [&](double value, const std::string& what, double lo, double hi) {
        if (!(std::isfinite(value) && value >= lo && value <= hi)) {
            error(label + ": " + what + " " + std::to_string(value) + " is outside [" +
                  std::to_string(lo) + ", " + std::to_string(hi) + "]");
        }
        return float(value);
    };
    // A number member of an extension object, `fallback` when absent.
    auto member = [&](const tinygltf::Value& object, const std::string& extension, const char* key,
                      double fallback) {
        if (!object.IsObject() || !object.Has(key))
            return fallback;
        const tinygltf::Value& v = object.Get(key);
        if (!v.IsNumber())
            error(label + ": " + extension + "." + key + " must be a number");
        return v.GetNumberAsDouble();
    };
    auto extension = [&](const char* key) -> const tinygltf::Value* {
        auto it = src.extensions.find(key);
        return it == src.extensions.end() ? nullptr : &it->second;
    };

    gpu::Material m{};
    const tinygltf::PbrMetallicRoughness& pbr = src.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() != 4)
        error(label + ": baseColorFactor needs 4 values");
    for (int c = 0; c < 3; ++c)
        m.baseColor[c] = number(pbr.baseColorFactor[size_t(c)], "baseColorFactor", 0, 1);
    m.metallic = number(pbr.metallicFactor, "metallicFactor", 0, 1);
    m.roughness = number(pbr.roughnessFactor, "roughnessFactor", 0, 1);
    m.baseColorTexture = -1;
    m.normalScale = 1.0f;
    // The texture coordinates a texture reads: its TEXCOORD set and KHR_texture_transform, which
    // may override the set and maps uv to T R S uv (the extension's matrix: offset, rotation
    // counter-clockwise in radians, scale). Both are baked into the material's vertex uvs.
    auto mapping = [&](const tinygltf::TextureInfo& info, const char* what) {
        std::pair<int, glm::dmat3> out{info.texCoord, glm::dmat3(1.0)};
        auto ext = info.extensions.find("KHR_texture_transform");
        if (ext == info.extensions.end()) return out;
        const tinygltf::Value& t = ext->second;
        const std::string where = label + ": " + what + " KHR_texture_transform";
        auto pair = [&](const char* key, double fallback) {
            glm::dvec2 v(fallback);
            if (!t.Has(key)) return v;
            const tinygltf::Value& a = t.Get(key);
            if (!a.IsArray() || a.ArrayLen() != 2 || !a.Get(0).IsNumber() || !a.Get(1).IsNumber())
                error(where + "." + key + " needs 2 numbers");
            v = {a.Get(0).GetNumberAsDouble(), a.Get(1).GetNumberAsDouble()};
            if (!std::isfinite(v.x) || !std::isfinite(v.y)) error(where + "." + key + " is not finite");
            return v;
        };
        const glm::dvec2 offset = pair("offset", 0.0), scale = pair("scale", 1.0);
        const double rotation = member(t, "KHR_texture_transform", "rotation", 0.0);
        if (!std::isfinite(rotation)) error(where + ".rotation is not finite");
        if (t.Has("texCoord")) {
            const double set = member(t, "KHR_texture_transform", "texCoord", 0.0);
            if (!(set >= 0 && set <= 31 && set == std::floor(set))) error(where + ".texCoord out of range");
            out.first = int(set);
        }
        const double c = std::cos(rotation), sn = std::sin(rotation);
        const glm::dmat3 T(1, 0, 0, 0, 1, 0, offset.x, offset.y, 1);  // column-major, as the extension
        const glm::dmat3 R(c, sn, 0, -sn, c, 0, 0, 0, 1);
        const glm::dmat3 S(scale.x, 0, 0, 0, scale.y, 0, 0, 0, 1);
        out.second = T * R * S;
        return out;
    };
    // One texture coordinate mapping per material (the vertices carry one uv): the first
    // texture sets it; a later one read through another set or transform is left out with a
    // warning. Returns the texture's index in Scene::textures, or -1 when left out.
    bool mapped = false;
    auto texture = [&](const tinygltf::TextureInfo& info, const char* what) {
        const auto [set, transform] = mapping(info, what);
        if (mapped && (m_texCoordSet[size_t(index)] != set || m_uvTransform[size_t(index)] != transform)) {
            ignoreFor(std::string(what) + " with another TEXCOORD set or texture transform than the "
                      "material's other textures is ignored",
                      name);
            return -1;
        }
        const int slot = convertTexture(info, label, what);
        m_texCoordSet[size_t(index)] = set;
        m_uvTransform[size_t(index)] = transform;
        mapped = true;
        return slot;
    };
    if (pbr.baseColorTexture.index != -1) {
        m.baseColorTexture = texture(pbr.baseColorTexture, "baseColorTexture");
    }
    if (pbr.metallicRoughnessTexture.index != -1) {
        m.metallicRoughnessTexture = uint32_t(texture(pbr.metallicRoughnessTexture, "metallicRoughnessTexture") + 1);
    }
    if (src.normalTexture.index != -1) {
        // tinygltf's NormalTextureInfo is a TextureInfo with a scale.
        tinygltf::TextureInfo info;
        info.index = src.normalTexture.index;
        info.texCoord = src.normalTexture.texCoord;
        info.extensions = src.normalTexture.extensions;
        m.normalTexture = uint32_t(texture(info, "normalTexture") + 1);
        m.normalScale = number(src.normalTexture.scale, "normalTexture.scale", -1e6, 1e6);
    }
    if (src.occlusionTexture.index != -1) {
        // Baked ambient occlusion darkens indirect light a rasterizer cannot trace; a path
        // tracer computes that occlusion itself, so applying it would count it twice.
        ignoreFor("occlusionTexture is not used (a path tracer computes occlusion; baked ambient "
                  "occlusion would count it twice)",
                  name);
    }
    if (src.emissiveTexture.index != -1) {
        m.emissiveTexture = uint32_t(texture(src.emissiveTexture, "emissiveTexture") + 1);
    }
    // alphaMode (glTF 2.0 sec. 3.9.5): MASK cuts the surface where alpha = baseColorFactor.a *
    // the base colour texture's alpha is below alphaCutoff. BLEND is partial coverage: the
    // surface is there with probability alpha and a ray passes on otherwise (MATERIAL_BLEND,
    // shaders/common/bsdf.glsl LOBE_PASS), which is what a rasterizer's compositing averages.
    if (src.alphaMode == "BLEND") {
        const double alpha = number(pbr.baseColorFactor[3], "baseColorFactor", 0, 1);
        m.flags |= gpu::MATERIAL_BLEND;
        m.coverage = float(alpha);
        if (alpha == 0.0) m_invisible[size_t(index)] = true;  // no texture can bring it back
    } else if (src.alphaMode == "MASK") {
        const double cutoff = number(src.alphaCutoff, "alphaCutoff", 0, HUGE_VAL);
        const double alpha = number(pbr.baseColorFactor[3], "baseColorFactor", 0, 1);
        if (m.baseColorTexture >= 0 && cutoff > 0.0) {
            // Compared with the texture's alpha alone; above 1 everything is cut.
            m.alphaCutoff = alpha > 0.0 ? float(std::min(cutoff / alpha, 2.0)) : 2.0f;
        } else if (alpha < cutoff) {
            m_invisible[size_t(index)] = true;
        }
    } else if (src.alphaMode != "OPAQUE") {
        error(label + ": unknown alphaMode " + inQuotes(src.alphaMode));
    }

    // emission = emissiveFactor * KHR_materials_emissive_strength.emissiveStrength
    if (src.emissiveFactor.size() != 3)
        error(label + ": emissiveFactor needs 3 values");
    double strength = 1.0;
    if (const tinygltf::Value* ext = extension("KHR_materials_emissive_strength")) {
        strength = member(*ext, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
        number(strength, "emissiveStrength", 0, HUGE_VAL);
    }
    for (int c = 0; c < 3; ++c) {
        const double e = number(src.emissiveFactor[size_t(c)], "emissiveFactor", 0, HUGE_VAL);
        m.emission[c] = number(e * strength, "emission", 0, FLT_MAX);
    }

    // An extension's texture (a textureInfo object, as tinygltf parses the core ones: index,
    // texCoord, extensions): its index in Scene::textures + 1, 0 when absent or left out.
    auto extensionTexture = [&](const tinygltf::Value& ext, const char* extensionName,
                                const char* key) -> uint32_t {
        if (!ext.Has(key)) return 0;
        const tinygltf::Value& t = ext.Get(key);
        if (!t.IsObject() || !t.Has("index") || !t.Get("index").IsNumber())
            error(label + ": " + extensionName + "." + key + " needs an index");
        tinygltf::TextureInfo info;
        info.index = int(t.Get("index").GetNumberAsDouble());
        info.texCoord = int(member(t, key, "texCoord", 0.0));
        if (t.Has("extensions") && t.Get("extensions").IsObject()) {
            const tinygltf::Value& extensions = t.Get("extensions");
            for (const std::string& k : extensions.Keys()) info.extensions[k] = extensions.Get(k);
        }
        return uint32_t(texture(info, key) + 1);
    };
    if (const tinygltf::Value* ext = extension("KHR_materials_transmission")) {
        m.transmission = number(member(*ext, "KHR_materials_transmission", "transmissionFactor", 0),
                                "transmissionFactor", 0, 1);
        m.transmissionTexture = extensionTexture(*ext, "KHR_materials_transmission", "transmissionTexture");
    }
    // KHR_materials_specular: the strength (specularFactor times specularTexture's alpha) and
    // F0 colour (specularColorFactor times specularColorTexture, sRGB) of the dielectric
    // reflection (shaders/common/bsdf.glsl coatFresnel).
    if (const tinygltf::Value* ext = extension("KHR_materials_specular")) {
        m.flags |= gpu::MATERIAL_SPECULAR;
        m.specular = float(number(member(*ext, "KHR_materials_specular", "specularFactor", 1.0),
                                  "specularFactor", 0, 1));
        m.specularColor = glm::vec3(1.0f);
        if (ext->Has("specularColorFactor")) {
            const tinygltf::Value& value = ext->Get("specularColorFactor");
            if (!value.IsArray() || value.ArrayLen() != 3)
                error(label + ": KHR_materials_specular.specularColorFactor needs 3 numbers");
            for (int c = 0; c < 3; ++c) {
                const tinygltf::Value& v = value.Get(c);
                if (!v.IsNumber()) error(label + ": specularColorFactor must hold numbers");
                m.specularColor[c] = float(number(v.GetNumberAsDouble(), "specularColorFactor", 0, 1e6));
            }
        }
        m.specularTexture = extensionTexture(*ext, "KHR_materials_specular", "specularTexture");
        m.specularColorTexture = extensionTexture(*ext, "KHR_materials_specular", "specularColorTexture");
    }
    // KHR_materials_clearcoat: a GGX coat of ior 1.5 over the material (shaders/common/bsdf.glsl
    // LOBE_CLEARCOAT): its factor (times clearcoatTexture's red) and roughness (times
    // clearcoatRoughnessTexture's green), and its own normal: clearcoatNormalTexture (with its
    // scale), else the interpolated vertex normal, not the normalTexture's (MaterialSample
    // clearcoatNormal in shaders/common/scene.glsl).
    if (const tinygltf::Value* ext = extension("KHR_materials_clearcoat")) {
        m.clearcoat = float(number(member(*ext, "KHR_materials_clearcoat", "clearcoatFactor", 0.0),
                                   "clearcoatFactor", 0, 1));
        m.clearcoatRoughness =
            float(number(member(*ext, "KHR_materials_clearcoat", "clearcoatRoughnessFactor", 0.0),
                         "clearcoatRoughnessFactor", 0, 1));
        m.clearcoatTexture = extensionTexture(*ext, "KHR_materials_clearcoat", "clearcoatTexture");
        m.clearcoatRoughnessTexture =
            extensionTexture(*ext, "KHR_materials_clearcoat", "clearcoatRoughnessTexture");
        m.clearcoatNormalTexture =
            extensionTexture(*ext, "KHR_materials_clearcoat", "clearcoatNormalTexture");
        m.clearcoatNormalScale = 1.0f;
        if (m.clearcoatNormalTexture != 0) {
            // A normalTextureInfo: its scale multiplies the tangent-space normal's x and y.
            const tinygltf::Value& info = ext->Get("clearcoatNormalTexture");
            m.clearcoatNormalScale = float(number(
                member(info, "clearcoatNormalTexture", "scale", 1.0), "clearcoatNormalTexture.scale",
                -1e6, 1e6));
        }
        if (m.clearcoat == 0.0f) {
            // No coat, whatever its textures.
            m.clearcoatTexture = 0;
            m.clearcoatNormalTexture = 0;
        }
    }
    // KHR_materials_sheen: the Charlie sheen lobe over the material (shaders/common/bsdf.glsl
    // LOBE_SHEEN): sheenColorFactor (times sheenColorTexture, sRGB) and sheenRoughnessFactor
    // (times sheenRoughnessTexture's alpha). Black: no sheen.
    if (const tinygltf::Value* ext = extension("KHR_materials_sheen")) {
        if (ext->Has("sheenColorFactor")) {
            const tinygltf::Value& value = ext->Get("sheenColorFactor");
            if (!value.IsArray() || value.ArrayLen() != 3)
                error(label + ": KHR_materials_sheen.sheenColorFactor needs 3 numbers");
            for (int c = 0; c < 3; ++c) {
                const tinygltf::Value& v = value.Get(c);
                if (!v.IsNumber()) error(label + ": sheenColorFactor must hold numbers");
                m.sheenColor[c] = float(number(v.GetNumberAsDouble(), "sheenColorFactor", 0, 1));
            }
        }
        m.sheenRoughness = float(number(member(*ext, "KHR_materials_sheen", "sheenRoughnessFactor", 0.0),
                                        "sheenRoughnessFactor", 0, 1));
        m.sheenColorTexture = extensionTexture(*ext, "KHR_materials_sheen", "sheenColorTexture");
        m.sheenRoughnessTexture = extensionTexture(*ext, "KHR_materials_sheen", "sheenRoughnessTexture");
    }
    m.ior = 1.5f;
    if (const tinygltf::Value* ext = extension("KHR_materials_ior")) {
        m.ior = number(member(*ext, "KHR_materials_ior", "ior", 1.5), "ior", 1, 1e3);
    }
    double thickness = 0.0;
    if (const tinygltf::Value* ext = extension("KHR_materials_volume")) {
        thickness = number(member(*ext, "KHR_materials_volume", "thicknessFactor", 0),
                           "thicknessFactor", 0, HUGE_VAL);
        const double distance =
            member(*ext, "KHR_materials_volume", "attenuationDistance", HUGE_VAL);
        if (!(distance > 0))
            error(label + ": attenuationDistance must be positive");
        glm::dvec3 color(1.0);
        if (ext->Has("attenuationColor")) {
            const tinygltf::Value& value = ext->Get("attenuationColor");
            if (!value.IsArray() || value.ArrayLen() != 3) {
                error(label + ": KHR_materials_volume.attenuationColor needs 3 numbers");
            }
            for (int c = 0; c < 3; ++c) {
                const tinygltf::Value& v = value.Get(c);
                if (!v.IsNumber())
                    error(label + ": attenuationColor must hold numbers");
                color[c] = number(v.GetNumberAsDouble(), "attenuationColor", 0, 1);
            }
        }
        // Beer-Lambert: the colour white light takes after travelling attenuationDistance inside,
        // so sigma_a = -ln(color) / distance (the extension's definition). A colour of 0 absorbs
        // everything within a micron of the surface (sigma_a capped at 1e6 per unit).
        if (std::isfinite(distance)) {
            for (int c = 0; c < 3; ++c) {
                m.absorption[c] = float(std::min(-std::log(std::max(color[c], 1e-300)) / distance, 1e6));
            }
        }
    }
    // Without a volume (or with thicknessFactor 0) transmission is thin-walled
    // (KHR_materials_volume: "thicknessFactor 0 means the material is thin-walled"): a sheet.
    if (m.transmission > 0.0f && thickness == 0.0) m.flags |= gpu::MATERIAL_THIN_WALLED;
    if (src.doubleSided) m.flags |= gpu::MATERIAL_DOUBLE_SIDED;
    return m;
}

int GltfLoader::convertTexture(const tinygltf::TextureInfo& info, const std::string& label,
                               const char* what) {
    const int index = info.index;
    if (index < 0 || size_t(index) >= m_model.textures.size()) {
        error(label + ": " + what + " index " + std::to_string(index) + " out of range (" +
              std::to_string(m_model.textures.size()) + " textures)");
    }
    if (info.texCoord < 0 || info.texCoord > 31) {
        error(label + ": " + what + " texCoord " + std::to_string(info.texCoord) + " out of range");
    }
    const tinygltf::Texture& texture = m_model.textures[size_t(index)];
    uint32_t wrap = 0;
    if (texture.sampler != -1) {
        if (texture.sampler < 0 || size_t(texture.sampler) >= m_model.samplers.size()) {
            error("texture " + std::to_string(index) + ": sampler " +
                  std::to_string(texture.sampler) + " out of range (" +
                  std::to_string(m_model.samplers.size()) + " samplers)");
        }
        const tinygltf::Sampler& sampler = m_model.samplers[size_t(texture.sampler)];
        auto mode = [&](int glMode) -> uint32_t {
            switch (glMode) {
                case TINYGLTF_TEXTURE_WRAP_REPEAT: return gpu::WRAP_REPEAT;
                case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return gpu::WRAP_CLAMP;
                case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return gpu::WRAP_MIRROR;
                default:
                    error("sampler " + std::to_string(texture.sampler) + ": unknown wrap mode " +
                          std::to_string(glMode));
            }
        };
        wrap = mode(sampler.wrapS) | (mode(sampler.wrapT) << 2);
    }
    int& slot = m_textureSlot[size_t(index)];
    if (slot < 0) {
        if (texture.source == -1) {
            error("texture " + std::to_string(index) + " has no image source");
        }
        if (texture.source < 0 || size_t(texture.source) >= m_model.images.size()) {
            error("texture " + std::to_string(index) + ": image " + std::to_string(texture.source) +
                  " out of range (" + std::to_string(m_model.images.size()) + " images)");
        }
        slot = int(m_scene.textures.size());
        m_scene.textures.push_back(decodeImage(texture.source));
        m_scene.textures.back().wrap = wrap;
    }
    return slot;
}

// Decodes an image to 8-bit RGBA (stb_image: any channel count, 8 or 16 bits per channel).
Texture GltfLoader::decodeImage(int index) {
    const tinygltf::Image& image = m_model.images[size_t(index)];
    const std::string name = !image.name.empty() ? image.name : image.uri;
    const std::string label =
        "image " + std::to_string(index) + (name.empty() ? "" : " (" + inQuotes(name) + ")");
    const unsigned char* bytes = nullptr;
    size_t size = 0;
    if (image.bufferView >= 0) {
        const tinygltf::BufferView& view = checkedView(image.bufferView, label);
        bytes = m_model.buffers[size_t(view.buffer)].data.data() + view.byteOffset;
        size = view.byteLength;
    } else if (!image.image.empty()) {
        bytes = image.image.data();
        size = image.image.size();
    } else if (!image.uri.empty() && image.uri.rfind("data:", 0) != 0) {
        // tinygltf only warned (held until the render goes ahead): say here why.
        error(label + " could not be read: uri " + inQuotes(image.uri) +
              " names no readable regular file");
    } else {
        error(label + " could not be read");
    }
    if (size == 0 || size > size_t(INT_MAX))
        error(label + " has no or too much data");

    // Decoded in the file's own channel count and expanded here: stb_image 2.27 converts
    // 16-bit PNM channels wrongly when asked for another count.
    int width = 0, height = 0, channels = 0;
    std::vector<uint32_t> texels;
    auto expand = [&](const auto* pixels, auto to8) {
        texels.resize(size_t(width) * size_t(height));
        for (size_t i = 0; i < texels.size(); ++i) {
            const auto* p = pixels + size_t(channels) * i;
            const uint32_t grey = to8(p[0]);
            const bool colour = channels >= 3;
            const uint32_t r = grey, g = colour ? to8(p[1]) : grey, b = colour ? to8(p[2]) : grey;
            const uint32_t a = channels == 2 ? to8(p[1]) : channels == 4 ? to8(p[3]) : 255u;
            texels[i] = r | (g << 8) | (b << 16) | (a << 24);
        }
    };
    if (stbi_is_16_bit_from_memory(bytes, int(size))) {
        std::unique_ptr<stbi_us, void (*)(void*)> pixels(
            stbi_load_16_from_memory(bytes, int(size), &width, &height, &channels, 0),
            stbi_image_free);
        if (!pixels || channels < 1 || channels > 4) {
            error(label + " could not be decoded: " + decodeFailure());
        }
        // 16 to 8 bits with rounding: round(v * 255 / 65535).
        expand(pixels.get(), [](uint32_t v) { return (v * 255u + 32767u) / 65535u; });
    } else {
        std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
            stbi_load_from_memory(bytes, int(size), &width, &height, &channels, 0),
            stbi_image_free);
        if (!pixels || channels < 1 || channels > 4) {
            error(label + " could not be decoded: " + decodeFailure());
        }
        expand(pixels.get(), [](uint32_t v) { return v; });
    }
    Texture texture;
    texture.name = name.empty() ? "image " + std::to_string(index) : oneLine(name);
    texture.width = uint32_t(width);
    texture.height = uint32_t(height);
    texture.rgba8 = std::move(texels);
    return texture;
}

// ---------------------------------------------------------------------------------------------
// Buffers and accessors

const tinygltf::BufferView& GltfLoader::checkedView(int index, const std::string& user) const {
    if (index < 0 || size_t(index) >= m_model.bufferViews.size()) {
        error(user + ": buffer view " + std::to_string(index) + " out of range (" +
              std::to_string(m_model.bufferViews.size()) + " buffer views)");
    }
    const tinygltf::BufferView& view = m_model.bufferViews[size_t(index)];
    if (view.buffer < 0 || size_t(view.buffer) >= m_model.buffers.size()) {
        error("buffer view " + std::to_string(index) + ": buffer " + std::to_string(view.buffer) +
              " out of range (" + std::to_string(m_model.buffers.size()) + " buffers)");
    }
    const size_t bufferSize = m_model.buffers[size_t(view.buffer)].data.size();
    if (view.byteOffset > bufferSize || view.byteLength > bufferSize - view.byteOffset) {
        error("buffer view " + std::to_string(index) + " (" + std::to_string(view.byteLength) +
              " bytes at offset " + std::to_string(view.byteOffset) +
              ") extends past the end of buffer " + std::to_string(view.buffer) + " (" +
              std::to_string(bufferSize) + " bytes)");
    }
    return view;
}

AccessorData GltfLoader::readAccessor(int index, const std::string& role) const {
    const std::string label = "accessor " + std::to_string(index) + " (" + role + ")";
    if (index < 0 || size_t(index) >= m_model.accessors.size()) {
        error(label + " out of range (" + std::to_string(m_model.accessors.size()) + " accessors)");
    }
    const tinygltf::Accessor& accessor = m_model.accessors[size_t(index)];
    const size_t components = size_t(componentCount(accessor.type));
    const size_t elementSize = componentSize(accessor.componentType) * components;
    if (elementSize == 0)
        error(label + " has an unsupported type or component type");
    if (accessor.count == 0)
        error(label + " has count 0");

    AccessorData data;
    data.count = accessor.count;
    data.componentType = accessor.componentType;
    if (accessor.bufferView == -1) {
        // glTF 2.0 §3.6.2.3: an accessor without a buffer view reads zeros (plus sparse values).
        if (accessor.count > kMaxZeroAccessorCount)
            error(label + " is too large");
        data.dense.assign(accessor.count * elementSize, 0);
        data.stride = elementSize;
    } else {
        const tinygltf::BufferView& view = checkedView(accessor.bufferView, label);
        data.stride = view.byteStride ? view.byteStride : elementSize;
        if (data.stride < elementSize) {
            error(label + ": element size " + std::to_string(elementSize) +
                  " exceeds the byte stride " + std::to_string(data.stride) + " of buffer view " +
                  std::to_string(accessor.bufferView));
        }
        // The last element, at byteOffset + stride * (count - 1), must end inside the view.
        const size_t available = view.byteLength;
        if (accessor.byteOffset > available || elementSize > available - accessor.byteOffset ||
            (accessor.count - 1) > (available - accessor.byteOffset - elementSize) / data.stride) {
            error(label + " reads past the end of buffer view " +
                  std::to_string(accessor.bufferView));
        }
        data.data = m_model.buffers[size_t(view.buffer)].data.data() + view.byteOffset +
                    accessor.byteOffset;
    }
    if (accessor.sparse.isSparse)
        applySparse(accessor, elementSize, label, data);
    return data;
}

// Sparse accessors (glTF 2.0 §3.6.2.3): a dense copy with `count` elements replaced.
void GltfLoader::applySparse(const tinygltf::Accessor& accessor, size_t elementSize,
                             const std::string& label, AccessorData& data) const {
    const auto& sparse = accessor.sparse;
    if (sparse.count < 1 || size_t(sparse.count) > accessor.count) {
        error(label + ": sparse count " + std::to_string(sparse.count) + " out of range");
    }
    if (data.dense.empty()) {
        data.dense.resize(accessor.count * elementSize);
        for (size_t i = 0; i < accessor.count; ++i) {
            std::memcpy(data.dense.data() + i * elementSize, data.data + i * data.stride,
                        elementSize);
        }
        data.stride = elementSize;
    }
    const size_t count = size_t(sparse.count);
    const size_t indexSize = componentSize(sparse.indices.componentType);
    if (!isUnsignedIndexType(sparse.indices.componentType)) {
        error(label + ": sparse indices must be unsigned byte, short or int");
    }
    // Tightly packed sparse data of `bytes` bytes at `offset` must lie inside its view.
    auto sparseData = [&](int viewIndex, int offset, size_t bytes, const char* what) {
        const tinygltf::BufferView& view = checkedView(viewIndex, label + " sparse " + what);
        if (offset < 0 || size_t(offset) > view.byteLength ||
            bytes > view.byteLength - size_t(offset)) {
            error(label + ": sparse " + what + " read past the end of buffer view " +
                  std::to_string(viewIndex));
        }
        return m_model.buffers[size_t(view.buffer)].data.data() + view.byteOffset + size_t(offset);
    };
    const uint8_t* indices = sparseData(sparse.indices.bufferView, sparse.indices.byteOffset,
                                        count * indexSize, "indices");
    const uint8_t* values = sparseData(sparse.values.bufferView, sparse.values.byteOffset,
                                       count * elementSize, "values");
    int64_t previous = -1;
    for (size_t k = 0; k < count; ++k) {
        const uint32_t i =
            AccessorData::readUnsigned(indices + k * indexSize, sparse.indices.componentType);
        if (i >= accessor.count || int64_t(i) <= previous) {
            error(label + ": sparse index " + std::to_string(i) +
                  " is out of range or not increasing");
        }
        previous = i;
        std::memcpy(data.dense.data() + size_t(i) * elementSize, values + k * elementSize,
                    elementSize);
    }
}

// ---------------------------------------------------------------------------------------------
// Scene graph

void GltfLoader::traverseScene() {
    if (m_model.scenes.empty())
        error("no scene: the file defines no scenes");
    int sceneIndex = m_model.defaultScene == -1 ? 0 : m_model.defaultScene;
    if (sceneIndex < 0 || size_t(sceneIndex) >= m_model.scenes.size()) {
        error("default scene " + std::to_string(sceneIndex) + " out of range (" +
              std::to_string(m_model.scenes.size()) + " scenes)");
    }
    const std::vector<tinygltf::Node>& nodes = m_model.nodes;
    const int nodeCount = int(nodes.size());

    // Every node has at most one parent (glTF 2.0 §3.5.1: the nodes form disjoint trees).
    std::vector<int> parent(nodes.size(), -1);
    for (int n = 0; n < nodeCount; ++n) {
        for (int child : nodes[size_t(n)].children) {
            if (child < 0 || child >= nodeCount) {
                error(nodeLabel(n) + ": child node " + std::to_string(child) + " out of range (" +
                      std::to_string(nodeCount) + " nodes)");
            }
            if (parent[size_t(child)] != -1) {
                error(nodeLabel(child) + " has several parents (nodes " +
                      std::to_string(parent[size_t(child)]) + " and " + std::to_string(n) + ")");
            }
            parent[size_t(child)] = n;
        }
    }
    // Walk up from every node: reaching a node of the current walk again is a cycle.
    enum : uint8_t { kUnvisited, kOnWalk, kReachesRoot };
    std::vector<uint8_t> state(nodes.size(), kUnvisited);
    for (int n = 0; n < nodeCount; ++n) {
        int at = n;
        while (at != -1 && state[size_t(at)] == kUnvisited) {
            state[size_t(at)] = kOnWalk;
            at = parent[size_t(at)];
        }
        if (at != -1 && state[size_t(at)] == kOnWalk)
            error("node cycle through " + nodeLabel(at));
        for (at = n; at != -1 && state[size_t(at)] == kOnWalk; at = parent[size_t(at)]) {
            state[size_t(at)] = kReachesRoot;
        }
    }

    const tinygltf::Scene& scene = m_model.scenes[size_t(sceneIndex)];
    std::vector<bool> listed(nodes.size(), false);
    for (int root : scene.nodes) {
        if (root < 0 || root >= nodeCount) {
            error("scene " + std::to_string(sceneIndex) + ": node " + std::to_string(root) +
                  " out of range (" + std::to_string(nodeCount) + " nodes)");
        }
        if (parent[size_t(root)] != -1) {
            error("scene " + std::to_string(sceneIndex) + ": root " + nodeLabel(root) +
                  " is also a child of node " + std::to_string(parent[size_t(root)]));
        }
        if (listed[size_t(root)]) {
            error("scene " + std::to_string(sceneIndex) + " lists " + nodeLabel(root) + " twice");
        }
        listed[size_t(root)] = true;
    }

    // Depth-first, children in file order (the camera order).
    struct Pending {
        int node;
        glm::dmat4 parentWorld;
    };
    std::vector<Pending> stack;
    for (auto it = scene.nodes.rbegin(); it != scene.nodes.rend(); ++it) {
        stack.push_back({*it, glm::dmat4(1.0)});
    }
    while (!stack.empty()) {
        const Pending pending = stack.back();
        stack.pop_back();
        const tinygltf::Node& node = nodes[size_t(pending.node)];
        const glm::dmat4 world = pending.parentWorld * localTransform(pending.node);
        if (node.camera != -1)
            addCamera(pending.node, world);
        if (auto light = node.extensions.find("KHR_lights_punctual"); light != node.extensions.end())
            addLight(pending.node, light->second, world);
        if (node.skin != -1)
            warnOnce("skins are ignored: skinned meshes keep their bind pose");
        if (node.mesh != -1) {
            if (node.mesh < 0 || size_t(node.mesh) >= m_model.meshes.size()) {
                error(nodeLabel(pending.node) + ": mesh " + std::to_string(node.mesh) +
                      " out of range (" + std::to_string(m_model.meshes.size()) + " meshes)");
            }
            const tinygltf::Mesh& mesh = m_model.meshes[size_t(node.mesh)];
            for (int p = 0; p < int(mesh.primitives.size()); ++p)
                addPrimitive(node.mesh, p, world);
        }
        for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) {
            stack.push_back({*it, world});
        }
    }
}

// A node's matrix, or T * R * S (glTF 2.0 §3.5.3).
glm::dmat4 GltfLoader::localTransform(int index) const {
    const tinygltf::Node& node = m_model.nodes[size_t(index)];
    auto finite = [&](const std::vector<double>& values, size_t expected, const char* what) {
        if (values.size() != expected) {
            error(nodeLabel(index) + ": " + what + " has " + std::to_string(values.size()) +
                  " values, expected " + std::to_string(expected));
        }
        for (double v : values) {
            if (!std::isfinite(v))
                error(nodeLabel(index) + ": " + what + " is not finite");
        }
    };
    if (!node.matrix.empty()) {
        finite(node.matrix, 16, "matrix");
        const glm::dmat4 m = glm::make_mat4(node.matrix.data());  // column-major, as glTF
        if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) {
            error(nodeLabel(index) + ": matrix is not an affine transform");
        }
        return m;
    }
    glm::dmat4 transform(1.0);
    if (!node.translation.empty()) {
        finite(node.translation, 3, "translation");
        transform = glm::translate(transform, glm::make_vec3(node.translation.data()));
    }
    if (!node.rotation.empty()) {
        finite(node.rotation, 4, "rotation");
        const std::vector<double>& r = node.rotation;  // x, y, z, w
        const glm::dquat q(r[3], r[0], r[1], r[2]);
        const double length = glm::length(q);
        if (!(length > 1e-6))
            error(nodeLabel(index) + ": rotation is not a unit quaternion");
        transform *= glm::mat4_cast(q / length);
    }
    if (!node.scale.empty()) {
        finite(node.scale, 3, "scale");
        transform = glm::scale(transform, glm::make_vec3(node.scale.data()));
    }
    return transform;
}

void GltfLoader::addCamera(int nodeIndex, const glm::dmat4& world) {
    const tinygltf::Node& node = m_model.nodes[size_t(nodeIndex)];
    if (node.camera < 0 || size_t(node.camera) >= m_model.cameras.size()) {
        error(nodeLabel(nodeIndex) + ": camera " + std::to_string(node.camera) + " out of range (" +
              std::to_string(m_model.cameras.size()) + " cameras)");
    }
    const tinygltf::Camera& src = m_model.cameras[size_t(node.camera)];
    const std::string label = "camera " + std::to_string(node.camera);
    if (src.type == "orthographic") {
        warnOnce("orthographic cameras are skipped (pmcr renders pinhole cameras)");
        return;
    }
    if (src.type != "perspective")
        error(label + " has unknown type " + inQuotes(src.type));
    const double yfov = src.perspective.yfov;
    const double aspect = src.perspective.aspectRatio;
    if (!(yfov > 0.0 && yfov < glm::pi<double>()))
        error(label + ": yfov must be in (0, pi)");
    if (!(aspect >= 0.0 && std::isfinite(aspect)))
        error(label + ": aspectRatio must be positive");

    // glTF cameras look down -Z with +Y up in their node's frame (glTF 2.0 §3.10.1).
    const glm::dmat3 linear(world);
    const glm::dvec3 forward = linear * glm::dvec3(0.0, 0.0, -1.0);
    const glm::dvec3 up = linear * glm::dvec3(0.0, 1.0, 0.0);
    const double forwardLength = glm::length(forward);
    const glm::dvec3 f = forward / forwardLength;
    const glm::dvec3 upOrthogonal = up - glm::dot(up, f) * f;
    const double upLength = glm::length(upOrthogonal);
    if (!(forwardLength > 1e-12 && upLength > 1e-9 * glm::length(up) && upLength > 1e-12)) {
        error(nodeLabel(nodeIndex) + ": degenerate camera transform");
    }
    Camera camera;
    camera.name = !src.name.empty() ? src.name : !node.name.empty() ? node.name : label;
    camera.position = glm::vec3(world[3]);
    camera.forward = glm::vec3(f);
    camera.up = glm::vec3(upOrthogonal / upLength);
    camera.right = glm::normalize(glm::cross(camera.forward, camera.up));
    camera.yfov = float(yfov);
    camera.aspect = float(aspect);
    m_scene.cameras.push_back(camera);
}

// A KHR_lights_punctual light: at the node's origin, shining down its -Z axis. glTF gives point
// and spot intensity in candela and directional in lux; pmcr takes them, as the Khronos sample
// viewer does, in the units of emissive radiance (cd/m^2 with KHR_materials_emissive_strength),
// so that I / d^2 and an emitter's L compare directly. `range` is ignored: the spec makes it
// optional, and physical light falls off with the inverse square alone.
void GltfLoader::addLight(int nodeIndex, const tinygltf::Value& extension, const glm::dmat4& world) {
    const std::string node = nodeLabel(nodeIndex);
    if (!extension.IsObject() || !extension.Has("light") || !extension.Get("light").IsInt())
        error(node + ": KHR_lights_punctual without a light index");
    const int index = extension.Get("light").GetNumberAsInt();
    if (index < 0 || size_t(index) >= m_model.lights.size()) {
        error(node + ": light " + std::to_string(index) + " out of range (" +
              std::to_string(m_model.lights.size()) + " lights)");
    }
    const tinygltf::Light& src = m_model.lights[size_t(index)];
    const std::string label = "light " + std::to_string(index);
    glm::dvec3 color(1.0);
    if (!src.color.empty()) {
        if (src.color.size() != 3) error(label + ": color needs 3 values");
        color = glm::dvec3(src.color[0], src.color[1], src.color[2]);
    }
    const glm::dvec3 intensity = color * src.intensity;
    if (!std::isfinite(intensity.x + intensity.y + intensity.z) ||
        glm::any(glm::lessThan(intensity, glm::dvec3(0.0))))
        error(label + ": color and intensity must be finite and >= 0");
    if (src.range > 0.0) warnOnce("KHR_lights_punctual: range is ignored (light falls off with 1/d^2)");

    gpu::PunctualLight light{};
    light.position = glm::vec3(world[3]);
    const glm::dvec3 direction = glm::dmat3(world) * glm::dvec3(0.0, 0.0, -1.0);
    if (!(glm::length(direction) > 1e-12)) error(node + ": degenerate light transform");
    light.direction = glm::vec3(glm::normalize(direction));
    light.intensity = glm::vec3(intensity);
    light.cosInner = 1.0f;
    light.cosOuter = 1.0f;
    if (src.type == "point") {
        light.type = gpu::PUNCTUAL_POINT;
    } else if (src.type == "directional") {
        light.type = gpu::PUNCTUAL_DIRECTIONAL;
    } else if (src.type == "spot") {
        const double inner = src.spot.innerConeAngle, outer = src.spot.outerConeAngle;
        if (!(inner >= 0.0 && inner < outer && outer <= 0.5 * glm::pi<double>()))
            error(label + ": spot cone angles must satisfy 0 <= inner < outer <= pi/2");
        light.type = gpu::PUNCTUAL_SPOT;
        light.cosInner = float(std::cos(inner));
        light.cosOuter = float(std::cos(outer));
    } else {
        error(label + " has unknown type " + inQuotes(src.type));
    }
    if (luminance(light.intensity) > 0.0f) {
        m_scene.punctualLights.push_back(light);
        m_scene.punctualLightNames.push_back(
            src.name.empty() ? label : label + " (" + inQuotes(src.name) + ")");
    }
}

void GltfLoader::addPrimitive(int meshIndex, int primitiveIndex, const glm::dmat4& world) {
    const tinygltf::Primitive& primitive =
        m_model.meshes[size_t(meshIndex)].primitives[size_t(primitiveIndex)];
    const std::string mesh = meshLabel(meshIndex);
    const std::string where = "primitive " + std::to_string(primitiveIndex) + " of " + mesh;
    switch (primitive.mode) {
        case TINYGLTF_MODE_POINTS:
        case TINYGLTF_MODE_LINE:
        case TINYGLTF_MODE_LINE_LOOP:
        case TINYGLTF_MODE_LINE_STRIP:
            warnOnce("points and lines are skipped (pmcr renders triangles only)");
            return;
        case TINYGLTF_MODE_TRIANGLES:
        case TINYGLTF_MODE_TRIANGLE_STRIP:
        case TINYGLTF_MODE_TRIANGLE_FAN:
            break;
        default:
            error(where + " has unknown mode " + std::to_string(primitive.mode));
    }
    if (!primitive.targets.empty())
        warnOnce("morph targets are ignored");

    uint32_t material = 0;
    int texCoordSet = -1;
    glm::dmat3 uvTransform(1.0);
    if (primitive.material == -1) {
        material = defaultMaterial();
    } else if (primitive.material < 0 || size_t(primitive.material) >= m_model.materials.size()) {
        error(where + ": material " + std::to_string(primitive.material) + " out of range (" +
              std::to_string(m_model.materials.size()) + " materials)");
    } else {
        material = uint32_t(primitive.material);
        texCoordSet = m_texCoordSet[size_t(primitive.material)];
        uvTransform = m_uvTransform[size_t(primitive.material)];
        if (m_invisible[size_t(primitive.material)]) return;  // cut away by its alpha everywhere
    }
    // A normal map of the material's or of its clear coat's needs the tangents.
    const bool normalMapped = m_scene.materials[material].normalTexture != 0 ||
                              m_scene.materials[material].clearcoatNormalTexture != 0;

    auto attribute = [&](const std::string& name) -> const int* {
        auto it = primitive.attributes.find(name);
        return it == primitive.attributes.end() ? nullptr : &it->second;
    };
    if (!attribute("POSITION"))
        error(where + " has no POSITION attribute");
    const int positionIndex = *attribute("POSITION");
    const AccessorData positions = readAccessor(positionIndex, "POSITION of " + mesh);
    const tinygltf::Accessor& positionAccessor = m_model.accessors[size_t(positionIndex)];
    if (positionAccessor.type != TINYGLTF_TYPE_VEC3 ||
        positionAccessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
        error("accessor " + std::to_string(positionIndex) + " (POSITION of " + mesh +
              ") must be float VEC3");
    }
    const size_t vertexCount = positions.count;

    AccessorData normals;
    const bool hasNormals = attribute("NORMAL") != nullptr;
    if (hasNormals) {
        const int normalIndex = *attribute("NORMAL");
        const std::string role = "NORMAL of " + mesh;
        normals = readAccessor(normalIndex, role);
        const tinygltf::Accessor& a = m_model.accessors[size_t(normalIndex)];
        if (a.type != TINYGLTF_TYPE_VEC3 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
            error("accessor " + std::to_string(normalIndex) + " (" + role + ") must be float VEC3");
        }
        if (normals.count != vertexCount) {
            error("accessor " + std::to_string(normalIndex) + " (" + role + ") has " +
                  std::to_string(normals.count) + " elements, POSITION has " +
                  std::to_string(vertexCount));
        }
    }

    AccessorData texcoords;
    if (texCoordSet >= 0) {
        const std::string name = "TEXCOORD_" + std::to_string(texCoordSet);
        if (!attribute(name)) {
            error(where + " has no " + name + " for the textures of " +
                  materialLabel(primitive.material));
        }
        const int texcoordIndex = *attribute(name);
        const std::string role = name + " of " + mesh;
        texcoords = readAccessor(texcoordIndex, role);
        const tinygltf::Accessor& a = m_model.accessors[size_t(texcoordIndex)];
        const bool validType =
            a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
            (a.normalized && (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                              a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
        if (a.type != TINYGLTF_TYPE_VEC2 || !validType) {
            error("accessor " + std::to_string(texcoordIndex) + " (" + role +
                  ") must be VEC2 of float or normalized unsigned byte/short");
        }
        if (texcoords.count != vertexCount) {
            error("accessor " + std::to_string(texcoordIndex) + " (" + role + ") has " +
                  std::to_string(texcoords.count) + " elements, POSITION has " +
                  std::to_string(vertexCount));
        }
    }

    AccessorData tangents;
    const bool hasTangents = normalMapped && attribute("TANGENT") != nullptr;
    if (hasTangents) {
        const int tangentIndex = *attribute("TANGENT");
        const std::string role = "TANGENT of " + mesh;
        tangents = readAccessor(tangentIndex, role);
        const tinygltf::Accessor& a = m_model.accessors[size_t(tangentIndex)];
        if (a.type != TINYGLTF_TYPE_VEC4 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
            error("accessor " + std::to_string(tangentIndex) + " (" + role + ") must be float VEC4");
        }
        if (tangents.count != vertexCount) {
            error("accessor " + std::to_string(tangentIndex) + " (" + role + ") has " +
                  std::to_string(tangents.count) + " elements, POSITION has " +
                  std::to_string(vertexCount));
        }
    }

    // Vertex indices of the primitive, validated.
    std::vector<uint32_t> indices;
    if (primitive.indices != -1) {
        const std::string role = "indices of " + mesh;
        const AccessorData data = readAccessor(primitive.indices, role);
        const tinygltf::Accessor& a = m_model.accessors[size_t(primitive.indices)];
        if (a.type != TINYGLTF_TYPE_SCALAR || !isUnsignedIndexType(a.componentType)) {
            error("accessor " + std::to_string(primitive.indices) + " (" + role +
                  ") must be SCALAR unsigned byte, short or int");
        }
        indices.resize(data.count);
        for (size_t i = 0; i < data.count; ++i) {
            indices[i] = data.index(i);
            if (indices[i] >= vertexCount) {
                error("accessor " + std::to_string(primitive.indices) + " (" + role + "): index " +
                      std::to_string(indices[i]) + " at position " + std::to_string(i) +
                      " out of range (" + std::to_string(vertexCount) + " vertices)");
            }
        }
    } else {
        indices.resize(vertexCount);
        for (size_t i = 0; i < vertexCount; ++i)
            indices[i] = uint32_t(i);
    }

    // Triangles from the topology (glTF 2.0 §3.7.2.1); strip/fan joints with a repeated
    // vertex are skipped.
    std::vector<glm::uvec3> triangles;
    const size_t n = indices.size();
    if (primitive.mode == TINYGLTF_MODE_TRIANGLES) {
        if (n % 3 != 0) {
            error(where + ": " + std::to_string(n) + " vertex indices, not a multiple of 3");
        }
        triangles.reserve(n / 3);
        for (size_t i = 0; i + 2 < n; i += 3) {
            triangles.emplace_back(indices[i], indices[i + 1], indices[i + 2]);
        }
    } else {
        for (size_t i = 0; i + 2 < n; ++i) {
            glm::uvec3 t;
            if (primitive.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
                t = {indices[i], indices[i + 1 + i % 2], indices[i + 2 - i % 2]};
            } else {
                t = {indices[i + 1], indices[i + 2], indices[0]};
            }
            if (t.x != t.y && t.y != t.z && t.x != t.z)
                triangles.push_back(t);
        }
    }
    if (m_scene.vertices.size() + vertexCount > kMaxVertices ||
        m_scene.triangles.size() + triangles.size() > kMaxTriangles) {
        error("scene too large (more than " + std::to_string(kMaxTriangles) +
              " triangles or vertices)");
    }

    // World-space vertices: normals by the inverse transpose, unusable ones (0,0,0).
    const glm::dmat3 linear(world);
    const double determinant = glm::determinant(linear);
    const glm::dmat3 normalMatrix =
        determinant != 0.0 ? glm::inverseTranspose(linear) : glm::dmat3(0.0);
    const uint32_t base = uint32_t(m_scene.vertices.size());
    for (size_t i = 0; i < vertexCount; ++i) {
        gpu::Vertex v{};
        v.position = glm::vec3(world * glm::dvec4(glm::dvec3(positions.vec3(i)), 1.0));
        if (hasNormals) {
            const glm::dvec3 normal = normalMatrix * glm::dvec3(normals.vec3(i));
            const double length = glm::length(normal);
            if (length > 0.0 && std::isfinite(length))
                v.normal = glm::vec3(normal / length);
        }
        if (texCoordSet >= 0) {
            const glm::vec2 uv = texcoords.texcoord(i);
            if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) {
                error(where + ": TEXCOORD_" + std::to_string(texCoordSet) +
                      " holds a non-finite value");
            }
            const glm::dvec3 mapped = uvTransform * glm::dvec3(uv, 1.0);
            v.u = float(mapped.x);
            v.v = float(mapped.y);
        }
        m_scene.vertices.push_back(v);
    }
    // A mirroring transform turns counter-clockwise triangles clockwise (glTF 2.0 §3.7.4).
    const bool flip = determinant < 0.0;
    for (glm::uvec3& t : triangles) {
        if (flip) std::swap(t.y, t.z);
        m_scene.triangles.push_back({base + t.x, base + t.y, base + t.z, material});
    }

    // Tangents of normal-mapped primitives (Scene::tangents, one per scene vertex once any
    // primitive has them): TANGENT transformed as a direction, its w flipped by a mirroring
    // transform (the bitangent cross(N, T) w must stay the transformed one); else generated.
    if (normalMapped && m_scene.tangents.empty()) m_scene.tangents.resize(base, glm::vec4(0.0f));
    if (!m_scene.tangents.empty()) {
        std::vector<glm::vec4> generated;
        if (normalMapped && !hasTangents) {
            generated = generateTangents(std::span(m_scene.vertices).subspan(base), triangles);
        }
        for (size_t i = 0; i < vertexCount; ++i) {
            glm::vec4 tangent(0.0f);
            if (hasTangents) {
                const glm::vec4 t = tangents.vec4(i);
                const glm::dvec3 d = linear * glm::dvec3(glm::vec3(t));
                const double length = glm::length(d);
                if (length > 0.0 && std::isfinite(length) && std::isfinite(t.w)) {
                    tangent = glm::vec4(glm::vec3(d / length), (t.w < 0.0f) != flip ? -1.0f : 1.0f);
                }
            } else if (normalMapped) {
                tangent = generated[i];
            }
            m_scene.tangents.push_back(tangent);
        }
    }
}

}  // namespace

Scene loadScene(const std::filesystem::path& path, const EnvironmentSpec& environment,
                const SceneLoadOptions& options) {
    try {
        return GltfLoader(path, environment, options).load();
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        fail(path.string(), "out of memory while loading the scene");
    } catch (const std::exception& e) {
        fail(path.string(), std::string("cannot load: ") + oneLine(e.what()));
    }
}

}  // namespace pmcr
