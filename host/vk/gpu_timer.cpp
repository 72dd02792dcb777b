#include "vk/gpu_timer.h"

#include "vk/check.h"
#include "vk/context.h"

namespace pmcr::vk {

GpuTimer::GpuTimer(Context& context, uint32_t maxDispatchesPerBatch) : m_context(context) {
    if (!context.timestampsSupported()) return;
    m_capacity = maxDispatchesPerBatch;
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = 2 * m_capacity;
    VK_CHECK(vkCreateQueryPool(context.device(), &info, nullptr, &m_pool));
}

GpuTimer::~GpuTimer() {
    if (m_pool) vkDestroyQueryPool(m_context.device(), m_pool, nullptr);
}

void GpuTimer::reset(VkCommandBuffer cmd) {
    m_names.clear();
    m_open = false;
    if (m_pool) vkCmdResetQueryPool(cmd, m_pool, 0, 2 * m_capacity);
}

void GpuTimer::begin(VkCommandBuffer cmd, const std::string& name) {
    if (!m_pool || m_names.size() >= m_capacity) return;
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, m_pool, uint32_t(2 * m_names.size()));
    m_names.push_back(name);
    m_open = true;
}

void GpuTimer::end(VkCommandBuffer cmd) {
    if (!m_pool || !m_open) return;
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, m_pool,
                        uint32_t(2 * m_names.size() - 1));
    m_open = false;
}

void GpuTimer::collect() {
    if (!m_pool || m_names.empty()) return;
    std::vector<uint64_t> stamps(2 * m_names.size());
    VK_CHECK(vkGetQueryPoolResults(m_context.device(), m_pool, 0, uint32_t(stamps.size()),
                                   stamps.size() * sizeof(uint64_t), stamps.data(), sizeof(uint64_t),
                                   VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    const uint32_t bits = m_context.timestampValidBits();
    const uint64_t mask = bits >= 64 ? ~0ull : ((1ull << bits) - 1);
    const double nsPerTick = m_context.limits().timestampPeriod;
    for (size_t i = 0; i < m_names.size(); ++i) {
        const uint64_t ticks = ((stamps[2 * i + 1] & mask) - (stamps[2 * i] & mask)) & mask;
        Total& t = m_totals[m_names[i]];
        t.milliseconds += double(ticks) * nsPerTick * 1e-6;
        t.dispatches += 1;
    }
    m_names.clear();
}

double GpuTimer::totalMilliseconds() const {
    double sum = 0.0;
    for (const auto& [name, total] : m_totals) sum += total.milliseconds;
    return sum;
}

}  // namespace pmcr::vk
