#include "methods/pssmlt/pssmlt_integrator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "methods/energy_redistribution/redistribution.h"
#include "methods/energy_redistribution/splat_film.h"
#include "methods/metropolis/bootstrap.h"
#include "methods/pt/pt_integrator.h"
#include "vk/command_batch.h"
#include "vk/context.h"

namespace pmcr {

namespace {

constexpr uint32_t kBootstrapChunk = 16384;             // bootstrap samples per submission (CPU)
// mmlt: the pilot's samples of each depth, and the share of the bootstrap spread evenly over
// the depths whatever the pilot found (so that a depth the pilot saw dark still has samples).
constexpr uint32_t kBootstrapPilotPerDepth = 512;
constexpr double kBootstrapFloorShare = 0.25;
constexpr uint32_t kMinTimedPerDepth = 256;  // mmlt under --time alone: bootstrap samples a depth at least
constexpr VkDeviceSize kMaxPrimaryBytes = 1ull << 30;   // primary-sample storage

// What a render did, for its statistics.
struct PssmltRun {
    const char* over;
    uint64_t bootstrapSamples;
    double normalization;
    uint32_t chains;
    uint32_t stepsPerPass;
    uint32_t fullStepsPerPass;  // one mutation per pixel; stepsPerPass is fewer under --time alone
    uint32_t passesPerBatch;
    uint32_t dimensions;
    float depositEnergy;
    uint64_t mutations;
};

// The image on the splat film and the statistics of a render, over either estimator.
RenderOutput pssmltOutput(RenderSession& session, SplatFilm& splat, const RedistributionBatch& batches,
                          const PssmltRun& run) {
    const uint32_t pixels = uint32_t(session.width()) * uint32_t(session.height());
    RenderOutput out;
    out.image = splat.resolve(run.depositEnergy);
    const int passes = splat.completedPasses();
    // Mutations per pixel: the passes, unless they were cut short (timedStepsPerPass).
    out.samplesPerPixel = double(passes) * run.stepsPerPass / run.fullStepsPerPass;
    out.cameraSamples = uint64_t(std::llround(out.samplesPerPixel * pixels));
    const Counters& c = session.counters();
    const uint64_t proposed = c.values[gpu::COUNTER_LARGE_PROPOSED] + c.values[gpu::COUNTER_SMALL_PROPOSED];
    const uint64_t accepted = c.values[gpu::COUNTER_LARGE_ACCEPTED] + c.values[gpu::COUNTER_SMALL_ACCEPTED];
    const double deposited = batches.depositedEnergy();
    out.methodStats = {
        {"passes", passes},
        {"bootstrap_samples", run.bootstrapSamples},
        {"normalization", run.normalization},  // b_hat: the image's total luminance
        {"chains", run.chains},
        {"steps_per_pass", run.stepsPerPass},  // per chain
        {"passes_per_batch", run.passesPerBatch},
        {"dimensions", run.dimensions},
        {"deposit_energy", run.depositEnergy},
        {"mutations", run.mutations},
        {"accepted", accepted},
        {"acceptance", proposed > 0 ? double(accepted) / double(proposed) : 0.0},
        // Each mutation deposits one e_d in all (a at y, 1 - a at x): zero up to float rounding
        // of the sums, unless deposits were dropped.
        {"energy_not_deposited", run.mutations > 0 ? 1.0 - deposited / double(run.mutations) : 0.0},
    };
    if (run.over) out.methodStats["over"] = run.over;
    out.methodStats.update(mutationStatistics(c));
    // ERPT's perturbations do not run here.
    for (const char* key : {"lens_proposed", "lens_acceptance", "caustic_proposed", "caustic_acceptance",
                            "invalid_proposals"})
        out.methodStats.erase(key);
    return out;
}

}  // namespace

PssmltOptions PssmltOptions::fromSettings(const RenderSettings& s, const char* method, uint32_t defaultBootstrap) {
    PssmltOptions o;
    o.bootstrapSpp = defaultBootstrap;
    const std::string over = s.optionString("over", "bdpt");
    if (over != "bdpt" && over != "pt") throw Error("--over: expected bdpt or pt, got '" + over + "'");
    o.overBdpt = over == "bdpt";
    const int bootstrap = s.optionInt("bootstrap", int(o.bootstrapSpp));
    const int least = defaultBootstrap == 0 ? 0 : 1;
    if (bootstrap < least || bootstrap > 4096)
        throw Error("--bootstrap: expected " + std::to_string(least) + "..4096 samples per pixel" +
                    (least == 0 ? " (0: automatic)" : ""));
    o.bootstrapSpp = uint32_t(bootstrap);
    const int chains = s.optionInt("chains", 0);
    if (chains < 0 || uint32_t(chains) > kMaxChains)
        throw Error("--chains: expected 0.." + std::to_string(kMaxChains) + " (0: automatic)");
    o.chains = uint32_t(chains);
    o.largeStepProbability = float(s.optionDouble("large-step", o.largeStepProbability));
    if (!(o.largeStepProbability >= 0.0f && o.largeStepProbability <= 1.0f))
        throw Error("--large-step: expected a probability in [0, 1]");
    o.sigma = float(s.optionDouble("sigma", o.sigma));
    if (!(o.sigma > 0.0f && o.sigma <= 1.0f)) throw Error("--sigma: expected 0 < sigma <= 1");
    const int steps = s.optionInt("steps-per-dispatch", int(o.stepsPerDispatch));
    if (steps < 1 || steps > 64) throw Error("--steps-per-dispatch: expected 1..64");
    o.stepsPerDispatch = uint32_t(steps);
    const int together = s.optionInt("passes-per-batch", 0);
    if (together < 0 || together > 1024) throw Error("--passes-per-batch: expected 0..1024 (0 = from the device)");
    o.passesPerBatch = uint32_t(together);
    if (s.maxDepth > gpu::PSSMLT_MAX_DEPTH)
        throw Error(std::string("--max-depth: ") + method + " holds the random numbers of at most " +
                    std::to_string(gpu::PSSMLT_MAX_DEPTH) + " bounces");
    return o;
}

uint32_t PssmltOptions::defaultPassesPerBatch(bool cpuDevice, uint64_t mutationsPerPass) {
    if (cpuDevice) return 1;
    const uint64_t target = uint64_t(1) << 20;
    return uint32_t(std::clamp<uint64_t>((target + mutationsPerPass - 1) / std::max<uint64_t>(mutationsPerPass, 1), 1, 64));
}

uint64_t PssmltOptions::bootstrapPerDepth(uint32_t pixels) const {
    return bootstrapSpp > 0 ? uint64_t(bootstrapSpp) * pixels : kAutoBootstrapPerDepth;
}

bool PssmltOptions::timeBudgeted(const RenderSettings& s) { return s.timeLimit > 0.0 && s.spp == 0; }

bool PssmltOptions::bootstrapTimeUp(const RenderSession& session, uint64_t taken) {
    return taken > 0 && session.elapsedSeconds() >= kBootstrapShareOfTime * session.settings().timeLimit;
}

uint32_t PssmltOptions::timedStepsPerPass(uint32_t steps, uint32_t chains, double samplesPerSecond,
                                          double timeLimit) {
    const double fit = samplesPerSecond * kPassShareOfTime * timeLimit / double(std::max(chains, 1u));
    if (!(fit >= 1.0)) return 1;
    return uint32_t(std::min(fit, double(steps)));
}

Pssmlt::Pssmlt(const RenderSettings& settings) : m_options(PssmltOptions::fromSettings(settings)) {}

RenderOutput Pssmlt::render(RenderSession& session) {
    return m_options.overBdpt ? renderChainsOverBdpt(session, m_options, false) : renderOverPt(session);
}

// The passes of started chains, shared by both bases: `together` passes at a time, each about
// one mutation per pixel, then the splat film completes them. With one pass at a time,
// runSteps(n) makes n steps of every chain (in dispatches sized to the device) and a pass can be
// abandoned between them; with several, recordSteps(n) records n steps of every chain into the
// open submission. Passes run together give the same bits as one at a time: the chains and
// their random numbers do not know where a submission ends, and the film sums integer quanta
// (PssmltTest.PassesRunTogetherSameImage). Returns the mutations made; `interrupted` tells
// whether the render was stopped.
template <typename RunSteps, typename RecordSteps>
uint64_t runPasses(RenderSession& session, SplatFilm& splat, RedistributionBatch& batches,
                   const vk::DescriptorSet& work, float depositEnergy, uint64_t pathsPerPass, uint32_t spp,
                   uint32_t chains, uint32_t stepsPerPass, uint32_t stepsPerDispatch, uint32_t together,
                   bool& interrupted, RunSteps runSteps, RecordSteps recordSteps) {
    uint64_t mutations = 0;
    PassClock clock(session);
    for (uint32_t pass = 0; pass < spp && !interrupted && clock.startPass();) {
        const uint32_t count = std::min(together, spp - pass);
        if (count == 1) {
            for (uint32_t done = 0; done < stepsPerPass;) {
                const uint32_t steps = std::min(stepsPerDispatch, stepsPerPass - done);
                runSteps(steps);
                mutations += uint64_t(chains) * steps;
                done += steps;
                if (clock.abandon()) {
                    interrupted = true;
                    break;
                }
            }
        } else {
            // All of `count` passes' steps in one submission, every chain in each dispatch.
            batches.begin();
            batches.batch().bind(work);
            recordSteps(count * stepsPerPass);
            batches.submit();
            mutations += uint64_t(chains) * stepsPerPass * count;
            interrupted = clock.abandon();
        }
        if (interrupted) break;
        completeRedistributionPass(session, splat, depositEnergy, pathsPerPass, pass + count - 1, spp, count);
        clock.passDone();
        pass += count;
    }
    return mutations;
}

RenderOutput Pssmlt::renderOverPt(RenderSession& session) {
    const RenderSettings& settings = session.settings();
    vk::Context& context = session.context();
    const PssmltOptions& o = m_options;
    const uint32_t pixels = uint32_t(session.width()) * uint32_t(session.height());
    const uint32_t spp = settings.spp > 0 ? settings.spp
                         : settings.timeLimit > 0.0 ? std::numeric_limits<uint32_t>::max()
                                                    : kDefaultSpp;
    const uint32_t chains =
        o.chains > 0 ? o.chains : std::min(pixels, PssmltOptions::defaultChains(context.isCpuDevice()));
    const uint32_t dimensions = PSSMLT_DIMENSIONS(settings.maxDepth);
    const VkDeviceSize primaryBytes = VkDeviceSize(chains) * dimensions * sizeof(gpu::PrimarySample);
    if (primaryBytes > kMaxPrimaryBytes)
        throw Error("pssmlt: " + std::to_string(chains) + " chains of " + std::to_string(dimensions) +
                    " random numbers need " + std::to_string(primaryBytes >> 20) +
                    " MiB (at most 1024); lower --chains or --max-depth");
    // One pass: about one mutation per pixel (fewer steps under --time alone, once the
    // bootstrap has measured the device).
    const uint32_t fullStepsPerPass = std::max(1u, uint32_t(std::lround(double(pixels) / chains)));
    uint32_t stepsPerPass = fullStepsPerPass;
    const bool budgeted = PssmltOptions::timeBudgeted(settings);
    const uint64_t bootstrapSamples = uint64_t(o.bootstrapSpp) * pixels;
    if (bootstrapSamples > std::numeric_limits<uint32_t>::max())
        throw Error("--bootstrap: more than 2^32 bootstrap samples; lower it");

    // Build the pipelines before the clock starts (compilation is not rendering).
    const vk::Kernel& bootstrapKernel =
        session.kernel(lightsKernelVariant(session.scene(), "methods/pssmlt/pssmlt_bootstrap"));
    const vk::Kernel& chainKernel =
        session.kernel(lightsKernelVariant(session.scene(), "methods/pssmlt/pssmlt_chains"));
    session.startClock();

    Film& film = session.film();
    SplatFilm splat(context, session.width(), session.height());
    vk::Buffer weights(context, bootstrapSamples * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                       "bootstrap weights", vk::MemoryUsage::Readback);
    vk::Buffer starts(context, VkDeviceSize(chains) * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      "chain starts");
    vk::Buffer chainStates(context, VkDeviceSize(chains) * sizeof(gpu::PssmltChain),
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pssmlt chains");
    vk::Buffer primary(context, primaryBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "primary samples");

    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "pssmlt");
    work.bind(gpu::PSSMLT_BINDING_WEIGHTS, weights);
    work.bind(gpu::PSSMLT_BINDING_CHAIN_STARTS, starts);
    work.bind(gpu::PSSMLT_BINDING_CHAINS, chainStates);
    work.bind(gpu::PSSMLT_BINDING_PRIMARY_SAMPLES, primary);
    work.bind(gpu::ERPT_BINDING_SPLAT, splat.pixels());
    work.bind(gpu::ERPT_BINDING_COUNTERS, film.counters());
    RedistributionBatch batches(session);
    vk::CommandBatch& batch = batches.batch();
    work.bind(gpu::ERPT_BINDING_ENERGY, batches.energy());

    gpu::PssmltPush push{};
    push.seed = settings.seed;
    push.maxDepth = settings.maxDepth;
    push.rrDepth = settings.rrDepth;
    push.dimensions = dimensions;
    push.chainStride = chains;
    push.largeStepProbability = o.largeStepProbability;
    push.sigma = o.sigma;

    // Bootstrap: F of uniform primary vectors, W_i = F(u_i) * pixels (Veach 1997 sec. 11.3.1).
    const uint32_t chunk = context.isCpuDevice() ? kBootstrapChunk : uint32_t(bootstrapSamples);
    const double bootstrapStart = session.elapsedSeconds();
    bool interrupted = false;
    uint32_t taken = 0;  // bootstrap samples drawn: [0, taken)
    for (uint32_t first = 0; first < bootstrapSamples && !interrupted; first += chunk) {
        if (budgeted && PssmltOptions::bootstrapTimeUp(session, taken)) break;
        batches.begin();
        batch.bind(work);
        push.first = first;
        push.count = std::min<uint32_t>(chunk, uint32_t(bootstrapSamples) - first);
        push.itemsPerInvocation = ptItemsPerInvocation(context, push.count);
        batch.dispatch(bootstrapKernel, push, (push.count + push.itemsPerInvocation - 1) / push.itemsPerInvocation);
        batches.submit();
        taken += push.count;
        interrupted = session.interrupted();
    }
    MetropolisStart start;
    if (!interrupted) {
        std::vector<float> w = weights.download<float>(taken);
        for (float& x : w) x *= float(pixels);
        start = chooseChainStarts(w, chains, settings.seed);
    }
    const double bootstrapSeconds = session.elapsedSeconds() - bootstrapStart;
    session.addPrepassSeconds(bootstrapSeconds);
    if (budgeted)
        stepsPerPass = PssmltOptions::timedStepsPerPass(fullStepsPerPass, chains, taken / bootstrapSeconds,
                                                        settings.timeLimit);
    const double normalization = start.normalization;
    // e_d: each pass's chains * steps deposits share b (the image's total luminance).
    const float depositEnergy = float(normalization / (double(chains) * stepsPerPass));

    uint64_t mutations = 0;
    DispatchSizer sizer(1024, chains, session.targetDispatchSeconds());
    auto runChains = [&](uint32_t steps, uint32_t flags) {
        push.steps = steps;
        push.flags = flags;
        for (uint32_t c = 0; c < chains;) {
            push.first = c;
            push.count = std::min(sizer.units(), chains - c);
            const auto t0 = std::chrono::steady_clock::now();
            batches.begin();
            batch.bind(work);
            batch.dispatch(chainKernel, push, push.count);
            batches.submit();
            sizer.record(uint64_t(push.count) * std::max(steps, 1u),
                         std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            c += push.count;
        }
    };
    // Passes run together (runPasses): the same bits for any count.
    const uint32_t together = o.passesPerBatch > 0
                                  ? o.passesPerBatch
                                  : PssmltOptions::defaultPassesPerBatch(context.isCpuDevice(),
                                                                         uint64_t(chains) * stepsPerPass);
    if (!start.samples.empty() && depositEnergy > 0.0f && std::isfinite(depositEnergy)) {
        starts.upload(start.samples);
        runChains(0, gpu::PSSMLT_FLAG_START);
        mutations = runPasses(session, splat, batches, work, depositEnergy,
                              uint64_t(pixels) * stepsPerPass / fullStepsPerPass, spp, chains, stepsPerPass,
                              o.stepsPerDispatch, together, interrupted, [&](uint32_t steps) { runChains(steps, 0); },
                              [&](uint32_t steps) {
                                  push.flags = 0;
                                  push.first = 0;
                                  push.count = chains;
                                  for (uint32_t done = 0; done < steps;) {
                                      push.steps = std::min(o.stepsPerDispatch, steps - done);
                                      batch.dispatch(chainKernel, push, push.count);
                                      done += push.steps;
                                  }
                              });
    }
    session.progress().finish();

    return pssmltOutput(session, splat, batches,
                        {"pt", taken, normalization, chains, stepsPerPass, fullStepsPerPass, together, dimensions,
                         depositEnergy, mutations});
}

// Over bdpt: the same bootstrap, chains, passes and deposits as over pt, a sample being one
// bidirectional sample (shared/pssmlt_types.h) and a step three dispatches over the chains: the
// proposal's subpaths, its connections into its splat list, the acceptance and deposits. mmlt
// (multiplexed) the same, a sample being one strategy of a chain's depth.
RenderOutput renderChainsOverBdpt(RenderSession& session, const PssmltOptions& o, bool multiplexed) {
    const RenderSettings& settings = session.settings();
    vk::Context& context = session.context();
    const uint32_t kDefaultSpp = Pssmlt::kDefaultSpp;
    const uint32_t pixels = uint32_t(session.width()) * uint32_t(session.height());
    const uint32_t spp = settings.spp > 0 ? settings.spp
                         : settings.timeLimit > 0.0 ? std::numeric_limits<uint32_t>::max()
                                                    : kDefaultSpp;
    const uint32_t chains =
        o.chains > 0 ? o.chains : std::min(pixels, PssmltOptions::defaultChains(context.isCpuDevice()));
    const uint32_t dimensions =
        multiplexed ? MMLT_DIMENSIONS(settings.maxDepth) : PSSMLT_BDPT_DIMENSIONS(settings.maxDepth);
    // mmlt: as many bootstrap samples of each depth 0 .. maxDepth (pbrt-v4 MLTIntegrator).
    const uint32_t depths = multiplexed ? settings.maxDepth + 1 : 1;
    const uint32_t cameraStride = settings.maxDepth + 2;
    const uint32_t lightStride = settings.maxDepth + 1;
    const uint32_t splatsPerList = PSSMLT_BDPT_SPLATS(settings.maxDepth);
    const VkDeviceSize primaryBytes = VkDeviceSize(chains) * dimensions * sizeof(gpu::PrimarySample);
    const VkDeviceSize vertexBytes = VkDeviceSize(chains) * (cameraStride + lightStride) * sizeof(gpu::BdptVertex);
    if (primaryBytes + vertexBytes > kMaxPrimaryBytes)
        throw Error(std::string(multiplexed ? "mmlt: " : "pssmlt: ") + std::to_string(chains) + " chains of " +
                    std::to_string(dimensions) +
                    " random numbers and their subpaths need " +
                    std::to_string((primaryBytes + vertexBytes) >> 20) +
                    " MiB (at most 1024); lower --chains or --max-depth");
    // One pass: about one mutation per pixel (fewer steps under --time alone). Under --time
    // alone pssmlt's bootstrap may stop early (`budgeted`); mmlt's is sized from its pilot.
    const uint32_t fullStepsPerPass = std::max(1u, uint32_t(std::lround(double(pixels) / chains)));
    uint32_t stepsPerPass = fullStepsPerPass;
    const bool timed = PssmltOptions::timeBudgeted(settings);
    const bool budgeted = !multiplexed && timed;
    // mmlt: a pilot of kBootstrapPilotPerDepth samples of each depth, then the bootstrap's
    // samples allocated to the depths by the pilot (allocateBootstrapByDepth).
    const uint64_t mainSamples =
        multiplexed ? o.bootstrapPerDepth(pixels) * depths : uint64_t(o.bootstrapSpp) * pixels;
    const uint64_t pilotSamples = multiplexed ? uint64_t(kBootstrapPilotPerDepth) * depths : 0;
    if (mainSamples > std::numeric_limits<uint32_t>::max() ||
        (multiplexed && kBootstrapPilotPerDepth + mainSamples > (uint64_t(1) << gpu::MMLT_DEPTH_SHIFT)))
        throw Error(multiplexed ? "--bootstrap: a depth could take more than 2^25 bootstrap samples; lower it"
                                : "--bootstrap: more than 2^32 bootstrap samples; lower it");

    // Build the pipelines before the clock starts (compilation is not rendering).
    const vk::Kernel& subpathsKernel = session.kernel(lightsKernelVariant(
        session.scene(), multiplexed ? "methods/mmlt/mmlt_subpaths" : "methods/pssmlt/pssmlt_bdpt_subpaths"));
    const vk::Kernel& connectKernel = session.kernel(lightsKernelVariant(
        session.scene(), multiplexed ? "methods/mmlt/mmlt_connect" : "methods/pssmlt/pssmlt_bdpt_connect"));
    const vk::Kernel& stepKernel = session.kernel("methods/pssmlt/pssmlt_bdpt_step");
    session.startClock();

    Film& film = session.film();
    SplatFilm splat(context, session.width(), session.height());
    vk::Buffer weights(context, std::max<uint64_t>(1, std::max(pilotSamples, mainSamples)) * sizeof(float),
                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                       "bootstrap weights", vk::MemoryUsage::Readback);
    vk::Buffer starts(context, VkDeviceSize(chains) * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      "chain starts");
    vk::Buffer chainStates(context, VkDeviceSize(chains) * sizeof(gpu::PssmltBdptChain),
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pssmlt bdpt chains");
    vk::Buffer primary(context, primaryBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "primary samples");
    vk::Buffer cameraVertices(context, VkDeviceSize(chains) * cameraStride * sizeof(gpu::BdptVertex),
                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pssmlt camera vertices");
    vk::Buffer lightVertices(context, VkDeviceSize(chains) * lightStride * sizeof(gpu::BdptVertex),
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pssmlt light vertices");
    vk::Buffer counts(context, VkDeviceSize(chains) * sizeof(gpu::uvec2), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      "pssmlt vertex counts");
    vk::Buffer splatLists(context, VkDeviceSize(chains) * 2 * splatsPerList * sizeof(gpu::PssmltSplat),
                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pssmlt splat lists");

    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "pssmlt over bdpt");
    work.bind(gpu::PSSMLT_BINDING_WEIGHTS, weights);
    work.bind(gpu::PSSMLT_BINDING_CHAIN_STARTS, starts);
    work.bind(gpu::PSSMLT_BINDING_PRIMARY_SAMPLES, primary);
    work.bind(gpu::PSSMLT_BINDING_CAMERA_VERTICES, cameraVertices);
    work.bind(gpu::PSSMLT_BINDING_LIGHT_VERTICES, lightVertices);
    work.bind(gpu::PSSMLT_BINDING_VERTEX_COUNTS, counts);
    work.bind(gpu::PSSMLT_BINDING_SPLATS, splatLists);
    work.bind(gpu::PSSMLT_BINDING_BDPT_CHAINS, chainStates);
    work.bind(gpu::ERPT_BINDING_SPLAT, splat.pixels());
    work.bind(gpu::ERPT_BINDING_COUNTERS, film.counters());
    RedistributionBatch batches(session);
    vk::CommandBatch& batch = batches.batch();
    work.bind(gpu::ERPT_BINDING_ENERGY, batches.energy());

    gpu::PssmltPush push{};
    push.seed = settings.seed;
    push.maxDepth = settings.maxDepth;
    // mmlt's subpaths have the lengths of their strategy: no Russian roulette (pbrt-v4's
    // MLTIntegrator has none), which would only end some of them short, F = 0.
    push.rrDepth = multiplexed ? std::numeric_limits<uint32_t>::max() : settings.rrDepth;
    push.dimensions = dimensions;
    push.chainStride = chains;
    push.largeStepProbability = o.largeStepProbability;
    push.sigma = o.sigma;
    push.cameraStride = cameraStride;
    push.lightStride = lightStride;
    // One step (or start) of chains [push.first, push.first + push.count), recorded into the batch.
    auto recordStep = [&] {
        batch.dispatch(subpathsKernel, push, push.count);
        batch.dispatch(connectKernel, push, push.count);
        batch.dispatch(stepKernel, push, push.count);
    };

    // Bootstrap: F of uniform primary vectors, W_i = F(u_i) * pixels (Veach 1997 sec. 11.3.1),
    // in ranges of weights [first, first + count) of samples first + sampleOffset on, each
    // sample a chain slot's start, `chains` samples a step and about kBootstrapChunk a submission
    // (a small image has few chains, and a submission per step took longer than its samples on
    // lavapipe: mmlt's default bootstrap at 20 x 20 is 99 steps of 400).
    struct BootstrapRange {
        uint32_t first, count, sampleOffset;
    };
    // (Under --time alone, a quarter as many: the bootstrap may stop after any submission.)
    const uint32_t stepsPerSubmission = std::max(1u, (budgeted ? kBootstrapChunk / 4 : kBootstrapChunk) / chains);
    const double bootstrapStart = session.elapsedSeconds();
    bool interrupted = false;
    uint64_t taken = 0;  // samples of the last bootstrap call
    // The weights of `ranges`, which cover [0, n); empty when interrupted. Budgeted (pssmlt:
    // one range from 0), it may stop early: the weights of [0, taken).
    auto bootstrap = [&](const std::vector<BootstrapRange>& ranges, uint64_t n) {
        size_t r = 0;
        uint32_t done = 0;  // of range r
        taken = 0;
        while (r < ranges.size() && !interrupted) {
            if (budgeted && PssmltOptions::bootstrapTimeUp(session, taken)) break;
            batches.begin();
            batch.bind(work);
            for (uint32_t k = 0; k < stepsPerSubmission && r < ranges.size(); ++k) {
                push.first = ranges[r].first + done;
                push.count = std::min(chains, ranges[r].count - done);
                push.sampleOffset = ranges[r].sampleOffset;
                push.flags = gpu::PSSMLT_FLAG_START | gpu::PSSMLT_FLAG_BOOTSTRAP;
                recordStep();
                done += push.count;
                taken += push.count;
                if (done == ranges[r].count) ++r, done = 0;
            }
            batches.submit();
            interrupted = session.interrupted();
        }
        std::vector<float> w;
        if (!interrupted) w = weights.download<float>(taken < n ? taken : n);
        for (float& x : w) x *= float(pixels);
        return w;
    };
    MetropolisStart start;
    std::vector<uint64_t> depthSamples;  // mmlt: the bootstrap's samples of each depth
    if (!multiplexed) {
        const std::vector<float> w = bootstrap({{0, uint32_t(mainSamples), 0}}, mainSamples);
        if (!interrupted) start = chooseChainStarts(w, chains, settings.seed);
    } else {
        // Sample k of depth d is (d << MMLT_DEPTH_SHIFT) + k: the pilot's are k < P, the
        // bootstrap's follow, so that they are apart (shared/pssmlt_types.h).
        const uint32_t P = kBootstrapPilotPerDepth;
        std::vector<BootstrapRange> ranges;
        for (uint32_t d = 0; d < depths; ++d)
            ranges.push_back({d * P, P, (d << gpu::MMLT_DEPTH_SHIFT) - d * P});
        const std::vector<float> pilot = bootstrap(ranges, pilotSamples);
        std::vector<double> means(depths, 0.0);
        for (uint32_t d = 0; d < depths && !interrupted; ++d) {
            for (uint32_t k = 0; k < P; ++k) {
                const double x = pilot[size_t(d) * P + k];
                if (std::isfinite(x) && x > 0.0) means[d] += x;
            }
            means[d] /= double(P);
        }
        // Under --time alone, as many as the pilot's rate fits into the bootstrap's share of
        // the budget (at least kMinTimedPerDepth a depth): 16384 a depth took 1.8-2.0 s of
        // `--time 2` on lavapipe at 320x180.
        uint64_t main = mainSamples;
        if (timed && !interrupted) {
            const double rate = double(pilotSamples) / std::max(1e-6, session.elapsedSeconds() - bootstrapStart);
            const double left = PssmltOptions::kBootstrapShareOfTime * settings.timeLimit - session.elapsedSeconds();
            main = std::clamp<uint64_t>(uint64_t(std::max(0.0, rate * left)),
                                        std::min<uint64_t>(mainSamples, uint64_t(kMinTimedPerDepth) * depths), mainSamples);
        }
        depthSamples = allocateBootstrapByDepth(means, main, kBootstrapFloorShare);
        std::vector<uint32_t> first(depths);
        ranges.clear();
        for (uint32_t d = 0, f = 0; d < depths; ++d) {
            first[d] = f;
            ranges.push_back({f, uint32_t(depthSamples[d]), (d << gpu::MMLT_DEPTH_SHIFT) + P - f});
            f += uint32_t(depthSamples[d]);
        }
        const std::vector<float> w = interrupted ? std::vector<float>() : bootstrap(ranges, main);
        push.sampleOffset = 0;
        if (!interrupted) {
            start = chooseChainStartsByStratum(w, depthSamples, chains, settings.seed);
            // The weights' index to the sample's number; chains in order of depth, so that
            // neighbouring invocations walk and connect paths of one length and a SIMD group
            // waits for no longer walk (which slot a chain takes changes nothing of its law).
            for (uint32_t& i : start.samples) {
                const uint32_t d = uint32_t(std::upper_bound(first.begin(), first.end(), i) - first.begin()) - 1;
                i = (d << gpu::MMLT_DEPTH_SHIFT) + P + (i - first[d]);
            }
            std::sort(start.samples.begin(), start.samples.end());
        }
    }
    const double bootstrapSeconds = session.elapsedSeconds() - bootstrapStart;
    session.addPrepassSeconds(bootstrapSeconds);
    if (timed)
        stepsPerPass = PssmltOptions::timedStepsPerPass(fullStepsPerPass, chains, taken / bootstrapSeconds,
                                                        settings.timeLimit);
    // mmlt: b is the sum over depths of each depth's mean weight (pbrt-v4 MLTIntegrator),
    // chooseChainStartsByStratum's b_hat.
    const double normalization = start.normalization;
    // e_d: each pass's chains * steps deposits share b (the image's total luminance).
    const float depositEnergy = float(normalization / (double(chains) * stepsPerPass));

    uint64_t mutations = 0;
    DispatchSizer sizer(1024, chains, session.targetDispatchSeconds());
    // `steps` steps (or the start) of every chain, a range of chains per submission.
    auto runChains = [&](uint32_t steps, uint32_t flags) {
        push.flags = flags;
        for (uint32_t c = 0; c < chains;) {
            push.first = c;
            push.count = std::min(sizer.units(), chains - c);
            const auto t0 = std::chrono::steady_clock::now();
            batches.begin();
            batch.bind(work);
            for (uint32_t k = 0; k < std::max(steps, 1u); ++k) recordStep();
            batches.submit();
            sizer.record(uint64_t(push.count) * std::max(steps, 1u),
                         std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            c += push.count;
        }
    };
    // Passes run together (runPasses): the same bits for any count.
    const uint32_t together = o.passesPerBatch > 0
                                  ? o.passesPerBatch
                                  : PssmltOptions::defaultPassesPerBatch(context.isCpuDevice(),
                                                                         uint64_t(chains) * stepsPerPass);
    if (!start.samples.empty() && depositEnergy > 0.0f && std::isfinite(depositEnergy)) {
        starts.upload(start.samples);
        runChains(0, gpu::PSSMLT_FLAG_START);
        mutations = runPasses(session, splat, batches, work, depositEnergy,
                              uint64_t(pixels) * stepsPerPass / fullStepsPerPass, spp, chains, stepsPerPass,
                              o.stepsPerDispatch, together, interrupted, [&](uint32_t steps) { runChains(steps, 0); },
                              [&](uint32_t steps) {
                                  push.flags = 0;
                                  push.first = 0;
                                  push.count = chains;
                                  for (uint32_t k = 0; k < steps; ++k) recordStep();
                              });
    }
    session.progress().finish();
    RenderOutput out = pssmltOutput(session, splat, batches,
                                    {multiplexed ? nullptr : "bdpt", taken,
                                     normalization, chains, stepsPerPass, fullStepsPerPass, together, dimensions,
                                     depositEnergy, mutations});
    if (multiplexed) {
        out.methodStats["bootstrap_pilot_samples"] = pilotSamples;
        out.methodStats["bootstrap_samples_per_depth"] = depthSamples;
    }
    return out;
}

MethodInfo pssmltMethod() {
    return {"pssmlt",
            "primary-sample-space MLT (Kelemen et al. 2002) over bdpt (--over pt: the path tracer); large "
            "steps make it ergodic over everything its estimator samples",
            true,
            {{"over", "bdpt",
              "the estimator the chains drive: bdpt (one camera and one light subpath, every strategy "
              "MIS-weighted; Kelemen et al. 2002 as Mitsuba's PSSMLT) or pt (the path tracer)"},
             {"bootstrap", "4", "samples per pixel (of the --over estimator) estimating b and starting the chains"},
             {"chains", "0", "chains in parallel (0: one per pixel, at most 4096 on a CPU device, 65536 on a GPU)"},
             {"large-step", "0.3", "probability of a large step (every random number drawn anew)"},
             {"sigma", "0.01", "small step: standard deviation of the wrapped Gaussian offset"},
             {"steps-per-dispatch", "4", "mutations per chain per dispatch"},
             {"passes-per-batch", "0", "passes whose steps run in one submission (0: 1 on a CPU device, enough to fill a GPU)"}},
            [](const RenderSettings& s) { return std::make_unique<Pssmlt>(s); }, ""};
}

}  // namespace pmcr
