#include "source_glb.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/error.h"

namespace pmcr::scenegen {

namespace {

using Json = nlohmann::json;

uint32_t readU32(const std::vector<uint8_t>& data, size_t offset) {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
        v |= uint32_t(data[offset + size_t(i)]) << (8 * i);
    return v;
}

class Reader {
public:
    explicit Reader(const std::filesystem::path& path) : m_file(path.string()) {
        std::ifstream stream(path, std::ios::binary);
        if (!stream)
            fail(m_file, "cannot open (is --assets right?)");
        const std::vector<uint8_t> data{std::istreambuf_iterator<char>(stream),
                                        std::istreambuf_iterator<char>()};
        // GLB container, glTF 2.0 section 4.4.
        if (data.size() < 28 || readU32(data, 0) != 0x46546C67u || readU32(data, 8) != data.size())
            fail(m_file, "not a .glb");
        const size_t jsonLength = readU32(data, 12);
        if (readU32(data, 16) != 0x4E4F534Au || 20 + jsonLength + 8 > data.size())
            fail(m_file, "bad JSON chunk");
        m_json =
            Json::parse(data.begin() + 20, data.begin() + 20 + long(jsonLength), nullptr, false);
        if (m_json.is_discarded() || !m_json.is_object())
            fail(m_file, "JSON chunk is not valid JSON");
        const size_t binAt = 20 + jsonLength;
        if (readU32(data, binAt + 4) != 0x004E4942u ||
            binAt + 8 + readU32(data, binAt) > data.size())
            fail(m_file, "bad BIN chunk");
        m_bin.assign(data.begin() + long(binAt) + 8,
                     data.begin() + long(binAt + 8 + readU32(data, binAt)));
    }

    SourceGlb read() {
        for (const auto& node : m_json.value("nodes", Json::array())) {
            if (node.contains("mesh") &&
                (node.contains("matrix") || node.contains("translation") ||
                 node.contains("rotation") || node.contains("scale") || node.contains("children")))
                fail(m_file, "a mesh node has a transform; only world-space meshes are read");
        }
        SourceGlb source;
        for (const auto& mesh : m_json.value("meshes", Json::array())) {
            for (const auto& p : mesh.at("primitives")) {
                if (p.value("mode", 4) != 4)
                    fail(m_file, "a primitive is not a triangle list");
                SourcePrimitive out;
                out.meshName = mesh.value("name", "");
                out.mesh.name = out.meshName;
                out.material = p.value("material", -1);
                const Json& attributes = p.at("attributes");
                out.mesh.positions = vec3s(attributes.at("POSITION").get<size_t>());
                if (attributes.contains("NORMAL"))
                    out.mesh.normals = vec3s(attributes["NORMAL"].get<size_t>());
                out.mesh.indices = indices(p.at("indices").get<size_t>());
                for (uint32_t i : out.mesh.indices) {
                    if (i >= out.mesh.positions.size())
                        fail(m_file, "mesh '" + out.meshName + "': index out of range");
                }
                source.primitives.push_back(std::move(out));
            }
        }
        source.json = std::move(m_json);
        return source;
    }

private:
    // The bytes of a tightly packed accessor of `elementSize`-byte elements.
    const uint8_t* data(const Json& accessor, size_t elementSize) const {
        const Json& view = m_json.at("bufferViews").at(accessor.at("bufferView").get<size_t>());
        if (view.value("byteStride", elementSize) != elementSize || accessor.contains("sparse"))
            fail(m_file, "an accessor is strided or sparse");
        const size_t offset =
            view.value("byteOffset", size_t(0)) + accessor.value("byteOffset", size_t(0));
        const size_t size = accessor.at("count").get<size_t>() * elementSize;
        if (offset + size >
                view.value("byteOffset", size_t(0)) + view.at("byteLength").get<size_t>() ||
            offset + size > m_bin.size())
            fail(m_file, "an accessor reads past its buffer view");
        return m_bin.data() + offset;
    }

    std::vector<glm::vec3> vec3s(size_t index) const {
        const Json& a = m_json.at("accessors").at(index);
        if (a.at("componentType") != 5126 || a.at("type") != "VEC3")
            fail(m_file, "accessor " + std::to_string(index) + " is not float VEC3");
        std::vector<glm::vec3> out(a.at("count").get<size_t>());
        std::memcpy(out.data(), data(a, sizeof(glm::vec3)), out.size() * sizeof(glm::vec3));
        return out;
    }

    std::vector<uint32_t> indices(size_t index) const {
        const Json& a = m_json.at("accessors").at(index);
        if (a.at("type") != "SCALAR")
            fail(m_file, "accessor " + std::to_string(index) + " is not SCALAR");
        std::vector<uint32_t> out(a.at("count").get<size_t>());
        if (a.at("componentType") == 5125) {
            std::memcpy(out.data(), data(a, 4), out.size() * 4);
        } else if (a.at("componentType") == 5123) {
            const uint8_t* p = data(a, 2);
            for (size_t i = 0; i < out.size(); ++i)
                out[i] = uint32_t(p[2 * i]) | uint32_t(p[2 * i + 1]) << 8;
        } else {
            fail(m_file, "accessor " + std::to_string(index) + " has unsupported indices");
        }
        return out;
    }

    std::string m_file;
    Json m_json;
    std::vector<uint8_t> m_bin;
};

}  // namespace

SourceGlb readSourceGlb(const std::filesystem::path& path) {
    try {
        return Reader(path).read();
    } catch (const Json::exception& e) {
        fail(path.string(), std::string("unexpected glTF layout: ") + e.what());
    }
}

const SourcePrimitive& sourcePrimitive(const SourceGlb& source, const std::string& meshName,
                                       const std::filesystem::path& path) {
    for (const auto& p : source.primitives) {
        if (p.meshName == meshName)
            return p;
    }
    fail(path.string(), "has no mesh named '" + meshName + "'");
}

}  // namespace pmcr::scenegen
