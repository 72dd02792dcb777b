#include "vk/pipeline_cache.h"

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/log.h"
#include "image/image.h"
#include "vk/check.h"

namespace pmcr::vk {

namespace {

constexpr char kMagic[8] = {'P', 'M', 'C', 'R', 'P', 'C', '0', '1'};
constexpr size_t kContainerHeader = sizeof(kMagic) + 2 * sizeof(uint64_t);  // magic, size, checksum

uint64_t fnv1a(const uint8_t* data, size_t size) {
    uint64_t h = 0xcbf29ce484222325ull;
    for (size_t i = 0; i < size; ++i) h = (h ^ data[i]) * 0x100000001b3ull;
    return h;
}

std::string hex(const uint8_t* bytes, size_t n) {
    static const char* digits = "0123456789abcdef";
    std::string s;
    for (size_t i = 0; i < n; ++i) {
        s += digits[bytes[i] >> 4];
        s += digits[bytes[i] & 15];
    }
    return s;
}

// The blob must begin with the Vulkan header of this device (VkPipelineCacheHeaderVersionOne).
bool matchesDevice(const std::vector<uint8_t>& blob, const VkPhysicalDeviceProperties& p) {
    if (blob.size() < 16 + VK_UUID_SIZE) return false;
    uint32_t words[4];
    std::memcpy(words, blob.data(), sizeof(words));
    return words[0] >= 16 + VK_UUID_SIZE && words[1] == VK_PIPELINE_CACHE_HEADER_VERSION_ONE &&
           words[2] == p.vendorID && words[3] == p.deviceID &&
           std::memcmp(blob.data() + 16, p.pipelineCacheUUID, VK_UUID_SIZE) == 0;
}

}  // namespace

std::filesystem::path PipelineCache::directory() {
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
        return std::filesystem::path(xdg) / "pmcr";
    if (const char* home = std::getenv("HOME"); home && *home)
        return std::filesystem::path(home) / ".cache" / "pmcr";
    return {};
}

std::vector<uint8_t> PipelineCache::wrap(const std::vector<uint8_t>& blob) {
    std::vector<uint8_t> file(kContainerHeader + blob.size());
    const uint64_t size = blob.size(), sum = fnv1a(blob.data(), blob.size());
    std::memcpy(file.data(), kMagic, sizeof(kMagic));
    std::memcpy(file.data() + sizeof(kMagic), &size, sizeof(size));
    std::memcpy(file.data() + sizeof(kMagic) + sizeof(size), &sum, sizeof(sum));
    if (!blob.empty()) std::memcpy(file.data() + kContainerHeader, blob.data(), blob.size());
    return file;
}

std::vector<uint8_t> PipelineCache::unwrap(const std::vector<uint8_t>& file, std::string& why) {
    if (file.size() < kContainerHeader || std::memcmp(file.data(), kMagic, sizeof(kMagic)) != 0) {
        why = "not a pmcr pipeline cache";
        return {};
    }
    uint64_t size = 0, sum = 0;
    std::memcpy(&size, file.data() + sizeof(kMagic), sizeof(size));
    std::memcpy(&sum, file.data() + sizeof(kMagic) + sizeof(size), sizeof(sum));
    if (size != file.size() - kContainerHeader) {
        why = "truncated";
        return {};
    }
    std::vector<uint8_t> blob(file.begin() + kContainerHeader, file.end());
    if (fnv1a(blob.data(), blob.size()) != sum) {
        why = "corrupt (checksum mismatch)";
        return {};
    }
    return blob;
}

PipelineCache::PipelineCache(VkDevice device, const VkPhysicalDeviceProperties& properties)
    : m_device(device) {
    const std::filesystem::path dir = directory();
    if (!dir.empty())
        m_path = dir / (hex(properties.pipelineCacheUUID, VK_UUID_SIZE) + "-" +
                        std::to_string(properties.vendorID) + "-" +
                        std::to_string(properties.driverVersion) + ".bin");
    std::error_code ec;
    if (!m_path.empty() && std::filesystem::is_regular_file(m_path, ec)) {
        std::ifstream in(m_path, std::ios::binary);
        std::vector<uint8_t> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::string why;
        std::vector<uint8_t> blob = unwrap(file, why);
        if (blob.empty() && why.empty()) why = "empty";
        if (!blob.empty() && !matchesDevice(blob, properties)) why = "made for another device or driver";
        if (why.empty())
            m_loaded = std::move(blob);
        else
            log::warning(m_path.string() + ": ignoring the pipeline cache: " + why);
    }
    VkPipelineCacheCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
    info.initialDataSize = m_loaded.size();
    info.pInitialData = m_loaded.empty() ? nullptr : m_loaded.data();
    if (vkCreatePipelineCache(m_device, &info, nullptr, &m_cache) != VK_SUCCESS) {
        // The driver refused data it wrote itself: start empty rather than fail.
        log::warning(m_path.string() + ": ignoring the pipeline cache: the driver refused it");
        m_loaded.clear();
        info.initialDataSize = 0;
        info.pInitialData = nullptr;
        VK_CHECK(vkCreatePipelineCache(m_device, &info, nullptr, &m_cache));
    }
}

PipelineCache::~PipelineCache() {
    if (m_cache) vkDestroyPipelineCache(m_device, m_cache, nullptr);
}

void PipelineCache::save() {
    if (m_path.empty() || !m_cache) return;
    size_t size = 0;
    if (vkGetPipelineCacheData(m_device, m_cache, &size, nullptr) != VK_SUCCESS || size == 0) return;
    std::vector<uint8_t> blob(size);
    if (vkGetPipelineCacheData(m_device, m_cache, &size, blob.data()) != VK_SUCCESS) return;
    blob.resize(size);
    if (blob == m_loaded) return;
    try {
        std::error_code ec;
        std::filesystem::create_directories(m_path.parent_path(), ec);
        const std::vector<uint8_t> file = wrap(blob);
        writeFileAtomically(m_path, [&](const std::filesystem::path& tmp) {
            std::ofstream out(tmp, std::ios::binary);
            out.write(reinterpret_cast<const char*>(file.data()), std::streamsize(file.size()));
            out.close();
            if (!out) throw std::runtime_error("write failed");
        });
        m_loaded = std::move(blob);
    } catch (const std::exception& e) {
        log::warning(m_path.string() + ": could not write the pipeline cache: " + e.what());
        m_path.clear();  // warn once
    }
}

}  // namespace pmcr::vk
