#include "render/session.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/interrupt.h"
#include "vk/command_batch.h"
#include "vk/context.h"

namespace pmcr {

RenderSession::RenderSession(vk::Context& context, const Scene& scene,
                             const RenderSettings& settings, int width, int height,
                             Communicator& comm)
    : m_context(context), m_comm(comm), m_settings(settings), m_width(width), m_height(height) {
    m_scene = std::make_unique<GpuScene>(context, context.layout(), scene, settings.camera, width, height);
    m_timer = std::make_unique<vk::GpuTimer>(context);
    m_film = std::make_unique<Film>(context, width, height);
    m_progress = std::make_unique<Progress>(settings.method, !settings.quiet);
    m_placeholder = vk::Buffer(context, 256, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "placeholder");
    m_placeholder.fill(0);
    m_pipelineSecondsAtStart = context.pipelineSeconds();
    m_start = std::chrono::steady_clock::now();
}

double RenderSession::pipelineSeconds() const {
    return m_context.pipelineSeconds() - m_pipelineSecondsAtStart + m_warmupSeconds;
}

uint64_t RenderSession::queueDrains() const { return m_context.queueDrains() - m_drainsAtClockStart; }

double RenderSession::deviceBusySeconds() const {
    return m_context.activity().busySeconds() - m_busyAtClockStart;
}

const vk::Kernel& RenderSession::kernel(const std::string& name, uint32_t kernelOptions) {
    const vk::Kernel& k = m_context.kernel(name, m_scene->features(), kernelOptions);
    if (std::find(m_kernels.begin(), m_kernels.end(), &k) == m_kernels.end()) m_kernels.push_back(&k);
    return k;
}

void RenderSession::startClock() {
    const auto warmupStart = std::chrono::steady_clock::now();
    // One workgroup of each kernel with all push constants zero: every kernel's invocation
    // count (invocationCount, memberCount, chainCount, recordCount) is then 0, so it does no
    // work, and the work set's bindings all point at the placeholder.
    if (!m_kernels.empty()) {
        vk::DescriptorSet idle(layout(), vk::DescriptorSet::Kind::Work, "warm-up work");
        for (uint32_t b = 0; b < gpu::WORK_BINDING_COUNT; ++b) idle.bind(b, m_placeholder);
        vk::CommandBatch batch(layout());
        batch.bind(m_scene->descriptorSet());
        batch.bind(idle);
        const std::array<uint8_t, gpu::PUSH_CONSTANT_BYTES> zero{};
        for (const vk::Kernel* k : m_kernels) batch.dispatch(*k, zero.data(), uint32_t(zero.size()), 1);
        batch.submitAndWait();
    }
    m_start = std::chrono::steady_clock::now();
    m_warmupSeconds += std::chrono::duration<double>(m_start - warmupStart).count();
    m_busyAtClockStart = m_context.activity().busySeconds();
    m_drainsAtClockStart = m_context.queueDrains();
}

double RenderSession::elapsedSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
}

bool RenderSession::timeUp() const {
    return m_settings.timeLimit > 0.0 && elapsedSeconds() >= m_settings.timeLimit;
}

bool RenderSession::interrupted() const { return interruptRequested(); }

bool RenderSession::shouldStop() const { return interrupted() || timeUp(); }

void RenderSession::updateSppProgress(uint64_t cameraSamples, double budgetSpp) {
    const double sppDone = double(cameraSamples) / (double(m_width) * double(m_height));
    const double fraction = m_settings.spp > 0 || m_settings.timeLimit <= 0.0
                                ? sppDone / budgetSpp
                                : elapsedSeconds() / m_settings.timeLimit;
    m_progress->update(fraction, sppDone, "spp");
}

void RenderSession::snapshotIfDue(uint64_t cameraSamples, const std::function<Image()>& resolve) {
    const double seconds = elapsedSeconds();
    const double spp = double(cameraSamples) / (double(m_width) * double(m_height));
    const auto& times = m_settings.snapshotSeconds;
    const auto& spps = m_settings.snapshotSpp;
    bool due = false;
    // One snapshot covers every scheduled point passed since the last one.
    while (m_nextSnapshotTime < times.size() && times[m_nextSnapshotTime] <= seconds) {
        ++m_nextSnapshotTime;
        due = true;
    }
    while (m_nextSnapshotSpp < spps.size() && spps[m_nextSnapshotSpp] <= spp) {
        ++m_nextSnapshotSpp;
        due = true;
    }
    if (!due) return;
    // The batches in flight finish on the clock first: the snapshot's time comes off it, and the
    // device's work during it would otherwise be free (pm at `--time 2` in `pmcr bench` had
    // 1.45 s of kernels per second of clock, and 4 spp where `pmcr render` reached 2.4).
    m_context.waitIdle();
    const auto start = std::chrono::steady_clock::now();
    m_snapshots.push_back({seconds, spp, resolve()});
    // Take the snapshot's cost off the render clock.
    const auto cost = std::chrono::steady_clock::now() - start;
    m_start += std::chrono::duration_cast<std::chrono::steady_clock::duration>(cost);
    m_snapshotOverhead += std::chrono::duration<double>(cost).count();
}

double RenderSession::nextSnapshotSpp() const {
    const auto& spps = m_settings.snapshotSpp;
    return m_nextSnapshotSpp < spps.size() ? spps[m_nextSnapshotSpp]
                                           : std::numeric_limits<double>::infinity();
}

double RenderSession::targetDispatchSeconds() const { return m_context.isCpuDevice() ? 0.05 : 0.02; }

double RenderSession::targetBatchSeconds() const { return m_context.isCpuDevice() ? 0.25 : 0.1; }

bool RenderSession::queueAnotherBatch(double inFlightSeconds, double nextSeconds) const {
    if (m_settings.timeLimit <= 0.0) return true;
    const double left = m_settings.timeLimit - elapsedSeconds() - inFlightSeconds;  // after the one in flight
    const double past = nextSeconds - left;  // how far past the limit the next one would end
    return left > 0.0 && past < left && past <= kBatchOvershootSeconds;
}

bool PassClock::startPass(uint32_t pass) {
    // The first pass starts even when a pre-pass used up the budget: a render always has an
    // image (pssmlt over bdpt once returned none after its 256x256 bootstrap overran --time 2).
    const bool first = m_completed == 0 && m_open.empty();
    if (m_session.interrupted() || (!first && m_session.timeUp())) return false;
    const double limit = m_session.settings().timeLimit;
    const double now = m_session.elapsedSeconds();
    double longest = m_longest;
    for (const auto& [id, start] : m_open) longest = std::max(longest, now - start);
    if (limit > 0.0 && !first && now + longest > limit) return false;
    std::erase_if(m_open, [&](const auto& p) { return p.first == pass; });
    m_open.emplace_back(pass, now);
    return true;
}

void PassClock::passDone(uint32_t pass) {
    const double now = m_session.elapsedSeconds();
    for (const auto& [id, start] : m_open)
        if (id == pass) m_longest = std::max(m_longest, now - start);
    std::erase_if(m_open, [&](const auto& p) { return p.first == pass; });
    ++m_completed;
}

bool PassClock::abandon(uint32_t pass) const {
    return m_session.interrupted() || ((m_completed > 0 || pass > 0) && m_session.timeUp());
}

DispatchSizer::DispatchSizer(uint32_t initialUnits, uint32_t maxUnits, double targetSeconds)
    : m_units(std::clamp<uint32_t>(initialUnits, 1u, std::max(maxUnits, 1u))),
      m_max(std::max(maxUnits, 1u)),
      m_target(targetSeconds) {}

void DispatchSizer::record(uint64_t units, double seconds) {
    if (units == 0 || seconds <= 0.0) return;
    const double perUnit = seconds / double(units);
    // Move halfway (in log space) towards the size that meets the target, never more than 4x.
    const double ideal = m_target / perUnit;
    const double next = std::sqrt(double(m_units) * ideal);
    const double clamped = std::clamp(next, double(m_units) / 4.0, double(m_units) * 4.0);
    m_units = uint32_t(std::clamp(clamped, 1.0, double(m_max)));
}

double InFlightTimer::wait(vk::CommandBatch& batch, std::chrono::steady_clock::time_point submitted) {
    batch.wait();
    const auto now = std::chrono::steady_clock::now();
    const double seconds = batch.lastDeviceSeconds() > 0.0
                               ? batch.lastDeviceSeconds()
                               : std::chrono::duration<double>(now - std::max(submitted, m_lastDone)).count();
    m_lastDone = now;
    return seconds;
}

}  // namespace pmcr
