// Everything a method needs while it renders: the device, the scene on the device, the film,
// GPU timing, counters, the clock and stop conditions (time budget, Ctrl-C), and progress.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/communicator.h"
#include "core/progress.h"
#include "image/image.h"
#include "render/film.h"
#include "render/gpu_scene.h"
#include "render/settings.h"
#include "vk/gpu_timer.h"
#include "vk/context.h"
#include "vk/pipeline.h"

namespace pmcr {
namespace vk {
class CommandBatch;
}  // namespace vk

// The result of a render: the image, the diagnostic images the method produces (alpha maps,
// strategy images, sample counts...), sample counts and method-specific statistics.
struct RenderOutput {
    Image image;
    std::vector<std::pair<std::string, Image>> diagnostics;  // (suffix, image), e.g. ("samples", ...)
    uint64_t cameraSamples = 0;                             // path-traced camera samples taken
    double samplesPerPixel = 0.0;                           // cameraSamples / pixels
    nlohmann::json methodStats = nlohmann::json::object();
};

// The image so far at one point of a render, for convergence plots.
struct Snapshot {
    double seconds = 0.0;          // on the render clock
    double samplesPerPixel = 0.0;  // camera samples taken so far / pixels
    Image image;
};

class RenderSession {
public:
    // `comm`: the processes rendering this image together (core/communicator.h); the session
    // renders this process's share (render/distributed.h gives each rank its settings).
    RenderSession(vk::Context& context, const Scene& scene, const RenderSettings& settings,
                  int width, int height, Communicator& comm = localCommunicator());

    vk::Context& context() { return m_context; }
    const vk::PipelineLayout& layout() const { return m_context.layout(); }
    // The kernel `name`, specialized for the scene's features (GpuScene::features) and
    // `kernelOptions` (gpu::KERNEL_OPTION_* bits: the papers' baselines a method was asked for,
    // BaselineOptions::kernelOptions); the session warms it up when the clock starts
    // (startClock).
    const vk::Kernel& kernel(const std::string& name, uint32_t kernelOptions = 0);
    const GpuScene& scene() const { return *m_scene; }
    const RenderSettings& settings() const { return m_settings; }
    Communicator& comm() { return m_comm; }
    vk::GpuTimer& timer() { return *m_timer; }
    Film& film() { return *m_film; }
    // A small buffer for work-set bindings a kernel declares but the current mode never reads
    // (e.g. the request list of pt in tile mode): Vulkan requires every statically used
    // descriptor to be valid.
    const vk::Buffer& placeholder() const { return m_placeholder; }
    Counters& counters() { return m_counters; }
    Progress& progress() { return *m_progress; }
    int width() const { return m_width; }
    int height() const { return m_height; }

    // The render clock starts when the method starts rendering (after scene upload, BVH and
    // kernel creation); time spent taking snapshots is not on it. First it dispatches every
    // kernel taken through kernel() once with no work: lavapipe compiles a pipeline's machine
    // code at its first dispatch, not at its creation (3 s for pmc-hi, 11 s for pmc-er on a
    // cold shader cache), and that is not the method's rendering time.
    void startClock();
    double elapsedSeconds() const;
    // Wall time spent taking snapshots (taken off the render clock).
    double snapshotOverheadSeconds() const { return m_snapshotOverhead; }
    // Wall time spent building this render's pipelines and compiling them (the warm-up of
    // startClock): outside the clock, and what the on-disk pipeline cache saves.
    double pipelineSeconds() const;
    // Seconds of the clock with a submission executing on the device (vk::DeviceActivity).
    double deviceBusySeconds() const;
    // The host's own submissions that waited for batches in flight since the clock started
    // (vk::Context::queueDrains): on a device whose memory the host cannot map, a staging copy.
    uint64_t queueDrains() const;
    // Pre-passes (ERPT's mean-luminance pass, the Metropolis bootstraps) run on the clock and
    // count in --time; methods report their length here for the stats.
    void addPrepassSeconds(double seconds) { m_prepassSeconds += seconds; }
    double prepassSeconds() const { return m_prepassSeconds; }
    bool timeUp() const;
    // Interrupted by the user or out of time: stop at the next batch boundary.
    bool shouldStop() const;
    bool interrupted() const;
    // shouldStop() on any rank (core/communicator.h), for methods whose ranks adapt together
    // and so must end their iterations together; a collective: every rank calls it in turn.
    bool shouldStopTogether() { return m_comm.anyTrue(shouldStop()); }

    // Progress of a render counted in camera samples per pixel: the share of `budgetSpp` done
    // under --spp (or the method's default budget), of the time limit under --time alone.
    void updateSppProgress(uint64_t cameraSamples, double budgetSpp);

    // Seconds a dispatch should take: short on a CPU device so the machine stays responsive,
    // and well under any GPU watchdog.
    double targetDispatchSeconds() const;
    double targetBatchSeconds() const;
    // Under --time, for a method that keeps two batches in flight: with one in flight that the
    // device has just begun (about `inFlightSeconds` of work), whether to queue one more of
    // about `nextSeconds`: only if that ends the render nearer the limit than stopping after
    // the one in flight, and at most kBatchOvershootSeconds past it (issue 38: T + 0.5 for
    // the image written). Always true without --time.
    bool queueAnotherBatch(double inFlightSeconds, double nextSeconds) const;
    static constexpr double kBatchOvershootSeconds = 0.15;

    // Integrators call this at every batch boundary with the camera samples taken so far and a
    // function that resolves the image so far: when a snapshot is due (settings.snapshotSeconds
    // or settings.snapshotSpp passed), the image is resolved and stored. One call per batch:
    //   session.snapshotIfDue(samples, [&] { return resolveAverage(film.download(), w, h); });
    void snapshotIfDue(uint64_t cameraSamples, const std::function<Image()>& resolve);
    // The next scheduled snapshot's samples per pixel (infinity when none is left), for
    // integrators that can end a batch there.
    double nextSnapshotSpp() const;
    std::vector<Snapshot> takeSnapshots() { return std::move(m_snapshots); }

private:
    vk::Context& m_context;
    Communicator& m_comm;
    RenderSettings m_settings;
    int m_width;
    int m_height;
    std::unique_ptr<GpuScene> m_scene;
    std::unique_ptr<vk::GpuTimer> m_timer;
    std::unique_ptr<Film> m_film;
    std::unique_ptr<Progress> m_progress;
    vk::Buffer m_placeholder;
    std::vector<const vk::Kernel*> m_kernels;  // taken through kernel(), warmed up by startClock
    Counters m_counters;
    std::chrono::steady_clock::time_point m_start;
    std::vector<Snapshot> m_snapshots;
    size_t m_nextSnapshotTime = 0;
    size_t m_nextSnapshotSpp = 0;
    double m_snapshotOverhead = 0.0;
    double m_pipelineSecondsAtStart = 0.0;  // the context's pipeline seconds before this render
    double m_warmupSeconds = 0.0;
    double m_busyAtClockStart = 0.0;
    uint64_t m_drainsAtClockStart = 0;
    double m_prepassSeconds = 0.0;
};

// The seed passes of a method whose pass cannot be cut short (ERPT, PMC-ER, MLT, PSSMLT: a
// partial pass is dropped, since it would darken the image), kept within --time: a pass starts
// only when the clock says it will end in time, judged by the longest pass so far, and a pass
// that overruns anyway is abandoned. The first pass always runs to the end, so a render
// always has an image.
class PassClock {
public:
    explicit PassClock(const RenderSession& session) : m_session(session) {}
    // Before each pass: false when the render should stop (Ctrl-C, time up, or a pass as long
    // as the longest so far, completed or still open, would end past the time limit). The
    // first pass is refused only on Ctrl-C.
    // Passes may overlap (PMC-ER's lanes): each is named by its number.
    bool startPass(uint32_t pass = 0);
    // After a pass completed.
    void passDone(uint32_t pass = 0);
    // During a pass: stop it (and drop it) on Ctrl-C, or when it ran past the time limit and
    // it is not the first (an earlier pass completed, or will).
    bool abandon(uint32_t pass = 0) const;
    double longestPassSeconds() const { return m_longest; }

private:
    const RenderSession& m_session;
    std::vector<std::pair<uint32_t, double>> m_open;  // passes started, not done: their start
    double m_longest = 0.0;
    uint32_t m_completed = 0;
};

// Chooses how much work goes into one dispatch from the throughput measured so far, so that a
// dispatch takes about `targetSeconds` on any device.
class DispatchSizer {
public:
    DispatchSizer(uint32_t initialUnits, uint32_t maxUnits, double targetSeconds);
    uint32_t units() const { return m_units; }
    // `units` work units took `seconds` of wall time.
    void record(uint64_t units, double seconds);

private:
    uint32_t m_units;
    uint32_t m_max;
    double m_target;
};

// Waits for the batches a method keeps in flight, oldest first, and tells each one's time on
// the device: its timestamps' span, else the wall time from when it could start (submitted,
// and the batch before it done). What a DispatchSizer learns from.
class InFlightTimer {
public:
    double wait(vk::CommandBatch& batch, std::chrono::steady_clock::time_point submitted);

private:
    std::chrono::steady_clock::time_point m_lastDone = std::chrono::steady_clock::now();
};

}  // namespace pmcr
