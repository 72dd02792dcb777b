#include "methods/pt/pt_integrator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include "core/error.h"
#include "methods/pmc_hi/pmc_hi.h"
#include "vk/command_batch.h"
#include "vk/context.h"

namespace pmcr {

PathTracer::PathTracer(const RenderSettings& settings, Mode mode)
    : m_mode(mode), m_lightSamples(1), m_baseline(parseBaselineOptions(settings)) {
    if (mode == Mode::Direct) {
        int n = settings.optionInt("light-samples", 1);
        if (n < 1 || n > 1024) throw Error("--light-samples: expected 1..1024");
        m_lightSamples = uint32_t(n);
    }
    if (mode == Mode::PmcHi) m_hi = parsePmcHiOptions(settings);
}

uint32_t ptItemsPerInvocation(const vk::Context& context, uint32_t items, uint32_t pathsPerItem) {
    if (!context.isCpuDevice()) return 1;
    // Up to 32 paths each (measured on lavapipe, pt on cornell-spheres: 8 pixels 1.27x the
    // samples/s of 1, 32 another 1.08x), while every CPU thread still gets 8 workgroups of a
    // dispatch (lavapipe runs one thread per core). 32 paths also keep an invocation's loop
    // iterations (every traversal step counts) as far below lavapipe's budget of 65535 per
    // invocation (tests/gpu/test_loop_limits.cpp) as the 64 passes of one pixel a small
    // image's dispatch may hold.
    const uint32_t threads = std::max(1u, std::thread::hardware_concurrency());
    const uint32_t perThread = 8 * gpu::WORKGROUP_SIZE * threads;
    const uint32_t byPaths = 32 / std::max(1u, pathsPerItem);
    return std::clamp<uint32_t>(std::min(items / perThread, byPaths), 1, 32);
}

void bindTileWork(vk::DescriptorSet& work, const Film& film, const RenderSession& session) {
    work.bind(gpu::PT_BINDING_FILM, film.pixels());
    work.bind(gpu::PT_BINDING_COUNTERS, film.counters());
    work.bind(gpu::PT_BINDING_REQUESTS, session.placeholder());
    work.bind(gpu::PT_BINDING_RESULTS, session.placeholder());
}

std::string lightsKernelVariant(const GpuScene& scene, const std::string& path) {
    const bool otherLights = scene.info().envKind != gpu::ENV_NONE || scene.info().punctualCount > 0;
    return path + (otherLights ? "_all_lights" : "");
}

std::string pathTracingKernel(const GpuScene& scene, const std::string& name) {
    return lightsKernelVariant(scene, "methods/pt/" + name);
}

RenderOutput PathTracer::render(RenderSession& session) {
    const RenderSettings& settings = session.settings();
    const vk::Kernel& kernel =
        session.kernel(m_mode == Mode::Full     ? pathTracingKernel(session.scene(), "pt")
                       : m_mode == Mode::Direct ? pathTracingKernel(session.scene(), "direct")
                                                : pmcHiKernel(session.scene()),
                       m_baseline.kernelOptions());
    Film& film = session.film();
    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "pt work");
    bindTileWork(work, film, session);

    // PMC-HI: its parameters for this scene, and the per-pixel sums of the adapted alpha.
    gpu::PmcHiPush hiPush{};
    vk::Buffer alphaSums;
    if (m_mode == Mode::PmcHi) {
        hiPush.hi = pmcHiParamsForScene(m_hi, session.scene());
        hiPush.hi.flags |= gpu::PMC_HI_FLAG_RECORD_ALPHA;
        alphaSums = vk::Buffer(session.context(),
                               VkDeviceSize(film.pixelCount()) * gpu::PMC_HI_ALPHA_STRIDE * sizeof(float),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                               "pmc-hi alpha sums");
        alphaSums.fill(0);
        work.bind(gpu::PMC_HI_BINDING_ALPHA, alphaSums);
        work.bind(gpu::PMC_HI_BINDING_ALPHA_START, session.placeholder());
        work.bind(gpu::PMC_HI_BINDING_ALPHA_OUT, session.placeholder());
    }

    const uint32_t pixels = film.pixelCount();
    // Without a sample count, a time limit alone decides when to stop.
    const uint32_t spp = settings.spp > 0 ? settings.spp
                         : settings.timeLimit > 0.0 ? std::numeric_limits<uint32_t>::max()
                                                    : kDefaultSpp;
    // A dispatch is part of a pass, or whole passes when one pass is less work than the sizer
    // asks for (small images): each invocation then takes that many consecutive samples of its
    // pixel, still one writer per pixel per dispatch, so a 64x64 pass does not pay a dispatch's
    // fixed cost and tail on its own (measured: about 12% of the rays per second on lavapipe).
    constexpr uint32_t kMaxPassesPerDispatch = 64;
    DispatchSizer sizer(std::min<uint32_t>(pixels, 4096),
                        uint32_t(std::min<uint64_t>(uint64_t(pixels) * kMaxPassesPerDispatch,
                                                    std::numeric_limits<uint32_t>::max())),
                        session.targetDispatchSeconds());

    gpu::PtPush push{};
    push.source = gpu::PT_SOURCE_TILE;
    push.flags = gpu::PT_FLAG_DEPOSIT;
    push.samplesPerPixel = 1;
    push.seed = settings.seed;
    push.maxDepth = m_mode == Mode::Full ? settings.maxDepth : 1;
    push.rrDepth = settings.rrDepth;
    push.lightSamples = m_lightSamples;

    vk::CommandBatch batch(session.layout(), &session.timer());
    uint32_t pass = 0;
    uint32_t offset = 0;
    uint64_t samples = 0;
    session.startClock();
    while (pass < spp && !session.shouldStop()) {
        // Record dispatches until the batch holds about targetBatchSeconds of work.
        const auto batchStart = std::chrono::steady_clock::now();
        batch.fill(film.counters(), 0);
        batch.bind(session.scene().descriptorSet());
        batch.bind(work);
        const double dispatchesPerBatch =
            std::max(1.0, session.targetBatchSeconds() / session.targetDispatchSeconds());
        uint64_t batchSamples = 0;
        // The batch ends at the next scheduled snapshot's pass, so the snapshot is the image of
        // exactly that many passes even when a dispatch holds several.
        const double snapshotSpp = session.nextSnapshotSpp();
        const uint32_t batchEnd = snapshotSpp > double(pass) && snapshotSpp < double(spp)
                                      ? uint32_t(std::ceil(snapshotSpp))
                                      : spp;
        for (int d = 0; d < int(dispatchesPerBatch) && pass < batchEnd; ++d) {
            uint32_t count = std::min(sizer.units(), pixels - offset);
            uint32_t passes = 1;
            if (offset == 0 && sizer.units() >= 2 * pixels) {
                passes = std::min(sizer.units() / pixels, batchEnd - pass);
                count = pixels;
            }
            push.pixelOffset = offset;
            push.invocationCount = count;
            push.samplesPerPixel = passes;
            push.sampleBase = pass;
            if (m_mode == Mode::PmcHi) {
                hiPush.pt = push;
                batch.dispatch(kernel, hiPush, count);
            } else {
                // pt.comp's paths in turn (camera_sample_kernel.glsl): on a CPU device each
                // invocation takes several pixels so that its SIMD lanes stay busy. The image
                // is the same bit for bit whatever the count.
                const uint32_t perInvocation =
                    m_mode == Mode::Full
                        ? ptItemsPerInvocation(session.context(), count, passes)
                        : 1;
                push.itemsPerInvocation = perInvocation;
                batch.dispatch(kernel, push, (count + perInvocation - 1) / perInvocation);
            }
            batchSamples += uint64_t(count) * passes;
            offset += count;
            if (offset == pixels) {
                offset = 0;
                pass += passes;
            }
        }
        batch.submitAndWait();
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - batchStart).count();
        sizer.record(batchSamples / std::max<uint32_t>(batch.dispatchCount(), 1), seconds /
                     std::max<uint32_t>(batch.dispatchCount(), 1));
        film.addCounters(session.counters());
        samples += batchSamples;
        session.updateSppProgress(samples, double(spp));
        session.snapshotIfDue(samples, [&] {
            return resolveAverage(film.download(), film.width(), film.height());
        });
    }
    session.progress().finish();

    RenderOutput out;
    auto pixelsData = film.download();
    out.image = resolveAverage(pixelsData, film.width(), film.height());
    out.cameraSamples = samples;
    out.samplesPerPixel = double(samples) / double(pixels);
    out.methodStats["passes_completed"] = pass;
    if (m_mode == Mode::Direct) out.methodStats["light_samples"] = m_lightSamples;
    if (m_mode == Mode::PmcHi)
        addPmcHiOutputs(out, hiPush.hi, session.scene(),
                        alphaSums.download<float>(size_t(pixels) * gpu::PMC_HI_ALPHA_STRIDE),
                        film.width(), film.height());
    return out;
}

MethodInfo ptMethod() {
    return {"pt", "path tracing with next-event estimation and MIS (the baseline)", true,
        {pixelSamplerOption(), misOption()},
        [](const RenderSettings& s) { return std::make_unique<PathTracer>(s, PathTracer::Mode::Full); },
        ""};
}

MethodInfo directMethod() {
    return {"direct", "direct lighting only, MIS of light and BSDF sampling (the PMC-HI baseline)", true,
        {{"light-samples", "1", "light samples (and as many BSDF samples) per camera sample"},
         pixelSamplerOption(), misOption()},
        [](const RenderSettings& s) { return std::make_unique<PathTracer>(s, PathTracer::Mode::Direct); },
        ""};
}

MethodInfo pmcHiMethod() {
    std::vector<MethodOption> options = pmcHiMethodOptions();
    options.push_back(pixelSamplerOption());  // no --mis: PMC-HI weighs by its mixture, not MIS
    return {"pmc-hi", "PMC-HI adaptive direct lighting (mixture of BSDF, light and cone sampling)", true,
        options,
        [](const RenderSettings& s) { return std::make_unique<PathTracer>(s, PathTracer::Mode::PmcHi); },
        ""};
}

}  // namespace pmcr
