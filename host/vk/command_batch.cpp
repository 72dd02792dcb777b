#include "vk/command_batch.h"

#include "core/error.h"
#include "shared/host_device.h"
#include "vk/buffer.h"
#include "vk/check.h"
#include "vk/context.h"
#include "vk/gpu_timer.h"
#include "vk/pipeline.h"

namespace pmcr::vk {

CommandBatch::CommandBatch(const PipelineLayout& layout, GpuTimer* timer)
    : m_context(layout.context()), m_layout(layout), m_timer(timer) {
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = m_context.commandPool();
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VK_CHECK(vkAllocateCommandBuffers(m_context.device(), &alloc, &m_cmd));
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkResult result = vkCreateFence(m_context.device(), &fenceInfo, nullptr, &m_fence);
    if (result != VK_SUCCESS) {
        vkFreeCommandBuffers(m_context.device(), m_context.commandPool(), 1, &m_cmd);
        throwVkError(result, "vkCreateFence", __FILE__, __LINE__);
    }
    if (m_timer && m_timer->enabled()) {
        VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        info.queryType = VK_QUERY_TYPE_TIMESTAMP;
        info.queryCount = 2 * kMaxTimedDispatches;
        result = vkCreateQueryPool(m_context.device(), &info, nullptr, &m_queries);
        if (result != VK_SUCCESS) {
            vkDestroyFence(m_context.device(), m_fence, nullptr);
            vkFreeCommandBuffers(m_context.device(), m_context.commandPool(), 1, &m_cmd);
            throwVkError(result, "vkCreateQueryPool", __FILE__, __LINE__);
        }
        try {
            m_stamps = std::make_unique<Buffer>(m_context, VkDeviceSize(2 * kMaxTimedDispatches) * sizeof(uint64_t),
                                                VK_BUFFER_USAGE_TRANSFER_DST_BIT, "timestamps",
                                                MemoryUsage::Readback);
        } catch (...) {
            vkDestroyQueryPool(m_context.device(), m_queries, nullptr);
            vkDestroyFence(m_context.device(), m_fence, nullptr);
            vkFreeCommandBuffers(m_context.device(), m_context.commandPool(), 1, &m_cmd);
            throw;
        }
    }
}

CommandBatch::~CommandBatch() {
    if (m_inFlight) {  // (never waited for: its end is when the host saw it)
        vkWaitForFences(m_context.device(), 1, &m_fence, VK_TRUE, UINT64_MAX);
        m_context.activity().completed(m_submittedAt, false, -1.0);
    }
    if (m_recording) vkEndCommandBuffer(m_cmd);
    if (m_queries) vkDestroyQueryPool(m_context.device(), m_queries, nullptr);
    vkDestroyFence(m_context.device(), m_fence, nullptr);
    vkFreeCommandBuffers(m_context.device(), m_context.commandPool(), 1, &m_cmd);
}

void CommandBatch::begin() {
    if (m_recording) return;
    wait();  // a batch in flight must finish before its command buffer is recorded again
    VK_CHECK(vkResetCommandBuffer(m_cmd, 0));
    VkCommandBufferBeginInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(m_cmd, &info));
    m_timed.clear();
    if (m_queries) vkCmdResetQueryPool(m_cmd, m_queries, 0, 2 * kMaxTimedDispatches);
    m_recording = true;
    m_dispatches = 0;
    // Writes of earlier submissions (transfers, dispatches, host) are visible to this batch.
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                            VK_ACCESS_HOST_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                            VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    vkCmdPipelineBarrier(m_cmd,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                             VK_PIPELINE_STAGE_HOST_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
                         1, &barrier, 0, nullptr, 0, nullptr);
    m_needsBarrier = false;
}

void CommandBatch::barrier() {
    if (!m_needsBarrier) return;
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                            VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    const VkPipelineStageFlags stages =
        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    vkCmdPipelineBarrier(m_cmd, stages, stages, 0, 1, &barrier, 0, nullptr, 0, nullptr);
    m_needsBarrier = false;
}

void CommandBatch::bind(const DescriptorSet& set) {
    begin();
    VkDescriptorSet handle = set.handle();
    vkCmdBindDescriptorSets(m_cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_layout.handle(), set.index(),
                            1, &handle, 0, nullptr);
}

void CommandBatch::dispatch(const Kernel& kernel, const void* push, uint32_t pushBytes,
                            uint32_t invocations) {
    begin();
    if (invocations == 0) return;
    const uint32_t groups = (invocations + gpu::WORKGROUP_SIZE - 1) / gpu::WORKGROUP_SIZE;
    if (groups > m_context.limits().maxComputeWorkGroupCount[0])
        throw Error("dispatch of " + std::to_string(invocations) + " invocations of " +
                    kernel.name() + " exceeds the device's workgroup count limit");
    barrier();
    vkCmdBindPipeline(m_cmd, VK_PIPELINE_BIND_POINT_COMPUTE, kernel.handle());
    if (pushBytes > 0)
        vkCmdPushConstants(m_cmd, m_layout.handle(), VK_SHADER_STAGE_COMPUTE_BIT, 0, pushBytes, push);
    const bool timed = m_queries && m_timed.size() < kMaxTimedDispatches;
    const uint32_t query = uint32_t(2 * m_timed.size());
    if (timed) vkCmdWriteTimestamp(m_cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, m_queries, query);
    vkCmdDispatch(m_cmd, groups, 1, 1);
    if (timed) {
        vkCmdWriteTimestamp(m_cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, m_queries, query + 1);
        m_timed.push_back(kernel.name());
    }
    m_needsBarrier = true;
    ++m_dispatches;
}

void CommandBatch::fill(const Buffer& buffer, uint32_t value) {
    begin();
    barrier();
    vkCmdFillBuffer(m_cmd, buffer.handle(), 0, VK_WHOLE_SIZE, value);
    m_needsBarrier = true;
}

void CommandBatch::copy(const Buffer& src, const Buffer& dst, uint64_t bytes) {
    begin();
    barrier();
    VkBufferCopy region{0, 0, bytes};
    vkCmdCopyBuffer(m_cmd, src.handle(), dst.handle(), 1, &region);
    m_needsBarrier = true;
}

void CommandBatch::submitAndWait() {
    submit();
    wait();
}

void CommandBatch::submit() {
    begin();
    // The timestamps copied to mapped memory by the batch itself: vkGetQueryPoolResults would
    // do too, but lavapipe's waits for the device to go idle first (Mesa 22.3, lvp_query.c),
    // which with a second batch in flight meant waiting for that one too.
    if (m_queries && !m_timed.empty()) {
        barrier();
        vkCmdCopyQueryPoolResults(m_cmd, m_queries, 0, uint32_t(2 * m_timed.size()), m_stamps->handle(), 0,
                                  sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT);
    }
    // Make every write of the batch visible to host reads of mapped memory.
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(m_cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
    VK_CHECK(vkEndCommandBuffer(m_cmd));
    m_recording = false;
    VK_CHECK(vkResetFences(m_context.device(), 1, &m_fence));
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &m_cmd;
    m_submittedAt = std::chrono::steady_clock::now();
    VK_CHECK(vkQueueSubmit(m_context.queue(), 1, &submit, m_fence));
    m_context.activity().submitted(m_submittedAt);
    m_inFlight = true;
}

bool CommandBatch::finished() const {
    return !m_inFlight || vkGetFenceStatus(m_context.device(), m_fence) == VK_SUCCESS;
}

void CommandBatch::wait() {
    if (!m_inFlight) return;
    const bool alreadySignalled = vkGetFenceStatus(m_context.device(), m_fence) == VK_SUCCESS;
    VK_CHECK(vkWaitForFences(m_context.device(), 1, &m_fence, VK_TRUE, UINT64_MAX));
    m_inFlight = false;
    const double span = collectTimes();
    m_lastDeviceSeconds = span;
    m_context.activity().completed(m_submittedAt, alreadySignalled, span);
}

double CommandBatch::collectTimes() {
    if (!m_queries || m_timed.empty()) return -1.0;
    const uint64_t* stamps = static_cast<const uint64_t*>(m_stamps->mapped());
    const uint32_t bits = m_context.timestampValidBits();
    const uint64_t mask = bits >= 64 ? ~0ull : ((1ull << bits) - 1);
    const double nsPerTick = m_context.limits().timestampPeriod;
    for (size_t i = 0; i < m_timed.size(); ++i) {
        const uint64_t ticks = ((stamps[2 * i + 1] & mask) - (stamps[2 * i] & mask)) & mask;
        m_timer->add(m_timed[i], double(ticks) * nsPerTick * 1e-6);
    }
    const uint64_t span = ((stamps[2 * m_timed.size() - 1] & mask) - (stamps[0] & mask)) & mask;
    m_timed.clear();
    return double(span) * nsPerTick * 1e-9;
}

}  // namespace pmcr::vk
