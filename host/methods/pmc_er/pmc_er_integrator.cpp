#include "methods/pmc_er/pmc_er_integrator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <optional>

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
// --lanes auto: two lanes once each holds this many members (below, the host's steps are short
// next to the device's, and smaller dispatches would fill a device less).
constexpr uint32_t kMinLaneMembers = 2048;

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
    const std::string lanes = s.optionString("lanes", "auto");
    if (lanes != "auto") {
        const int n = s.optionInt("lanes", 0);
        if (n < 1 || n > 16) throw Error("--lanes: expected auto or 1..16");
        o.lanes = uint32_t(n);
    }
    return o;
}

PmcEr::PmcEr(const RenderSettings& settings) : m_options(PmcErOptions::fromSettings(settings)) {}

namespace {

// A generator for each pass's pool (lane kPoolLane: the same for every lane) and for each lane's
// survival draws in a pass: seeded by a hash of (render seed, pass, lane) on one stream (streams
// whose increments differ by 2 repeat each other's outputs one step apart), so that a lane's pass
// is a function of the seed alone, whatever the order the host comes to the lanes in.
constexpr uint32_t kPoolLane = 0xffffffffu;
Pcg32 passGenerator(uint32_t seed, uint32_t pass, uint32_t lane) {
    // splitmix64's finaliser (Steele, Lea and Flood, OOPSLA 2014).
    uint64_t z = ((uint64_t(seed) << 32) | pass) ^ (uint64_t(lane) * 0xd1b54a32d192ed03ULL);
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return Pcg32(z ^ (z >> 31), 0x504d432d4552ULL);  // "PMC-ER"
}

// One lane of the population (pmc_er_integrator.h): `size` members, the buffers, command batch and
// work sets they need, and where the lane is in its pass. A lane's batch holds one step of its
// schedule: a regeneration round, an iteration's mutations, a drain step or the pass's end.
struct Lane {
    enum class Phase { Idle, Regenerate, Mutate, Drain, Finish };

    Lane(RenderSession& session, uint32_t index_, uint32_t size_, const PmcErOptions& o, uint32_t pixels,
         const vk::Buffer& strategy, const vk::Buffer& pixelStats)
        : index(index_),
          size(size_),
          paths(size_, int(o.radii.size()), o.resampleRate, o.epsilon, o.adaptRate),
          batches(session, true),
          requests(session.context(), VkDeviceSize(size_) * sizeof(gpu::SampleRequest), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                   "pmc-er pool requests", vk::MemoryUsage::Upload),
          seedSlots(session.context(), VkDeviceSize(size_) * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                    "pmc-er seed slots", vk::MemoryUsage::Upload),
          chains(session.context(), VkDeviceSize(size_) * sizeof(gpu::ChainState), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                 "pmc-er paths"),
          chainVertices(session.context(), VkDeviceSize(size_) * 2 * gpu::CHAIN_MAX_VERTICES * sizeof(gpu::ChainVertex),
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pmc-er path vertices"),
          members(session.context(), VkDeviceSize(size_) * sizeof(gpu::PmcErMember), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                  "pmc-er members", vk::MemoryUsage::Readback),
          active(session.context(), VkDeviceSize(size_) * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                 "pmc-er active members", vk::MemoryUsage::Upload),
          film(session.context(), VkDeviceSize(pixels) * sizeof(gpu::SplatPixel), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
               "pmc-er lane film"),
          filmReadback(session.context(), VkDeviceSize(pixels) * sizeof(gpu::SplatPixel), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                       "pmc-er lane film (readback)", vk::MemoryUsage::Readback),
          records(session.context(), recordCapacity(), "pmc-er path"),
          ptWork(session.layout(), vk::DescriptorSet::Kind::Work, "pmc-er pool paths"),
          work(session.layout(), vk::DescriptorSet::Kind::Work, "pmc-er population") {
        film.fill(0);
        members.fill(0);
        records.bindTracer(ptWork, session, requests, &batches.counters());
        records.bindSeeds(work);
        work.bind(gpu::ERPT_BINDING_CHAINS, chains);
        work.bind(gpu::ERPT_BINDING_CHAIN_VERTICES, chainVertices);
        work.bind(gpu::ERPT_BINDING_SPLAT, film);
        work.bind(gpu::ERPT_BINDING_COUNTERS, batches.counters());
        work.bind(gpu::ERPT_BINDING_PIXEL_STATS, pixelStats);
        work.bind(gpu::ERPT_BINDING_ENERGY, batches.energy());
        work.bind(gpu::PMC_ER_BINDING_MEMBERS, members);
        work.bind(gpu::PMC_ER_BINDING_STRATEGY, strategy);
        work.bind(gpu::PMC_ER_BINDING_SEED_SLOTS, seedSlots);
        work.bind(gpu::PMC_ER_BINDING_ACTIVE, active);
    }

    // Pool paths traced at once: a regeneration of more slots traces them in chunks.
    uint32_t recordCapacity() const { return std::min(kRecordChunk, size); }

    uint32_t index;
    uint32_t size;
    PathPopulation paths;
    RedistributionBatch batches;
    vk::Buffer requests, seedSlots, chains, chainVertices, members, active, film, filmReadback;
    PathRecords records;
    vk::DescriptorSet ptWork, work;

    Phase phase = Phase::Idle;
    bool done = false;          // no pass left to take part in
    uint32_t pass = 0;          // the pass of the batch in flight
    uint32_t nextPass = 0;
    std::optional<StratifiedPixelPool> pool;  // this lane's share of the pass's pool
    Pcg32 rng;                                // survival draws (passGenerator, per pass)
    std::vector<uint32_t> slots;              // Regenerate: the slots the round fills
    uint32_t round = 0;                       // Regenerate: refill round
    uint32_t seedDispatches = 0;              // in this pass: keeps the seed kernel's numbers apart
    uint64_t drainBudget = 0;
    bool drainStarted = false;
    uint64_t batchUnits = 0;                  // mutation dispatch units in the batch (DispatchSizer)
};

}  // namespace

RenderOutput PmcEr::render(RenderSession& session) {
    const RenderSettings& settings = session.settings();
    const PmcErOptions& o = m_options;
    const int width = session.width(), height = session.height();
    const uint32_t pixels = uint32_t(width) * uint32_t(height);

    // Population, the pool a pass uses (Npool = k P, k >= N / P) and the iterations using it up.
    const uint32_t population = o.population > 0 ? o.population
        : o.paperPopulation ? std::max<uint32_t>(64, uint32_t(std::lround(kPaperMembersPerPixel * pixels)))
                            : std::max<uint32_t>(64, pixels / kPixelsPerMember);
    const int components = int(o.radii.size());
    const uint32_t replacements = PathPopulation(population, components, o.resampleRate, o.epsilon, o.adaptRate)
                                      .replacementsPerIteration();
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
    const uint32_t laneCount = std::min(population, o.lanes > 0 ? o.lanes : population >= 2 * kMinLaneMembers ? 2u : 1u);

    // Each kernel in the variant for the scene's lights (punctual lights, an environment).
    auto kernel = [&](const std::string& path) -> const vk::Kernel& {
        return session.kernel(lightsKernelVariant(session.scene(), path));
    };
    const vk::Kernel& recordKernel = kernel("methods/pt/pt_record");
    const vk::Kernel& seedKernel = kernel("methods/pmc_er/pmc_er_seed");
    const vk::Kernel& mutateKernel = kernel("methods/pmc_er/pmc_er_mutate");
    const vk::Kernel& finishKernel = session.kernel("methods/pmc_er/pmc_er_finish");
    session.kernel(pathTracingKernel(session.scene(), "pt"));  // the pre-pass
    // The buffers, before the clock starts (nothing in them depends on the pre-pass).
    vk::Context& context = session.context();
    SplatFilm splat(context, width, height);  // the completed passes (the lanes deposit on films of their own)
    vk::Buffer strategy(context, VkDeviceSize(pixels) * gpu::PMC_ER_MAX_RADII * sizeof(uint32_t),
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pmc-er strategy");
    strategy.fill(0);
    vk::Buffer pixelStats(context, pixels * sizeof(gpu::PixelChainStats), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                          "pmc-er pixel stats");
    pixelStats.fill(0);
    std::vector<std::unique_ptr<Lane>> lanes;
    for (uint32_t l = 0; l < laneCount; ++l)
        lanes.push_back(std::make_unique<Lane>(session, l, population / laneCount + (l < population % laneCount ? 1 : 0),
                                               o, pixels, strategy, pixelStats));

    session.startClock();

    // e_d = E~ / (T N M) (PMC-ER eq. 4), E~ = P x mean pixel luminance (eq. 2-3).
    const double meanLuminance = estimateMeanLuminance(session, o.prepassSpp);
    const double imageEnergy = meanLuminance * double(pixels);
    const double mutationsPerPass = double(iterations) * double(population) * double(o.mutations);
    const float depositEnergy = float(imageEnergy / mutationsPerPass);
    // A path of luminance L carries L P / Npool of pixel value, L P / (Npool e_d) deposits.
    const float seedScale = float(double(pixels) / double(poolPerPass) / double(depositEnergy));

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
    uint64_t activeSteps = 0;  // member steps dispatched (mutations made, or fewer at death)
    double hostSeconds = 0.0;  // the host's steps between a lane's batches
    DispatchSizer sizer(1024, population, session.targetDispatchSeconds());

    // Records the path tracing of the next positions of the lane's pool and the members made of
    // them in lane.slots (chunks of the record buffer, one after another in the batch); slots
    // beyond what is left of the pool stay empty. False when there is nothing to regenerate.
    auto recordRegenerate = [&](Lane& lane) -> bool {
        const uint32_t n = uint32_t(std::min<uint64_t>(lane.slots.size(), lane.pool->remaining()));
        if (n == 0) return false;
        std::vector<gpu::SampleRequest> req(n);
        const uint32_t capacity = lane.recordCapacity();
        for (uint32_t first = 0; first < n; first += capacity) {
            const uint32_t count = std::min(capacity, n - first);
            std::vector<PoolSample> samples = lane.pool->next(count);
            // Traced in pixel order: neighbouring invocations trace neighbouring rays (the pool's
            // order spreads them over the image, which made tracing twice as slow on lavapipe).
            // Which slot a path fills does not matter.
            std::sort(samples.begin(), samples.end(), [](const PoolSample& x, const PoolSample& y) {
                return x.pixel != y.pixel ? x.pixel < y.pixel : x.sampleIndex < y.sampleIndex;
            });
            // The pixel's own sampler sequence places the position and drives the path.
            for (uint32_t i = 0; i < count; ++i) {
                req[first + i].pixel = samples[i].pixel;
                req[first + i].sampleIndex = samples[i].sampleIndex;
                req[first + i].raster = glm::vec2(0.0f);
            }
        }
        lane.requests.upload(req.data(), n * sizeof(gpu::SampleRequest));
        lane.seedSlots.upload(lane.slots.data(), n * sizeof(uint32_t));
        lane.batches.begin();
        vk::CommandBatch& batch = lane.batches.batch();
        for (uint32_t first = 0; first < n; first += capacity) {
            const uint32_t count = std::min(capacity, n - first);
            batch.bind(lane.ptWork);
            ptPush.invocationCount = count;
            ptPush.requestOffset = first;
            ptPush.recordOffset = 0;
            // pt_record.comp takes several paths per invocation in turn on a CPU device.
            ptPush.itemsPerInvocation = ptItemsPerInvocation(context, count);
            batch.dispatch(recordKernel, ptPush, (count + ptPush.itemsPerInvocation - 1) / ptPush.itemsPerInvocation);
            batch.bind(lane.work);
            push.memberCount = count;
            push.slotBase = first;
            push.pass = lane.pass;
            push.iteration = lane.seedDispatches++ * laneCount + lane.index;
            batch.dispatch(seedKernel, push, count);
        }
        lane.batches.launch();
        lane.phase = Lane::Phase::Regenerate;
        return true;
    };
    // Records `steps` mutations of every member with energy, in dispatches the sizer keeps short.
    // The members go through a list of those with energy in the order of their current pixels:
    // dispatching every slot left invocations idle on dead members (most of them late in a
    // pass), and slots in birth order made neighbouring invocations trace paths far apart in
    // the image. Which invocation runs a member changes none of its random numbers: same image.
    // False when no member has energy.
    auto recordMutate = [&](Lane& lane, const std::vector<gpu::PmcErMember>& state, uint32_t steps,
                            Lane::Phase phase) -> bool {
        const std::vector<uint32_t> list = activeMembers(state);
        if (list.empty()) return false;
        lane.active.upload(list);
        const uint32_t count = uint32_t(list.size());
        lane.batches.begin();
        vk::CommandBatch& batch = lane.batches.batch();
        lane.batchUnits = 0;
        for (uint32_t done = 0; done < steps;) {
            push.steps = std::min(o.stepsPerDispatch, steps - done);
            for (uint32_t m = 0; m < count;) {
                batch.bind(lane.work);
                push.memberBase = m;
                push.memberCount = std::min(sizer.units(), count - m);
                batch.dispatch(mutateKernel, push, push.memberCount);
                lane.batchUnits += uint64_t(push.memberCount) * push.steps / o.stepsPerDispatch;
                activeSteps += uint64_t(push.memberCount) * push.steps;
                m += push.memberCount;
            }
            done += push.steps;
        }
        lane.batches.launch();
        lane.phase = phase;
        return true;
    };
    // The pass's end for this lane: every member deposits what it has left, and the lane's film
    // is copied out for the host and cleared for its next pass.
    auto recordFinish = [&](Lane& lane, const std::vector<gpu::PmcErMember>& state) {
        for (const auto& m : state) {
            remainderEnergy += std::max(0.0f, m.remaining) * m.shares;
            for (int k = 0; k < components; ++k) alphaSum[size_t(k)] += m.alpha[k];
            ++alphaMembers;
        }
        lane.batches.begin();
        vk::CommandBatch& batch = lane.batches.batch();
        batch.bind(lane.work);
        push.memberBase = 0;
        push.memberCount = lane.size;
        batch.dispatch(finishKernel, push, lane.size);
        batch.copy(lane.film, lane.filmReadback, lane.film.size());
        batch.fill(lane.film, 0);
        lane.batches.launch();
        lane.phase = Lane::Phase::Finish;
    };
    // Drain: the members go on mutating, without regeneration, until they have deposited their
    // energy (the population's energy grows over a pass: members without energy deposit
    // nothing, so fewer than N M deposits balance each iteration's seeds) or the pass has made
    // twice its budget of mutations; what is left is deposited at once.
    auto drainStep = [&](Lane& lane, const std::vector<gpu::PmcErMember>& state) {
        double left = 0.0, most = 0.0;
        uint64_t alive = 0;
        for (const auto& m : state) {
            left += std::max(0.0f, m.remaining) * m.shares;
            most = std::max(most, double(m.remaining));
            alive += m.remaining > 0.0f ? 1 : 0;
        }
        if (left > 0.0 && lane.drainBudget > 0) {
            const uint32_t steps = uint32_t(std::clamp(std::ceil(most), 1.0, double(4 * o.mutations)));
            lane.drainBudget -= std::min<uint64_t>(lane.drainBudget, alive * steps);
            if (!lane.drainStarted) drainedEnergy += left;
            lane.drainStarted = true;
            if (recordMutate(lane, state, steps, Lane::Phase::Drain)) return;
        }
        recordFinish(lane, state);
    };
    // After an iteration's mutations: the pass's drain once the lane's pool is used up, else
    // adapt, eliminate and regenerate (sec. 4.5).
    auto iterate = [&](Lane& lane, std::vector<gpu::PmcErMember>& state) {
        ++iterationsRun;
        if (lane.pool->remaining() == 0) {
            lane.drainBudget = uint64_t(iterations) * lane.size * o.mutations;
            lane.drainStarted = false;
            drainStep(lane, state);
            return;
        }
        lane.paths.adapt(state);
        const PathResampleResult r = lane.paths.eliminate(state, lane.rng);
        eliminated += r.eliminated;
        lane.members.upload(state);
        // The eliminated members' slots and any other empty one (a member that has deposited all
        // its energy) take new paths.
        std::vector<uint32_t> empty;
        for (uint32_t i = 0; i < lane.size; ++i)
            if (!(state[i].remaining > 0.0f)) empty.push_back(i);
        lane.slots = o.refillRounds > 1 ? std::move(empty) : r.regenerate;
        lane.round = 0;
        if (!recordRegenerate(lane) && !recordMutate(lane, state, o.mutations, Lane::Phase::Mutate))
            drainStep(lane, state);  // no member and nothing left to make one of
    };

    // Passes: a lane takes part in every pass in order, and at most two are open at once (a
    // lane done with pass p may start p + 1 while the others finish p). A pass is complete when
    // every lane has finished its share; its films' sum joins the image.
    PassClock clock(session);
    uint32_t passLimit = passes;   // lowered when the clock stops starting passes
    uint32_t dropFrom = passes;    // passes abandoned (time up or Ctrl-C) from this one on
    uint32_t started = 0, completed = 0;
    struct OpenPass {
        std::vector<uint64_t> deposits;
        uint32_t lanesDone = 0;
    };
    std::map<uint32_t, OpenPass> open;
    auto startPass = [&](Lane& lane) {
        const uint32_t pass = lane.nextPass;
        if (pass >= std::min(passLimit, dropFrom)) {
            lane.done = true;
            return;
        }
        if (pass >= started) {
            if (pass > completed + 1) return;  // waits for pass `completed` to complete
            if (!clock.startPass(pass)) {
                passLimit = pass;
                lane.done = true;
                return;
            }
            started = pass + 1;
        }
        lane.pass = pass;
        lane.nextPass = pass + 1;
        Pcg32 poolRng = passGenerator(settings.seed, pass, kPoolLane);
        lane.pool.emplace(width, height, rounds, pass * rounds, poolRng, lane.index, laneCount);
        lane.rng = passGenerator(settings.seed, pass, lane.index);
        lane.seedDispatches = 0;
        lane.slots.resize(lane.size);
        for (uint32_t i = 0; i < lane.size; ++i) lane.slots[i] = i;
        lane.round = 0;
        if (!recordRegenerate(lane)) recordFinish(lane, lane.members.download<gpu::PmcErMember>(lane.size));
    };
    // The host's step after a lane's batch completed: what it found, then the lane's next batch.
    auto step = [&](Lane& lane) {
        const Lane::Phase phase = lane.phase;
        lane.batches.complete();
        const auto hostStart = std::chrono::steady_clock::now();
        lane.phase = Lane::Phase::Idle;
        const double deviceSeconds = lane.batches.batch().lastDeviceSeconds();
        if ((phase == Lane::Phase::Mutate || phase == Lane::Phase::Drain) && deviceSeconds > 0.0)
            sizer.record(lane.batchUnits, deviceSeconds);
        if (lane.pass >= dropFrom || clock.abandon(lane.pass)) {
            dropFrom = std::min(dropFrom, lane.pass);  // this pass and any after it are dropped
            open.erase(open.lower_bound(dropFrom), open.end());
        } else if (phase == Lane::Phase::Finish) {
            std::vector<uint64_t> deposits = lane.filmReadback.download<uint64_t>(size_t(pixels) * 3);
            OpenPass& p = open[lane.pass];
            if (p.deposits.empty()) p.deposits = std::move(deposits);
            else for (size_t i = 0; i < deposits.size(); ++i) p.deposits[i] += deposits[i];
            // Passes complete in order: a lane finishes p before it starts p + 1.
            if (++p.lanesDone == laneCount) {
                splat.addPasses(p.deposits, 1);
                open.erase(lane.pass);
                ++completed;
                clock.passDone(lane.pass);
                reportRedistributionPass(session, splat, depositEnergy, poolPerPass, lane.pass, passes);
            }
            startPass(lane);
        } else {
            auto state = lane.members.download<gpu::PmcErMember>(lane.size);
            uint64_t made = 0;
            for (auto& m : state) {
                made += m.mutations;
                m.mutations = 0;  // counted: start afresh
            }
            if (made > 0) {
                mutationsRun += made;
                lane.members.upload(state);
            }
            if (phase == Lane::Phase::Regenerate) {
                // Slots whose birth had no shares (floor(U + E / Q) = 0, or only direct paths)
                // take the next pool paths at once rather than an iteration later. Which slot a
                // path fills changes neither its energy nor its lifetime law: still unbiased.
                std::vector<uint32_t> empty;
                for (uint32_t s : lane.slots)
                    if (!(state[s].remaining > 0.0f)) empty.push_back(s);
                lane.slots.swap(empty);
                if (++lane.round < o.refillRounds && recordRegenerate(lane)) {
                } else if (!recordMutate(lane, state, o.mutations, Lane::Phase::Mutate)) {
                    iterate(lane, state);
                }
            } else if (phase == Lane::Phase::Mutate) {
                iterate(lane, state);
            } else {
                drainStep(lane, state);
            }
        }
        hostSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - hostStart).count();
    };

    if (depositEnergy > 0.0f && std::isfinite(depositEnergy) && std::isfinite(seedScale)) {
        // The batches in flight, oldest first: the host waits for the oldest, works on its lane
        // and queues that lane's next batch behind the others'.
        std::deque<Lane*> inFlight;
        for (auto& lane : lanes) {
            startPass(*lane);
            if (lane->phase != Lane::Phase::Idle) inFlight.push_back(lane.get());
        }
        while (!inFlight.empty()) {
            Lane& lane = *inFlight.front();
            inFlight.pop_front();
            step(lane);
            if (lane.phase != Lane::Phase::Idle) inFlight.push_back(&lane);
            // A lane waiting for a pass to complete may go on now.
            for (auto& other : lanes)
                if (other->phase == Lane::Phase::Idle && !other->done &&
                    std::find(inFlight.begin(), inFlight.end(), other.get()) == inFlight.end()) {
                    startPass(*other);
                    if (other->phase != Lane::Phase::Idle) inFlight.push_back(other.get());
                }
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
    double seedEnergy = 0.0, depositedEnergy = 0.0, directEnergy = 0.0;
    for (const auto& lane : lanes) {
        seedEnergy += lane->batches.seedEnergy();
        depositedEnergy += lane->batches.depositedEnergy();
        directEnergy += lane->batches.directEnergy();
    }
    nlohmann::json meanAlpha = nlohmann::json::array();
    for (int k = 0; k < components; ++k)
        meanAlpha.push_back(alphaMembers > 0 ? alphaSum[size_t(k)] / double(alphaMembers) : 0.0);
    out.methodStats = {
        {"passes", done},
        {"population", population},
        {"lanes", laneCount},
        {"host_seconds", hostSeconds},  // the host's steps between a lane's batches
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
         {"lanes", "auto", "lanes the population is split into, adapted and resampled apart so that the host works on one while the device runs another (auto: 2 from 4096 members, else 1)"},
         {"birth", "equal", "equal: every member starts with the mean path energy Q and floor(U + E/Q) shares; path: the paper's E_remain = E", true}},
        [](const RenderSettings& s) { return std::make_unique<PmcEr>(s); }, ""};
}

}  // namespace pmcr
