#include "methods/mlt/mlt_integrator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "methods/energy_redistribution/redistribution.h"
#include "methods/energy_redistribution/splat_film.h"
#include "methods/metropolis/bootstrap.h"
#include "methods/pt/pt_integrator.h"
#include "render/film.h"
#include "vk/command_batch.h"
#include "vk/context.h"

namespace pmcr {

namespace {

constexpr uint32_t kBootstrapChunk = 16384;  // bootstrap samples per dispatch (scratch chain slots)

// A CPU device: pixels / 16 chains (1024..65536). A GPU needs far more threads at work (issue
// 38: 4096 chains kept an H200 14% busy at 256x256): one chain per pixel, up to 2^18. A
// function of the image size and the device only, so a seed still gives its image.
uint32_t defaultChains(uint32_t pixels, bool cpuDevice) {
    return cpuDevice ? std::clamp<uint32_t>(pixels / 16, 1024, 65536) : std::clamp<uint32_t>(pixels, 1024, 1u << 18);
}

}  // namespace

MltOptions MltOptions::fromSettings(const RenderSettings& s) {
    MltOptions o;
    const int bootstrap = s.optionInt("bootstrap", int(o.bootstrapSpp));
    if (bootstrap < 1 || bootstrap > 1024) throw Error("--bootstrap: expected 1..1024 samples per pixel");
    o.bootstrapSpp = uint32_t(bootstrap);
    const int chains = s.optionInt("chains", 0);
    if (chains < 0 || chains > (1 << 20)) throw Error("--chains: expected 1..1048576 (0: from the image size and the device)");
    o.chains = uint32_t(chains);
    o.largeStep = float(s.optionDouble("large-step", o.largeStep));
    if (!(o.largeStep > 0.0f && o.largeStep <= 1.0f))
        throw Error("--large-step: expected a probability in (0, 1] (0 would not be ergodic)");
    o.perturbation = PerturbationOptions::fromSettings(s);
    const int steps = s.optionInt("steps-per-dispatch", int(o.stepsPerDispatch));
    if (steps < 1 || steps > 64) throw Error("--steps-per-dispatch: expected 1..64");
    o.stepsPerDispatch = uint32_t(steps);
    const int together = s.optionInt("passes-per-batch", 0);
    if (together < 0 || together > 1024) throw Error("--passes-per-batch: expected 0..1024 (0 = from the device)");
    o.passesPerBatch = uint32_t(together);
    const std::string direct = s.optionString("direct", "separate");
    if (direct != "separate" && direct != "chains")
        throw Error("--direct: expected separate or chains, got '" + direct + "'");
    o.separateDirect = direct == "separate";
    return o;
}

Mlt::Mlt(const RenderSettings& settings) : m_options(MltOptions::fromSettings(settings)) {}

RenderOutput Mlt::render(RenderSession& session) {
    const RenderSettings& settings = session.settings();
    vk::Context& context = session.context();
    const MltOptions& o = m_options;
    const uint32_t pixels = uint32_t(session.width()) * uint32_t(session.height());
    const uint32_t passes = settings.spp > 0 ? settings.spp
                            : settings.timeLimit > 0.0 ? std::numeric_limits<uint32_t>::max()
                                                       : kDefaultSpp;
    const uint32_t chainCount = o.chains > 0 ? o.chains : defaultChains(pixels, context.isCpuDevice());
    // Mutations per chain per pass: about one mutation per pixel in all.
    const uint32_t stepsPerPass = std::max<uint32_t>(1, uint32_t(std::lround(double(pixels) / chainCount)));
    // Passes run together (issue 38): on a GPU a pass of one step per chain lasts about a
    // millisecond, and the device would wait for the host between passes. The chains carry
    // their random numbers between submissions and the splat film sums integer quanta, so the
    // image is the same bits for any count (MltTest.PassesRunTogetherSameImage).
    const uint64_t stepsEachPass = uint64_t(chainCount) * stepsPerPass;
    const uint32_t together =
        o.passesPerBatch > 0 ? o.passesPerBatch
        : context.isCpuDevice() ? 1u
                                : uint32_t(std::clamp<uint64_t>(((uint64_t(1) << 20) + stepsEachPass - 1) / stepsEachPass, 1, 64));
    const uint64_t bootstrapSamples = uint64_t(o.bootstrapSpp) * pixels;
    if (bootstrapSamples > (uint64_t(1) << 28)) throw Error("mlt: --bootstrap too large for this image (2^28 samples at most)");

    auto kernel = [&](const std::string& path) -> const vk::Kernel& {
        return session.kernel(lightsKernelVariant(session.scene(), path));
    };
    const vk::Kernel& seedKernel = kernel("methods/mlt/mlt_seed");
    const vk::Kernel& chainKernel = kernel("methods/mlt/mlt_chains");
    const vk::Kernel& directKernel = session.kernel(pathTracingKernel(session.scene(), "pt"));
    session.startClock();

    Film& film = session.film();
    SplatFilm splat(context, session.width(), session.height());
    const uint32_t slots = std::max(chainCount, kBootstrapChunk);
    vk::Buffer chains(context, chainCount * sizeof(gpu::ChainState), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "mlt chains");
    vk::Buffer chainVertices(context, VkDeviceSize(slots) * 2 * gpu::CHAIN_MAX_VERTICES * sizeof(gpu::ChainVertex),
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "mlt chain vertices");
    vk::Buffer weights(context, bootstrapSamples * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                       "mlt bootstrap weights", vk::MemoryUsage::Readback);
    vk::Buffer starts(context, chainCount * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "mlt chain starts");
    vk::Buffer pixelStats(context, pixels * sizeof(gpu::PixelChainStats), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "mlt pixel stats");
    vk::Buffer accepted(context, pixels * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "mlt accepted");
    pixelStats.fill(0);
    accepted.fill(0);

    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "mlt");
    work.bind(gpu::ERPT_BINDING_CHAINS, chains);
    work.bind(gpu::ERPT_BINDING_CHAIN_VERTICES, chainVertices);
    work.bind(gpu::ERPT_BINDING_SPLAT, splat.pixels());
    work.bind(gpu::ERPT_BINDING_COUNTERS, film.counters());
    work.bind(gpu::ERPT_BINDING_PIXEL_STATS, pixelStats);
    work.bind(gpu::MLT_BINDING_WEIGHTS, weights);
    work.bind(gpu::MLT_BINDING_STARTS, starts);
    work.bind(gpu::MLT_BINDING_ACCEPTED, accepted);
    RedistributionBatch batches(session);
    vk::CommandBatch& batch = batches.batch();
    work.bind(gpu::ERPT_BINDING_ENERGY, batches.energy());
    // --direct separate: path tracing at depth 1 into the session's film.
    film.clear();
    vk::DescriptorSet directWork(session.layout(), vk::DescriptorSet::Kind::Work, "mlt direct");
    bindTileWork(directWork, film, session);
    gpu::PtPush directPush{};
    directPush.source = gpu::PT_SOURCE_TILE;
    directPush.flags = gpu::PT_FLAG_DEPOSIT;
    directPush.samplesPerPixel = 1;
    directPush.seed = settings.seed ^ 0x6d6c7444u;
    directPush.maxDepth = 1;
    directPush.rrDepth = settings.rrDepth;
    directPush.pixelOffset = 0;
    directPush.invocationCount = pixels;
    directPush.itemsPerInvocation = ptItemsPerInvocation(context, pixels);
    uint32_t directPasses = 0;
    gpu::MltPush push{};
    push.seed = settings.seed;
    push.maxDepth = std::min(settings.maxDepth, gpu::PATH_MAX_VERTICES - 1);
    push.mutationMode = o.perturbation.mutationMode;
    push.largeStep = o.largeStep;
    push.lensRadius = o.perturbation.lensRadius;
    push.causticThetaMin = o.perturbation.causticThetaMin;
    push.causticThetaMax = o.perturbation.causticThetaMax;
    push.causticProbability = o.perturbation.causticProbability;
    push.minVertices = o.separateDirect ? 3 : 1;

    // The bootstrap: weights W_i = F / p of independent samples.
    const double bootstrapStart = session.elapsedSeconds();
    for (uint64_t first = 0; first < bootstrapSamples && !session.interrupted(); first += kBootstrapChunk) {
        batches.begin();
        batch.bind(work);
        push.flags = 0;
        push.chainBase = uint32_t(first);
        push.chainCount = uint32_t(std::min<uint64_t>(kBootstrapChunk, bootstrapSamples - first));
        batch.dispatch(seedKernel, push, push.chainCount);
        batches.submit();
    }
    const uint64_t bootstrapRays = session.counters().values[gpu::COUNTER_RAYS];
    MetropolisStart start;
    if (!session.interrupted())
        start = chooseChainStarts(weights.download<float>(bootstrapSamples), chainCount,
                                  (uint64_t(settings.seed) << 32) ^ 0x6d6c74ULL);
    session.addPrepassSeconds(session.elapsedSeconds() - bootstrapStart);
    // e_d: each pass's chainCount * stepsPerPass deposits of e_d sum to b_hat in expectation.
    const double depositEnergy = start.normalization / (double(chainCount) * stepsPerPass);

    // Without any path for the chains (a scene lit directly only, with --direct separate), the
    // passes are the direct ones alone.
    const bool chainsRun = !start.samples.empty() && std::isfinite(depositEnergy) && depositEnergy > 0.0;
    // The image: the chains' passes, plus the direct passes' average.
    auto resolve = [&]() {
        Image image = splat.resolve(chainsRun ? float(depositEnergy) : 0.0f);
        if (directPasses > 0) {
            const Image direct = resolveAverage(film.download(), session.width(), session.height());
            for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] += direct.rgb[i];
        }
        return image;
    };

    uint64_t chainSteps = 0;
    if (chainsRun || (o.separateDirect && !session.interrupted())) {
        if (chainsRun) starts.upload(start.samples.data(), start.samples.size() * sizeof(uint32_t));
        batches.begin();
        batch.bind(work);
        push.flags = gpu::MLT_FLAG_START;
        push.chainBase = 0;
        push.chainCount = chainCount;
        if (chainsRun) batch.dispatch(seedKernel, push, chainCount);
        batches.submit();

        push.flags = 0;
        DispatchSizer sizer(1024, chainCount, session.targetDispatchSeconds());
        PassClock clock(session);
        for (uint32_t pass = 0; pass < passes && clock.startPass();) {
            const uint32_t count = std::min(together, passes - pass);
            bool interrupted = false;
            if (count == 1) {
                if (o.separateDirect) {
                    batches.begin();
                    batch.bind(directWork);
                    directPush.sampleBase = pass;
                    batch.dispatch(directKernel, directPush,
                                   (pixels + directPush.itemsPerInvocation - 1) / directPush.itemsPerInvocation);
                    batches.submit();
                }
                for (uint32_t done = 0; chainsRun && done < stepsPerPass && !interrupted;) {
                    push.steps = std::min(o.stepsPerDispatch, stepsPerPass - done);
                    for (uint32_t c = 0; c < chainCount;) {
                        batches.begin();
                        batch.bind(work);
                        push.chainBase = c;
                        push.chainCount = std::min(sizer.units(), chainCount - c);
                        const auto t0 = std::chrono::steady_clock::now();
                        batch.dispatch(chainKernel, push, push.chainCount);
                        batches.submit();
                        chainSteps += uint64_t(push.chainCount) * push.steps;
                        sizer.record(push.chainCount,
                                     std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
                        c += push.chainCount;
                    }
                    done += push.steps;
                    interrupted = clock.abandon();
                }
            } else {
                // `count` passes in one submission: their direct passes, then all their steps,
                // every chain in each dispatch.
                batches.begin();
                if (o.separateDirect) {
                    batch.bind(directWork);
                    for (uint32_t p = pass; p < pass + count; ++p) {
                        directPush.sampleBase = p;
                        batch.dispatch(directKernel, directPush,
                                       (pixels + directPush.itemsPerInvocation - 1) / directPush.itemsPerInvocation);
                    }
                }
                batch.bind(work);
                push.chainBase = 0;
                push.chainCount = chainCount;
                for (uint32_t done = 0; chainsRun && done < count * stepsPerPass;) {
                    push.steps = std::min(o.stepsPerDispatch, count * stepsPerPass - done);
                    batch.dispatch(chainKernel, push, push.chainCount);
                    chainSteps += uint64_t(push.chainCount) * push.steps;
                    done += push.steps;
                }
                batches.submit();
                interrupted = clock.abandon();
            }
            if (o.separateDirect) directPasses += count;
            if (interrupted) break;  // a partial pass would be a darker, biased image
            splat.completePass(count);
            clock.passDone();
            pass += count;
            session.snapshotIfDue(uint64_t(splat.completedPasses()) * pixels, resolve);
            session.progress().update(passes != std::numeric_limits<uint32_t>::max()
                                          ? double(pass) / double(passes)
                                          : session.elapsedSeconds() / settings.timeLimit,
                                      double(pass), "passes");
        }
    }
    session.progress().finish();

    RenderOutput out;
    out.image = resolve();
    const auto stats = pixelStats.download<gpu::PixelChainStats>(pixels);
    const auto acceptedCounts = accepted.download<uint32_t>(pixels);
    Image chainsImage(session.width(), session.height()), proposalsImage(session.width(), session.height()),
        acceptedImage(session.width(), session.height());
    for (uint32_t i = 0; i < pixels; ++i)
        for (int c = 0; c < 3; ++c) {
            chainsImage.rgb[3 * i + c] = float(stats[i].chainsStarted);
            proposalsImage.rgb[3 * i + c] = float(stats[i].proposals);
            acceptedImage.rgb[3 * i + c] = float(acceptedCounts[i]);
        }
    out.diagnostics.push_back({"chains", chainsImage});
    out.diagnostics.push_back({"proposals", proposalsImage});
    out.diagnostics.push_back({"accepted", acceptedImage});
    const int done = splat.completedPasses();
    // Mutations, not camera paths: the paper's "mutations per pixel" (one per pixel per pass).
    out.cameraSamples = uint64_t(done) * chainCount * stepsPerPass;
    out.samplesPerPixel = done;

    const Counters& c = session.counters();
    out.methodStats = {
        {"passes", done},
        {"bootstrap_samples", bootstrapSamples},
        {"bootstrap_rays", bootstrapRays},
        {"normalization", start.normalization},  // b_hat: the image's summed pixel luminance
        {"deposit_energy", depositEnergy},
        {"chains", chainCount},
        {"steps_per_pass", stepsPerPass},
        {"passes_per_batch", together},
        {"mutations_per_pixel", double(done) * chainCount * stepsPerPass / pixels},
        {"chain_steps", chainSteps},
        {"large_step", o.largeStep},
        {"direct_passes", directPasses},  // --direct separate: depth-1 path-traced passes
        {"acceptance", chainSteps > 0 ? double(c.values[gpu::COUNTER_LENS_ACCEPTED] + c.values[gpu::COUNTER_CAUSTIC_ACCEPTED] +
                                                c.values[gpu::COUNTER_LARGE_ACCEPTED]) / double(chainSteps)
                                      : 0.0},
        {"deposited_energy", batches.depositedEnergy()},  // units of e_d: one per chain step
    };
    out.methodStats.update(mutationStatistics(c));
    return out;
}

MethodInfo mltMethod() {
    std::vector<MethodOption> options = {
        {"bootstrap", "4", "bootstrap samples per pixel: b and the chains' start paths"},
        {"chains", "0", "chains run in parallel (0: pixels / 16 within 1024..65536 on a CPU device; one per pixel up to 262144 on a GPU)"},
        {"large-step", "0.25", "probability of an independent mutation (a fresh path); > 0 keeps the chains ergodic: the perturbations alone keep a path's vertex count and type sequence"}};
    for (const MethodOption& o : PerturbationOptions::help()) options.push_back(o);
    options.push_back({"direct", "separate", "separate: the emitter seen directly and direct light at the first hit by path tracing (1 spp per pass), the chains take the rest; chains: the chains take every path"});
    options.push_back({"steps-per-dispatch", "4", "mutations per chain per dispatch"});
    options.push_back({"passes-per-batch", "0", "passes whose steps run in one submission (0: 1 on a CPU device, enough to fill a GPU)"});
    return {"mlt", "Metropolis light transport: ERPT's lens and caustic perturbations plus independent mutations",
            true, options, [](const RenderSettings& s) { return std::make_unique<Mlt>(s); }, ""};
}

}  // namespace pmcr
