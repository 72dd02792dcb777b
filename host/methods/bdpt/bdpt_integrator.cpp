#include "methods/bdpt/bdpt_integrator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"
#include "methods/energy_redistribution/splat_film.h"
#include "methods/pt/pt_integrator.h"
#include "vk/command_batch.h"
#include "vk/context.h"

namespace pmcr {

BdptIntegrator::BdptIntegrator(const RenderSettings& settings)
    : m_baseline(parseBaselineOptions(settings)),
      m_strategyImages(settings.optionBool("strategy-images", false)) {}

namespace {

// Camera samples whose subpaths one dispatch holds: the vertex buffers take about 64 MiB on a
// CPU device (lavapipe's dispatches stay short anyway) and 1 GiB on a GPU, where a dispatch
// needs hundreds of thousands of samples to fill the device.
uint32_t samplesPerDispatchLimit(const vk::Context& context, const gpu::BdptPush& push, uint32_t pixels) {
    const uint64_t bytesPerSample =
        uint64_t(push.cameraStride + push.lightStride) * sizeof(gpu::BdptVertex) + sizeof(gpu::uvec2);
    const uint64_t budget = context.isCpuDevice() ? (64ull << 20) : (1ull << 30);
    return uint32_t(std::clamp<uint64_t>(budget / bytesPerSample, 256, pixels));
}

// The name of strategy (s, t) in the diagnostics: "s1-t3".
std::string strategyName(uint32_t s, uint32_t t) {
    return "s" + std::to_string(s) + "-t" + std::to_string(t);
}

}  // namespace

RenderOutput BdptIntegrator::render(RenderSession& session) {
    const RenderSettings& settings = session.settings();
    const uint32_t options = m_baseline.kernelOptions();
    const vk::Kernel& subpaths =
        session.kernel(lightsKernelVariant(session.scene(), "methods/bdpt/bdpt_subpaths"), options);
    const vk::Kernel& connect =
        session.kernel(lightsKernelVariant(session.scene(), "methods/bdpt/bdpt_connect"), options);
    Film& film = session.film();
    const uint32_t pixels = film.pixelCount();

    gpu::BdptPush push{};
    push.seed = settings.seed;
    push.maxDepth = settings.maxDepth;
    push.rrDepth = settings.rrDepth;
    push.cameraStride = settings.maxDepth + 2;
    push.lightStride = settings.maxDepth + 1;
    push.flags = m_strategyImages ? gpu::BDPT_FLAG_STRATEGY_IMAGES : 0u;

    const uint32_t capacity = samplesPerDispatchLimit(session.context(), push, pixels);
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    vk::Buffer cameraVertices(session.context(), VkDeviceSize(capacity) * push.cameraStride * sizeof(gpu::BdptVertex),
                              usage, "bdpt camera vertices");
    vk::Buffer lightVertices(session.context(), VkDeviceSize(capacity) * push.lightStride * sizeof(gpu::BdptVertex),
                             usage, "bdpt light vertices");
    vk::Buffer counts(session.context(), VkDeviceSize(capacity) * sizeof(gpu::uvec2), usage, "bdpt vertex counts");
    SplatFilm splats(session.context(), film.width(), film.height());
    const size_t strategyFloats = size_t(pixels) * gpu::BDPT_STRATEGY_COUNT * 6;
    vk::Buffer strategies(session.context(), m_strategyImages ? strategyFloats * sizeof(float) : 16, usage,
                          "bdpt strategy images");
    strategies.fill(0);
    vk::Buffer queue(session.context(), gpu::BDPT_QUEUE_SLOTS * sizeof(uint32_t), usage, "bdpt queue");

    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "bdpt work");
    work.bind(gpu::BDPT_BINDING_FILM, film.pixels());
    work.bind(gpu::BDPT_BINDING_COUNTERS, film.counters());
    work.bind(gpu::BDPT_BINDING_CAMERA_VERTICES, cameraVertices);
    work.bind(gpu::BDPT_BINDING_LIGHT_VERTICES, lightVertices);
    work.bind(gpu::BDPT_BINDING_COUNTS, counts);
    work.bind(gpu::BDPT_BINDING_STRATEGIES, strategies);
    work.bind(gpu::BDPT_BINDING_SPLAT, splats.pixels());
    work.bind(gpu::BDPT_BINDING_QUEUE, queue);
    // Walks and connections in turn on a CPU device (bdpt_connect_kernel.glsl): up to 64
    // samples an invocation, from a queue (two slots per dispatch pair).
    push.itemsPerInvocation = session.context().isCpuDevice() ? 64 : 1;

    const uint32_t spp = settings.spp > 0 ? settings.spp
                         : settings.timeLimit > 0.0 ? std::numeric_limits<uint32_t>::max()
                                                    : kDefaultSpp;
    DispatchSizer sizer(std::min<uint32_t>(capacity, 4096), capacity, session.targetDispatchSeconds());

    // The image so far: the camera-side strategies' per-pixel means plus the light tracing
    // splats over the light subpaths traced per pixel (Veach 1997 sec. 10.3.4).
    uint64_t samples = 0;
    auto resolve = [&] {
        Image image = resolveAverage(film.download(), film.width(), film.height());
        if (samples == 0) return image;
        const Image light = splats.resolveTotal(double(pixels) / double(samples));
        for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] += light.rgb[i];
        return image;
    };

    vk::CommandBatch batch(session.layout(), &session.timer());
    uint32_t pass = 0;
    uint32_t offset = 0;
    session.startClock();
    while (pass < spp && !session.shouldStop()) {
        const auto batchStart = std::chrono::steady_clock::now();
        batch.fill(film.counters(), 0);
        batch.fill(queue, 0);
        batch.bind(session.scene().descriptorSet());
        batch.bind(work);
        const double dispatchesPerBatch = std::min<double>(
            gpu::BDPT_QUEUE_SLOTS / 2, std::max(1.0, session.targetBatchSeconds() / session.targetDispatchSeconds()));
        const double snapshotSpp = session.nextSnapshotSpp();
        const uint32_t batchEnd = snapshotSpp > double(pass) && snapshotSpp < double(spp)
                                      ? uint32_t(std::ceil(snapshotSpp))
                                      : spp;
        uint64_t batchSamples = 0;
        uint32_t dispatches = 0;
        for (int d = 0; d < int(dispatchesPerBatch) && pass < batchEnd; ++d) {
            const uint32_t count = std::min(sizer.units(), pixels - offset);
            push.pixelOffset = offset;
            push.count = count;
            push.sampleIndex = pass;
            push.queueSlot = 2 * dispatches;
            batch.dispatch(subpaths, push, count);
            push.queueSlot = 2 * dispatches + 1;
            batch.dispatch(connect, push, count);
            ++dispatches;
            batchSamples += count;
            offset += count;
            if (offset == pixels) {
                offset = 0;
                ++pass;
            }
        }
        batch.submitAndWait();
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - batchStart).count();
        sizer.record(batchSamples / std::max(dispatches, 1u), seconds / std::max(dispatches, 1u));
        film.addCounters(session.counters());
        samples += batchSamples;
        session.updateSppProgress(samples, double(spp));
        session.snapshotIfDue(samples, resolve);
    }
    session.progress().finish();

    RenderOutput out;
    out.image = resolve();
    out.cameraSamples = samples;
    out.samplesPerPixel = double(samples) / double(pixels);
    out.methodStats["passes_completed"] = pass;
    out.methodStats["light_subpaths"] = samples;
    out.methodStats["samples_per_dispatch_limit"] = capacity;
    out.methodStats["mis"] = m_baseline.mis == MisHeuristic::Balance ? "balance" : "power";
    if (m_strategyImages && samples > 0) {
        // Each strategy's image over the camera samples (and light subpaths) per pixel.
        const auto sums = strategies.download<float>(strategyFloats);
        const double scale = double(pixels) / double(samples);
        for (uint32_t depth = 0; depth <= gpu::BDPT_STRATEGY_MAX_DEPTH; ++depth) {
            for (uint32_t s = 0; s <= depth + 1; ++s) {
                const uint32_t t = depth + 2 - s;
                if (s == 1 && t == 1) continue;
                const uint32_t index = depth * (depth + 3) / 2 + s;
                Image weighted(film.width(), film.height());
                Image unweighted(film.width(), film.height());
                for (uint32_t p = 0; p < pixels; ++p) {
                    const size_t base = (size_t(p) * gpu::BDPT_STRATEGY_COUNT + index) * 6;
                    for (int c = 0; c < 3; ++c) {
                        weighted.rgb[3 * p + c] = float(sums[base + c] * scale);
                        unweighted.rgb[3 * p + c] = float(sums[base + 3 + c] * scale);
                    }
                }
                out.diagnostics.emplace_back("strategy-" + strategyName(s, t), std::move(weighted));
                out.diagnostics.emplace_back("strategy-" + strategyName(s, t) + "-unweighted",
                                             std::move(unweighted));
            }
        }
    }
    return out;
}

MethodInfo bdptMethod() {
    return {"bdpt", "bidirectional path tracing: every connection strategy of a camera and a light subpath, MIS-weighted",
            true,
            {misOption(), pixelSamplerOption(),
             {"strategy-images", "off",
              "on: write each (s, t) strategy's image, MIS-weighted and unweighted, for paths of up to 4 bounces "
              "(SCENE.strategy-s1-t3.exr, ...)"}},
            [](const RenderSettings& s) { return std::make_unique<BdptIntegrator>(s); },
            ""};
}

}  // namespace pmcr
