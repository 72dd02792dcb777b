#include "gltf_check.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <tuple>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace pmcr::scenegen {

namespace {

using Json = nlohmann::json;

// glTF 2.0 enumerations (specification section 5).
constexpr int kUnsignedByte = 5121;
constexpr int kUnsignedShort = 5123;
constexpr int kUnsignedInt = 5125;
constexpr int kFloat = 5126;
constexpr int kTriangles = 4;

uint32_t readU32(const std::vector<uint8_t>& data, size_t offset) {
    return uint32_t(data[offset]) | uint32_t(data[offset + 1]) << 8 |
           uint32_t(data[offset + 2]) << 16 | uint32_t(data[offset + 3]) << 24;
}

size_t componentSize(int componentType) {
    switch (componentType) {
        case 5120:
        case kUnsignedByte:
            return 1;
        case 5122:
        case kUnsignedShort:
            return 2;
        case kUnsignedInt:
        case kFloat:
            return 4;
        default:
            return 0;
    }
}

size_t componentCount(const std::string& type) {
    if (type == "SCALAR")
        return 1;
    if (type == "VEC2")
        return 2;
    if (type == "VEC3")
        return 3;
    if (type == "VEC4" || type == "MAT2")
        return 4;
    if (type == "MAT3")
        return 9;
    if (type == "MAT4")
        return 16;
    return 0;
}

double luminance(const glm::dvec3& rgb) {
    return 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z;  // Rec. 709 / sRGB primaries
}

// A validated accessor: element i starts at base + i * stride.
struct Accessor {
    const uint8_t* base = nullptr;
    size_t count = 0;
    size_t stride = 0;
    int componentType = 0;
    std::string type;

    glm::vec3 vec3(size_t i) const {
        glm::vec3 v;
        std::memcpy(&v, base + i * stride, sizeof(v));
        return v;
    }
    uint32_t index(size_t i) const {
        const uint8_t* p = base + i * stride;
        if (componentType == kUnsignedByte)
            return *p;
        if (componentType == kUnsignedShort) {
            uint16_t v;
            std::memcpy(&v, p, sizeof(v));
            return v;
        }
        uint32_t v;
        std::memcpy(&v, p, sizeof(v));
        return v;
    }
};

class Checker {
public:
    explicit Checker(const std::filesystem::path& path) : m_file(path.string()) {}

    CheckReport run(const std::filesystem::path& path) {
        readContainer(path);
        checkAsset();
        checkExtensions();
        checkBufferViews();
        checkMaterials();
        checkMeshes();
        checkNodesAndCamera();
        checkExtras();
        if (m_report.emissiveTriangles == 0 && !hasEnvironment())
            problem("no emissive triangles and no extras.pmcr.environment");
        return m_report;
    }

private:
    [[noreturn]] void problem(const std::string& message) const { fail(m_file, message); }

    const Json& member(const Json& object, const char* key, const std::string& where) const {
        if (!object.is_object() || !object.contains(key))
            problem(where + " has no " + key);
        return object[key];
    }

    const Json& array(const char* key) const {
        static const Json empty = Json::array();
        if (!m_json.contains(key))
            return empty;
        if (!m_json[key].is_array())
            problem(std::string(key) + " is not an array");
        return m_json[key];
    }

    size_t unsignedValue(const Json& value, const std::string& what) const {
        if (!value.is_number_unsigned())
            problem(what + " is not a non-negative integer");
        return value.get<size_t>();
    }

    size_t indexInto(const Json& value, const char* arrayName, const std::string& what) const {
        const size_t i = unsignedValue(value, what);
        if (i >= array(arrayName).size()) {
            problem(what + " = " + std::to_string(i) + " is out of range of " + arrayName);
        }
        return i;
    }

    double number(const Json& object, const char* key, double fallback,
                  const std::string& where) const {
        if (!object.contains(key))
            return fallback;
        if (!object[key].is_number())
            problem(where + "." + key + " is not a number");
        return object[key].get<double>();
    }

    static std::vector<uint8_t> readBytes(const std::filesystem::path& path) {
        std::ifstream stream(path, std::ios::binary);
        if (!stream)
            fail(path.string(), "cannot open");
        return {std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
    }

    // A .gltf is the JSON text alone; its buffers are files named by uri (section 3.6.1.1).
    void readContainer(const std::filesystem::path& path) {
        m_directory = path.parent_path();
        const std::vector<uint8_t> data = readBytes(path);
        m_report.fileBytes = data.size();
        if (path.extension() == ".gltf") {
            m_glb = false;
            m_json = Json::parse(data.begin(), data.end(), nullptr, false);
            if (m_json.is_discarded() || !m_json.is_object())
                problem("not valid JSON");
            return;
        }
        readGlb(data);
    }

    // GLB container (glTF 2.0 section 4.4): header, JSON chunk, optional BIN chunk.
    void readGlb(const std::vector<uint8_t>& data) {
        if (data.size() < 20)
            problem("too short for a .glb");
        if (readU32(data, 0) != 0x46546C67u)
            problem("not a .glb (bad magic)");
        if (readU32(data, 4) != 2u)
            problem("GLB container version is not 2");
        if (readU32(data, 8) != data.size())
            problem("GLB header length differs from file size");
        const size_t jsonLength = readU32(data, 12);
        if (readU32(data, 16) != 0x4E4F534Au)
            problem("first GLB chunk is not JSON");
        if (jsonLength % 4 != 0 || 20 + jsonLength > data.size()) {
            problem("JSON chunk length is misaligned or runs past the end of the file");
        }
        m_json =
            Json::parse(data.begin() + 20, data.begin() + 20 + long(jsonLength), nullptr, false);
        if (m_json.is_discarded() || !m_json.is_object())
            problem("JSON chunk is not valid JSON");
        size_t offset = 20 + jsonLength;
        if (offset < data.size()) {
            if (offset + 8 > data.size())
                problem("truncated BIN chunk header");
            const size_t binLength = readU32(data, offset);
            if (readU32(data, offset + 4) != 0x004E4942u)
                problem("second GLB chunk is not BIN");
            if (binLength % 4 != 0 || offset + 8 + binLength != data.size()) {
                problem("BIN chunk length is misaligned or does not end the file");
            }
            m_glbBin.assign(data.begin() + long(offset) + 8, data.end());
        }
    }

    void checkAsset() {
        const Json& asset = member(m_json, "asset", "the file");
        const Json& version = member(asset, "version", "asset");
        if (!version.is_string() || version.get<std::string>() != "2.0") {
            problem("asset.version is not \"2.0\"");
        }
    }

    void checkExtensions() {
        for (const auto& e : array("extensionsUsed")) {
            if (!e.is_string())
                problem("extensionsUsed holds a non-string");
            if (!m_extensionsUsed.insert(e.get<std::string>()).second) {
                problem("extensionsUsed lists " + e.get<std::string>() + " twice");
            }
        }
        for (const auto& e : array("extensionsRequired")) {
            if (!e.is_string() || !m_extensionsUsed.count(e.get<std::string>())) {
                problem("extensionsRequired names an extension missing from extensionsUsed");
            }
        }
        m_report.extensionsUsed.assign(m_extensionsUsed.begin(), m_extensionsUsed.end());
    }

    void checkBufferViews() {
        const Json& buffers = array("buffers");
        for (size_t b = 0; b < buffers.size(); ++b) {
            const std::string where = "buffer " + std::to_string(b);
            const size_t length =
                unsignedValue(member(buffers[b], "byteLength", where), where + ".byteLength");
            if (m_glb) {
                if (buffers[b].contains("uri"))
                    problem(where + " is external; expected GLB-stored");
                // The BIN chunk may be up to 3 bytes longer than the buffer (section 4.4.3.3).
                if (b != 0 || length > m_glbBin.size() || m_glbBin.size() - length > 3) {
                    problem(where + ".byteLength does not match the BIN chunk");
                }
                m_buffers.push_back(m_glbBin);
                continue;
            }
            m_buffers.push_back(readExternal(member(buffers[b], "uri", where), where));
            // The generator writes each file exactly; a longer or shorter one is stale.
            if (m_buffers.back().size() != length) {
                problem(where + ".byteLength is " + std::to_string(length) + " but " +
                        buffers[b]["uri"].get<std::string>() + " holds " +
                        std::to_string(m_buffers.back().size()) + " bytes");
            }
        }
        const Json& views = array("bufferViews");
        for (size_t v = 0; v < views.size(); ++v) {
            const std::string where = "bufferView " + std::to_string(v);
            const size_t buffer =
                indexInto(member(views[v], "buffer", where), "buffers", where + ".buffer");
            const size_t length =
                unsignedValue(member(views[v], "byteLength", where), where + ".byteLength");
            const size_t offset = views[v].contains("byteOffset")
                                      ? unsignedValue(views[v]["byteOffset"], where + ".byteOffset")
                                      : 0;
            if (length == 0)
                problem(where + " is empty");
            if (offset % 4 != 0)
                problem(where + ".byteOffset is not a multiple of 4");
            if (offset + length > buffers[buffer]["byteLength"].get<size_t>()) {
                problem(where + " runs past the end of buffer " + std::to_string(buffer));
            }
            if (views[v].contains("byteStride")) {
                const size_t stride = unsignedValue(views[v]["byteStride"], where + ".byteStride");
                if (stride < 4 || stride > 252 || stride % 4 != 0) {
                    problem(where + ".byteStride is not a multiple of 4 in [4, 252]");
                }
            }
        }
    }

    // A buffer file: a relative path below the .gltf's folder (no data: URI, no "..").
    std::vector<uint8_t> readExternal(const Json& uri, const std::string& where) {
        if (!uri.is_string())
            problem(where + ".uri is not a string");
        const std::string text = uri.get<std::string>();
        const std::filesystem::path relative(text);
        if (text.empty() || text.starts_with("data:") || relative.is_absolute() ||
            text.find('\\') != std::string::npos || text.find('%') != std::string::npos) {
            problem(where + ".uri '" + text + "' is not a plain relative file name");
        }
        for (const auto& part : relative) {
            if (part == "..")
                problem(where + ".uri '" + text + "' leaves the scene's folder");
        }
        m_report.externalFiles.push_back(text);
        return readBytes(m_directory / relative);
    }

    Accessor accessor(size_t index) const {
        const std::string where = "accessor " + std::to_string(index);
        const Json& a = array("accessors")[index];
        if (a.contains("sparse"))
            problem(where + " is sparse; the generator never writes one");
        const size_t viewIndex =
            indexInto(member(a, "bufferView", where), "bufferViews", where + ".bufferView");
        const Json& view = array("bufferViews")[viewIndex];
        Accessor result;
        result.count = unsignedValue(member(a, "count", where), where + ".count");
        const Json& componentType = member(a, "componentType", where);
        const Json& type = member(a, "type", where);
        if (!componentType.is_number_integer() || !type.is_string()) {
            problem(where + " has a malformed componentType or type");
        }
        result.componentType = componentType.get<int>();
        result.type = type.get<std::string>();
        const size_t component = componentSize(result.componentType);
        const size_t components = componentCount(result.type);
        if (component == 0 || components == 0)
            problem(where + " has an unknown type");
        if (result.count == 0)
            problem(where + " has count 0");
        const size_t element = component * components;
        const size_t offset =
            a.contains("byteOffset") ? unsignedValue(a["byteOffset"], where + ".byteOffset") : 0;
        const size_t viewOffset = view.value("byteOffset", size_t(0));
        const size_t viewLength = view["byteLength"].get<size_t>();
        result.stride = view.value("byteStride", element);
        if (offset % component != 0 || (viewOffset + offset) % component != 0) {
            problem(where + " is not aligned to its component size");
        }
        if (result.stride < element)
            problem(where + ": byteStride is smaller than an element");
        if (offset + result.stride * (result.count - 1) + element > viewLength) {
            problem(where + " reads past the end of bufferView " + std::to_string(viewIndex));
        }
        result.base = m_buffers[view["buffer"].get<size_t>()].data() + viewOffset + offset;
        return result;
    }

    void checkMaterials() {
        const Json& materials = array("materials");
        m_report.materials = materials.size();
        for (size_t i = 0; i < materials.size(); ++i) {
            const Json& m = materials[i];
            const std::string where = "material " + std::to_string(i);
            auto inUnit = [&](double v, const std::string& what) {
                if (!(v >= 0.0 && v <= 1.0))
                    problem(where + ": " + what + " is outside [0, 1]");
            };
            if (m.contains("pbrMetallicRoughness")) {
                const Json& pbr = m["pbrMetallicRoughness"];
                if (pbr.contains("baseColorFactor")) {
                    const Json& c = pbr["baseColorFactor"];
                    if (!c.is_array() || c.size() != 4)
                        problem(where + ": bad baseColorFactor");
                    for (const auto& x : c)
                        inUnit(x.get<double>(), "baseColorFactor");
                }
                inUnit(number(pbr, "metallicFactor", 1.0, where), "metallicFactor");
                inUnit(number(pbr, "roughnessFactor", 1.0, where), "roughnessFactor");
            }
            glm::dvec3 emission(0.0);
            if (m.contains("emissiveFactor")) {
                const Json& e = m["emissiveFactor"];
                if (!e.is_array() || e.size() != 3)
                    problem(where + ": bad emissiveFactor");
                for (int c = 0; c < 3; ++c) {
                    emission[c] = e[c].get<double>();
                    inUnit(emission[c], "emissiveFactor");
                }
            }
            if (m.contains("extensions")) {
                const Json& ext = m["extensions"];
                for (const auto& item : ext.items()) {
                    if (!m_extensionsUsed.count(item.key())) {
                        problem(where + " uses " + item.key() + " missing from extensionsUsed");
                    }
                    m_extensionsSeen.insert(item.key());
                }
                if (ext.contains("KHR_materials_emissive_strength")) {
                    const double s = number(ext["KHR_materials_emissive_strength"],
                                            "emissiveStrength", 1.0, where);
                    if (!(s >= 0.0))
                        problem(where + ": negative emissiveStrength");
                    emission *= s;
                }
                if (ext.contains("KHR_materials_transmission")) {
                    inUnit(
                        number(ext["KHR_materials_transmission"], "transmissionFactor", 0.0, where),
                        "transmissionFactor");
                }
                if (ext.contains("KHR_materials_ior")) {
                    const double ior = number(ext["KHR_materials_ior"], "ior", 1.5, where);
                    if (!(ior == 0.0 || ior >= 1.0))
                        problem(where + ": ior below 1");
                }
                if (ext.contains("KHR_materials_volume") &&
                    !ext.contains("KHR_materials_transmission")) {
                    problem(where + ": KHR_materials_volume without KHR_materials_transmission");
                }
            }
            m_emission.push_back(emission);
            if (emission != glm::dvec3(0.0))
                ++m_report.emissiveMaterials;
        }
    }

    void checkMeshes() {
        const Json& meshes = array("meshes");
        m_report.meshes = meshes.size();
        m_report.boundsMin = glm::dvec3(std::numeric_limits<double>::max());
        m_report.boundsMax = glm::dvec3(-std::numeric_limits<double>::max());
        for (size_t mi = 0; mi < meshes.size(); ++mi) {
            const Json& primitives = member(meshes[mi], "primitives", "mesh " + std::to_string(mi));
            if (!primitives.is_array() || primitives.empty()) {
                problem("mesh " + std::to_string(mi) + " has no primitives");
            }
            const std::string name = meshes[mi].value("name", "mesh " + std::to_string(mi));
            for (size_t pi = 0; pi < primitives.size(); ++pi) {
                checkPrimitive(primitives[pi],
                               "mesh " + std::to_string(mi) + " primitive " + std::to_string(pi),
                               name);
            }
        }
        if (m_report.triangles == 0)
            problem("no triangles");
        if (m_report.emitterArea > 0.0)
            m_report.emitterNormal /= m_report.emitterArea;
        for (const auto& used : m_extensionsUsed) {
            if (!m_extensionsSeen.count(used))
                problem("extensionsUsed lists unused " + used);
        }
    }

    void checkPrimitive(const Json& p, const std::string& where, const std::string& name) {
        if (p.value("mode", kTriangles) != kTriangles)
            problem(where + " is not a triangle list");
        const Json& attributes = member(p, "attributes", where);
        const Accessor pos =
            accessor(indexInto(member(attributes, "POSITION", where + ".attributes"), "accessors",
                               where + " POSITION"));
        if (pos.componentType != kFloat || pos.type != "VEC3") {
            problem(where + ": POSITION is not float VEC3");
        }
        // POSITION must carry min and max (section 3.7.2.1), equal to the data's bounds.
        const Json& posJson = array("accessors")[attributes["POSITION"].get<size_t>()];
        glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        for (size_t i = 0; i < pos.count; ++i) {
            const glm::vec3 v = pos.vec3(i);
            if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
                problem(where + ": non-finite position");
            }
            lo = glm::min(lo, v);
            hi = glm::max(hi, v);
        }
        for (int c = 0; c < 3; ++c) {
            const Json& mn = member(posJson, "min", where + " POSITION");
            const Json& mx = member(posJson, "max", where + " POSITION");
            if (!mn.is_array() || !mx.is_array() || mn.size() != 3 || mx.size() != 3 ||
                mn[c].get<float>() != lo[c] || mx[c].get<float>() != hi[c]) {
                problem(where + ": POSITION min/max differ from the data");
            }
        }
        m_report.boundsMin = glm::min(m_report.boundsMin, glm::dvec3(lo));
        m_report.boundsMax = glm::max(m_report.boundsMax, glm::dvec3(hi));
        m_report.vertices += pos.count;

        bool smooth = false;
        Accessor nrm;
        if (attributes.contains("NORMAL")) {
            smooth = true;
            nrm = accessor(indexInto(attributes["NORMAL"], "accessors", where + " NORMAL"));
            if (nrm.componentType != kFloat || nrm.type != "VEC3" || nrm.count != pos.count) {
                problem(where + ": NORMAL is not float VEC3 with one normal per vertex");
            }
            for (size_t i = 0; i < nrm.count; ++i) {
                if (std::abs(glm::length(glm::dvec3(nrm.vec3(i))) - 1.0) > 1e-5) {
                    problem(where + ": normal " + std::to_string(i) + " is not unit length");
                }
            }
        }

        const Accessor idx =
            accessor(indexInto(member(p, "indices", where), "accessors", where + ".indices"));
        if (idx.type != "SCALAR" ||
            (idx.componentType != kUnsignedByte && idx.componentType != kUnsignedShort &&
             idx.componentType != kUnsignedInt)) {
            problem(where + ": indices are not unsigned scalars");
        }
        if (idx.count % 3 != 0)
            problem(where + ": index count is not a multiple of 3");
        const size_t material =
            indexInto(member(p, "material", where), "materials", where + ".material");
        const glm::dvec3 emission = m_emission[material];

        // Vertices welded by exact position, so that faces with their own corners still close.
        std::map<std::tuple<float, float, float>, uint32_t> weld;
        std::vector<uint32_t> welded(pos.count);
        for (size_t i = 0; i < pos.count; ++i) {
            const glm::vec3 q = pos.vec3(i);
            welded[i] = weld.try_emplace({q.x, q.y, q.z}, uint32_t(weld.size())).first->second;
        }
        std::set<std::pair<uint32_t, uint32_t>> edges;
        bool manifold = true;
        double volume = 0.0;
        for (size_t t = 0; t < idx.count / 3; ++t) {
            uint32_t v[3];
            for (int k = 0; k < 3; ++k) {
                v[k] = idx.index(3 * t + k);
                if (v[k] >= pos.count)
                    problem(where + ": index out of range of POSITION");
            }
            const glm::dvec3 p0 = pos.vec3(v[0]), p1 = pos.vec3(v[1]), p2 = pos.vec3(v[2]);
            const glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
            const double area = 0.5 * glm::length(n);
            // Signed volume by the divergence theorem; each directed edge must occur once.
            volume += glm::dot(p0, glm::cross(p1, p2)) / 6.0;
            for (int k = 0; k < 3; ++k) {
                manifold = edges.insert({welded[v[k]], welded[v[(k + 1) % 3]]}).second && manifold;
            }
            if (!(area > 1e-12))
                problem(where + ": triangle " + std::to_string(t) + " is degenerate");
            if (smooth) {
                const glm::dvec3 shading = glm::dvec3(nrm.vec3(v[0])) + glm::dvec3(nrm.vec3(v[1])) +
                                           glm::dvec3(nrm.vec3(v[2]));
                if (glm::dot(n, shading) <= 0.0) {
                    problem(where + ": triangle " + std::to_string(t) +
                            " is wound against its normals");
                }
            }
            if (emission != glm::dvec3(0.0)) {
                ++m_report.emissiveTriangles;
                m_report.emitterArea += area;
                // One-sided Lambertian emitter: exitance pi * L, so power = pi * area * L.
                m_report.emittedPower += std::numbers::pi * area * luminance(emission);
                m_report.emitterNormal += 0.5 * n;
            }
        }
        for (const auto& [a, b] : edges) {
            if (!edges.count({b, a}))
                manifold = false;
        }
        if (manifold)
            m_report.closedMeshes.push_back({name, volume});
        m_report.triangles += idx.count / 3;
        if (smooth)
            m_report.smoothTriangles += idx.count / 3;
    }

    void checkNodesAndCamera() {
        const Json& nodes = array("nodes");
        const Json& cameras = array("cameras");
        if (cameras.empty())
            problem("no camera");
        for (size_t i = 0; i < cameras.size(); ++i) {
            const std::string where = "camera " + std::to_string(i);
            if (cameras[i].value("type", std::string()) != "perspective") {
                problem(where + " is not perspective");
            }
            const Json& persp = member(cameras[i], "perspective", where);
            const double yfov = number(persp, "yfov", 0.0, where);
            const double znear = number(persp, "znear", 0.0, where);
            if (!(yfov > 0.0 && yfov < std::numbers::pi))
                problem(where + ": bad yfov");
            if (!(znear > 0.0))
                problem(where + ": znear must be positive");
            if (persp.contains("zfar") && !(number(persp, "zfar", 0.0, where) > znear)) {
                problem(where + ": zfar must exceed znear");
            }
        }
        bool haveCamera = false;
        std::set<size_t> meshNodes;
        for (size_t i = 0; i < nodes.size(); ++i) {
            const Json& n = nodes[i];
            const std::string where = "node " + std::to_string(i);
            // The generator writes a flat node list with world-space meshes.
            if (n.contains("children") || n.contains("matrix") || n.contains("scale")) {
                problem(where + " has children, a matrix or a scale");
            }
            if (n.contains("mesh")) {
                indexInto(n["mesh"], "meshes", where + ".mesh");
                meshNodes.insert(n["mesh"].get<size_t>());
                if (n.contains("translation") || n.contains("rotation")) {
                    problem(where + ": mesh nodes must carry no transform");
                }
            }
            if (n.contains("camera")) {
                const size_t c = indexInto(n["camera"], "cameras", where + ".camera");
                if (n.contains("rotation")) {
                    const Json& q = n["rotation"];
                    double norm = 0.0;
                    for (const auto& x : q)
                        norm += x.get<double>() * x.get<double>();
                    if (q.size() != 4 || std::abs(norm - 1.0) > 1e-6) {
                        problem(where + ": rotation is not a unit quaternion");
                    }
                }
                if (!haveCamera) {
                    haveCamera = true;
                    if (n.contains("translation")) {
                        for (int k = 0; k < 3; ++k) {
                            m_report.cameraPosition[k] = n["translation"][k].get<double>();
                        }
                    }
                    m_report.cameraYfov = cameras[c]["perspective"]["yfov"].get<double>();
                }
            }
        }
        if (!haveCamera)
            problem("no node holds a camera");
        if (meshNodes.size() != array("meshes").size())
            problem("a mesh is not used by any node");

        const Json& scenes = array("scenes");
        const size_t scene =
            indexInto(m_json.contains("scene") ? m_json["scene"] : Json(0), "scenes", "scene");
        std::set<size_t> roots;
        for (const auto& r : member(scenes[scene], "nodes", "the scene")) {
            if (!roots.insert(indexInto(r, "nodes", "scene node")).second) {
                problem("the scene lists a node twice");
            }
        }
        if (roots.size() != nodes.size())
            problem("the scene does not list every node");
    }

    bool hasEnvironment() const {
        return m_json.contains("extras") && m_json["extras"].contains("pmcr") &&
               m_json["extras"]["pmcr"].contains("environment") &&
               m_json["extras"]["pmcr"]["environment"].is_string();
    }

    void checkExtras() {
        const Json& extras = member(m_json, "extras", "the file");
        const Json& pmcr = member(extras, "pmcr", "extras");
        auto size = [&](const char* key) {
            const size_t v =
                unsignedValue(member(pmcr, key, "extras.pmcr"), std::string("extras.pmcr.") + key);
            if (v == 0 || v > 16384)
                problem(std::string("extras.pmcr.") + key + " out of range");
            return int(v);
        };
        m_report.width = size("width");
        m_report.height = size("height");
        if (pmcr.contains("paper_width") != pmcr.contains("paper_height"))
            problem("extras.pmcr needs both paper_width and paper_height or neither");
        if (pmcr.contains("paper_width")) {
            m_report.paperWidth = size("paper_width");
            m_report.paperHeight = size("paper_height");
        }
    }

    std::string m_file;
    Json m_json;
    std::filesystem::path m_directory;
    bool m_glb = true;
    std::vector<uint8_t> m_glbBin;
    std::vector<std::vector<uint8_t>> m_buffers;  // contents of buffers[i]
    std::set<std::string> m_extensionsUsed;
    std::set<std::string> m_extensionsSeen;
    std::vector<glm::dvec3> m_emission;
    CheckReport m_report;
};

}  // namespace

CheckReport checkScene(const std::filesystem::path& path) {
    return Checker(path).run(path);
}

std::string formatReport(const std::filesystem::path& path, const CheckReport& r) {
    std::ostringstream out;
    out.precision(6);
    out << path.string() << ": ok, " << r.fileBytes << " bytes, " << r.width << "x" << r.height;
    if (r.paperWidth > 0)
        out << " (paper " << r.paperWidth << "x" << r.paperHeight << ")";
    for (const auto& file : r.externalFiles)
        out << ", " << file;
    out << "\n  " << r.meshes << " meshes, " << r.vertices << " vertices, " << r.triangles
        << " triangles (" << r.smoothTriangles << " with normals), " << r.materials
        << " materials\n  emitters: " << r.emissiveMaterials << " materials, "
        << r.emissiveTriangles << " triangles, area " << r.emitterArea << ", power "
        << r.emittedPower << ", mean normal (" << r.emitterNormal.x << ", " << r.emitterNormal.y
        << ", " << r.emitterNormal.z << ")\n  bounds (" << r.boundsMin.x << ", " << r.boundsMin.y
        << ", " << r.boundsMin.z << ") - (" << r.boundsMax.x << ", " << r.boundsMax.y << ", "
        << r.boundsMax.z << "), camera at (" << r.cameraPosition.x << ", " << r.cameraPosition.y
        << ", " << r.cameraPosition.z << "), yfov " << r.cameraYfov << "\n  extensions:";
    for (const auto& e : r.extensionsUsed)
        out << " " << e;
    if (r.extensionsUsed.empty())
        out << " none";
    out << "\n  closed meshes (signed volume):";
    for (const auto& [name, volume] : r.closedMeshes)
        out << " " << name << " " << volume;
    if (r.closedMeshes.empty())
        out << " none";
    return out.str();
}

}  // namespace pmcr::scenegen
