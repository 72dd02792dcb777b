#include "methods/pm/pm_integrator.h"

#include <algorithm>
#include <chrono>
#include <limits>

#include "core/error.h"
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
    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "pm work");
    bindTileWork(work, film, session);
    PhotonMap map(session, m_photons, double(m_sppPerPass));

    const uint32_t pixels = film.pixelCount();
    const uint32_t spp = settings.spp > 0 ? settings.spp
                         : settings.timeLimit > 0.0 ? std::numeric_limits<uint32_t>::max()
                                                    : kDefaultSpp;
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

    vk::CommandBatch batch(session.layout(), &session.timer());
    uint32_t sample = 0;  // camera samples per pixel completed
    uint32_t offset = 0;  // next pixel of the current sample
    uint64_t samples = 0;
    session.startClock();
    while (sample < spp && !session.shouldStop()) {
        if (offset == 0 && sample % m_sppPerPass == 0) map.preparePass(sample / m_sppPerPass, work);
        // One batch: dispatches over the pixels of this camera sample, about targetBatchSeconds.
        const auto batchStart = std::chrono::steady_clock::now();
        batch.fill(film.counters(), 0);
        batch.bind(session.scene().descriptorSet());
        batch.bind(work);
        const double dispatchesPerBatch =
            std::max(1.0, session.targetBatchSeconds() / session.targetDispatchSeconds());
        uint64_t batchSamples = 0;
        for (int d = 0; d < int(dispatchesPerBatch) && offset < pixels; ++d) {
            const uint32_t count = std::min(sizer.units(), pixels - offset);
            push.pixelOffset = offset;
            push.invocationCount = count;
            push.sampleBase = sample;
            batch.dispatch(kernel, push, count);
            batchSamples += count;
            offset += count;
        }
        batch.submitAndWait();
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - batchStart).count();
        const uint32_t dispatches = std::max<uint32_t>(batch.dispatchCount(), 1);
        sizer.record(batchSamples / dispatches, seconds / dispatches);
        film.addCounters(session.counters());
        samples += batchSamples;
        if (offset == pixels) {
            offset = 0;
            sample += 1;
        }
        session.updateSppProgress(samples, double(spp));
        session.snapshotIfDue(samples, [&] {
            return resolveAverage(film.download(), film.width(), film.height());
        });
    }
    session.progress().finish();

    RenderOutput out;
    out.image = resolveAverage(film.download(), film.width(), film.height());
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
