// Image files (OpenEXR, PFM, PNG), atomic writes, crop and the false-colour map.
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tinyexr.h>

// stb_image's functions stay private to this file, so they cannot clash with the
// implementation another translation unit of the project defines.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

#include "core/error.h"
#include "image/colormap.h"
#include "image/image.h"
#include "image/image_io.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace pmcr {
namespace {

std::vector<uint8_t> readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const fs::path& path, const std::vector<uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

void appendFloat(std::vector<uint8_t>& bytes, float value, bool bigEndian) {
    const uint32_t v = std::bit_cast<uint32_t>(value);
    for (int b = 0; b < 4; ++b)
        bytes.push_back(uint8_t(v >> (8 * (bigEndian ? 3 - b : b))));
}

std::vector<uint8_t> asBytes(const std::string& text) {
    return {text.begin(), text.end()};
}

std::vector<fs::path> listDir(const fs::path& dir) {
    std::vector<fs::path> entries;
    for (const auto& entry : fs::directory_iterator(dir))
        entries.push_back(entry.path());
    return entries;
}

// A 7x3 image of awkward floats: signed zeros, negatives, huge, tiny, subnormal and infinite.
Image awkwardImage() {
    const float values[] = {0.0f,
                            -0.0f,
                            1.0f,
                            -1.0f,
                            0.1f,
                            -3.75e-7f,
                            1e30f,
                            -1e30f,
                            std::numeric_limits<float>::max(),
                            std::numeric_limits<float>::min(),
                            std::numeric_limits<float>::denorm_min(),
                            -std::numeric_limits<float>::denorm_min(),
                            std::numeric_limits<float>::infinity(),
                            65504.0f,
                            3.14159265f};
    Image image(7, 3);
    for (size_t i = 0; i < image.rgb.size(); ++i) {
        image.rgb[i] = values[i % std::size(values)] * (i % 2 ? 1.0f : 1.0f + float(i) / 64.0f);
    }
    return image;
}

void expectBitExact(const Image& expected, const Image& actual) {
    ASSERT_EQ(expected.width, actual.width);
    ASSERT_EQ(expected.height, actual.height);
    ASSERT_EQ(expected.rgb.size(), actual.rgb.size());
    for (size_t i = 0; i < expected.rgb.size(); ++i) {
        EXPECT_EQ(std::bit_cast<uint32_t>(expected.rgb[i]), std::bit_cast<uint32_t>(actual.rgb[i]))
            << "component " << i << ": " << expected.rgb[i] << " vs " << actual.rgb[i];
    }
}

// Runs `f`, expecting a one-line pmcr::Error that names `file` and contains `problem`.
template <typename F>
void expectError(F&& f, const std::string& file, const std::string& problem) {
    try {
        f();
        ADD_FAILURE() << "no error; expected one about " << problem;
    } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_EQ(message.rfind(file + ": ", 0), 0u) << message;
        EXPECT_NE(message.find(problem), std::string::npos) << message;
    }
}

// An EXR written through tinyexr's own API: channels named `names`, stored as `pixelType`,
// `planes[c]` holding width * height values of that type.
std::vector<uint8_t> tinyexrScanline(const std::vector<std::string>& names, int pixelType,
                                     std::vector<std::vector<uint8_t>>& planes, int width,
                                     int height) {
    const int n = int(names.size());
    std::vector<EXRChannelInfo> channels(static_cast<size_t>(n));
    std::vector<int> types(size_t(n), pixelType);
    std::vector<unsigned char*> pointers(static_cast<size_t>(n));
    for (int c = 0; c < n; ++c) {
        std::memset(&channels[c], 0, sizeof(EXRChannelInfo));
        std::strcpy(channels[c].name, names[c].c_str());
        pointers[c] = planes[c].data();
    }
    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = n;
    header.channels = channels.data();
    header.pixel_types = types.data();
    header.requested_pixel_types = types.data();
    header.compression_type = TINYEXR_COMPRESSIONTYPE_NONE;
    EXRImage image;
    InitEXRImage(&image);
    image.images = pointers.data();
    image.width = width;
    image.height = height;
    image.num_channels = n;
    unsigned char* memory = nullptr;
    const char* err = nullptr;
    const size_t size = SaveEXRImageToMemory(&image, &header, &memory, &err);
    if (size == 0) {
        const std::string message = err ? err : "unknown";
        FreeEXRErrorMessage(err);
        throw std::runtime_error("tinyexr: " + message);
    }
    std::vector<uint8_t> bytes(memory, memory + size);
    std::free(memory);
    return bytes;
}

std::vector<uint8_t> floatPlane(const std::vector<float>& values) {
    std::vector<uint8_t> plane(values.size() * 4);
    std::memcpy(plane.data(), values.data(), plane.size());
    return plane;
}

TEST(ImageIo, ExrRoundTripIsBitExact) {
    const fs::path dir = test::tempDir("exr-roundtrip");
    const Image image = awkwardImage();
    writeHdr(dir / "a.exr", image);
    expectBitExact(image, readHdr(dir / "a.exr"));
    // The upper-case extension selects the same format.
    writeHdr(dir / "b.EXR", image);
    expectBitExact(image, readHdr(dir / "b.EXR"));
}

TEST(ImageIo, ExrHeaderIsFloatBgrZip) {
    const std::vector<uint8_t> bytes = encodeExr(awkwardImage(), "x.exr");
    EXRVersion version;
    ASSERT_EQ(ParseEXRVersionFromMemory(&version, bytes.data(), bytes.size()), TINYEXR_SUCCESS);
    EXRHeader header;
    InitEXRHeader(&header);
    const char* err = nullptr;
    ASSERT_EQ(ParseEXRHeaderFromMemory(&header, &version, bytes.data(), bytes.size(), &err),
              TINYEXR_SUCCESS);
    EXPECT_EQ(header.tiled, 0);
    EXPECT_EQ(header.compression_type, TINYEXR_COMPRESSIONTYPE_ZIP);
    ASSERT_EQ(header.num_channels, 3);
    const char* expected[] = {"B", "G", "R"};
    for (int c = 0; c < 3; ++c) {
        EXPECT_STREQ(header.channels[c].name, expected[c]);
        EXPECT_EQ(header.pixel_types[c], TINYEXR_PIXELTYPE_FLOAT);
    }
    FreeEXRHeader(&header);
}

TEST(ImageIo, ExrChannelsAreMatchedByName) {
    // Distinct values per channel expose any swap of R and B.
    Image image(3, 2);
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 3; ++x)
            image.set(x, y, {float(x + 10 * y), 100.0f, -float(x + 1)});
    }
    const Image back = decodeExr(encodeExr(image, "x.exr"), "x.exr");
    expectBitExact(image, back);
}

TEST(ImageIo, ReadsHalfFloatExrWithAlpha) {
    // Half bit patterns with exact float values, in channel order A, B, G, R.
    const uint16_t halfBits[] = {0x0000, 0x3C00, 0x3800, 0xC000, 0x7BFF, 0x0400, 0x0001, 0x4248};
    const float floats[] = {0.0f, 1.0f, 0.5f, -2.0f, 65504.0f, 0x1p-14f, 0x1p-24f, 3.140625f};
    const int width = 5, height = 3, n = width * height;
    std::vector<std::vector<uint8_t>> planes(4, std::vector<uint8_t>(size_t(n) * 2));
    Image expected(width, height);
    for (int i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {  // c: 0 = R, 1 = G, 2 = B; plane 3 - c
            const int k = (i + 3 * c) % 8;
            std::memcpy(&planes[size_t(3 - c)][size_t(i) * 2], &halfBits[k], 2);
            expected.rgb[size_t(i) * 3 + size_t(c)] = floats[k];
        }
        const uint16_t alpha = 0x3C00;
        std::memcpy(&planes[0][size_t(i) * 2], &alpha, 2);
    }
    const fs::path dir = test::tempDir("exr-half");
    writeBytes(dir / "half.exr", tinyexrScanline({"A", "B", "G", "R"}, TINYEXR_PIXELTYPE_HALF,
                                                 planes, width, height));
    expectBitExact(expected, readHdr(dir / "half.exr"));
}

// `image` as a tiled float EXR in 4x4 tiles, written through tinyexr's own API. With `mipmap`
// the file also holds the mipmap levels (rounded down), filled with crops of `image`. A non-empty
// `typeAttribute` adds a "type" string attribute (tinyexr writes none for single-part files).
std::vector<uint8_t> tinyexrTiled(const Image& image, const std::string& typeAttribute = "",
                                  bool mipmap = false) {
    const int tile = 4;
    struct Level {
        std::vector<std::vector<float>> data;
        std::vector<unsigned char*> pointers;
        std::vector<EXRTile> tiles;
        EXRImage exr;
    };
    int levelCount = 1;
    while (mipmap && std::max(image.width, image.height) >> levelCount > 0)
        ++levelCount;
    std::vector<Level> levels(static_cast<size_t>(levelCount));
    for (int l = 0; l < levelCount; ++l) {
        const Image content =
            crop(image, 0, 0, std::max(image.width >> l, 1), std::max(image.height >> l, 1));
        Level& level = levels[size_t(l)];
        const int tilesX = (content.width + tile - 1) / tile;
        const int numTiles = tilesX * ((content.height + tile - 1) / tile);
        level.data.assign(size_t(numTiles) * 3, std::vector<float>(tile * tile, 0.0f));
        level.pointers.resize(level.data.size());
        level.tiles.resize(static_cast<size_t>(numTiles));
        for (int t = 0; t < numTiles; ++t) {
            EXRTile& current = level.tiles[size_t(t)];
            current = {};
            current.offset_x = t % tilesX;
            current.offset_y = t / tilesX;
            current.level_x = current.level_y = l;
            current.width = std::min(tile, content.width - current.offset_x * tile);
            current.height = std::min(tile, content.height - current.offset_y * tile);
            for (int c = 0; c < 3; ++c) {
                std::vector<float>& plane = level.data[size_t(t * 3 + c)];
                for (int j = 0; j < current.height; ++j) {
                    for (int i = 0; i < current.width; ++i) {
                        const glm::vec3 p =
                            content.at(current.offset_x * tile + i, current.offset_y * tile + j);
                        plane[size_t(j * tile + i)] = p[2 - c];
                    }
                }
                level.pointers[size_t(t * 3 + c)] = reinterpret_cast<unsigned char*>(plane.data());
            }
            current.images = &level.pointers[size_t(t * 3)];
        }
        InitEXRImage(&level.exr);
        level.exr.tiles = level.tiles.data();
        level.exr.num_tiles = numTiles;
        level.exr.width = content.width;
        level.exr.height = content.height;
        level.exr.level_x = level.exr.level_y = l;
        level.exr.num_channels = 3;
        if (l > 0)
            levels[size_t(l - 1)].exr.next_level = &level.exr;
    }

    const char* names[] = {"B", "G", "R"};
    EXRChannelInfo channels[3] = {};
    int types[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
    for (int c = 0; c < 3; ++c)
        std::strcpy(channels[c].name, names[c]);
    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = 3;
    header.channels = channels;
    header.pixel_types = types;
    header.requested_pixel_types = types;
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
    header.tiled = 1;
    header.tile_size_x = tile;
    header.tile_size_y = tile;
    header.tile_level_mode = mipmap ? TINYEXR_TILE_MIPMAP_LEVELS : TINYEXR_TILE_ONE_LEVEL;
    header.tile_rounding_mode = TINYEXR_TILE_ROUND_DOWN;
    header.data_window = {0, 0, image.width - 1, image.height - 1};
    header.display_window = header.data_window;
    std::string typeValue = typeAttribute;
    EXRAttribute attribute = {};
    if (!typeValue.empty()) {
        std::strcpy(attribute.name, "type");
        std::strcpy(attribute.type, "string");
        attribute.value = reinterpret_cast<unsigned char*>(typeValue.data());
        attribute.size = int(typeValue.size());
        header.num_custom_attributes = 1;
        header.custom_attributes = &attribute;
    }
    unsigned char* memory = nullptr;
    const char* err = nullptr;
    const size_t size = SaveEXRImageToMemory(&levels[0].exr, &header, &memory, &err);
    if (size == 0) {
        const std::string message = err ? err : "unknown";
        FreeEXRErrorMessage(err);
        throw std::runtime_error("tinyexr: " + message);
    }
    std::vector<uint8_t> bytes(memory, memory + size);
    std::free(memory);
    return bytes;
}

TEST(ImageIo, ReadsTiledExr) {
    // 7x5 pixels in 4x4 tiles: 2x2 tiles, the right and bottom ones partial.
    Image expected(7, 5);
    for (size_t i = 0; i < expected.rgb.size(); ++i)
        expected.rgb[i] = float(i) * 0.25f - 3.0f;
    expectBitExact(expected, decodeExr(tinyexrTiled(expected), "tiled.exr"));
    expectBitExact(expected, decodeExr(tinyexrTiled(expected, "tiledimage"), "tiled.exr"));
    // With mipmap levels 7x5, 3x2 and 1x1 the first level is read.
    expectBitExact(expected, decodeExr(tinyexrTiled(expected, "", true), "mipmap.exr"));
}

TEST(ImageIo, ReadsUintExr) {
    const uint32_t values[] = {0, 7, 4000000000u, 65536, 1, 2, 3, 4, 5};
    std::vector<std::vector<uint8_t>> planes(3, std::vector<uint8_t>(12));
    Image expected(3, 1);
    for (int c = 0; c < 3; ++c) {  // c: 0 = R, 1 = G, 2 = B; planes in order B, G, R
        for (int i = 0; i < 3; ++i) {
            const uint32_t v = values[3 * c + i];
            std::memcpy(&planes[size_t(2 - c)][size_t(i) * 4], &v, 4);
            expected.rgb[size_t(3 * i + c)] = float(v);
        }
    }
    expectBitExact(expected,
                   decodeExr(tinyexrScanline({"B", "G", "R"}, TINYEXR_PIXELTYPE_UINT, planes, 3, 1),
                             "uint.exr"));
}

// Offset of the value of header attribute `name` of type `type` in an EXR file.
size_t attributeValue(const std::vector<uint8_t>& bytes, const std::string& name,
                      const std::string& type) {
    std::string key = name;
    key.push_back('\0');
    key += type;
    key.push_back('\0');
    const auto it = std::search(bytes.begin(), bytes.end(), key.begin(), key.end());
    if (it == bytes.end())
        throw std::runtime_error("no attribute " + name);
    return size_t(it - bytes.begin()) + key.size() + 4;  // after the int32 size
}

// Files on which tinyexr 1.0.1 itself aborts (assertions) unless decodeExr rejects them first.
TEST(ImageIo, FilesTinyexrWouldAbortOnAreErrors) {
    const Image image(6, 5);
    const std::vector<uint8_t> tiled = tinyexrTiled(image, "tiledimage");
    std::vector<uint8_t> bytes = tiled;
    bytes[attributeValue(bytes, "tiles", "tiledesc") + 8] = 3;  // level mode 3 does not exist
    expectError([&] { decodeExr(bytes, "t.exr"); }, "t.exr", "invalid OpenEXR tile description");

    bytes = tiled;
    bytes[attributeValue(bytes, "tiles", "tiledesc")] = 0;  // tile width 0
    expectError([&] { decodeExr(bytes, "t.exr"); }, "t.exr", "invalid OpenEXR tile description");

    bytes = tiled;
    bytes[attributeValue(bytes, "type", "string")] = 'X';
    expectError([&] { decodeExr(bytes, "t.exr"); }, "t.exr",
                "unsupported OpenEXR part type 'Xiledimage'");
    bytes[attributeValue(bytes, "type", "string") + 1] = '\n';  // the message stays one line
    expectError([&] { decodeExr(bytes, "t.exr"); }, "t.exr",
                "unsupported OpenEXR part type 'X?ledimage'");

    bytes = tiled;
    bytes[5] &= uint8_t(~0x2);  // version flags: not tiled, but the type says tiled
    expectError([&] { decodeExr(bytes, "t.exr"); }, "t.exr",
                "unsupported OpenEXR part type 'tiledimage'");

    // Data window 4 pixels wide: the file's second tile column starts right at its edge.
    Image wide(7, 5);
    bytes = tinyexrTiled(wide);
    bytes[attributeValue(bytes, "dataWindow", "box2i") + 8] = 3;
    expectError([&] { decodeExr(bytes, "t.exr"); }, "t.exr",
                "OpenEXR tile (1, 0) lies outside its level");

    bytes = encodeExr(image, "h.exr");
    bytes[attributeValue(bytes, "dataWindow", "box2i") + 11] = 0x70;  // max x = 2^30 + 5
    expectError([&] { decodeExr(bytes, "h.exr"); }, "h.exr", "is empty or too large");
}

TEST(ImageIo, ExrWithoutRgbChannelsIsAnError) {
    std::vector<std::vector<uint8_t>> planes = {floatPlane(std::vector<float>(6, 0.5f))};
    const fs::path dir = test::tempDir("exr-y");
    const fs::path path = dir / "luma.exr";
    writeBytes(path, tinyexrScanline({"Y"}, TINYEXR_PIXELTYPE_FLOAT, planes, 3, 2));
    expectError([&] { readHdr(path); }, path.string(), "no R, G, B channels (channels: Y)");
}

TEST(ImageIo, PfmRoundTripIsBitExact) {
    const fs::path dir = test::tempDir("pfm-roundtrip");
    const Image image = awkwardImage();
    writeHdr(dir / "a.pfm", image);
    expectBitExact(image, readHdr(dir / "a.pfm"));
}

TEST(ImageIo, PfmIsLittleEndianBottomRowFirst) {
    Image image(2, 2);
    image.set(0, 0, {1, 2, 3});  // top row
    image.set(1, 0, {4, 5, 6});
    image.set(0, 1, {7, 8, 9});  // bottom row
    image.set(1, 1, {10, 11, 12});
    std::vector<uint8_t> expected = asBytes("PF\n2 2\n-1.0\n");
    for (float v : {7, 8, 9, 10, 11, 12, 1, 2, 3, 4, 5, 6})
        appendFloat(expected, v, false);
    EXPECT_EQ(encodePfm(image, "x.pfm"), expected);
}

TEST(ImageIo, ReadsBigEndianPfm) {
    std::vector<uint8_t> bytes = asBytes("PF\n3 2\n1.0\n");
    for (int i = 0; i < 18; ++i)
        appendFloat(bytes, float(i) - 2.5f, true);
    const fs::path dir = test::tempDir("pfm-be");
    writeBytes(dir / "be.pfm", bytes);
    const Image image = readHdr(dir / "be.pfm");
    ASSERT_EQ(image.width, 3);
    ASSERT_EQ(image.height, 2);
    // The file's first row is the image's bottom row.
    EXPECT_EQ(image.at(0, 1), glm::vec3(-2.5f, -1.5f, -0.5f));
    EXPECT_EQ(image.at(2, 1), glm::vec3(3.5f, 4.5f, 5.5f));
    EXPECT_EQ(image.at(0, 0), glm::vec3(6.5f, 7.5f, 8.5f));
    EXPECT_EQ(image.at(2, 0), glm::vec3(12.5f, 13.5f, 14.5f));
}

TEST(ImageIo, ReadsGreyscalePfmBothEndiannesses) {
    for (bool bigEndian : {false, true}) {
        // Header tokens separated by spaces rather than newlines are accepted too.
        std::vector<uint8_t> bytes = asBytes(bigEndian ? "Pf 2 3 1.0\n" : "Pf\n2 3\n-1.0\n");
        for (int i = 0; i < 6; ++i)
            appendFloat(bytes, float(i * i), bigEndian);
        const Image image = decodePfm(bytes, "grey.pfm");
        ASSERT_EQ(image.width, 2);
        ASSERT_EQ(image.height, 3);
        EXPECT_EQ(image.at(0, 2), glm::vec3(0.0f));
        EXPECT_EQ(image.at(1, 2), glm::vec3(1.0f));
        EXPECT_EQ(image.at(0, 1), glm::vec3(4.0f));
        EXPECT_EQ(image.at(1, 0), glm::vec3(25.0f));
    }
}

TEST(ImageIo, PfmScaleMagnitudeMultipliesPixels) {
    std::vector<uint8_t> bytes = asBytes("PF\n1 1\n-2.5\n");
    for (float v : {1.0f, -2.0f, 0.5f})
        appendFloat(bytes, v, false);
    EXPECT_EQ(decodePfm(bytes, "s.pfm").at(0, 0), glm::vec3(2.5f, -5.0f, 1.25f));
}

TEST(ImageIo, MalformedPfmHeadersAreErrors) {
    const std::pair<std::string, std::string> cases[] = {
        {"P6\n1 1\n255\n", "not a PFM file"},
        {"PF", "not a PFM file"},
        {"PF\n", "truncated PFM header"},
        {"PF\n2", "truncated PFM header"},
        {"PF\n0 1\n-1.0\n", "invalid PFM width '0'"},
        {"PF\n1 -3\n-1.0\n", "invalid PFM height '-3'"},
        {"PF\n1x 1\n-1.0\n", "invalid PFM width '1x'"},
        {"PF\n99999999999 1\n-1.0\n", "invalid PFM width"},
        {"PF\n1 1\n0\n", "invalid PFM scale '0'"},
        {"PF\n1 1\nnan\n", "invalid PFM scale 'nan'"},
        {"PF\n1 1\n-1.0", "truncated PFM header"},
        {"PF\n2 2\n-1.0\n0123456789",
         "truncated PFM: 2x2 pixels need 48 bytes of data, file has 10"},
        {"PF\n2000000000 2000000000\n-1.0\n", "too large"},
    };
    for (const auto& [text, problem] : cases) {
        SCOPED_TRACE(text);
        expectError([&] { decodePfm(asBytes(text), "bad.pfm"); }, "bad.pfm", problem);
    }
}

TEST(ImageIo, TruncatedFilesAreOneLineErrors) {
    const fs::path dir = test::tempDir("truncated");
    const Image image = awkwardImage();
    for (const char* name : {"t.exr", "t.pfm"}) {
        const fs::path path = dir / name;
        writeHdr(path, image);
        const std::vector<uint8_t> full = readBytes(path);
        for (size_t length = 0; length < full.size(); length += (length < 64 ? 1 : 7)) {
            SCOPED_TRACE(std::string(name) + " cut at " + std::to_string(length));
            writeBytes(path, std::vector<uint8_t>(full.begin(), full.begin() + ptrdiff_t(length)));
            expectError([&] { readHdr(path); }, path.string(), "");
        }
    }
}

TEST(ImageIo, CorruptExrNeverCrashes) {
    // Flip bytes of a valid file at random (fixed seed): each result either decodes or is a
    // one-line error; with ZIP data a crash in the decoder would show here.
    const std::vector<uint8_t> valid = encodeExr(awkwardImage(), "c.exr");
    std::mt19937 rng(1234);
    int errors = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        std::vector<uint8_t> bytes = valid;
        const int flips = 1 + int(rng() % 4);
        for (int f = 0; f < flips; ++f)
            bytes[rng() % bytes.size()] ^= uint8_t(1 + rng() % 255);
        try {
            const Image image = decodeExr(bytes, "c.exr");
            EXPECT_EQ(image.rgb.size(), image.pixelCount() * 3);
        } catch (const Error& e) {
            ++errors;
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
        }
    }
    EXPECT_GT(errors, 0);
}

TEST(ImageIo, ReadErrorsNameTheFile) {
    const fs::path dir = test::tempDir("read-errors");
    expectError([&] { readHdr(dir / "missing.exr"); }, (dir / "missing.exr").string(),
                "cannot open: no such file or directory");
    expectError([&] { readHdr(dir / "missing.png"); }, (dir / "missing.png").string(),
                "unknown HDR image extension '.png' (expected .exr or .pfm)");
    expectError([&] { readHdr(dir / "noext"); }, (dir / "noext").string(), "no file extension");
    writeBytes(dir / "empty.pfm", {});
    expectError([&] { readHdr(dir / "empty.pfm"); }, (dir / "empty.pfm").string(), "empty file");
    writeBytes(dir / "text.exr", asBytes("hello, this is not an image"));
    expectError([&] { readHdr(dir / "text.exr"); }, (dir / "text.exr").string(),
                "not an OpenEXR file");
    fs::create_directory(dir / "folder.exr");
    expectError([&] { readHdr(dir / "folder.exr"); }, (dir / "folder.exr").string(),
                "is a directory");
}

TEST(ImageIo, WriteErrorsNameTheFileAndLeaveNothing) {
    const fs::path dir = test::tempDir("write-errors");
    const Image image = awkwardImage();
    expectError([&] { writeHdr(dir / "x.png", image); }, (dir / "x.png").string(),
                "unknown HDR image extension '.png'");
    expectError([&] { writeHdr(dir / "no/such/dir/x.exr", image); },
                (dir / "no/such/dir/x.exr").string(), "does not exist");
    writeBytes(dir / "file", asBytes("x"));
    expectError([&] { writePng(dir / "file/x.png", image); }, (dir / "file/x.png").string(),
                "is not a directory");
    expectError([&] { writeHdr(dir / "empty.pfm", Image()); }, (dir / "empty.pfm").string(),
                "cannot write an empty image (0x0)");
    expectError([&] { writePng(dir / "empty.png", Image(0, 4)); }, (dir / "empty.png").string(),
                "empty");
    expectError([&] { writePng(dir / "nan.png", image, NAN); }, (dir / "nan.png").string(),
                "exposure must be finite");
    EXPECT_EQ(listDir(dir), std::vector<fs::path>{dir / "file"});
}

TEST(ImageIo, UnwritableDirectoryIsReported) {
    if (::geteuid() == 0)
        GTEST_SKIP() << "root ignores directory permissions";
    const fs::path dir = test::tempDir("unwritable");
    fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec);
    expectError([&] { writeHdr(dir / "x.exr", awkwardImage()); }, (dir / "x.exr").string(),
                "permission denied");
    fs::permissions(dir, fs::perms::owner_all);
    EXPECT_TRUE(listDir(dir).empty());
}

TEST(AtomicWrite, ThrowingWriterLeavesNoFile) {
    const fs::path dir = test::tempDir("atomic-throw");
    const fs::path path = dir / "out.exr";
    fs::path seenTmp;
    expectError(
        [&] {
            writeFileAtomically(path, [&](const fs::path& tmp) {
                seenTmp = tmp;
                std::ofstream(tmp) << "partial";
                throw std::runtime_error("disk on fire");
            });
        },
        path.string(), "disk on fire");
    EXPECT_EQ(seenTmp.parent_path(), dir);
    EXPECT_NE(seenTmp.filename().string().find(".out.exr.tmp-" + std::to_string(::getpid())),
              std::string::npos)
        << seenTmp;
    EXPECT_TRUE(listDir(dir).empty());
}

TEST(AtomicWrite, FailedRewriteKeepsTheOldFile) {
    const fs::path dir = test::tempDir("atomic-keep");
    const fs::path path = dir / "out.pfm";
    writeHdr(path, awkwardImage());
    const std::vector<uint8_t> before = readBytes(path);
    EXPECT_THROW(writeFileAtomically(path,
                                     [](const fs::path& tmp) {
                                         std::ofstream(tmp) << "half";
                                         throw Error("writer: failed");
                                     }),
                 Error);
    EXPECT_EQ(readBytes(path), before);
    EXPECT_EQ(listDir(dir), std::vector<fs::path>{path});
}

TEST(AtomicWrite, ReplacesAndLeavesNoTemporaries) {
    const fs::path dir = test::tempDir("atomic-ok");
    const fs::path path = dir / "out.txt";
    for (const std::string text : {"first version, longer", "second"}) {
        writeFileAtomically(path, [&](const fs::path& tmp) { std::ofstream(tmp) << text; });
        EXPECT_EQ(readBytes(path), asBytes(text));
    }
    // A relative path in the working directory has no parent to name.
    const fs::path cwd = fs::current_path();
    fs::current_path(dir);
    writeFileAtomically("here.txt", [](const fs::path& tmp) { std::ofstream(tmp) << "x"; });
    fs::current_path(cwd);
    std::vector<fs::path> entries = listDir(dir);
    std::sort(entries.begin(), entries.end());
    EXPECT_EQ(entries, (std::vector<fs::path>{dir / "here.txt", path}));
}

TEST(AtomicWrite, TargetThatIsADirectoryIsAnError) {
    const fs::path dir = test::tempDir("atomic-dir");
    fs::create_directory(dir / "sub");
    expectError([&] { writeFileAtomically(dir / "sub", [](const fs::path&) {}); },
                (dir / "sub").string(), "is a directory");
}

TEST(Png, SrgbEncodeFollowsIec61966) {
    EXPECT_EQ(srgbEncode(0.0f), 0.0f);
    EXPECT_NEAR(srgbEncode(1.0f), 1.0f, 1e-6f);
    EXPECT_NEAR(srgbEncode(0.001f), 0.01292f, 1e-7f);  // linear segment
    EXPECT_NEAR(srgbEncode(0.18f), 0.4613561f, 2e-6f);
    EXPECT_NEAR(srgbEncode(0.5f), 0.7353570f, 2e-6f);
    // The two pieces meet at the breakpoint (to the curve's published precision).
    EXPECT_NEAR(srgbEncode(0.0031308f), srgbEncode(std::nextafter(0.0031308f, 1.0f)), 1e-6f);
    for (int i = 1; i <= 1000; ++i) {
        EXPECT_GT(srgbEncode(float(i) / 1000.0f), srgbEncode(float(i - 1) / 1000.0f));
    }
}

TEST(Png, ToSrgb8AppliesExposureClampAndZeroesNonFinite) {
    Image image(4, 2);
    image.set(0, 0, {0.0f, 1.0f, 0.5f});
    image.set(1, 0, {0.25f, 2.0f, -1.0f});
    image.set(2, 0, {NAN, INFINITY, -INFINITY});
    image.set(3, 0, {0.001f, 0.0031308f, 0.2f});
    const std::vector<uint8_t> p = toSrgb8(image, 0.0f);
    ASSERT_EQ(p.size(), 24u);
    EXPECT_EQ(std::vector<uint8_t>(p.begin(), p.begin() + 12),
              (std::vector<uint8_t>{0, 255, 188, 137, 255, 0, 0, 0, 0, 3, 10, 124}));
    // +1 stop doubles the linear value before encoding: 0.25 -> 0.5 -> 188.
    EXPECT_EQ(toSrgb8(image, 1.0f)[3], 188);
    EXPECT_EQ(toSrgb8(image, -1.0f)[1], 188);
    EXPECT_EQ(toSrgb8(image, 1000.0f)[0], 0);  // 0 times an infinite scale stays 0
}

TEST(Png, WritesAPngThatDecodesToTheEncodedPixels) {
    const fs::path dir = test::tempDir("png");
    Image image(7, 3);
    for (size_t i = 0; i < image.rgb.size(); ++i)
        image.rgb[i] = float(i) / 40.0f;
    image.rgb[5] = NAN;
    image.rgb[7] = INFINITY;
    const fs::path path = dir / "out.png";
    writePng(path, image, 0.5f);

    const std::vector<uint8_t> bytes = readBytes(path);
    ASSERT_GT(bytes.size(), 33u);
    const uint8_t signature[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    EXPECT_EQ(std::memcmp(bytes.data(), signature, 8), 0);
    EXPECT_EQ(std::memcmp(bytes.data() + 12, "IHDR", 4), 0);
    EXPECT_EQ(bytes[19], 7);  // big-endian width and height
    EXPECT_EQ(bytes[23], 3);

    int w = 0, h = 0, channels = 0;
    stbi_uc* decoded = stbi_load_from_memory(bytes.data(), int(bytes.size()), &w, &h, &channels, 3);
    ASSERT_NE(decoded, nullptr);
    EXPECT_EQ(w, 7);
    EXPECT_EQ(h, 3);
    EXPECT_EQ(channels, 3);
    EXPECT_EQ(std::vector<uint8_t>(decoded, decoded + 63), toSrgb8(image, 0.5f));
    stbi_image_free(decoded);
    EXPECT_EQ(listDir(dir), std::vector<fs::path>{path});
}

TEST(Crop, CopiesTheRectangle) {
    Image image(5, 4);
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 5; ++x)
            image.set(x, y, {float(x), float(y), float(x * y)});
    }
    const Image c = crop(image, 1, 2, 3, 2);
    ASSERT_EQ(c.width, 3);
    ASSERT_EQ(c.height, 2);
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 3; ++x)
            EXPECT_EQ(c.at(x, y), image.at(x + 1, y + 2));
    }
    expectBitExact(image, crop(image, 0, 0, 5, 4));
}

TEST(Crop, RejectsRectanglesOutsideTheImage) {
    const Image image(5, 4);
    const int bad[][4] = {{-1, 0, 2, 2}, {0, -1, 2, 2},        {4, 0, 2, 1}, {0, 3, 1, 2},
                          {0, 0, 0, 1},  {0, 0, 1, 0},         {0, 0, 6, 4}, {2147483647, 0, 1, 1},
                          {0, 0, -2, 2}, {1, 1, 2147483647, 1}};
    for (const auto& r : bad) {
        EXPECT_THROW(crop(image, r[0], r[1], r[2], r[3]), Error)
            << r[0] << " " << r[1] << " " << r[2] << " " << r[3];
    }
}

float rec709Luminance(const glm::vec3& c) {
    return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;  // ITU-R BT.709
}

TEST(Colormap, EndpointsAndMonotonicLuminance) {
    // viridis runs from #440154 to #FDE725 (sRGB), returned as linear RGB.
    const auto linear = [](int v) {
        const float s = float(v) / 255.0f;
        return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
    };
    const glm::vec3 low = viridis(0.0f);
    const glm::vec3 high = viridis(1.0f);
    EXPECT_NEAR(low.r, linear(0x44), 1e-6f);
    EXPECT_NEAR(low.g, linear(0x01), 1e-6f);
    EXPECT_NEAR(low.b, linear(0x54), 1e-6f);
    EXPECT_NEAR(high.r, linear(0xFD), 1e-6f);
    EXPECT_NEAR(high.g, linear(0xE7), 1e-6f);
    EXPECT_NEAR(high.b, linear(0x25), 1e-6f);
    float previous = rec709Luminance(low);
    for (int i = 1; i <= 1024; ++i) {
        const float l = rec709Luminance(viridis(float(i) / 1024.0f));
        EXPECT_GT(l, previous) << "t = " << float(i) / 1024.0f;
        previous = l;
    }
}

TEST(Colormap, FalseColorMapsAndClamps) {
    const std::vector<float> values = {0.0f, 1.0f, 2.0f, 4.0f, -3.0f, NAN};
    const Image image = falseColor(values, 3, 2, 2.0f);
    ASSERT_EQ(image.width, 3);
    ASSERT_EQ(image.height, 2);
    EXPECT_EQ(image.at(0, 0), viridis(0.0f));
    EXPECT_EQ(image.at(1, 0), viridis(0.5f));
    EXPECT_EQ(image.at(2, 0), viridis(1.0f));
    EXPECT_EQ(image.at(0, 1), viridis(1.0f));
    EXPECT_EQ(image.at(1, 1), viridis(0.0f));
    EXPECT_EQ(image.at(2, 1), viridis(0.0f));
    EXPECT_THROW(falseColor(values, 2, 2, 1.0f), Error);
    EXPECT_THROW(falseColor(values, 3, 2, 0.0f), Error);
    EXPECT_THROW(falseColor(values, 3, 2, INFINITY), Error);
}

}  // namespace
}  // namespace pmcr
