// Per-kernel GPU time from timestamp queries, accumulated over a whole render and reported by
// `--stats` and the stats JSON. Devices without compute timestamps report nothing.
#pragma once

#include <volk.h>

#include <map>
#include <string>
#include <vector>

namespace pmcr::vk {

class Context;

class GpuTimer {
public:
    struct Total {
        double milliseconds = 0.0;
        uint64_t dispatches = 0;
    };

    explicit GpuTimer(Context& context, uint32_t maxDispatchesPerBatch = 1024);
    ~GpuTimer();
    GpuTimer(const GpuTimer&) = delete;
    GpuTimer& operator=(const GpuTimer&) = delete;

    bool enabled() const { return m_pool != VK_NULL_HANDLE; }
    // Recording: reset once per command buffer, then begin/end around each dispatch.
    void reset(VkCommandBuffer cmd);
    void begin(VkCommandBuffer cmd, const std::string& name);
    void end(VkCommandBuffer cmd);
    // After the command buffer completed: read the queries and add them to the totals.
    void collect();

    const std::map<std::string, Total>& totals() const { return m_totals; }
    double totalMilliseconds() const;

private:
    Context& m_context;
    VkQueryPool m_pool = VK_NULL_HANDLE;
    uint32_t m_capacity = 0;
    std::vector<std::string> m_names;  // one per begin/end pair in the current batch
    bool m_open = false;
    std::map<std::string, Total> m_totals;
};

}  // namespace pmcr::vk
