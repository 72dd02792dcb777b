// Independent validation of the committed procedural scenes (scenes/*.glb, written by
// pmcr-scenegen): the GLB container and the glTF 2.0 JSON are parsed here from scratch, without
// the generator's code or tinygltf, and checked for what pmcr's loader relies on.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "test_util.h"

namespace {

using Json = nlohmann::json;

struct Glb {
    Json json;
    std::vector<uint8_t> bin;
};

uint32_t u32(const std::vector<uint8_t>& d, size_t at) {
    uint32_t v;
    std::memcpy(&v, d.data() + at, 4);  // GLB is little-endian, as are the test machines
    return v;
}

// GLB layout (glTF 2.0 section 4.4): 12-byte header, JSON chunk, BIN chunk.
void loadGlb(const std::string& name, Glb& out) {
    const auto path = pmcr::test::sourcePath("scenes/" + name + ".glb");
    std::ifstream stream(path, std::ios::binary);
    ASSERT_TRUE(stream) << path;
    const std::vector<uint8_t> d{std::istreambuf_iterator<char>(stream),
                                 std::istreambuf_iterator<char>()};
    ASSERT_GE(d.size(), 28u);
    ASSERT_EQ(u32(d, 0), 0x46546C67u) << "magic";
    ASSERT_EQ(u32(d, 4), 2u) << "container version";
    ASSERT_EQ(u32(d, 8), d.size()) << "header length";
    const size_t jsonLength = u32(d, 12);
    ASSERT_EQ(u32(d, 16), 0x4E4F534Au) << "JSON chunk type";
    ASSERT_EQ(jsonLength % 4, 0u);
    ASSERT_LE(20 + jsonLength + 8, d.size());
    out.json = Json::parse(d.begin() + 20, d.begin() + 20 + long(jsonLength), nullptr, false);
    ASSERT_FALSE(out.json.is_discarded()) << "JSON chunk does not parse";
    const size_t binAt = 20 + jsonLength;
    const size_t binLength = u32(d, binAt);
    ASSERT_EQ(u32(d, binAt + 4), 0x004E4942u) << "BIN chunk type";
    ASSERT_EQ(binAt + 8 + binLength, d.size());
    out.bin.assign(d.begin() + long(binAt) + 8, d.end());
}

glm::dvec3 emission(const Json& material) {
    glm::dvec3 e(0.0);
    if (material.contains("emissiveFactor")) {
        for (int c = 0; c < 3; ++c)
            e[c] = material["emissiveFactor"][c].get<double>();
    }
    const Json& ext = material.value("extensions", Json::object());
    if (ext.contains("KHR_materials_emissive_strength")) {
        e *= ext["KHR_materials_emissive_strength"]["emissiveStrength"].get<double>();
    }
    return e;
}

// Reads float VEC3 element i of an accessor whose bounds were validated.
glm::dvec3 readVec3(const Glb& g, const Json& accessor, size_t i) {
    const Json& view = g.json["bufferViews"][accessor["bufferView"].get<size_t>()];
    const size_t at = view.value("byteOffset", size_t(0)) +
                      accessor.value("byteOffset", size_t(0)) +
                      i * view.value("byteStride", size_t(12));
    float v[3];
    std::memcpy(v, g.bin.data() + at, sizeof(v));
    return {v[0], v[1], v[2]};
}

uint32_t readIndex(const Glb& g, const Json& accessor, size_t i) {
    const Json& view = g.json["bufferViews"][accessor["bufferView"].get<size_t>()];
    const size_t at =
        view.value("byteOffset", size_t(0)) + accessor.value("byteOffset", size_t(0)) + 4 * i;
    uint32_t v;
    std::memcpy(&v, g.bin.data() + at, 4);
    return v;
}

const std::vector<std::string> kScenes = {"cornell-spheres", "cornell-glass", "cornell-specular",
                                          "cornell-classic", "furnace",       "furnace-sphere"};

class SceneFile : public ::testing::TestWithParam<std::string> {};

TEST_P(SceneFile, IsValidGltfForPmcr) {
    Glb g;
    ASSERT_NO_FATAL_FAILURE(loadGlb(GetParam(), g));
    const Json& j = g.json;
    EXPECT_EQ(j["asset"]["version"], "2.0");

    // Default image size.
    EXPECT_GT(j["extras"]["pmcr"]["width"].get<int>(), 0);
    EXPECT_GT(j["extras"]["pmcr"]["height"].get<int>(), 0);

    // A perspective camera held by a node.
    ASSERT_TRUE(j.contains("cameras") && !j["cameras"].empty());
    EXPECT_EQ(j["cameras"][0]["type"], "perspective");
    EXPECT_GT(j["cameras"][0]["perspective"]["yfov"].get<double>(), 0.0);
    EXPECT_GT(j["cameras"][0]["perspective"]["znear"].get<double>(), 0.0);
    bool cameraNode = false;
    for (const auto& n : j["nodes"])
        cameraNode = cameraNode || n.contains("camera");
    EXPECT_TRUE(cameraNode);

    // Materials: at least one emitter; every extension declared.
    std::set<std::string> used;
    for (const auto& e : j.value("extensionsUsed", Json::array()))
        used.insert(e.get<std::string>());
    int emissive = 0;
    for (const auto& m : j["materials"]) {
        if (emission(m) != glm::dvec3(0.0))
            ++emissive;
        const Json extensions = m.value("extensions", Json::object());
        for (const auto& item : extensions.items()) {
            EXPECT_TRUE(used.count(item.key())) << item.key() << " not in extensionsUsed";
        }
    }
    EXPECT_GE(emissive, 1);

    // Buffer views inside the one GLB buffer, 4-byte aligned; the BIN chunk pads by < 4 bytes.
    ASSERT_EQ(j["buffers"].size(), 1u);
    const size_t bufferLength = j["buffers"][0]["byteLength"].get<size_t>();
    EXPECT_LE(bufferLength, g.bin.size());
    EXPECT_LT(g.bin.size() - bufferLength, 4u);
    for (const auto& v : j["bufferViews"]) {
        const size_t offset = v.value("byteOffset", size_t(0));
        EXPECT_EQ(offset % 4, 0u);
        EXPECT_LE(offset + v["byteLength"].get<size_t>(), bufferLength);
    }
    // Accessors inside their buffer views.
    for (const auto& a : j["accessors"]) {
        const size_t componentBytes = a["componentType"] == 5126 || a["componentType"] == 5125 ? 4
                                      : a["componentType"] == 5123                             ? 2
                                                                                               : 1;
        const size_t components = a["type"] == "VEC3" ? 3 : a["type"] == "SCALAR" ? 1 : 0;
        ASSERT_GT(components, 0u) << "unexpected accessor type " << a["type"];
        const Json& view = j["bufferViews"][a["bufferView"].get<size_t>()];
        const size_t element = componentBytes * components;
        const size_t stride = view.value("byteStride", element);
        const size_t count = a["count"].get<size_t>();
        ASSERT_GT(count, 0u);
        EXPECT_LE(a.value("byteOffset", size_t(0)) + stride * (count - 1) + element,
                  view["byteLength"].get<size_t>());
    }

    // Triangle lists: POSITION with min/max bounding the data, u32 indices in range.
    size_t triangles = 0;
    for (const auto& mesh : j["meshes"]) {
        for (const auto& p : mesh["primitives"]) {
            EXPECT_EQ(p.value("mode", 4), 4);
            const Json& pos = j["accessors"][p["attributes"]["POSITION"].get<size_t>()];
            ASSERT_TRUE(pos.contains("min") && pos.contains("max"));
            const size_t vertices = pos["count"].get<size_t>();
            for (size_t i = 0; i < vertices; ++i) {
                const glm::dvec3 v = readVec3(g, pos, i);
                for (int c = 0; c < 3; ++c) {
                    ASSERT_GE(v[c], pos["min"][c].get<double>());
                    ASSERT_LE(v[c], pos["max"][c].get<double>());
                }
            }
            const Json& idx = j["accessors"][p["indices"].get<size_t>()];
            ASSERT_EQ(idx["componentType"], 5125);
            ASSERT_EQ(idx["count"].get<size_t>() % 3, 0u);
            for (size_t i = 0; i < idx["count"].get<size_t>(); ++i) {
                ASSERT_LT(readIndex(g, idx, i), vertices);
            }
            triangles += idx["count"].get<size_t>() / 3;
        }
    }
    EXPECT_GT(triangles, 0u);
}

INSTANTIATE_TEST_SUITE_P(Committed, SceneFile, ::testing::ValuesIn(kScenes), [](const auto& info) {
    std::string name = info.param;
    for (char& c : name) {
        if (c == '-')
            c = '_';
    }
    return name;
});

// Front-face normal (CCW, glTF 2.0 section 3.7.2.1) summed over a mesh's triangles, weighted by
// twice their area; and the sum of dot(normal, centroid - point) over triangles.
struct Facing {
    glm::dvec3 normalSum{0.0};
    double towardsPoint = 0.0;  // > 0 when every front face looks towards `point` on average
    size_t awayFromPoint = 0;   // triangles whose front face looks away from `point`
    size_t triangles = 0;
};

Facing facing(const Glb& g, const std::string& meshName, const glm::dvec3& point) {
    Facing f;
    for (const auto& mesh : g.json["meshes"]) {
        if (mesh.value("name", "") != meshName)
            continue;
        for (const auto& p : mesh["primitives"]) {
            const Json& pos = g.json["accessors"][p["attributes"]["POSITION"].get<size_t>()];
            const Json& idx = g.json["accessors"][p["indices"].get<size_t>()];
            for (size_t t = 0; t < idx["count"].get<size_t>() / 3; ++t) {
                const glm::dvec3 a = readVec3(g, pos, readIndex(g, idx, 3 * t));
                const glm::dvec3 b = readVec3(g, pos, readIndex(g, idx, 3 * t + 1));
                const glm::dvec3 c = readVec3(g, pos, readIndex(g, idx, 3 * t + 2));
                const glm::dvec3 n = glm::cross(b - a, c - a);
                f.normalSum += n;
                const double toward = glm::dot(n, point - (a + b + c) / 3.0);
                f.towardsPoint += toward;
                if (toward < 0.0)
                    ++f.awayFromPoint;
                ++f.triangles;
            }
        }
    }
    return f;
}

const Json* materialNamed(const Glb& g, const std::string& name) {
    for (const auto& m : g.json["materials"]) {
        if (m.value("name", "") == name)
            return &m;
    }
    return nullptr;
}

// The Cornell scenes keep Bitterli's light (radiance 17, 12, 4, facing down), walls facing into
// the room, and camera (eye (0, 1, 6.8), vertical fov 19.5 degrees).
TEST(SceneFiles, CornellBoxesMatchBitterli) {
    for (const std::string name :
         {"cornell-spheres", "cornell-glass", "cornell-specular", "cornell-classic"}) {
        SCOPED_TRACE(name);
        Glb g;
        ASSERT_NO_FATAL_FAILURE(loadGlb(name, g));
        const Json* light = materialNamed(g, "Light");
        ASSERT_NE(light, nullptr);
        const glm::dvec3 le = emission(*light);
        EXPECT_NEAR(le.x, 17.0, 1e-9);
        EXPECT_NEAR(le.y, 12.0, 1e-9);
        EXPECT_NEAR(le.z, 4.0, 1e-9);
        const Facing lightFacing = facing(g, "Light", glm::dvec3(0.0));
        EXPECT_LT(lightFacing.normalSum.y, 0.0);
        EXPECT_NEAR(std::abs(lightFacing.normalSum.y), 2.0 * 0.47 * 0.38, 1e-5);  // 2 x area
        for (const std::string wall : {"Floor", "Ceiling", "BackWall", "LeftWall", "RightWall"}) {
            const Facing f = facing(g, wall, {0.0, 1.0, 0.0});
            EXPECT_GT(f.towardsPoint, 0.0) << wall;
            EXPECT_EQ(f.awayFromPoint, 0u) << wall;
        }
        const Json& cam = g.json["cameras"][0]["perspective"];
        EXPECT_NEAR(cam["yfov"].get<double>(), 19.5 * std::numbers::pi / 180.0, 1e-12);
        bool found = false;
        for (const auto& n : g.json["nodes"]) {
            if (!n.contains("camera"))
                continue;
            found = true;
            EXPECT_FALSE(n.contains("rotation"));
            EXPECT_EQ(n["translation"], Json::array({0.0, 1.0, 6.8}));
        }
        EXPECT_TRUE(found);
    }
}

// Furnaces: every surface is Lambertian albedo 0.5 with emitted radiance 0.5 (the analytic
// answer in scenes/README.md depends on it), and the enclosure faces its centre.
TEST(SceneFiles, FurnacesHaveTheAnalyticSetup) {
    for (const std::string name : {"furnace", "furnace-sphere"}) {
        SCOPED_TRACE(name);
        Glb g;
        ASSERT_NO_FATAL_FAILURE(loadGlb(name, g));
        for (const auto& m : g.json["materials"]) {
            const Json& pbr = m["pbrMetallicRoughness"];
            EXPECT_EQ(pbr["baseColorFactor"], Json::array({0.5, 0.5, 0.5, 1.0}));
            EXPECT_EQ(pbr.value("metallicFactor", 1.0), 0.0);
            EXPECT_EQ(pbr.value("roughnessFactor", 1.0), 1.0);
            EXPECT_EQ(emission(m), glm::dvec3(0.5));
            EXPECT_FALSE(m.contains("extensions"));
        }
        const Facing enclosure = facing(g, "Enclosure", glm::dvec3(0.0));
        EXPECT_GT(enclosure.triangles, 0u);
        EXPECT_EQ(enclosure.awayFromPoint, 0u);
        EXPECT_GT(enclosure.towardsPoint, 0.0);
    }
    Glb g;
    ASSERT_NO_FATAL_FAILURE(loadGlb("furnace-sphere", g));
    // The inner sphere faces outwards, towards the enclosure and the camera.
    const Facing inner = facing(g, "InnerSphere", glm::dvec3(0.0));
    EXPECT_GT(inner.triangles, 0u);
    EXPECT_EQ(inner.awayFromPoint, inner.triangles);
}

}  // namespace
