#include "image/image_io.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string_view>

#include <tinyexr.h>

#include "core/error.h"

namespace pmcr {

namespace {

// The largest image decoded (pixels): bounds the memory a hostile header can ask for.
constexpr uint64_t kMaxPixels = uint64_t(1) << 28;

// Text from a file made safe for a one-line message: control bytes become '?', at most 64.
std::string printable(std::string_view text) {
    std::string out(text.substr(0, 64));
    for (char& c : out) {
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
            c = '?';
    }
    return out;
}

// The one-line text of a tinyexr error message, which is then freed.
std::string takeExrError(const char* err, int code) {
    std::string text = err ? err : "";
    if (err)
        FreeEXRErrorMessage(err);
    for (char& c : text) {
        if (static_cast<unsigned char>(c) < 0x20)
            c = ' ';
    }
    while (!text.empty() && (text.back() == ' ' || text.back() == '.'))
        text.pop_back();
    return text.empty() ? "tinyexr error " + std::to_string(code) : text;
}

// Owns a parsed EXRHeader.
struct ExrHeader {
    EXRHeader h;
    ExrHeader() { InitEXRHeader(&h); }
    ~ExrHeader() { FreeEXRHeader(&h); }
    ExrHeader(const ExrHeader&) = delete;
    ExrHeader& operator=(const ExrHeader&) = delete;
};

// Owns a successfully loaded EXRImage (tinyexr frees it itself when loading fails).
struct ExrImage {
    EXRImage image;
    bool loaded = false;
    ExrImage() { InitEXRImage(&image); }
    ~ExrImage() {
        if (loaded)
            FreeEXRImage(&image);
    }
    ExrImage(const ExrImage&) = delete;
    ExrImage& operator=(const ExrImage&) = delete;
};

void checkImage(const Image& image, const std::string& name) {
    if (image.width <= 0 || image.height <= 0) {
        fail(name, "cannot write an empty image (" + std::to_string(image.width) + "x" +
                       std::to_string(image.height) + ")");
    }
    if (image.rgb.size() != image.pixelCount() * 3) {
        fail(name, "image data holds " + std::to_string(image.rgb.size()) + " floats, expected " +
                       std::to_string(image.pixelCount() * 3));
    }
}

// Reads one pixel component of a loaded channel as float (requested type FLOAT or UINT).
float exrValue(const unsigned char* plane, int pixelType, size_t index) {
    if (pixelType == TINYEXR_PIXELTYPE_UINT) {
        uint32_t v;
        std::memcpy(&v, plane + index * 4, 4);
        return float(v);
    }
    float v;
    std::memcpy(&v, plane + index * 4, 4);
    return v;
}

uint32_t byteSwap(uint32_t v) {
    return (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
}

bool isPfmSpace(uint8_t c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

}  // namespace

std::vector<uint8_t> encodeExr(const Image& image, const std::string& name) {
    checkImage(image, name);
    // OpenEXR stores channels sorted by name and tinyexr writes them in the order given: B, G, R.
    const size_t n = image.pixelCount();
    std::vector<float> planes[3];
    for (int c = 0; c < 3; ++c) {
        planes[c].resize(n);
        for (size_t i = 0; i < n; ++i)
            planes[c][i] = image.rgb[3 * i + size_t(2 - c)];
    }
    EXRChannelInfo channels[3] = {};
    const char* channelNames[3] = {"B", "G", "R"};
    int pixelTypes[3];
    int storedTypes[3];
    unsigned char* imagePlanes[3];
    for (int c = 0; c < 3; ++c) {
        std::strcpy(channels[c].name, channelNames[c]);
        channels[c].x_sampling = 1;
        channels[c].y_sampling = 1;
        pixelTypes[c] = TINYEXR_PIXELTYPE_FLOAT;
        storedTypes[c] = TINYEXR_PIXELTYPE_FLOAT;
        imagePlanes[c] = reinterpret_cast<unsigned char*>(planes[c].data());
    }

    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = 3;
    header.channels = channels;
    header.pixel_types = pixelTypes;
    header.requested_pixel_types = storedTypes;
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;

    EXRImage exr;
    InitEXRImage(&exr);
    exr.images = imagePlanes;
    exr.width = image.width;
    exr.height = image.height;
    exr.num_channels = 3;

    unsigned char* memory = nullptr;
    const char* err = nullptr;
    const size_t size = SaveEXRImageToMemory(&exr, &header, &memory, &err);
    if (size == 0 || !memory) {
        std::free(memory);
        fail(name, "cannot encode OpenEXR: " + takeExrError(err, 0));
    }
    std::vector<uint8_t> bytes(memory, memory + size);
    std::free(memory);
    return bytes;
}

namespace {

// The largest tile edge accepted; keeps tinyexr's tile-count arithmetic far from overflow.
constexpr int64_t kMaxTileSize = int64_t(1) << 16;

// tinyexr 1.0.1 as Debian builds it (assertions enabled) aborts on some malformed headers
// instead of returning an error: a "tiles" attribute that is not 9 bytes or has level mode 3, a
// "type" attribute that disagrees with the version flags, huge data windows. This walks the
// attributes of a single-part header (OpenEXR file layout: name\0 type\0 int32 size, value; a 0
// byte ends the header) and says what is wrong with them, or returns "" to let tinyexr parse it.
std::string checkExrHeader(std::span<const uint8_t> bytes, bool tiled) {
    size_t pos = 8;  // after the magic number and version field
    const auto readString = [&](std::string_view& out) {
        const auto end = std::find(bytes.begin() + ptrdiff_t(pos), bytes.end(), uint8_t(0));
        if (end == bytes.end())
            return false;
        const size_t length = size_t(end - bytes.begin()) - pos;
        out = std::string_view(reinterpret_cast<const char*>(bytes.data()) + pos, length);
        pos += length + 1;
        return true;
    };
    const auto readInt = [](const uint8_t* p) {
        return int32_t(uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 |
                       uint32_t(p[3]) << 24);
    };
    bool hasTiles = false;
    for (;;) {
        if (pos >= bytes.size())
            return "truncated OpenEXR header";
        if (bytes[pos] == 0)
            break;
        std::string_view attribute, type;
        if (!readString(attribute) || !readString(type) || bytes.size() - pos < 4) {
            return "truncated OpenEXR header";
        }
        const uint32_t size = uint32_t(readInt(bytes.data() + pos));
        pos += 4;
        if (size > bytes.size() - pos)
            return "truncated OpenEXR header";
        const uint8_t* value = bytes.data() + pos;
        pos += size;

        if (attribute == "tiles" && tiled) {
            const int64_t tileW = size == 9 ? int64_t(uint32_t(readInt(value))) : 0;
            const int64_t tileH = size == 9 ? int64_t(uint32_t(readInt(value + 4))) : 0;
            if (tileW < 1 || tileH < 1 || tileW > kMaxTileSize || tileH > kMaxTileSize ||
                (value[8] & 0x3) == 3) {
                return "invalid OpenEXR tile description";
            }
            hasTiles = true;
        } else if (attribute == "type") {
            const std::string_view part(reinterpret_cast<const char*>(value),
                                        size_t(std::find(value, value + size, 0) - value));
            if (part != (tiled ? "tiledimage" : "scanlineimage")) {
                return "unsupported OpenEXR part type '" + printable(part) + "'";
            }
        } else if (attribute == "dataWindow" && size >= 16) {
            const int64_t width = int64_t(readInt(value + 8)) - readInt(value) + 1;
            const int64_t height = int64_t(readInt(value + 12)) - readInt(value + 4) + 1;
            if (width <= 0 || height <= 0 || uint64_t(width) * uint64_t(height) > kMaxPixels) {
                return "OpenEXR data window of " + std::to_string(width) + "x" +
                       std::to_string(height) + " pixels is empty or too large";
            }
        }
    }
    if (tiled && !hasTiles)
        return "tiled OpenEXR file without a tile description";
    return "";
}

// tinyexr 1.0.1 decodes a tile whose coordinates put it exactly at the right or bottom edge of
// its level as 0 pixels wide, then aborts on an assertion. This checks the coordinates of every
// chunk the tile offset table points to (OpenEXR file layout: after the header, one uint64
// offset per tile of every level; each chunk starts with int32 tile x, y, level x, level y).
std::string checkExrTiles(std::span<const uint8_t> bytes, const EXRHeader& header) {
    const int64_t width = int64_t(header.data_window.max_x) - header.data_window.min_x + 1;
    const int64_t height = int64_t(header.data_window.max_y) - header.data_window.min_y + 1;
    const int64_t tileW = header.tile_size_x;
    const int64_t tileH = header.tile_size_y;
    const bool roundUp = header.tile_rounding_mode == TINYEXR_TILE_ROUND_UP;
    // Level counts and sizes of OpenEXR's mipmap and ripmap levels, rounded down or up.
    const auto roundLog2 = [&](int64_t x) {
        int log = 0;
        while ((int64_t(1) << (log + 1)) <= x)
            ++log;
        return (roundUp && (int64_t(1) << log) < x) ? log + 1 : log;
    };
    const auto levelSize = [&](int64_t size, int level) {
        int64_t s = size >> level;
        if (roundUp && (s << level) < size)
            ++s;
        return std::max<int64_t>(s, 1);
    };
    int levelsX = 1, levelsY = 1;
    if (header.tile_level_mode == TINYEXR_TILE_MIPMAP_LEVELS) {
        levelsX = levelsY = roundLog2(std::max(width, height)) + 1;
    } else if (header.tile_level_mode == TINYEXR_TILE_RIPMAP_LEVELS) {
        levelsX = roundLog2(width) + 1;
        levelsY = roundLog2(height) + 1;
    }
    const auto tiles = [&](int lx, int ly) {
        return uint64_t((levelSize(width, lx) + tileW - 1) / tileW) *
               uint64_t((levelSize(height, ly) + tileH - 1) / tileH);
    };
    uint64_t count = 0;
    for (int ly = 0; ly < levelsY; ++ly) {
        for (int lx = 0; lx < levelsX; ++lx) {
            if (header.tile_level_mode != TINYEXR_TILE_RIPMAP_LEVELS && lx != ly)
                continue;
            count += tiles(lx, ly);
        }
    }

    const size_t table = 8 + size_t(header.header_len);
    if (table > bytes.size() || count > (bytes.size() - table) / 8)
        return "truncated OpenEXR tile offset table";
    const auto readInt = [&](size_t at) {
        uint32_t v = 0;
        for (int b = 3; b >= 0; --b)
            v = (v << 8) | bytes[at + size_t(b)];
        return int32_t(v);
    };
    for (uint64_t i = 0; i < count; ++i) {
        uint64_t offset = 0;
        for (int b = 7; b >= 0; --b)
            offset = (offset << 8) | bytes[table + 8 * i + size_t(b)];
        // tinyexr would guess a missing offset by scanning the chunks; refuse such files.
        if (offset == 0 || offset >= bytes.size())
            return "incomplete OpenEXR tile offset table";
        if (offset + 20 > bytes.size())
            continue;  // tinyexr reports the missing data
        const int64_t tx = readInt(offset), ty = readInt(offset + 4);
        const int lx = readInt(offset + 8), ly = readInt(offset + 12);
        if (lx < 0 || ly < 0 || lx >= levelsX || ly >= levelsY)
            continue;  // tinyexr reports the level mismatch
        if (tx < 0 || ty < 0 || tx * tileW >= levelSize(width, lx) ||
            ty * tileH >= levelSize(height, ly)) {
            return "OpenEXR tile (" + std::to_string(tx) + ", " + std::to_string(ty) +
                   ") lies outside its level";
        }
    }
    return "";
}

// Parses and decodes a single-part OpenEXR file whose header passed checkExrHeader.
Image loadExr(std::span<const uint8_t> bytes, EXRVersion& version, const std::string& name) {
    ExrHeader header;
    const char* err = nullptr;
    const int headerResult =
        ParseEXRHeaderFromMemory(&header.h, &version, bytes.data(), bytes.size(), &err);
    if (headerResult != TINYEXR_SUCCESS) {
        fail(name, "invalid OpenEXR header: " + takeExrError(err, headerResult));
    }

    // Locate R, G, B by name; any other channel (A, layers) is ignored.
    int index[3] = {-1, -1, -1};
    std::string found;
    for (int c = 0; c < header.h.num_channels; ++c) {
        const std::string_view channel = header.h.channels[c].name;
        if (c < 16)
            found += (found.empty() ? "" : ", ") + printable(channel);
        else if (c == 16)
            found += ", ...";
        const size_t rgb = std::string_view("RGB").find(channel);
        if (channel.size() == 1 && rgb != std::string_view::npos)
            index[rgb] = c;
    }
    if (index[0] < 0 || index[1] < 0 || index[2] < 0) {
        fail(name, "OpenEXR file has no R, G, B channels (channels: " +
                       (found.empty() ? std::string("none") : found) + ")");
    }
    for (int c : index) {
        if (header.h.channels[c].x_sampling != 1 || header.h.channels[c].y_sampling != 1) {
            fail(name, "subsampled OpenEXR channel " + printable(header.h.channels[c].name) +
                           " is not supported");
        }
    }
    for (int c = 0; c < header.h.num_channels; ++c) {
        const int type = header.h.pixel_types[c];
        if (type != TINYEXR_PIXELTYPE_UINT && type != TINYEXR_PIXELTYPE_HALF &&
            type != TINYEXR_PIXELTYPE_FLOAT) {
            fail(name, "invalid pixel type " + std::to_string(type) + " of OpenEXR channel " +
                           printable(header.h.channels[c].name));
        }
        if (type == TINYEXR_PIXELTYPE_HALF) {
            header.h.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
        }
    }
    if (header.h.tiled) {
        const std::string problem = checkExrTiles(bytes, header.h);
        if (!problem.empty())
            fail(name, problem);
    }
    const EXRBox2i& window = header.h.data_window;
    const int64_t width = int64_t(window.max_x) - window.min_x + 1;
    const int64_t height = int64_t(window.max_y) - window.min_y + 1;

    if (uint64_t(width) * uint64_t(height) * uint64_t(header.h.num_channels) > 4 * kMaxPixels) {
        fail(name, "OpenEXR file of " + std::to_string(width) + "x" + std::to_string(height) +
                       " pixels with " + std::to_string(header.h.num_channels) +
                       " channels is too large");
    }

    ExrImage exr;
    // tinyexr frees a scanline image's channels on failure only if num_channels is already set.
    exr.image.num_channels = header.h.num_channels;
    const int loadResult =
        LoadEXRImageFromMemory(&exr.image, &header.h, bytes.data(), bytes.size(), &err);
    if (loadResult != TINYEXR_SUCCESS) {
        fail(name, "corrupt or truncated OpenEXR data: " + takeExrError(err, loadResult));
    }
    exr.loaded = true;
    if (exr.image.width != width || exr.image.height != height) {
        fail(name, "OpenEXR image size does not match its data window");
    }

    Image image{int(width), int(height)};
    const int* types = header.h.requested_pixel_types;
    if (!header.h.tiled) {
        if (!exr.image.images)
            fail(name, "OpenEXR file holds no scanline pixels");
        for (int c = 0; c < 3; ++c) {
            const unsigned char* plane = exr.image.images[index[c]];
            for (size_t i = 0; i < image.pixelCount(); ++i) {
                image.rgb[3 * i + size_t(c)] = exrValue(plane, types[index[c]], i);
            }
        }
        return image;
    }

    // Tiled: place each tile of the first level; its pixel rows have a stride of tile_size_x.
    if (!exr.image.tiles)
        fail(name, "OpenEXR file holds no tiles");
    const int tileW = header.h.tile_size_x;
    const int tileH = header.h.tile_size_y;
    for (int t = 0; t < exr.image.num_tiles; ++t) {
        const EXRTile& tile = exr.image.tiles[t];
        for (int j = 0; j < tile.height; ++j) {
            for (int i = 0; i < tile.width; ++i) {
                const int64_t x = int64_t(tile.offset_x) * tileW + i;
                const int64_t y = int64_t(tile.offset_y) * tileH + j;
                if (x < 0 || y < 0 || x >= width || y >= height)
                    continue;
                const size_t src = size_t(j) * size_t(tileW) + size_t(i);
                const size_t dst = size_t(y) * size_t(width) + size_t(x);
                for (int c = 0; c < 3; ++c) {
                    image.rgb[3 * dst + size_t(c)] =
                        exrValue(tile.images[index[c]], types[index[c]], src);
                }
            }
        }
    }
    return image;
}

}  // namespace

Image decodeExr(std::span<const uint8_t> bytes, const std::string& name) {
    EXRVersion version;
    const int versionResult = ParseEXRVersionFromMemory(&version, bytes.data(), bytes.size());
    if (versionResult == TINYEXR_ERROR_INVALID_MAGIC_NUMBER)
        fail(name, "not an OpenEXR file");
    if (versionResult != TINYEXR_SUCCESS) {
        fail(name, "truncated OpenEXR file or unsupported OpenEXR version");
    }
    if (version.multipart)
        fail(name, "multi-part OpenEXR files are not supported");
    if (version.non_image)
        fail(name, "deep OpenEXR images are not supported");
    const std::string problem = checkExrHeader(bytes, version.tiled != 0);
    if (!problem.empty())
        fail(name, problem);
    // tinyexr is C++ inside: a malformed file may also surface as std::out_of_range and such.
    try {
        return loadExr(bytes, version, name);
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        fail(name, std::string("corrupt OpenEXR file (") + e.what() + ")");
    }
}

std::vector<uint8_t> encodePfm(const Image& image, const std::string& name) {
    checkImage(image, name);
    const std::string header =
        "PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1.0\n";
    std::vector<uint8_t> bytes(header.begin(), header.end());
    const size_t rowFloats = size_t(image.width) * 3;
    bytes.reserve(header.size() + image.rgb.size() * 4);
    // PFM rows run from the bottom of the image to the top; -1.0 scale means little-endian.
    for (int y = image.height - 1; y >= 0; --y) {
        for (size_t i = 0; i < rowFloats; ++i) {
            uint32_t v = std::bit_cast<uint32_t>(image.rgb[size_t(y) * rowFloats + i]);
            if constexpr (std::endian::native == std::endian::big)
                v = byteSwap(v);
            for (int b = 0; b < 4; ++b)
                bytes.push_back(uint8_t(v >> (8 * b)));
        }
    }
    return bytes;
}

Image decodePfm(std::span<const uint8_t> bytes, const std::string& name) {
    if (bytes.size() < 3 || bytes[0] != 'P' || (bytes[1] != 'F' && bytes[1] != 'f') ||
        !isPfmSpace(bytes[2])) {
        fail(name, "not a PFM file (expected \"PF\" or \"Pf\")");
    }
    const int channels = bytes[1] == 'F' ? 3 : 1;
    size_t pos = 2;
    // The next whitespace-separated header token (at most 64 characters).
    auto token = [&](const char* what) {
        while (pos < bytes.size() && isPfmSpace(bytes[pos]))
            ++pos;
        const size_t begin = pos;
        while (pos < bytes.size() && !isPfmSpace(bytes[pos]) && pos - begin < 64)
            ++pos;
        if (pos == begin || pos >= bytes.size())
            fail(name, std::string("truncated PFM header ") + what);
        return std::string_view(reinterpret_cast<const char*>(bytes.data()) + begin, pos - begin);
    };
    auto parseInt = [&](std::string_view text, const char* what) {
        int value = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (ec != std::errc() || end != text.data() + text.size() || value <= 0) {
            fail(name, std::string("invalid PFM ") + what + " '" + printable(text) + "'");
        }
        return value;
    };
    const int width = parseInt(token("(width)"), "width");
    const int height = parseInt(token("(height)"), "height");
    const std::string_view scaleText = token("(scale)");
    float scale = 0.0f;
    const auto [end, ec] =
        std::from_chars(scaleText.data(), scaleText.data() + scaleText.size(), scale);
    if (ec != std::errc() || end != scaleText.data() + scaleText.size() || !std::isfinite(scale) ||
        scale == 0.0f) {
        fail(name, "invalid PFM scale '" + printable(scaleText) + "'");
    }
    ++pos;  // the single whitespace character that ends the header

    const size_t available = bytes.size() - pos;
    const uint64_t pixels = uint64_t(width) * uint64_t(height);
    if (pixels > kMaxPixels) {
        fail(name, "PFM image of " + std::to_string(width) + "x" + std::to_string(height) +
                       " pixels is too large");
    }
    const uint64_t needed = pixels * uint64_t(channels) * 4;
    if (available < needed) {
        fail(name, "truncated PFM: " + std::to_string(width) + "x" + std::to_string(height) +
                       " pixels need " + std::to_string(needed) + " bytes of data, file has " +
                       std::to_string(available));
    }

    // Negative scale: little-endian data (Debevec's PFM definition); |scale| multiplies.
    const bool swap = (scale < 0.0f) != (std::endian::native == std::endian::little);
    const float factor = std::fabs(scale);
    Image image(width, height);
    const uint8_t* data = bytes.data() + pos;
    for (int row = 0; row < height; ++row) {
        const int y = height - 1 - row;
        for (int x = 0; x < width; ++x) {
            const size_t src = (size_t(row) * size_t(width) + size_t(x)) * size_t(channels);
            glm::vec3 pixel;
            for (int c = 0; c < 3; ++c) {
                uint32_t v;
                std::memcpy(&v, data + (src + size_t(channels == 3 ? c : 0)) * 4, 4);
                if (swap)
                    v = byteSwap(v);
                pixel[c] = std::bit_cast<float>(v);
                if (factor != 1.0f)
                    pixel[c] *= factor;
            }
            image.set(x, y, pixel);
        }
    }
    return image;
}

}  // namespace pmcr
