// Records a batch of compute dispatches into one command buffer, submits it and waits.
// A batch is the unit of work between two host checks (progress, Ctrl-C, adaptation): callers
// size it so that it finishes in well under a second on lavapipe, since a long submission makes
// lavapipe unresponsive and a real GPU may kill it.
//
// Every dispatch after the first is preceded by a compute->compute memory barrier, so
// consecutive dispatches may depend on each other; the batch ends with a compute->host barrier so
// the host may read mapped results after submitAndWait().
#pragma once

#include <volk.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pmcr::vk {

class Context;
class Kernel;
class DescriptorSet;
class PipelineLayout;
class Buffer;
class GpuTimer;

class CommandBatch {
public:
    CommandBatch(const PipelineLayout& layout, GpuTimer* timer = nullptr);
    ~CommandBatch();
    CommandBatch(const CommandBatch&) = delete;
    CommandBatch& operator=(const CommandBatch&) = delete;

    void bind(const DescriptorSet& set);
    // Dispatches ceil(invocations / WORKGROUP_SIZE) workgroups of `kernel` with `push` constants.
    void dispatch(const Kernel& kernel, const void* push, uint32_t pushBytes, uint32_t invocations);
    template <class Push>
    void dispatch(const Kernel& kernel, const Push& push, uint32_t invocations) {
        static_assert(sizeof(Push) <= 128, "push constants are limited to 128 bytes");
        dispatch(kernel, &push, uint32_t(sizeof(Push)), invocations);
    }
    void fill(const Buffer& buffer, uint32_t value);
    void copy(const Buffer& src, const Buffer& dst, uint64_t bytes);
    uint32_t dispatchCount() const { return m_dispatches; }

    // Ends, submits and waits; the batch can then be recorded again from scratch.
    void submitAndWait();
    // The same in two steps, so that the host can work while the device runs the batch (with
    // a second batch recorded meanwhile: two in flight). wait() after submit() only.
    void submit();
    void wait();
    // Whether the submission in flight has completed (its fence signalled), without waiting.
    bool finished() const;
    // The last completed submission's span on the device in seconds, first dispatch's start to
    // last one's end, from timestamps (< 0 without them): what a batch cost the device, even
    // when the host came to wait for it late.
    double lastDeviceSeconds() const { return m_lastDeviceSeconds; }

private:
    void begin();
    void barrier();

    Context& m_context;
    const PipelineLayout& m_layout;
    GpuTimer* m_timer;
    // Timestamps around each dispatch (with a timer on a device that has them): a pool of
    // 2 kMaxTimedDispatches queries per batch, names in dispatch order.
    static constexpr uint32_t kMaxTimedDispatches = 1024;
    VkQueryPool m_queries = VK_NULL_HANDLE;
    std::unique_ptr<Buffer> m_stamps;  // the batch's timestamps, copied there at its end (mapped)
    std::vector<std::string> m_timed;
    // Adds the completed batch's dispatch times to the timer; returns its span on the device in
    // seconds, first dispatch's start to last one's end (-1 without timestamps).
    double collectTimes();
    VkCommandBuffer m_cmd = VK_NULL_HANDLE;
    VkFence m_fence = VK_NULL_HANDLE;
    bool m_recording = false;
    bool m_inFlight = false;
    double m_lastDeviceSeconds = -1.0;
    std::chrono::steady_clock::time_point m_submittedAt{};
    bool m_needsBarrier = false;
    uint32_t m_dispatches = 0;
};

}  // namespace pmcr::vk
