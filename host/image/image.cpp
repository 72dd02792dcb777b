#include "image/image.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

#include "core/error.h"
#include "image/image_io.h"

namespace fs = std::filesystem;

namespace pmcr {

namespace {

// strerror text starting in lower case, e.g. "no such file or directory".
std::string errnoText(int error) {
    std::string text = std::strerror(error);
    if (!text.empty())
        text[0] = char(std::tolower(static_cast<unsigned char>(text[0])));
    return text;
}

// Closes a POSIX file descriptor on scope exit.
struct FileDescriptor {
    int fd;
    explicit FileDescriptor(int f) : fd(f) {}
    ~FileDescriptor() {
        if (fd >= 0)
            ::close(fd);
    }
    FileDescriptor(const FileDescriptor&) = delete;
    FileDescriptor& operator=(const FileDescriptor&) = delete;
    // Closes now, reporting the error a delayed write may only show here.
    int close() {
        const int result = ::close(fd);
        fd = -1;
        return result;
    }
};

std::vector<uint8_t> readFileBytes(const fs::path& path) {
    const std::string name = path.string();
    FileDescriptor file(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    if (file.fd < 0)
        fail(name, "cannot open: " + errnoText(errno));
    struct stat info;
    if (::fstat(file.fd, &info) != 0)
        fail(name, "cannot read: " + errnoText(errno));
    if (S_ISDIR(info.st_mode))
        fail(name, "is a directory, not an image file");
    if (!S_ISREG(info.st_mode))
        fail(name, "not a regular file");
    std::vector<uint8_t> bytes(size_t(info.st_size));
    size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::read(file.fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0)
            fail(name, "cannot read: " + errnoText(errno));
        if (n == 0)
            break;
        done += size_t(n);
    }
    bytes.resize(done);
    return bytes;
}

// Writes `bytes` to the existing file `path`; throws std::runtime_error (writeFileAtomically
// names the target file).
void writeBytes(const fs::path& path, const std::vector<uint8_t>& bytes) {
    FileDescriptor file(::open(path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC));
    if (file.fd < 0)
        throw std::runtime_error("cannot open temporary file: " + errnoText(errno));
    size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(file.fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            throw std::runtime_error("cannot write: " + errnoText(n < 0 ? errno : EIO));
        done += size_t(n);
    }
    if (file.close() != 0)
        throw std::runtime_error("cannot write: " + errnoText(errno));
}

void syncFile(const fs::path& path) {
    FileDescriptor file(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    if (file.fd < 0)
        throw std::runtime_error("temporary file vanished: " + errnoText(errno));
    if (::fsync(file.fd) != 0 || file.close() != 0) {
        throw std::runtime_error("cannot write: " + errnoText(errno));
    }
}

std::string describeCreateError(int error, const fs::path& dir) {
    const std::string quoted = std::string("'").append(dir.string()).append("'");
    switch (error) {
        case ENOENT:
            return "directory " + quoted + " does not exist";
        case ENOTDIR:
            return quoted + " is not a directory";
        case EACCES:
        case EPERM:
            return "permission denied to create files in directory " + quoted;
        case EROFS:
            return "directory " + quoted + " is on a read-only file system";
        default:
            return "cannot create a file in directory " + quoted + ": " + errnoText(error);
    }
}

std::string lowerExtension(const fs::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

[[noreturn]] void failExtension(const fs::path& path) {
    const std::string ext = path.extension().string();
    fail(path.string(), ext.empty()
                            ? "no file extension (expected .exr or .pfm)"
                            : "unknown HDR image extension '" + ext + "' (expected .exr or .pfm)");
}

}  // namespace

void writeFileAtomically(const fs::path& path,
                         const std::function<void(const fs::path& tmp)>& write) {
    const std::string name = path.string();
    if (!path.has_filename())
        fail(name, "not a file name");
    std::error_code ec;
    if (fs::is_directory(path, ec))
        fail(name, "is a directory");
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");

    // Create the temporary here, so a missing or unwritable directory is reported as such; the
    // pid and a process-wide counter keep names unique, O_EXCL skips stale leftovers.
    static std::atomic<unsigned> counter{0};
    fs::path tmp;
    for (int attempt = 0;; ++attempt) {
        tmp = dir /
              std::string(".")
                  .append(path.filename().string())
                  .append(".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(++counter));
        const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) {
            ::close(fd);
            break;
        }
        if (errno != EEXIST || attempt == 100)
            fail(name, describeCreateError(errno, dir));
    }

    try {
        write(tmp);
        syncFile(tmp);
        if (::rename(tmp.c_str(), path.c_str()) != 0) {
            throw std::runtime_error("cannot replace the file: " + errnoText(errno));
        }
    } catch (const Error&) {
        fs::remove(tmp, ec);
        throw;
    } catch (const std::exception& e) {
        fs::remove(tmp, ec);
        fail(name, e.what());
    } catch (...) {
        fs::remove(tmp, ec);
        fail(name, "unknown error while writing");
    }

    // Make the rename itself durable; a failure here leaves a complete file, so it is ignored.
    FileDescriptor directory(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (directory.fd >= 0)
        ::fsync(directory.fd);
}

void writeHdr(const fs::path& path, const Image& image) {
    const std::string ext = lowerExtension(path);
    std::vector<uint8_t> bytes;
    if (ext == ".exr") {
        bytes = encodeExr(image, path.string());
    } else if (ext == ".pfm") {
        bytes = encodePfm(image, path.string());
    } else {
        failExtension(path);
    }
    writeFileAtomically(path, [&](const fs::path& tmp) { writeBytes(tmp, bytes); });
}

Image readHdr(const fs::path& path) {
    const std::string ext = lowerExtension(path);
    if (ext != ".exr" && ext != ".pfm")
        failExtension(path);
    const std::vector<uint8_t> bytes = readFileBytes(path);
    if (bytes.empty())
        fail(path.string(), "empty file");
    return ext == ".exr" ? decodeExr(bytes, path.string()) : decodePfm(bytes, path.string());
}

float srgbEncode(float linear) {
    // sRGB OETF, IEC 61966-2-1:1999 section 5.2.
    if (linear <= 0.0031308f)
        return 12.92f * linear;
    return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

std::vector<uint8_t> toSrgb8(const Image& image, float exposure) {
    const float scale = std::exp2(exposure);
    std::vector<uint8_t> pixels(image.rgb.size());
    for (size_t i = 0; i < image.rgb.size(); ++i) {
        const float value = image.rgb[i];
        float v = std::isfinite(value) ? value * scale : 0.0f;
        // Clamp to [0,1]; NaN (0 * an infinite scale) becomes 0.
        v = v > 0.0f ? std::min(v, 1.0f) : 0.0f;
        pixels[i] = uint8_t(std::lround(srgbEncode(v) * 255.0f));
    }
    return pixels;
}

void writePng(const fs::path& path, const Image& image, float exposure) {
    const std::string name = path.string();
    if (!std::isfinite(exposure))
        fail(name, "exposure must be finite");
    if (image.width <= 0 || image.height <= 0 || image.rgb.size() != image.pixelCount() * 3) {
        fail(name, "cannot write an empty or malformed image (" + std::to_string(image.width) +
                       "x" + std::to_string(image.height) + ")");
    }
    if (image.rgb.size() > size_t(INT_MAX))
        fail(name, "image too large for PNG");
    const std::vector<uint8_t> pixels = toSrgb8(image, exposure);
    std::vector<uint8_t> png;
    const auto append = [](void* context, void* data, int size) {
        auto* out = static_cast<std::vector<uint8_t>*>(context);
        const auto* bytes = static_cast<const uint8_t*>(data);
        out->insert(out->end(), bytes, bytes + size);
    };
    if (!stbi_write_png_to_func(append, &png, image.width, image.height, 3, pixels.data(),
                                image.width * 3)) {
        fail(name, "PNG encoding failed");
    }
    writeFileAtomically(path, [&](const fs::path& tmp) { writeBytes(tmp, png); });
}

Image crop(const Image& image, int x, int y, int w, int h) {
    if (w <= 0 || h <= 0 || x < 0 || y < 0 || int64_t(x) + w > image.width ||
        int64_t(y) + h > image.height) {
        throw Error("crop: rectangle " + std::to_string(w) + "x" + std::to_string(h) + " at (" +
                    std::to_string(x) + ", " + std::to_string(y) + ") is empty or outside the " +
                    std::to_string(image.width) + "x" + std::to_string(image.height) + " image");
    }
    Image out(w, h);
    for (int row = 0; row < h; ++row) {
        const auto begin = image.rgb.begin() + ptrdiff_t((size_t(y + row) * image.width + x) * 3);
        std::copy(begin, begin + ptrdiff_t(size_t(w) * 3),
                  out.rgb.begin() + ptrdiff_t(size_t(row) * w * 3));
    }
    return out;
}

}  // namespace pmcr
