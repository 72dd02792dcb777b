#include "methods/pm/pm_integrator.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <limits>
#include <memory>
#include <string>

#include "core/error.h"
#include "render/film.h"
#include "methods/pt/pt_integrator.h"
#include "vk/command_batch.h"

namespace pmcr {

std::string photonGatherKernel(const GpuScene& scene, bool pmcHi) {
    return lightsKernelVariant(scene, pmcHi ? "methods/pm/pm_gather_hi" : "methods/pm/pm_gather");
}

PhotonMapper::PhotonMapper(const RenderSettings& settings)
    : m_photons(PhotonMapOptions::fromSettings(settings)) {
    const int n = settings.optionInt("light-samples", 1);
    if (n < 1 || n > 64) throw Error("--light-samples: expected 1..64");
    m_lightSamples = uint32_t(n);
    const int perPass = settings.optionInt("spp-per-pass", 1);
    if (perPass < 1 || perPass > 4096) throw Error("--spp-per-pass: expected 1..4096");
    m_sppPerPass = uint32_t(perPass);
}

RenderOutput PhotonMapper::render(RenderSession& session) {
    const RenderSettings& settings = session.settings();
    const vk::Kernel& kernel = session.kernel(photonGatherKernel(session.scene(), false));
    Film& film = session.film();
    PhotonMap map(session, m_photons, double(m_sppPerPass));

    const uint32_t pixels = film.pixelCount();
    const uint32_t spp = settings.spp > 0 ? settings.spp
                         : settings.timeLimit > 0.0 ? std::numeric_limits<uint32_t>::max()
                                                    : kDefaultSpp;
    // The photon passes the camera samples need (unbounded under --time alone).
    const uint32_t passes = spp == std::numeric_limits<uint32_t>::max()
                                ? std::numeric_limits<uint32_t>::max()
                                : (spp + m_sppPerPass - 1) / m_sppPerPass;
    DispatchSizer sizer(std::min<uint32_t>(pixels, 4096), pixels, session.targetDispatchSeconds());
    gpu::PtPush push{};
    push.source = gpu::PT_SOURCE_TILE;
    push.flags = gpu::PT_FLAG_DEPOSIT;
    push.samplesPerPixel = 1;
    push.seed = settings.seed;
    push.maxDepth = settings.maxDepth;
    push.rrDepth = settings.rrDepth;
    push.lightSamples = m_lightSamples;
    push.itemsPerInvocation = 1;

    // Two gather batches in flight (issue 38), each with its own counters and work set (bound
    // to its pass's photon map): while the device gathers one, the host records the next.
    // Batches run in submission order (each begins with a barrier on the ones before), so the
    // film's sums are the same as one batch at a time.
    struct GatherSlot {
        vk::Buffer counters;
        std::unique_ptr<vk::DescriptorSet> work;
        std::unique_ptr<vk::CommandBatch> batch;
        uint64_t samples = 0;
        uint32_t dispatches = 0;
        std::chrono::steady_clock::time_point submitted;
        bool pending = false;
    };
    std::array<GatherSlot, 2> slots;
    for (size_t i = 0; i < slots.size(); ++i) {
        GatherSlot& slot = slots[i];
        const std::string tag = std::to_string(i);
        slot.counters = Film::makeCounters(session.context(), "pm counters " + tag);
        slot.work = std::make_unique<vk::DescriptorSet>(session.layout(), vk::DescriptorSet::Kind::Work, "pm work " + tag);
        bindTileWork(*slot.work, film, session);
        slot.work->bind(gpu::PT_BINDING_COUNTERS, slot.counters);
        slot.batch = std::make_unique<vk::CommandBatch>(session.layout(), &session.timer());
    }

    uint32_t sample = 0;  // camera samples per pixel issued
    uint32_t offset = 0;  // next pixel of the current sample
    uint64_t samples = 0;  // camera samples gathered (their batches complete)
    const bool timed = settings.timeLimit > 0.0;
    uint64_t passSamplesLeft = 0;  // of the current pass, not yet issued
    double gatherSeconds = 0.0;    // the device's, over the samples gathered
    InFlightTimer inFlight;
    // A completed batch: its counters and samples join the totals, the sizer learns its time
    // on the device.
    auto finishBatch = [&](GatherSlot& slot) {
        if (!slot.pending) return;
        const double seconds = inFlight.wait(*slot.batch, slot.submitted);
        slot.pending = false;
        sizer.record(slot.samples / slot.dispatches, seconds / slot.dispatches);
        gatherSeconds += seconds;
        Film::addCounters(slot.counters, session.counters());
        samples += slot.samples;
        session.updateSppProgress(samples, double(spp));
    };
    // The film once every batch in flight is in (oldest first).
    auto resolve = [&](GatherSlot& older, GatherSlot& newer) {
        finishBatch(older);
        finishBatch(newer);
        return resolveAverage(film.download(), film.width(), film.height());
    };

    session.startClock();
    for (size_t turn = 0; sample < spp && !session.shouldStop(); ++turn) {
        GatherSlot& slot = slots[turn % 2];
        GatherSlot& other = slots[(turn + 1) % 2];
        finishBatch(slot);  // (the other, newer batch goes on running)
        // Under --time, another batch only if it ends the render nearer the limit (the one in
        // flight, unless finished, is taken as just begun; both take about as long per sample
        // as the batches so far). Two in flight at the limit had `--time 2` write at 2.58 s on
        // lavapipe.
        if (timed && samples > 0) {
            const double perSample = gatherSeconds / double(samples);
            const bool running = other.pending && !other.batch->finished();
            const double next = double(running ? other.samples : slot.samples) * perSample;
            if (!session.queueAnotherBatch(running ? double(other.samples) * perSample : 0.0, next)) break;
        }
        session.snapshotIfDue(samples, [&] { return resolve(slot, other); });
        // A new photon pass: its map was shot and sorted while the passes before it were
        // gathered; the next one is shot now, ahead of this pass's gathers. (No batch in
        // flight reads pass - 2's map: the one in flight is of pass - 1 at the oldest.)
        const uint32_t pass = sample / m_sppPerPass;
        const bool passStart = offset == 0 && sample % m_sppPerPass == 0;
        if (passStart) {
            map.preparePass(pass, pass + 1 >= passes ? PhotonMap::Next::No
                                  : timed             ? PhotonMap::Next::IfLikelyGathered
                                                      : PhotonMap::Next::Yes);
            passSamplesLeft = uint64_t(std::min(m_sppPerPass, spp - sample)) * pixels;
        }
        // Under --time, the next pass is shot once this one's gathers look like ending before
        // the clock does (from the device's seconds per sample so far): a pass shot and never
        // gathered would cost the device its shoot and add nothing to the image.
        if (timed && pass + 1 < passes && !map.shotAhead(pass + 1) && samples > 0 &&
            session.elapsedSeconds() + double(passSamplesLeft) * gatherSeconds / double(samples) <
                settings.timeLimit)
            map.shootAhead(pass + 1);
        map.bindPass(pass, *slot.work);
        // One batch: dispatches over the pixels of this camera sample, about targetBatchSeconds.
        vk::CommandBatch& batch = *slot.batch;
        batch.fill(slot.counters, 0);
        batch.bind(session.scene().descriptorSet());
        batch.bind(*slot.work);
        const double dispatchesPerBatch =
            std::max(1.0, session.targetBatchSeconds() / session.targetDispatchSeconds());
        slot.samples = 0;
        for (int d = 0; d < int(dispatchesPerBatch) && offset < pixels; ++d) {
            const uint32_t count = std::min(sizer.units(), pixels - offset);
            push.pixelOffset = offset;
            push.invocationCount = count;
            push.sampleBase = sample;
            batch.dispatch(kernel, push, count);
            slot.samples += count;
            offset += count;
        }
        passSamplesLeft -= slot.samples;
        slot.dispatches = std::max<uint32_t>(batch.dispatchCount(), 1);
        slot.submitted = std::chrono::steady_clock::now();
        batch.submit();
        slot.pending = true;
        // The next pass's photons, queued ahead of this batch, are sorted while it runs.
        map.buildNextInBackground();
        if (offset == pixels) {
            offset = 0;
            sample += 1;
        }
    }
    // Stopped or done: the batches in flight, oldest first, join the image.
    const bool firstIsOlder = !slots[1].pending || (slots[0].pending && slots[0].submitted <= slots[1].submitted);
    RenderOutput out;
    out.image = firstIsOlder ? resolve(slots[0], slots[1]) : resolve(slots[1], slots[0]);
    session.progress().finish();
    out.cameraSamples = samples;
    out.samplesPerPixel = double(samples) / double(pixels);
    out.methodStats = map.stats();
    out.methodStats["light_samples"] = m_lightSamples;
    out.methodStats["spp_per_pass"] = m_sppPerPass;
    return out;
}

MethodInfo pmMethod() {
    std::vector<MethodOption> options = PhotonMapOptions::methodOptions();
    options.push_back({"spp-per-pass", "1", "camera samples per pixel per photon pass"});
    options.push_back({"light-samples", "1", "direct lighting at the gather point: light samples (and as many BSDF samples)"});
    return {"pm",
            "photon mapping with a final gather [BIASED]: consistent with --progressive on (the "
            "default), biased at a fixed radius",
            false, options,
            [](const RenderSettings& s) { return std::make_unique<PhotonMapper>(s); }, ""};
}

}  // namespace pmcr
