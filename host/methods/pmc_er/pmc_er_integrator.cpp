#include "methods/pmc_er/pmc_er_integrator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/random.h"
#include "methods/energy_redistribution/energy_estimate.h"
#include "methods/energy_redistribution/path_records.h"
#include "methods/energy_redistribution/redistribution.h"
#include "methods/energy_redistribution/splat_film.h"
#include "methods/erpt/erpt_integrator.h"
#include "methods/pmc_er/path_population.h"
#include "methods/pmc_er/stratified_pixel_pool.h"
#include "methods/pmc_pt/pixel_population.h"
#include "methods/pt/pt_integrator.h"
#include "vk/command_batch.h"
#include "vk/context.h"

namespace pmcr {

namespace {

constexpr uint32_t kRecordChunk = 16384;  // new paths traced at once
constexpr double kPaperMembersPerPixel = 5000.0 / (640.0 * 480.0);
// --population auto: one member per 4 pixels. The paper's 5000 per 640x480 leaves lavapipe's
// dispatches too small to fill the device; measured on cornell-glass 128x128 at equal time (Eff
// over ERPT, geometric mean of 2 seeds): the paper's 267 members 0.19, 1024 0.41, 4096 0.50,
// 16384 0.41 (docs/methods.md, PMC-ER).
constexpr uint32_t kPixelsPerMember = 4;

}  // namespace

PmcErOptions PmcErOptions::fromSettings(const RenderSettings& s) {
    PmcErOptions o;
    const std::string population = s.optionString("population", "auto");
    if (population == "paper") {
        o.paperPopulation = true;
    } else if (population != "auto") {
        const int n = s.optionInt("population", 0);
        if (n < 1 || n > 4000000) throw Error("--population: expected auto, paper or 1..4000000");
        o.population = uint32_t(n);
    }
    const int mutations = s.optionInt("mutations", int(o.mutations));
    if (mutations < 1 || mutations > 4096) throw Error("--mutations: expected 1..4096");
    o.mutations = uint32_t(mutations);
    o.radii = parseRadii(s.optionString("radii", "5,10,50"));
    o.resampleRate = s.optionDouble("resample-rate", o.resampleRate);
    if (!(o.resampleRate > 0.0 && o.resampleRate <= 1.0)) throw Error("--resample-rate: expected (0, 1]");
    o.epsilon = s.optionDouble("epsilon", o.epsilon);
    if (!(o.epsilon >= 0.0 && o.epsilon <= 1.0)) throw Error("--epsilon: expected 0..1");
    // Beyond the paper (its members start uniform and adapt fully): given starting weights and
    // partial or no adaptation, which bench/pmc-er-ceiling uses to render fixed mixtures.
    o.initialAlpha.assign(o.radii.size(), 1.0 / double(o.radii.size()));
    if (s.optionString("initial-alpha", "uniform") != "uniform") {
        const std::string text = s.optionString("initial-alpha", "");
        const std::vector<double> w = s.optionNumbers("initial-alpha", "");
        double sum = 0.0;
        bool negative = false;
        for (double v : w) {
            sum += v;
            negative = negative || v < 0.0;
        }
        if (w.size() != o.radii.size() || negative || !(sum > 0.0))
            throw Error("--initial-alpha: expected uniform or " + std::to_string(o.radii.size()) +
                        " non-negative weights, one per radius, not all zero, got '" + text + "'");
        for (size_t k = 0; k < w.size(); ++k) o.initialAlpha[k] = w[k] / sum;
    }
    o.adaptRate = s.optionDouble("adapt-rate", o.adaptRate);
    if (!(o.adaptRate >= 0.0 && o.adaptRate <= 1.0)) throw Error("--adapt-rate: expected 0..1");
    o.causticProbability = float(s.optionDouble("caustic-probability", o.causticProbability));
    if (!(o.causticProbability >= 0.0f && o.causticProbability <= 1.0f))
        throw Error("--caustic-probability: expected a probability");
    const int passSpp = s.optionInt("pass-spp", int(o.passSpp));
    if (passSpp < 1 || passSpp > 4096) throw Error("--pass-spp: expected 1..4096");
    o.passSpp = uint32_t(passSpp);
    const int refill = s.optionInt("refill-rounds", int(o.refillRounds));
    if (refill < 1 || refill > 64) throw Error("--refill-rounds: expected 1..64");
    o.refillRounds = uint32_t(refill);
    const std::string acceptance = s.optionString("acceptance", "component");
    if (acceptance == "mixture") o.mixtureAcceptance = true;
    else if (acceptance != "component") throw Error("--acceptance: expected mixture or component, got '" + acceptance + "'");
    const std::string lifetime = s.optionString("lifetime", "100");
    if (lifetime == "auto") {
        o.lifetime = 0.0;
    } else {
        o.lifetime = s.optionDouble("lifetime", o.lifetime);
        if (!(o.lifetime >= 1.0 && o.lifetime <= 1e6)) throw Error("--lifetime: expected auto or 1..1e6 mutations");
    }
    const std::string redistribute = s.optionString("redistribute", "indirect");
    if (redistribute == "indirect") o.depositDirect = true;
    else if (redistribute == "all") o.depositDirect = false;
    else throw Error("--redistribute: expected indirect or all, got '" + redistribute + "'");
    const int prepass = s.optionInt("prepass-spp", int(o.prepassSpp));
    if (prepass < 1 || prepass > 4096) throw Error("--prepass-spp: expected 1..4096");
    o.prepassSpp = uint32_t(prepass);
    const std::string birth = s.optionString("birth", "equal");
    if (birth == "equal") o.birth = gpu::PMC_ER_BIRTH_EQUAL;
    else if (birth == "path") o.birth = gpu::PMC_ER_BIRTH_PATH;
    else throw Error("--birth: expected equal or path, got '" + birth + "'");
    const int steps = s.optionInt("steps-per-dispatch", int(o.stepsPerDispatch));
    if (steps < 1 || steps > 64) throw Error("--steps-per-dispatch: expected 1..64");
    o.stepsPerDispatch = uint32_t(steps);
    return o;
}

PmcEr::PmcEr(const RenderSettings& settings) : m_options(PmcErOptions::fromSettings(settings)) {}

RenderOutput PmcEr::render(RenderSession& session) {
    const RenderSettings& settings = session.settings();
    vk::Context& context = session.context();
    const PmcErOptions& o = m_options;
    const int width = session.width(), height = session.height();
    const uint32_t pixels = uint32_t(width) * uint32_t(height);

    // Population, the pool a pass uses (Npool = k P, k >= N / P) and the iterations using it up.
    const uint32_t population = o.population > 0 ? o.population
        : o.paperPopulation ? std::max<uint32_t>(64, uint32_t(std::lround(kPaperMembersPerPixel * pixels)))
                            : std::max<uint32_t>(64, pixels / kPixelsPerMember);
    const int components = int(o.radii.size());
    PathPopulation paths(population, components, o.resampleRate, o.epsilon, o.adaptRate);
    const uint32_t replacements = paths.replacementsPerIteration();
    // A render of fewer paths per pixel than a pass is one shorter pass.
    const uint32_t rounds = std::max(settings.spp > 0 ? std::min(o.passSpp, settings.spp) : o.passSpp,
                                     (population + pixels - 1) / pixels);
    const uint64_t poolPerPass = uint64_t(rounds) * pixels;
    const uint32_t iterations = replacements > 0
        ? 1u + uint32_t((poolPerPass - population + replacements - 1) / replacements)
        : 1u;
    const uint32_t passes = settings.spp > 0
        ? std::max<uint32_t>(1, uint32_t(std::lround(double(settings.spp) * pixels / double(poolPerPass))))
        : settings.timeLimit > 0.0 ? std::numeric_limits<uint32_t>::max()
                                   : std::max<uint32_t>(1, uint32_t(std::lround(double(kDefaultSpp) * pixels / double(poolPerPass))));

    // Each kernel in the variant for the scene's lights (punctual lights, an environment).
    auto kernel = [&](const std::string& path) -> const vk::Kernel& {
        return session.kernel(lightsKernelVariant(session.scene(), path));
    };
    const vk::Kernel& recordKernel = kernel("methods/pt/pt_record");
    const vk::Kernel& seedKernel = kernel("methods/pmc_er/pmc_er_seed");
    const vk::Kernel& mutateKernel = kernel("methods/pmc_er/pmc_er_mutate");
    const vk::Kernel& finishKernel = session.kernel("methods/pmc_er/pmc_er_finish");
    session.kernel(pathTracingKernel(session.scene(), "pt"));  // the pre-pass
    session.startClock();

    // e_d = E~ / (T N M) (PMC-ER eq. 4), E~ = P x mean pixel luminance (eq. 2-3).
    const double meanLuminance = estimateMeanLuminance(session, o.prepassSpp);
    const double imageEnergy = meanLuminance * double(pixels);
    const double mutationsPerPass = double(iterations) * double(population) * double(o.mutations);
    const float depositEnergy = float(imageEnergy / mutationsPerPass);
    // A path of luminance L carries L P / Npool of pixel value, L P / (Npool e_d) deposits.
    const float seedScale = float(double(pixels) / double(poolPerPass) / double(depositEnergy));

    Film& film = session.film();
    SplatFilm splat(context, width, height);
    const uint32_t recordCapacity = std::min<uint32_t>(kRecordChunk, std::max(population, replacements));
    vk::Buffer requests(context, recordCapacity * sizeof(gpu::SampleRequest), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                        "pmc-er pool requests");
    PathRecords records(context, recordCapacity, "pmc-er path");
    vk::Buffer seedSlots(context, recordCapacity * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                         "pmc-er seed slots");
    vk::Buffer chains(context, VkDeviceSize(population) * sizeof(gpu::ChainState), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      "pmc-er paths");
    vk::Buffer chainVertices(context, VkDeviceSize(population) * 2 * gpu::CHAIN_MAX_VERTICES * sizeof(gpu::ChainVertex),
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pmc-er path vertices");
    vk::Buffer members(context, VkDeviceSize(population) * sizeof(gpu::PmcErMember), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                       "pmc-er members", vk::MemoryUsage::Readback);
    vk::Buffer active(context, VkDeviceSize(population) * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      "pmc-er active members");
    vk::Buffer strategy(context, VkDeviceSize(pixels) * gpu::PMC_ER_MAX_RADII * sizeof(uint32_t),
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pmc-er strategy");
    strategy.fill(0);
    vk::Buffer pixelStats(context, pixels * sizeof(gpu::PixelChainStats), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                          "pmc-er pixel stats");
    pixelStats.fill(0);

    vk::DescriptorSet ptWork(session.layout(), vk::DescriptorSet::Kind::Work, "pmc-er pool paths");
    records.bindTracer(ptWork, session, requests);
    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "pmc-er population");
    records.bindSeeds(work);
    work.bind(gpu::ERPT_BINDING_CHAINS, chains);
    work.bind(gpu::ERPT_BINDING_CHAIN_VERTICES, chainVertices);
    work.bind(gpu::ERPT_BINDING_SPLAT, splat.pixels());
    work.bind(gpu::ERPT_BINDING_COUNTERS, film.counters());
    work.bind(gpu::ERPT_BINDING_PIXEL_STATS, pixelStats);
    RedistributionBatch batches(session);
    vk::CommandBatch& batch = batches.batch();
    work.bind(gpu::ERPT_BINDING_ENERGY, batches.energy());
    work.bind(gpu::PMC_ER_BINDING_MEMBERS, members);
    work.bind(gpu::PMC_ER_BINDING_STRATEGY, strategy);
    work.bind(gpu::PMC_ER_BINDING_SEED_SLOTS, seedSlots);
    work.bind(gpu::PMC_ER_BINDING_ACTIVE, active);

    gpu::PtPush ptPush{};
    ptPush.source = gpu::PT_SOURCE_LIST;
    ptPush.flags = 0;  // records only: the paths reach the image through their members
    ptPush.seed = settings.seed;
    ptPush.maxDepth = std::min(settings.maxDepth, gpu::PATH_MAX_VERTICES - 1);
    ptPush.rrDepth = settings.rrDepth;

    gpu::PmcErPush push{};
    push.seed = settings.seed;
    push.componentCount = uint32_t(components);
    push.seedScale = seedScale;
    for (int k = 0; k < components; ++k) {
        push.radii[k] = float(o.radii[size_t(k)]);
        push.initialAlpha[k] = float(o.initialAlpha[size_t(k)]);
    }
    push.causticProbability = o.causticProbability;
    push.birth = o.birth;
    // Q: a member's lifetime in mutations (units of e_d); by default the mean energy of a pool
    // path, the mutations a member makes on average. Like ERPT's chain length it does not change
    // the expected deposits, only how far each member carries them.
    push.birthEnergy = o.lifetime > 0.0 ? float(o.lifetime) : float(mutationsPerPass / double(poolPerPass));
    // The lens perturbation's angles past a D vertex: ERPT's default law (ERPT footnote 4).
    const PerturbationOptions erptDefaults;
    push.lensThetaMin = erptDefaults.causticThetaMin;
    push.lensThetaMax = erptDefaults.causticThetaMax;
    push.flags = (o.depositDirect ? gpu::ERPT_FLAG_DEPOSIT_DIRECT : 0u) |
                 (o.mixtureAcceptance ? gpu::PMC_ER_FLAG_MIXTURE_ACCEPTANCE : 0u);

    uint64_t mutationsRun = 0, eliminated = 0, iterationsRun = 0;
    double remainderEnergy = 0.0;  // deposited at the passes' ends, in units of e_d
    double drainedEnergy = 0.0;    // held by the population when the passes' drains started
    std::vector<double> alphaSum(size_t(components), 0.0);
    uint64_t alphaMembers = 0;
    DispatchSizer sizer(1024, population, session.targetDispatchSeconds());

    // Work goes into batches of a few dispatches (one submission each, on the render clock).
    const uint32_t perBatch = uint32_t(std::clamp(
        session.targetBatchSeconds() / session.targetDispatchSeconds(), 1.0, 64.0));
    uint32_t inBatch = 0;
    uint64_t batchUnits = 0;
    auto batchStart = std::chrono::steady_clock::now();
    auto flush = [&]() {
        if (inBatch == 0) return;
        batches.submit();
        if (batchUnits > 0)
            sizer.record(batchUnits, std::chrono::duration<double>(std::chrono::steady_clock::now() - batchStart).count());
        inBatch = 0;
        batchUnits = 0;
    };
    auto open = [&]() {
        if (inBatch > 0) return;
        batches.begin();
        batchStart = std::chrono::steady_clock::now();
    };

    // Records the path tracing of the next pool positions and the members made of them in
    // `slots` (chunks beyond the first need the record buffers again: submitted in between).
    // Slots beyond what is left of the pool stay empty.
    uint32_t seedDispatches = 0;  // in this pass: keeps the seed kernel's random numbers apart
    auto regenerate = [&](StratifiedPixelPool& pool, const std::vector<uint32_t>& slots, uint32_t pass) {
        for (size_t first = 0; first < slots.size() && pool.remaining() > 0; first += recordCapacity) {
            std::vector<PoolSample> samples =
                pool.next(uint32_t(std::min<size_t>(recordCapacity, slots.size() - first)));
            const uint32_t n = uint32_t(samples.size());
            // Traced in pixel order: neighbouring invocations trace neighbouring rays (the pool's
            // order spreads them over the image, which made tracing twice as slow on lavapipe).
            // Which slot a path fills does not matter.
            std::sort(samples.begin(), samples.end(), [](const PoolSample& x, const PoolSample& y) {
                return x.pixel != y.pixel ? x.pixel < y.pixel : x.sampleIndex < y.sampleIndex;
            });
            // The pixel's own sampler sequence places the position and drives the path.
            std::vector<gpu::SampleRequest> req(n);
            for (uint32_t i = 0; i < n; ++i) {
                req[i].pixel = samples[i].pixel;
                req[i].sampleIndex = samples[i].sampleIndex;
                req[i].raster = glm::vec2(0.0f);
            }
            flush();
            requests.upload(req.data(), n * sizeof(gpu::SampleRequest));
            seedSlots.upload(slots.data() + first, n * sizeof(uint32_t));
            open();
            batch.bind(ptWork);
            ptPush.invocationCount = n;
            ptPush.requestOffset = 0;
            ptPush.recordOffset = 0;
            // pt_record.comp takes several paths per invocation in turn on a CPU device.
            ptPush.itemsPerInvocation = ptItemsPerInvocation(session.context(), n);
            batch.dispatch(recordKernel, ptPush, (n + ptPush.itemsPerInvocation - 1) / ptPush.itemsPerInvocation);
            batch.bind(work);
            push.memberCount = n;
            push.pass = pass;
            push.iteration = seedDispatches++;
            batch.dispatch(seedKernel, push, n);
            inBatch += 2;
        }
    };
    // Regenerates `slots` until each holds a member with energy or the pool is used up: a path
    // born without shares (floor(U + E / Q) = 0, or only direct paths) leaves its slot empty,
    // and the next pool path takes it at once rather than an iteration later. Which slot a
    // path fills changes neither its energy nor its lifetime law: still unbiased.
    auto regenerateAlive = [&](StratifiedPixelPool& pool, std::vector<uint32_t> slots, uint32_t pass) {
        for (uint32_t round = 0; !slots.empty() && pool.remaining() > 0 && round < o.refillRounds; ++round) {
            regenerate(pool, slots, pass);
            flush();
            const auto state = members.download<gpu::PmcErMember>(population);
            std::vector<uint32_t> empty;
            for (uint32_t s : slots)
                if (!(state[s].remaining > 0.0f)) empty.push_back(s);
            slots.swap(empty);
        }
    };
    // Records `steps` mutations of every member with energy, in dispatches the sizer keeps short.
    // The members go through a list of those with energy in the order of their current pixels:
    // dispatching every slot left invocations idle on dead members (most of them late in a
    // pass), and slots in birth order made neighbouring invocations trace paths far apart in
    // the image. Which invocation runs a member changes none of its random numbers: same image.
    uint64_t activeSteps = 0;  // member steps dispatched (mutations made, or fewer at death)
    auto mutate = [&](uint32_t steps) {
        flush();
        const std::vector<uint32_t> list = activeMembers(members.download<gpu::PmcErMember>(population));
        if (list.empty()) return;
        active.upload(list);
        const uint32_t count = uint32_t(list.size());
        for (uint32_t done = 0; done < steps;) {
            push.steps = std::min(o.stepsPerDispatch, steps - done);
            for (uint32_t m = 0; m < count;) {
                open();
                batch.bind(work);
                push.memberBase = m;
                push.memberCount = std::min(sizer.units(), count - m);
                batch.dispatch(mutateKernel, push, push.memberCount);
                batchUnits += uint64_t(push.memberCount) * push.steps / o.stepsPerDispatch;
                activeSteps += uint64_t(push.memberCount) * push.steps;
                m += push.memberCount;
                if (++inBatch >= perBatch) flush();
            }
            done += push.steps;
        }
    };
    auto downloadMembers = [&]() {
        flush();
        auto state = members.download<gpu::PmcErMember>(population);
        for (auto& m : state) {
            mutationsRun += m.mutations;
            m.mutations = 0;  // counted: start afresh
        }
        members.upload(state);
        return state;
    };

    bool interrupted = false;
    // One generator for the whole render (pool shifts, survival draws). Not one PCG stream per
    // pass: streams whose increments differ by 2 repeat each other's outputs one step apart, so
    // render seeds r and r + 2 would share their passes' random numbers.
    Pcg32 rng(settings.seed, 0x504d432d4552ULL);  // "PMC-ER"
    if (depositEnergy > 0.0f && std::isfinite(depositEnergy) && std::isfinite(seedScale)) {
        PassClock clock(session);
        for (uint32_t pass = 0; pass < passes && clock.startPass(); ++pass) {
            StratifiedPixelPool pool(width, height, rounds, pass * rounds, rng);
            std::vector<uint32_t> all(population);
            for (uint32_t i = 0; i < population; ++i) all[i] = i;
            seedDispatches = 0;
            regenerateAlive(pool, all, pass);
            for (;;) {
                mutate(o.mutations);
                ++iterationsRun;
                auto state = downloadMembers();
                if (clock.abandon()) {
                    interrupted = true;
                    break;
                }
                if (pool.remaining() == 0) break;
                // Adapt, eliminate, regenerate (sec. 4.5).
                paths.adapt(state);
                const PathResampleResult r = paths.eliminate(state, rng);
                eliminated += r.eliminated;
                members.upload(state);
                // The eliminated members' slots and any other empty one (a member that has
                // deposited all its energy) take new paths.
                std::vector<uint32_t> empty;
                for (uint32_t i = 0; i < population; ++i)
                    if (!(state[i].remaining > 0.0f)) empty.push_back(i);
                regenerateAlive(pool, o.refillRounds > 1 ? empty : r.regenerate, pass);
            }
            if (interrupted) break;
            // Drain: the members go on mutating, without regeneration, until they have deposited
            // their energy (the population's energy grows over a pass: members without energy
            // deposit nothing, so fewer than N M deposits balance each iteration's seeds) or the
            // pass has made twice its budget of mutations; what is left is deposited at once.
            uint64_t drainBudget = uint64_t(iterations) * population * o.mutations;
            for (bool first = true;; first = false) {
                auto state = downloadMembers();
                double left = 0.0, most = 0.0;
                uint64_t alive = 0;
                for (const auto& m : state) {
                    left += std::max(0.0f, m.remaining) * m.shares;
                    most = std::max(most, double(m.remaining));
                    alive += m.remaining > 0.0f ? 1 : 0;
                }
                if (left <= 0.0 || drainBudget == 0 || clock.abandon()) break;
                const uint32_t steps = uint32_t(std::clamp(std::ceil(most), 1.0, double(4 * o.mutations)));
                drainBudget -= std::min<uint64_t>(drainBudget, alive * steps);
                if (first) drainedEnergy += left;
                mutate(steps);
            }
            if (clock.abandon()) {
                interrupted = true;
                break;
            }
            auto state = downloadMembers();
            for (const auto& m : state) {
                remainderEnergy += std::max(0.0f, m.remaining) * m.shares;
                for (int k = 0; k < components; ++k) alphaSum[size_t(k)] += m.alpha[k];
                ++alphaMembers;
            }
            batches.begin();
            batch.bind(work);
            push.memberBase = 0;
            push.memberCount = population;
            batch.dispatch(finishKernel, push, population);
            batches.submit();
            completeRedistributionPass(session, splat, depositEnergy, poolPerPass, pass, passes);
            clock.passDone();
        }
    }
    session.progress().finish();

    RenderOutput out;
    out.image = splat.resolve(depositEnergy);
    // Strategy image (PMC-ER fig. 6): the share of each radius among the mutations made at a
    // pixel as red, green, blue, scaled by the pixel's mutation count over the 99th percentile.
    auto counts = strategy.download<uint32_t>(size_t(pixels) * gpu::PMC_ER_MAX_RADII);
    std::vector<double> totals(pixels);
    for (uint32_t p = 0; p < pixels; ++p)
        totals[p] = double(counts[3 * p]) + double(counts[3 * p + 1]) + double(counts[3 * p + 2]);
    std::vector<double> sorted = totals;
    const size_t q = std::min<size_t>(sorted.size() - 1, size_t(0.99 * double(sorted.size())));
    std::nth_element(sorted.begin(), sorted.begin() + ptrdiff_t(q), sorted.end());
    const double bright = std::max(1.0, sorted[q]);
    Image strategyImage(width, height), mutationsImage(width, height);
    for (uint32_t p = 0; p < pixels; ++p) {
        const double scale = totals[p] > 0.0 ? std::min(1.0, totals[p] / bright) / totals[p] : 0.0;
        for (int c = 0; c < 3; ++c) {
            strategyImage.rgb[3 * p + size_t(c)] = float(double(counts[3 * p + size_t(c)]) * scale);
            mutationsImage.rgb[3 * p + size_t(c)] = float(totals[p]);
        }
    }
    out.diagnostics.push_back({"strategy", strategyImage});
    out.diagnostics.push_back({"mutations", mutationsImage});
    const int done = splat.completedPasses();
    out.cameraSamples = uint64_t(done) * poolPerPass;
    out.samplesPerPixel = double(out.cameraSamples) / double(pixels);

    const Counters& c = session.counters();
    const double seedEnergy = batches.seedEnergy(), depositedEnergy = batches.depositedEnergy();
    const double directEnergy = batches.directEnergy();
    nlohmann::json meanAlpha = nlohmann::json::array();
    for (int k = 0; k < components; ++k)
        meanAlpha.push_back(alphaMembers > 0 ? alphaSum[size_t(k)] / double(alphaMembers) : 0.0);
    out.methodStats = {
        {"passes", done},
        {"population", population},
        {"iterations_per_pass", iterations},  // without refills (--refill-rounds 1)
        {"iterations_run", iterationsRun},
        {"replacements_per_iteration", replacements},
        {"pool_paths_per_pass", poolPerPass},
        {"redistribute", o.depositDirect ? "indirect" : "all"},
        {"acceptance", o.mixtureAcceptance ? "mixture" : "component"},
        {"mutations_per_member", o.mutations},
        {"birth", o.birth == gpu::PMC_ER_BIRTH_EQUAL ? "equal" : "path"},
        {"birth_energy", push.birthEnergy},
        {"mean_luminance_prepass", meanLuminance},
        {"deposit_energy", depositEnergy},
        {"mutations", c.values[gpu::COUNTER_LENS_PROPOSED] + c.values[gpu::COUNTER_CAUSTIC_PROPOSED]},
        {"member_mutations", mutationsRun},  // as counted by the members (= mutations)
        {"active_member_steps", activeSteps},  // invocation steps dispatched, >= mutations
        {"eliminated", eliminated},
        {"mean_final_alpha", meanAlpha},
        // In units of e_d, completed passes and any interrupted one.
        {"seed_energy", seedEnergy},
        {"deposited_energy", depositedEnergy},
        {"remainder_energy", remainderEnergy},  // deposited by the members at the passes' ends
        {"drain_energy", drainedEnergy},
        // Zero in expectation only (path_population.h): the noise of survival and roulette.
        {"deposited_vs_seed_energy", seedEnergy > 0.0 ? depositedEnergy / seedEnergy - 1.0 : 0.0},
        // The share of the image's energy deposited straight from direct seed paths.
        {"direct_energy_share", directEnergy + seedEnergy > 0.0 ? directEnergy / (directEnergy + seedEnergy) : 0.0},
    };
    out.methodStats.update(mutationStatistics(c));
    return out;
}

MethodInfo pmcErMethod() {
    return {"pmc-er", "population Monte Carlo energy redistribution: a population of light paths, adapted radii",
        true,
        {{"population", "auto", "light paths in the population; auto = one per 4 pixels, paper = the paper's 5000 per 640x480 pixels (at least 64)"},
         {"mutations", "1", "mutations per member per iteration (paper 16-20; fewer measured better)"},
         {"radii", "5,10,50", "perturbation radii in pixels, 1 to 3, separated by , or / (strategy image: red, green, blue)"},
         {"resample-rate", "0.4", "share of the population eliminated (by remaining energy) and regenerated per iteration"},
         {"epsilon", "0.1", "floor of the radius weights alpha"},
         {"initial-alpha", "uniform", "a new member's radius weights: uniform (the paper) or one weight per radius (',' or '/' between; normalised)"},
         {"adapt-rate", "1", "how far each update moves a member's weights to sec. 4.5's (1: all the way, the paper; 0: they stay fixed)"},
         {"caustic-probability", "0.9", "gamma_caustic: chance of a caustic perturbation where it applies"},
         {"pass-spp", "4", "pool paths per pixel per pass, exactly that many in every pixel (sets the iterations); passes are averaged"},
         {"acceptance", "component", "component: each radius's own transition density (eq. 9); mixture: the density of the whole radius mixture (eq. 8)"},
         {"lifetime", "100", "Q, mutations a member of equal births lives (auto: the mean pool path energy in deposits, as the paper's mutations per iteration imply)"},
         {"refill-rounds", "8", "times a slot left empty by a birth without energy is refilled from the pool at once (1: never)"},
         {"redistribute", "indirect", "indirect: seed paths with at most one scattering vertex are deposited at their pixel, the rest make members; all: every path (the paper)"},
         {"prepass-spp", "4", "path-traced samples per pixel estimating the image energy"},
         {"steps-per-dispatch", "4", "mutations per member per dispatch"},
         {"birth", "equal", "equal: every member starts with the mean path energy Q and floor(U + E/Q) shares; path: the paper's E_remain = E", true}},
        [](const RenderSettings& s) { return std::make_unique<PmcEr>(s); }, ""};
}

}  // namespace pmcr
