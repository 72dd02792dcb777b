// A VkPipelineCache kept on disk between runs, so that the second render of a scene on a GPU
// compiles nothing: `$XDG_CACHE_HOME/pmcr/` (else `~/.cache/pmcr/`), one file per device and
// driver (named by the device's pipelineCacheUUID and driver version).
//
// The file is pmcr's own small container around the driver's blob: a magic string, the blob's
// size and an FNV-1a checksum of it, then the blob. A file that is truncated, corrupt or made for
// another device or driver is ignored with one warning and replaced at exit; the driver never
// sees bytes that did not come from it. With no cache directory (neither variable set) the cache
// lives in memory only. Writes are atomic (a temporary file renamed over the old one), so two
// processes rendering at once leave one whole file.
#pragma once

#include <volk.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace pmcr::vk {

class PipelineCache {
public:
    // Loads the cache file of `physicalDevice` (if any) and creates the VkPipelineCache.
    PipelineCache(VkDevice device, const VkPhysicalDeviceProperties& properties);
    ~PipelineCache();
    PipelineCache(const PipelineCache&) = delete;
    PipelineCache& operator=(const PipelineCache&) = delete;

    VkPipelineCache handle() const { return m_cache; }
    // The file this cache is read from and written to (empty when there is none).
    const std::filesystem::path& path() const { return m_path; }
    // Writes the cache back when the driver's data changed since it was loaded. Errors are
    // ignored (a warning once): a cache that cannot be written costs time, never a render.
    void save();

    // The cache directory from the environment: $XDG_CACHE_HOME/pmcr, else $HOME/.cache/pmcr,
    // else empty.
    static std::filesystem::path directory();
    // The container's bytes for a driver blob, and the blob from a container (empty, with the
    // reason in `why`, when the bytes are not a whole, intact container).
    static std::vector<uint8_t> wrap(const std::vector<uint8_t>& blob);
    static std::vector<uint8_t> unwrap(const std::vector<uint8_t>& file, std::string& why);

private:
    VkDevice m_device;
    VkPipelineCache m_cache = VK_NULL_HANDLE;
    std::filesystem::path m_path;
    std::vector<uint8_t> m_loaded;  // the driver's blob as loaded (empty if none)
};

}  // namespace pmcr::vk
