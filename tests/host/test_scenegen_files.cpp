// Independent validation of the committed scenes (scenes/*.glb and scenes/*.gltf with their
// buffer files, written by pmcr-scenegen): the GLB container and the glTF 2.0 JSON are parsed
// here from scratch, without the generator's code or tinygltf, and checked for what pmcr's loader
// relies on and for what each scene is meant to show.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "scene/gltf_loader.h"
#include "test_util.h"

namespace {

using Json = nlohmann::json;

struct SceneData {
    Json json;
    std::vector<std::vector<uint8_t>> buffers;  // contents of json["buffers"][i]
    bool glb = true;
    size_t glbPadding = 0;  // BIN chunk bytes beyond buffer 0's byteLength
};

uint32_t u32(const std::vector<uint8_t>& d, size_t at) {
    uint32_t v;
    std::memcpy(&v, d.data() + at, 4);  // GLB is little-endian, as are the test machines
    return v;
}

std::vector<uint8_t> readFile(const std::filesystem::path& path) {
    std::ifstream stream(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
}

// GLB layout (glTF 2.0 section 4.4): 12-byte header, JSON chunk, BIN chunk.
void loadGlb(const std::filesystem::path& path, SceneData& out) {
    const std::vector<uint8_t> d = readFile(path);
    ASSERT_GE(d.size(), 28u) << path;
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
    ASSERT_EQ(out.json["buffers"].size(), 1u);
    ASSERT_FALSE(out.json["buffers"][0].contains("uri"));
    const size_t length = out.json["buffers"][0]["byteLength"].get<size_t>();
    ASSERT_LE(length, binLength);
    out.glbPadding = binLength - length;
    out.buffers.emplace_back(d.begin() + long(binAt) + 8, d.begin() + long(binAt + 8 + length));
}

// A .gltf and its buffer files, named by uris relative to it (section 3.6.1.1).
void loadGltf(const std::filesystem::path& path, SceneData& out) {
    const std::vector<uint8_t> d = readFile(path);
    out.glb = false;
    out.json = Json::parse(d.begin(), d.end(), nullptr, false);
    ASSERT_FALSE(out.json.is_discarded()) << path << " does not parse";
    for (const auto& buffer : out.json["buffers"]) {
        ASSERT_TRUE(buffer.contains("uri"));
        const std::string uri = buffer["uri"].get<std::string>();
        ASSERT_FALSE(uri.starts_with("data:") || uri.starts_with("/") ||
                     uri.find("..") != std::string::npos)
            << uri;
        out.buffers.push_back(readFile(path.parent_path() / uri));
        ASSERT_EQ(out.buffers.back().size(), buffer["byteLength"].get<size_t>()) << uri;
    }
}

// scenes/<name>.glb, else scenes/<name>.gltf.
void loadScene(const std::string& name, SceneData& out) {
    const auto glb = pmcr::test::sourcePath("scenes/" + name + ".glb");
    const auto gltf = pmcr::test::sourcePath("scenes/" + name + ".gltf");
    if (std::filesystem::exists(glb)) {
        ASSERT_FALSE(std::filesystem::exists(gltf)) << name << " exists as .glb and .gltf";
        loadGlb(glb, out);
    } else {
        ASSERT_TRUE(std::filesystem::exists(gltf)) << "no scenes/" << name << ".glb or .gltf";
        loadGltf(gltf, out);
    }
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

const std::vector<uint8_t>& viewBuffer(const SceneData& g, const Json& view) {
    return g.buffers.at(view["buffer"].get<size_t>());
}

// Reads float VEC3 element i of an accessor whose bounds were validated.
glm::dvec3 readVec3(const SceneData& g, const Json& accessor, size_t i) {
    const Json& view = g.json["bufferViews"][accessor["bufferView"].get<size_t>()];
    const size_t at = view.value("byteOffset", size_t(0)) +
                      accessor.value("byteOffset", size_t(0)) +
                      i * view.value("byteStride", size_t(12));
    float v[3];
    std::memcpy(v, viewBuffer(g, view).data() + at, sizeof(v));
    return {v[0], v[1], v[2]};
}

uint32_t readIndex(const SceneData& g, const Json& accessor, size_t i) {
    const Json& view = g.json["bufferViews"][accessor["bufferView"].get<size_t>()];
    const size_t at =
        view.value("byteOffset", size_t(0)) + accessor.value("byteOffset", size_t(0)) + 4 * i;
    uint32_t v;
    std::memcpy(&v, viewBuffer(g, view).data() + at, 4);
    return v;
}

const std::vector<std::string> kScenes = {
    "cornell-spheres",     "cornell-glass", "cornell-specular",
    "cornell-classic",     "furnace",       "furnace-sphere",
    "checkers-two-lights", "plant-shadows", "dragon-direct",
    "dragon-caustic",      "room",          "veach-mis",
    "glass-caustic-torus", "sky-spheres",   "lamp-room",
    "sky-materials"};

class SceneFile : public ::testing::TestWithParam<std::string> {};

TEST_P(SceneFile, IsValidGltfForPmcr) {
    SceneData g;
    ASSERT_NO_FATAL_FAILURE(loadScene(GetParam(), g));
    const Json& j = g.json;
    EXPECT_EQ(j["asset"]["version"], "2.0");

    // Default image size, small enough for a benchmark run on lavapipe (at most 256 x 256
    // pixels' worth).
    const int width = j["extras"]["pmcr"]["width"].get<int>();
    const int height = j["extras"]["pmcr"]["height"].get<int>();
    EXPECT_GT(width, 0);
    EXPECT_GT(height, 0);
    EXPECT_LE(width * height, 256 * 256);

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
    // Lit by emitters, or by the environment image its extras name (beside it in scenes/).
    if (j["extras"]["pmcr"].contains("environment"))
        EXPECT_TRUE(std::filesystem::exists(
            pmcr::test::sourcePath("scenes/" + j["extras"]["pmcr"]["environment"].get<std::string>())));
    else
        EXPECT_GE(emissive, 1);

    // Buffer views inside their buffers, 4-byte aligned; a BIN chunk pads by < 4 bytes.
    EXPECT_LT(g.glbPadding, 4u);
    for (const auto& v : j["bufferViews"]) {
        const size_t offset = v.value("byteOffset", size_t(0));
        EXPECT_EQ(offset % 4, 0u);
        ASSERT_LT(v["buffer"].get<size_t>(), g.buffers.size());
        EXPECT_LE(offset + v["byteLength"].get<size_t>(), viewBuffer(g, v).size());
    }
    // Accessors inside their buffer views.
    for (const auto& a : j["accessors"]) {
        const size_t componentBytes = a["componentType"] == 5126 || a["componentType"] == 5125 ? 4
                                      : a["componentType"] == 5123                             ? 2
                                                                                               : 1;
        const size_t components = a["type"] == "VEC3"     ? 3
                                  : a["type"] == "VEC2"   ? 2
                                  : a["type"] == "SCALAR" ? 1
                                                          : 0;
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

Facing facing(const SceneData& g, const std::string& meshName, const glm::dvec3& point) {
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

const Json* materialNamed(const SceneData& g, const std::string& name) {
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
        SceneData g;
        ASSERT_NO_FATAL_FAILURE(loadScene(name, g));
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
        SceneData g;
        ASSERT_NO_FATAL_FAILURE(loadScene(name, g));
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
    SceneData g;
    ASSERT_NO_FATAL_FAILURE(loadScene("furnace-sphere", g));
    // The inner sphere faces outwards, towards the enclosure and the camera.
    const Facing inner = facing(g, "InnerSphere", glm::dvec3(0.0));
    EXPECT_GT(inner.triangles, 0u);
    EXPECT_EQ(inner.awayFromPoint, inner.triangles);
}

// The triangles of every primitive of the mesh named `name` (world space: the generator writes
// mesh nodes without transforms).
struct Triangles {
    std::vector<glm::dvec3> positions;  // three per triangle
    std::set<size_t> materials;
    std::set<size_t> buffers;  // buffers holding the POSITION data
};

Triangles trianglesOf(const SceneData& g, const std::string& name) {
    Triangles out;
    for (const auto& mesh : g.json["meshes"]) {
        if (mesh.value("name", "") != name)
            continue;
        for (const auto& p : mesh["primitives"]) {
            const Json& pos = g.json["accessors"][p["attributes"]["POSITION"].get<size_t>()];
            const Json& idx = g.json["accessors"][p["indices"].get<size_t>()];
            out.materials.insert(p["material"].get<size_t>());
            out.buffers.insert(
                g.json["bufferViews"][pos["bufferView"].get<size_t>()]["buffer"].get<size_t>());
            for (size_t i = 0; i < idx["count"].get<size_t>(); ++i)
                out.positions.push_back(readVec3(g, pos, readIndex(g, idx, i)));
        }
    }
    return out;
}

glm::dvec3 crossOf(const Triangles& t, size_t i) {
    return glm::cross(t.positions[3 * i + 1] - t.positions[3 * i],
                      t.positions[3 * i + 2] - t.positions[3 * i]);
}

double areaOf(const Triangles& t) {
    double area = 0.0;
    for (size_t i = 0; i < t.positions.size() / 3; ++i)
        area += 0.5 * glm::length(crossOf(t, i));
    return area;
}

// Signed volume (divergence theorem: positive when front faces point out) of a closed mesh, or
// NaN when some directed edge, with vertices welded by position, lacks exactly one opposite.
double closedVolume(const Triangles& t) {
    using Key = std::pair<std::tuple<double, double, double>, std::tuple<double, double, double>>;
    std::map<Key, int> edges;
    double volume = 0.0;
    auto key = [](const glm::dvec3& v) { return std::tuple{v.x, v.y, v.z}; };
    for (size_t i = 0; i < t.positions.size() / 3; ++i) {
        const glm::dvec3* p = &t.positions[3 * i];
        volume += glm::dot(p[0], glm::cross(p[1], p[2])) / 6.0;
        for (int k = 0; k < 3; ++k)
            ++edges[{key(p[k]), key(p[(k + 1) % 3])}];
    }
    for (const auto& [edge, count] : edges) {
        const auto opposite = edges.find({edge.second, edge.first});
        if (count != 1 || opposite == edges.end() || opposite->second != 1)
            return std::numeric_limits<double>::quiet_NaN();
    }
    return volume;
}

double luminance(const glm::dvec3& rgb) {
    return 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z;
}

// Emitted power of a one-sided Lambertian emitter mesh, divided by pi: area * luminance(Le).
double powerOverPi(const SceneData& g, const std::string& name) {
    const Triangles t = trianglesOf(g, name);
    EXPECT_EQ(t.materials.size(), 1u) << name;
    return areaOf(t) * luminance(emission(g.json["materials"][*t.materials.begin()]));
}

// The papers' image sizes in extras.pmcr.paper_{width,height} (read by --paper-size).
TEST(SceneFiles, PaperSizesAreThePapers) {
    const std::map<std::string, std::pair<int, int>> expected = {
        {"cornell-spheres", {640, 480}},
        {"cornell-glass", {640, 480}},
        {"cornell-specular", {640, 480}},
        {"cornell-classic", {640, 480}},
        {"checkers-two-lights", {500, 500}},
        {"plant-shadows", {720, 405}},
        {"dragon-direct", {512, 256}},
        {"dragon-caustic", {900, 900}},
        {"room", {720, 405}},
        {"veach-mis", {1280, 720}},
        {"glass-caustic-torus", {640, 480}},
        {"lamp-room", {720, 405}}};
    for (const auto& name : kScenes) {
        SCOPED_TRACE(name);
        SceneData g;
        ASSERT_NO_FATAL_FAILURE(loadScene(name, g));
        const Json& pmcr = g.json["extras"]["pmcr"];
        const auto found = expected.find(name);
        if (found == expected.end()) {
            EXPECT_FALSE(pmcr.contains("paper_width") || pmcr.contains("paper_height"));
            continue;
        }
        EXPECT_EQ(pmcr.value("paper_width", 0), found->second.first);
        EXPECT_EQ(pmcr.value("paper_height", 0), found->second.second);
    }
}

// Glass is a solid: KHR_materials_volume with a thickness (else glTF makes it thin-walled), on
// closed meshes whose front faces point out; only sky-materials' window panes are thin on purpose.
TEST(SceneFiles, GlassIsClosedAndFacesOut) {
    size_t glassMeshes = 0;
    for (const auto& name : kScenes) {
        SCOPED_TRACE(name);
        SceneData g;
        ASSERT_NO_FATAL_FAILURE(loadScene(name, g));
        std::set<size_t> glass;
        for (size_t m = 0; m < g.json["materials"].size(); ++m) {
            const Json ext = g.json["materials"][m].value("extensions", Json::object());
            if (!ext.contains("KHR_materials_transmission"))
                continue;
            const std::string material = g.json["materials"][m]["name"].get<std::string>();
            if (name == "sky-materials" && material.find("Pane") != std::string::npos)
                continue;
            glass.insert(m);
            ASSERT_TRUE(ext.contains("KHR_materials_volume"));
            EXPECT_GT(ext["KHR_materials_volume"]["thicknessFactor"].get<double>(), 0.0);
        }
        for (const auto& mesh : g.json["meshes"]) {
            const Triangles t = trianglesOf(g, mesh["name"].get<std::string>());
            if (!glass.count(*t.materials.begin()))
                continue;
            ++glassMeshes;
            EXPECT_GT(closedVolume(t), 0.0) << mesh["name"];  // NaN (open) fails too
        }
    }
    EXPECT_GE(glassMeshes, 6u);  // three Cornell glass spheres, the egg, the ball, the dome
}

// sky-materials shows each material extension of issue 41: thin panes (transmission without a
// volume, one rough), a BLEND leaf card with a base colour texture whose alpha varies (read
// through TEXCOORD_0), clearcoat, sheen and a tinted KHR_materials_specular, every extension
// declared.
TEST(SceneFiles, SkyMaterialsShowsEachExtension) {
    SceneData g;
    ASSERT_NO_FATAL_FAILURE(loadScene("sky-materials", g));
    const Json& j = g.json;
    std::map<std::string, Json> materials;
    for (const auto& m : j["materials"]) materials[m["name"].get<std::string>()] = m;
    for (const char* pane : {"WindowPane", "FrostedPane"}) {
        SCOPED_TRACE(pane);
        const Json ext = materials.at(pane).value("extensions", Json::object());
        EXPECT_TRUE(ext.contains("KHR_materials_transmission"));
        EXPECT_FALSE(ext.contains("KHR_materials_volume"));
    }
    EXPECT_GT(materials.at("FrostedPane")["pbrMetallicRoughness"]["roughnessFactor"].get<double>(), 0.0);
    const Json& leaf = materials.at("LeafCard");
    EXPECT_EQ(leaf["alphaMode"], "BLEND");
    ASSERT_TRUE(leaf["pbrMetallicRoughness"].contains("baseColorTexture"));
    ASSERT_TRUE(j.contains("images") && j.contains("textures"));
    EXPECT_EQ(j["images"][0]["mimeType"], "image/png");
    EXPECT_TRUE(materials.at("CarPaint")["extensions"].contains("KHR_materials_clearcoat"));
    EXPECT_TRUE(materials.at("SheenCloth")["extensions"].contains("KHR_materials_sheen"));
    const Json& specular = materials.at("GoldTintedPlastic")["extensions"]["KHR_materials_specular"];
    EXPECT_NE(specular["specularColorFactor"], Json::array({1.0, 1.0, 1.0}));
    bool uvs = false;
    for (const auto& mesh : j["meshes"])
        if (mesh["name"] == "LeafCard") uvs = mesh["primitives"][0]["attributes"].contains("TEXCOORD_0");
    EXPECT_TRUE(uvs) << "the leaf card reads its texture through TEXCOORD_0";
    // The leaf texture's alpha: 0 around the leaf, partial coverage inside.
    const pmcr::Scene s = pmcr::loadScene(pmcr::test::sourcePath("scenes/sky-materials.glb"));
    ASSERT_EQ(s.textures.size(), 1u);
    int transparent = 0, partial = 0;
    for (const uint32_t texel : s.textures[0].rgba8) {
        const uint32_t alpha = texel >> 24;
        transparent += alpha == 0;
        partial += alpha > 0 && alpha < 255;
    }
    EXPECT_GT(transparent, 0);
    EXPECT_GT(partial, 0);
}

// PMC-HI's checkerboard: two lights of equal power whose areas differ 100 times; the near-mirror
// and rough glossy squares.
TEST(SceneFiles, CheckersHaveTwoEqualPowerLights) {
    SceneData g;
    ASSERT_NO_FATAL_FAILURE(loadScene("checkers-two-lights", g));
    const double large = areaOf(trianglesOf(g, "LargeLight"));
    const double small = areaOf(trianglesOf(g, "SmallLight"));
    EXPECT_NEAR(large / small, 100.0, 1e-3);
    EXPECT_NEAR(powerOverPi(g, "LargeLight") / powerOverPi(g, "SmallLight"), 1.0, 1e-5);
    const Json* sharp = materialNamed(g, "GlossySquareSharp");
    const Json* rough = materialNamed(g, "GlossySquareRough");
    ASSERT_TRUE(sharp && rough);
    EXPECT_LE(sharp->at("pbrMetallicRoughness")["roughnessFactor"].get<double>(), 0.1);
    EXPECT_GE(rough->at("pbrMetallicRoughness")["roughnessFactor"].get<double>(), 0.3);
}

// Veach's MIS scene keeps the pbrt lights (radius 1, 0.5, 0.05 at equal power) and plates
// (GGX alpha 0.01, 0.05, 0.1, 0.25, i.e. roughness sqrt(alpha)).
TEST(SceneFiles, VeachMisMatchesPbrt) {
    SceneData g;
    ASSERT_NO_FATAL_FAILURE(loadScene("veach-mis", g));
    for (auto [name, radius] : {std::pair{"LightRadius1", 1.0}, std::pair{"LightRadius0.5", 0.5},
                                std::pair{"LightRadius0.05", 0.05}}) {
        SCOPED_TRACE(name);
        const Triangles t = trianglesOf(g, name);
        glm::dvec3 center(0.0);
        for (const auto& p : t.positions)
            center += p / double(t.positions.size());
        for (const auto& p : t.positions)
            ASSERT_NEAR(glm::length(p - center), radius, 1e-6 * radius + 1e-6);
        EXPECT_NEAR(center.y, 6.5, 1e-6);
        EXPECT_GT(closedVolume(t), 0.0);
        EXPECT_NEAR(powerOverPi(g, name) / powerOverPi(g, "LightRadius1"), 1.0, 1e-5);
    }
    for (auto [name, alpha] : {std::pair{"Smooth", 0.01}, std::pair{"Glossy", 0.05},
                               std::pair{"Rough", 0.1}, std::pair{"SuperRough", 0.25}}) {
        const Json* m = materialNamed(g, name);
        ASSERT_NE(m, nullptr) << name;
        EXPECT_EQ(m->at("pbrMetallicRoughness")["metallicFactor"].get<double>(), 1.0);
        EXPECT_NEAR(m->at("pbrMetallicRoughness")["roughnessFactor"].get<double>(),
                    std::sqrt(alpha), 1e-12);
    }
}

// Veach's room: walls facing into the room, a smooth glass egg, two lamps.
TEST(SceneFiles, RoomWallsFaceInAndTheEggIsSmoothGlass) {
    SceneData g;
    ASSERT_NO_FATAL_FAILURE(loadScene("room", g));
    const Facing walls = facing(g, "Walls", {0.0, 4.0, 0.0});
    EXPECT_EQ(walls.triangles, 10u);  // five walls: the side towards the camera is open
    EXPECT_EQ(walls.awayFromPoint, 0u);
    const Json* glass = materialNamed(g, "Glass");
    ASSERT_NE(glass, nullptr);
    EXPECT_EQ(glass->at("pbrMetallicRoughness")["roughnessFactor"].get<double>(), 0.0);
    int emitters = 0;
    for (const auto& m : g.json["materials"])
        emitters += emission(m) != glm::dvec3(0.0);
    EXPECT_EQ(emitters, 2);
}

// The dragon's 202,520 triangles are stored once, in meshes/stanford-dragon.bin, and both dragon
// scenes reference that file.
TEST(SceneFiles, DragonIsStoredOnce) {
    for (const std::string name : {"dragon-direct", "dragon-caustic"}) {
        SCOPED_TRACE(name);
        SceneData g;
        ASSERT_NO_FATAL_FAILURE(loadScene(name, g));
        const Triangles dragon = trianglesOf(g, "Dragon");
        EXPECT_EQ(dragon.positions.size(), 3u * 202520u);
        ASSERT_EQ(dragon.buffers.size(), 1u);
        EXPECT_EQ(g.json["buffers"][*dragon.buffers.begin()]["uri"], "meshes/stanford-dragon.bin");
        double lowest = std::numeric_limits<double>::max();
        for (const auto& p : dragon.positions)
            lowest = std::min(lowest, p.y);
        EXPECT_EQ(lowest, 0.0);  // standing on the floor
    }
}

// The dragon-caustic ball is clear of the dragon, and the light is small and outside it.
TEST(SceneFiles, DragonCausticBallIsClearOfTheDragon) {
    SceneData g;
    ASSERT_NO_FATAL_FAILURE(loadScene("dragon-caustic", g));
    const Triangles ball = trianglesOf(g, "GlassBall");
    glm::dvec3 center(0.0);
    for (const auto& p : ball.positions)
        center += p / double(ball.positions.size());
    const double radius = glm::length(ball.positions[0] - center);
    for (const auto& p : trianglesOf(g, "Dragon").positions)
        ASSERT_GT(glm::length(p - center), radius);
    EXPECT_LT(areaOf(trianglesOf(g, "Light")), 0.1);
}

// The torus lies inside the dome's cavity and the light outside the dome, so every light path
// to the torus crosses the glass.
TEST(SceneFiles, TorusIsUnderTheDomeAndTheLightOutside) {
    SceneData g;
    ASSERT_NO_FATAL_FAILURE(loadScene("glass-caustic-torus", g));
    const Triangles dome = trianglesOf(g, "GlassDome");
    double lowest = std::numeric_limits<double>::max();
    for (const auto& p : dome.positions)
        lowest = std::min(lowest, p.y);
    const glm::dvec3 base(0.0, lowest, 0.0);  // the dome is centred on the y axis
    double inner = std::numeric_limits<double>::max(), outer = 0.0;
    for (const auto& p : dome.positions) {
        inner = std::min(inner, glm::length(p - base));
        outer = std::max(outer, glm::length(p - base));
    }
    for (const auto& p : trianglesOf(g, "Torus").positions) {
        ASSERT_LT(glm::length(p - base), inner);
        ASSERT_GE(p.y, base.y);
    }
    for (const auto& p : trianglesOf(g, "Light").positions)
        ASSERT_GT(glm::length(p - base), outer);
}

// The lamp room (PMC-IP / PMC-HI fig. 1): a closed room, walls facing in, with everything inside
// it; lit by a bulb in an open lamp shade and a window; no glass, no mirrors, no near-specular
// coat (caustic-free); and the camera cannot see the bulb: the bulb lies inside the shade's
// truncated cone between its rims and the eye outside it, level with it, so the segment from the
// eye to any point of the bulb leaves the (convex) cone through its side, the shade.
TEST(SceneFiles, LampRoomIsClosedCausticFreeAndHidesItsBulb) {
    SceneData g;
    ASSERT_NO_FATAL_FAILURE(loadScene("lamp-room", g));
    Triangles room;
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const std::string wall :
         {"Floor", "Ceiling", "BackWall", "FrontWall", "LeftWall", "RightWall"}) {
        const Triangles t = trianglesOf(g, wall);
        ASSERT_EQ(t.positions.size(), 6u) << wall;
        room.positions.insert(room.positions.end(), t.positions.begin(), t.positions.end());
    }
    for (const auto& p : room.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const glm::dvec3 extent = hi - lo;
    EXPECT_NEAR(closedVolume(room), -extent.x * extent.y * extent.z, 1e-9);  // closed, facing in
    for (const auto& mesh : g.json["meshes"]) {
        for (const auto& p : trianglesOf(g, mesh["name"].get<std::string>()).positions) {
            ASSERT_TRUE(glm::all(glm::greaterThanEqual(p, lo)) &&
                        glm::all(glm::lessThanEqual(p, hi)))
                << mesh["name"];
        }
    }

    std::set<std::string> emitters;
    for (const auto& m : g.json["materials"]) {
        if (emission(m) != glm::dvec3(0.0))
            emitters.insert(m["name"].get<std::string>());
        EXPECT_FALSE(m.contains("extensions") &&
                     m["extensions"].contains("KHR_materials_transmission"))
            << m["name"];
        const Json& pbr = m["pbrMetallicRoughness"];
        EXPECT_EQ(pbr.value("metallicFactor", 1.0), 0.0) << m["name"];
        EXPECT_GE(pbr.value("roughnessFactor", 1.0), 0.3) << m["name"];
    }
    EXPECT_EQ(emitters, (std::set<std::string>{"Bulb", "Window"}));
    EXPECT_GT(powerOverPi(g, "Bulb"), 1.5 * powerOverPi(g, "Window"));  // lit mostly by the lamp

    // The shade: a vertical truncated cone open at both ends, radius r(y) between its rims.
    const Triangles shade = trianglesOf(g, "LampShade");
    ASSERT_FALSE(shade.positions.empty());
    glm::dvec3 axis(0.0);
    double bottom = std::numeric_limits<double>::max(), top = -bottom;
    for (const auto& p : shade.positions) {
        axis += p / double(shade.positions.size());
        bottom = std::min(bottom, p.y);
        top = std::max(top, p.y);
    }
    double bottomRadius = 0.0, topRadius = 0.0;
    for (const auto& p : shade.positions) {
        const double r = glm::length(glm::dvec2(p.x - axis.x, p.z - axis.z));
        (p.y == bottom ? bottomRadius : topRadius) = r;
    }
    auto radiusAt = [&](double y) {
        return bottomRadius + (topRadius - bottomRadius) * (y - bottom) / (top - bottom);
    };
    // The cone's polygon is inscribed in the circle of radius r: its sides are r cos(pi / n) away.
    const double inscribed = std::cos(std::numbers::pi / double(shade.positions.size() / 6));
    for (const auto& p : trianglesOf(g, "Bulb").positions) {
        EXPECT_GT(p.y, bottom);
        EXPECT_LT(p.y, top);
        EXPECT_LT(glm::length(glm::dvec2(p.x - axis.x, p.z - axis.z)), inscribed * radiusAt(p.y));
    }
    glm::dvec3 eye(0.0);
    for (const auto& n : g.json["nodes"]) {
        if (n.contains("camera"))
            eye = {n["translation"][0].get<double>(), n["translation"][1].get<double>(),
                   n["translation"][2].get<double>()};
    }
    EXPECT_GT(eye.y, bottom);
    EXPECT_LT(eye.y, top);
    EXPECT_GT(glm::length(glm::dvec2(eye.x - axis.x, eye.z - axis.z)), radiusAt(eye.y));
}

// Every scene file in scenes/ is one of the scenes above (so the tests here and in
// tests/stat/test_scenes_render.cpp cover it) and has its row in scenes/README.md's table, and
// every licence file that README names is present.
TEST(SceneFiles, EverySceneIsListedInTheReadmeWithItsLicence) {
    const std::filesystem::path dir = pmcr::test::sourcePath("scenes");
    std::ifstream stream(dir / "README.md");
    const std::string readme{std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
    ASSERT_FALSE(readme.empty());
    std::set<std::string> files;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        const auto ext = entry.path().extension();
        if (ext == ".glb" || ext == ".gltf") files.insert(entry.path().stem().string());
    }
    // The generated scenes, third-party samples copied unchanged (lit by --env), and samples
    // set on a ground plane under the sky (pmcr-scenegen --on-ground).
    std::vector<std::string> listed = kScenes;
    listed.push_back("MetalRoughSpheresNoTextures");
    listed.push_back("MetalRoughSpheres-sky");
    listed.push_back("GlassVaseFlowers-sky");
    EXPECT_EQ(files, std::set<std::string>(listed.begin(), listed.end()));
    for (const std::string& name : listed) {
        SCOPED_TRACE(name);
        // A table row: "| `name` ..." with a source and a licence column (9 columns).
        const size_t row = readme.find("\n| `" + name + "`");
        ASSERT_NE(row, std::string::npos) << "no scenes/README.md row";
        const std::string line = readme.substr(row + 1, readme.find('\n', row + 1) - row - 1);
        EXPECT_EQ(std::count(line.begin(), line.end(), '|'), 10) << line;
    }
    size_t at = 0;
    int licences = 0;
    while ((at = readme.find("`licenses/", at)) != std::string::npos) {
        const size_t end = readme.find('`', at + 1);
        const std::string file = readme.substr(at + 1, end - at - 1);
        if (file.back() != '/') {  // "`licenses/`" names the folder
            EXPECT_TRUE(std::filesystem::is_regular_file(dir / file)) << file;
            ++licences;
        }
        at = end + 1;
    }
    EXPECT_GE(licences, 4);
}

}  // namespace
