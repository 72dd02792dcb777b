#include "methods/pmc_pt/pmc_pt_integrator.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "core/error.h"
#include "image/image.h"
#include "methods/pt/pixel_order.h"
#include "methods/pt/pt_integrator.h"
#include "vk/command_batch.h"
#include "vk/context.h"

namespace pmcr {

namespace {

constexpr uint32_t kDispatchesPerBatch = 8;    // at most
constexpr uint32_t kDispatchCapacity = 16384;  // camera samples per dispatch at most
constexpr uint32_t kBatchesInFlight = 6;       // about 1.5 s of work on lavapipe
constexpr uint64_t kMaxStepDraws = 1u << 22;   // eye paths in a grown step at most
constexpr double kMaxOvershootSeconds = 0.2;   // --time: how far a step may end past the limit

// Traces a step's two request lists, the pool draws and the members' mutations, with up to
// kBatchesInFlight batches in flight (issue 38): queued lists are cut into batches in queue
// order, and the batches in flight keep the device busy while the host reduces a step,
// resamples the population and writes the next step's requests. Each list has its own requests
// and results on the device, so one can be traced while the other is written; each batch its
// own counters.
class StepTracer {
public:
    enum List { kPool = 0, kMembers = 1 };

    StepTracer(RenderSession& session, const vk::Kernel& kernel, const gpu::PtPush& push)
        : m_session(session), m_kernel(kernel), m_push(push),
          m_sizer(2048, kDispatchCapacity, session.targetDispatchSeconds()) {
        for (uint32_t b = 0; b < kBatchesInFlight; ++b) {
            Batch& batch = m_batches[b];
            const std::string tag = std::to_string(b);
            batch.counters = Film::makeCounters(session.context(), "pmc-pt counters " + tag);
            for (List list : {kPool, kMembers}) {
                batch.sets[list] = std::make_unique<vk::DescriptorSet>(
                    session.layout(), vk::DescriptorSet::Kind::Work, "pmc-pt work " + tag);
                batch.sets[list]->bind(gpu::PT_BINDING_FILM, session.film().pixels());
                batch.sets[list]->bind(gpu::PT_BINDING_COUNTERS, batch.counters);
            }
            batch.batch = std::make_unique<vk::CommandBatch>(session.layout(), &session.timer());
        }
    }
    // Room for `requests` requests of `list` on the device; none of its batches in flight.
    void reserve(List list, size_t requests) {
        Lane& lane = m_lanes[list];
        if (requests > lane.capacity) {
            const char* name = list == kPool ? "pmc-pt pool " : "pmc-pt members ";
            lane.capacity = requests;
            lane.requests =
                vk::Buffer(m_session.context(), lane.capacity * sizeof(gpu::SampleRequest),
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, std::string(name) + "requests",
                           vk::MemoryUsage::Upload);
            lane.results = vk::Buffer(m_session.context(), lane.capacity * sizeof(glm::vec4),
                                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                      std::string(name) + "results", vk::MemoryUsage::Readback);
            for (Batch& batch : m_batches) {
                batch.sets[list]->bind(gpu::PT_BINDING_REQUESTS, lane.requests);
                batch.sets[list]->bind(gpu::PT_BINDING_RESULTS, lane.results);
            }
        }
    }

    // Queues `requests` (taken; `requests` gets an old list back to reuse), traced with the
    // render seed `seed`, behind the lists queued before; `list`'s previous requests must be
    // finished. Each batch's requests are uploaded when it is recorded.
    void queue(List list, std::vector<gpu::SampleRequest>& requests, uint32_t seed) {
        reserve(list, requests.size());
        Lane& lane = m_lanes[list];
        lane.list.swap(requests);
        lane.size = lane.list.size();
        lane.submitted = lane.completed = 0;
        lane.seed = seed;
        m_order.push_back(list);
        submitBatches();
    }

    // Waits until `list`'s queued requests are traced and reads their results; false when the
    // render was interrupted first (then every queued list is dropped and nothing is in flight).
    // Once all of the list is submitted it can no longer be dropped: from then on its results are
    // read as they come in, and `resultsIn(n)` (if given) is told that the first n are there, so
    // the host can reduce them while the device traces the rest.
    bool finish(List list, std::vector<glm::vec4>& results,
                const std::function<void(size_t)>& resultsIn = nullptr) {
        if (m_dropped) return false;
        Lane& lane = m_lanes[list];
        results.resize(lane.size);
        size_t read = 0;
        for (;;) {
            submitBatches();
            if (lane.submitted == lane.size && lane.completed > read) {
                lane.results.download(&results[read], (lane.completed - read) * sizeof(glm::vec4),
                                      read * sizeof(glm::vec4));
                read = lane.completed;
                if (resultsIn) resultsIn(read);
            }
            if (lane.completed == lane.size) return true;
            if (m_inFlight == 0) {  // interrupted: nothing more is submitted
                m_order.clear();
                for (Lane& l : m_lanes) l.size = l.submitted = l.completed = 0;
                m_dropped = true;
                return false;
            }
            retireOldest();
        }
    }

    // The device's seconds per eye path over the batches completed so far (0 before the first).
    double secondsPerEyePath() const {
        return m_eyePaths > 0 ? m_deviceSeconds / double(m_eyePaths) : 0.0;
    }
    // The eye paths traced so far (batches completed).
    uint64_t eyePathsTraced() const { return m_eyePaths; }

private:
    struct Lane {
        std::vector<gpu::SampleRequest> list;  // on the host
        vk::Buffer requests, results;
        size_t capacity = 0, size = 0, submitted = 0, completed = 0;
        uint32_t seed = 0;
    };
    struct Batch {
        vk::Buffer counters;
        std::array<std::unique_ptr<vk::DescriptorSet>, 2> sets;  // per list
        std::unique_ptr<vk::CommandBatch> batch;  // destroyed first: waits for its submission
        List list = kPool;
        uint64_t samples = 0;
        uint32_t dispatches = 0;
        std::chrono::steady_clock::time_point submitted;
    };

    // Submits batches of the queued lists while a batch is free (one at first, until the sizer
    // has learned from it); none once interrupted.
    void submitBatches() {
        const uint32_t perBatch = uint32_t(std::clamp(
            m_session.targetBatchSeconds() / m_session.targetDispatchSeconds(), 1.0,
            double(kDispatchesPerBatch)));
        const uint32_t limit = m_retired > 0 ? kBatchesInFlight : 1;
        while (m_inFlight < limit && !m_order.empty() && !m_session.interrupted()) {
            const List list = m_order.front();
            Lane& lane = m_lanes[list];
            Batch& b = m_batches[(m_oldest + m_inFlight) % kBatchesInFlight];
            vk::CommandBatch& batch = *b.batch;
            batch.fill(b.counters, 0);
            batch.bind(m_session.scene().descriptorSet());
            batch.bind(*b.sets[list]);
            m_push.seed = lane.seed;
            const size_t first = lane.submitted;
            const size_t end =
                std::min<size_t>(lane.size, first + size_t(perBatch) * m_sizer.units());
            lane.requests.upload(&lane.list[first], (end - first) * sizeof(gpu::SampleRequest),
                                 first * sizeof(gpu::SampleRequest));
            uint32_t d = 0;
            for (; d < perBatch && lane.submitted < end; ++d) {
                const uint32_t count =
                    uint32_t(std::min<size_t>(m_sizer.units(), end - lane.submitted));
                m_push.requestOffset = uint32_t(lane.submitted);
                m_push.invocationCount = count;
                // pt.comp takes several requests per invocation in turn on a CPU device.
                m_push.itemsPerInvocation = ptItemsPerInvocation(m_session.context(), count);
                batch.dispatch(m_kernel, m_push,
                               (count + m_push.itemsPerInvocation - 1) / m_push.itemsPerInvocation);
                lane.submitted += count;
            }
            b.list = list;
            b.samples = lane.submitted - first;
            b.dispatches = d;
            b.submitted = std::chrono::steady_clock::now();
            batch.submit();
            ++m_inFlight;
            if (lane.submitted == lane.size) m_order.pop_front();
        }
    }

    // Waits for the oldest batch; the sizer learns from its time on the device.
    void retireOldest() {
        Batch& b = m_batches[m_oldest];
        const double seconds = m_timer.wait(*b.batch, b.submitted);
        m_sizer.record(b.samples / b.dispatches, seconds / double(b.dispatches));
        m_deviceSeconds += seconds;
        m_eyePaths += b.samples;
        Film::addCounters(b.counters, m_session.counters());
        m_lanes[b.list].completed += b.samples;
        m_oldest = (m_oldest + 1) % kBatchesInFlight;
        --m_inFlight;
        ++m_retired;
    }

    RenderSession& m_session;
    const vk::Kernel& m_kernel;
    gpu::PtPush m_push;
    DispatchSizer m_sizer;
    InFlightTimer m_timer;
    std::array<Lane, 2> m_lanes;
    std::deque<List> m_order;  // lists with requests not yet submitted, in queue order
    std::array<Batch, kBatchesInFlight> m_batches;
    uint32_t m_oldest = 0, m_inFlight = 0;
    uint64_t m_retired = 0;
    double m_deviceSeconds = 0.0;  // of the batches completed
    uint64_t m_eyePaths = 0;
    bool m_dropped = false;
};

// With several ranks (core/communicator.h): every rank's luminance statistics summed, and the
// mean of their pixel estimates, so that they all resample by the same importance beta'.
void poolImportanceStatistics(Communicator& comm, std::vector<RunningStats>& stats,
                              std::vector<double>& luminance) {
    const size_t pixels = stats.size();
    std::vector<double> v(4 * pixels);
    for (size_t p = 0; p < pixels; ++p) {
        v[4 * p + 0] = double(stats[p].count);
        v[4 * p + 1] = stats[p].sum;
        v[4 * p + 2] = stats[p].sumSq;
        v[4 * p + 3] = luminance[p];
    }
    comm.allReduceSum(v);
    for (size_t p = 0; p < pixels; ++p) {
        stats[p] = {uint32_t(v[4 * p]), v[4 * p + 1], v[4 * p + 2]};
        luminance[p] = v[4 * p + 3] / double(comm.size());
    }
}

}  // namespace

PmcPtOptions PmcPtOptions::fromSettings(const RenderSettings& s) {
    PmcPtOptions o;
    const std::string population = s.optionString("population", "auto");
    if (population != "auto") {
        const int n = s.optionInt("population", 0);
        if (n < 1 || n > 10000000) throw Error("--population: expected auto or 1..10000000");
        o.population = uint32_t(n);
    }
    const int mutations = s.optionInt("mutations", int(o.mutations));
    if (mutations < 1 || mutations > 4096) throw Error("--mutations: expected 1..4096");
    o.mutations = uint32_t(mutations);
    o.radii = parseRadii(s.optionString("radii", "5,10,50"));
    const int poolSpp = s.optionInt("pool-spp", int(o.poolSpp));
    if (poolSpp < 1 || poolSpp > 256) throw Error("--pool-spp: expected 1..256");
    o.poolSpp = uint32_t(poolSpp);
    const int adaptEvery = s.optionInt("adapt-every", int(o.adaptEvery));
    if (adaptEvery < 1) throw Error("--adapt-every: expected a positive number of resample steps");
    o.adaptEvery = uint32_t(adaptEvery);
    o.resampleRate = s.optionDouble("resample-rate", o.resampleRate);
    if (!(o.resampleRate >= 0.0 && o.resampleRate <= 1.0))
        throw Error("--resample-rate: expected a share of the population, 0..1");
    o.epsilon = s.optionDouble("epsilon", o.epsilon);
    if (!(o.epsilon >= 0.0 && o.epsilon < 1.0)) throw Error("--epsilon: expected 0 <= epsilon < 1");
    const std::string estimator = s.optionString("estimator", "steps");
    if (estimator != "steps" && estimator != "average")
        throw Error("--estimator: expected steps or average, got '" + estimator + "'");
    o.plainAverage = estimator == "average";
    o.stepGrowth = s.optionDouble("step-growth", o.stepGrowth);
    if (!(o.stepGrowth >= 1.0 && o.stepGrowth <= 4.0))
        throw Error("--step-growth: expected a factor per step, 1..4");
    o.defensive = s.optionDouble("defensive", o.defensive);
    if (!(o.defensive > 0.0 && o.defensive < 1.0))
        throw Error("--defensive: expected a share of the eye paths, 0 < share < 1");
    return o;
}

uint32_t PmcPtOptions::populationFor(uint64_t pixels) const {
    if (population > 0) return population;
    // Members whose TR mutations make `defensive` of a step's draws the pool's.
    const double poolDraws = double(poolSpp) * double(pixels);
    return uint32_t(std::max<double>(
        16.0, std::round(poolDraws * (1.0 - defensive) / (defensive * double(mutations)))));
}

PmcPt::PmcPt(const RenderSettings& settings)
    : m_options(PmcPtOptions::fromSettings(settings)), m_baseline(parseBaselineOptions(settings)) {}

RenderOutput PmcPt::render(RenderSession& session) {
    const RenderSettings& settings = session.settings();
    const PmcPtOptions& o = m_options;
    const int width = session.width(), height = session.height();
    const uint32_t pixels = uint32_t(width) * uint32_t(height);

    PopulationSettings ps;
    ps.size = o.populationFor(pixels);
    ps.mutations = o.mutations;
    ps.radii = o.radii;
    ps.resampleRate = o.resampleRate;
    ps.epsilon = o.epsilon;
    // The first step's draws (one unit): TR per member plus poolSpp pool draws in every pixel.
    // Step t is m_t units: m_t TR mutations per member and m_t poolSpp pool draws per pixel.
    const uint32_t poolSpp = o.poolSpp;
    const uint64_t mutationDraws = uint64_t(ps.size) * ps.mutations;
    const uint64_t poolDraws = uint64_t(poolSpp) * pixels;
    const uint64_t drawsPerStep = mutationDraws + poolDraws;
    if (drawsPerStep > std::numeric_limits<uint32_t>::max() / 2)
        throw Error("pmc-pt: --population times --mutations is too large");
    // A step's host buffers (requests, results, draws: about 50 bytes an eye path) stay near
    // 200 MB at most.
    const uint64_t maxMultiplier = std::max<uint64_t>(1, kMaxStepDraws / drawsPerStep);
    // --spp N: N eye paths per pixel on average in all, in whole units (the schedule of step
    // sizes is fixed in advance, so the steps' weights are deterministic).
    auto unitsFor = [&](double spp) {
        return std::max<uint64_t>(1, uint64_t(std::llround(spp * double(pixels) /
                                                           double(drawsPerStep))));
    };
    const uint64_t unitLimit = settings.spp > 0         ? unitsFor(double(settings.spp))
                               : settings.timeLimit > 0.0 ? std::numeric_limits<uint64_t>::max()
                                                          : unitsFor(double(kDefaultSpp));
    // Step sizes grow geometrically (--step-growth G: m_t = round(G^t) units, at most
    // maxMultiplier): early steps are small, so the population adapts soon, and later ones
    // large, so most of a pixel's samples are in few stratified sets (the step average gives up
    // the stratification between steps; see the header).
    auto scheduled = [&](uint64_t step) {
        const double m = std::round(std::pow(o.stepGrowth, double(std::min<uint64_t>(step, 64))));
        return uint64_t(std::clamp(m, 1.0, double(maxMultiplier)));
    };

    // Pipelines and buffers before the clock starts.
    const vk::Kernel& kernel =
        session.kernel(pathTracingKernel(session.scene(), "pt"), m_baseline.kernelOptions());
    gpu::PtPush push{};
    push.source = gpu::PT_SOURCE_LIST;
    push.flags = gpu::PT_FLAG_WRITE_RESULTS;
    push.seed = settings.seed;
    push.maxDepth = settings.maxDepth;
    push.rrDepth = settings.rrDepth;
    push.lightSamples = 1;
    StepTracer tracer(session, kernel, push);
    // The first step's (one unit; later ones grow them while none of their list is in flight).
    tracer.reserve(StepTracer::kPool, poolDraws);
    tracer.reserve(StepTracer::kMembers, mutationDraws);

    Pcg32 rng(settings.seed, 0x504d432d5054ULL);  // "PMC-PT"
    // Each step's render seed, which scrambles every pixel's sequence afresh. (One generator,
    // not one stream per step: PCG streams whose increments differ by 2 repeat each other's
    // outputs one step apart.)
    Pcg32 stepSeeds(settings.seed, 0x53544550ULL);  // "STEP"
    PixelPopulation population(ps, width, height, rng);
    PositionPool pool(width, height);
    PixelImportance importance;
    const int k = population.components();

    // Per pixel: the sum over steps of the step averages I_t, the plain sums, the luminance
    // statistics beta needs, and the strategy counts.
    std::vector<glm::dvec3> stepSum(pixels, glm::dvec3(0.0));
    std::vector<glm::dvec3> plainSum(pixels, glm::dvec3(0.0));
    std::vector<RunningStats> pixelLuminance(pixels);
    std::vector<std::array<uint32_t, kMaxPopulationRadii>> strategy(pixels, {0u, 0u, 0u});
    uint64_t steps = 0, units = 0, samples = 0, adaptations = 0;
    ResampleCounts resampled;

    auto estimate = [&](uint32_t p) {
        if (o.plainAverage)
            return pixelLuminance[p].count > 0 ? plainSum[p] / double(pixelLuminance[p].count)
                                               : glm::dvec3(0.0);
        // The steps' average weighted by their sizes in units, which depend only on the
        // schedule (and, with --time, on the clock), never on radiance values.
        return units > 0 ? stepSum[p] / double(units) : glm::dvec3(0.0);
    };
    auto resolve = [&] {
        Image image(width, height);
        for (uint32_t p = 0; p < pixels; ++p) {
            const glm::dvec3 v = estimate(p);
            image.rgb[3 * p + 0] = float(v.x);
            image.rgb[3 * p + 1] = float(v.y);
            image.rgb[3 * p + 2] = float(v.z);
        }
        return image;
    };

    // A step's host lists: the pool's requests and results (pixel p's stepPoolSpp draws at
    // stepPoolSpp times p's place in the Morton order), the members' (pixels in order, the draws
    // that landed in p from memberFirst[p] on, in draw order) and which draw each member
    // request is.
    std::vector<PositionDraw> draws;
    std::vector<gpu::SampleRequest> requests;
    requests.resize(std::max(poolDraws, mutationDraws));  // the first step's, before the clock
    std::vector<glm::vec4> poolResults, memberResults;
    std::vector<uint32_t> memberCount(pixels), memberFirst(pixels), next(pixels), drawOf;
    double hostSeconds = 0.0;  // population, requests and reduction: the method's own overhead
    auto since = [](std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    const std::vector<uint32_t> mortonPixels = mortonPixelOrder(width, height);
    std::vector<uint32_t> mortonRank(pixels);  // each pixel's place in mortonPixels
    for (uint32_t i = 0; i < pixels; ++i) mortonRank[mortonPixels[i]] = i;
    // The size in units of step `step`, decided while the step before it (`running` units, 0:
    // none) traces its members: the schedule's, at most what is left of --spp, and with --time
    // at most the units expected to end nearest the limit, from the device's time per eye path
    // so far. The device works through its queue without pause, so the running step ends once
    // the eye paths queued and not yet traced are, from now. (That used to be taken as every eye
    // path so far at the device's rate from the clock's start, which left out the host's share
    // of the clock: with batches reported done as they finish, `--time 3` wrote at 3.78 s once.)
    // 0 when the render is done.
    auto nextStepUnits = [&](uint64_t step, uint64_t running) -> uint64_t {
        uint64_t m = std::min(scheduled(step), unitLimit - units - running);
        const double perUnit = tracer.secondsPerEyePath() * double(drawsPerStep);
        if (settings.timeLimit > 0.0 && perUnit > 0.0) {
            const uint64_t queued = (units + running) * drawsPerStep;
            const uint64_t traced = std::min(queued, tracer.eyePathsTraced());
            const double runningEnds =
                session.elapsedSeconds() + double(queued - traced) * tracer.secondsPerEyePath();
            const double fit = std::max(0.0, (settings.timeLimit - runningEnds) / perUnit);
            // The units that end nearest the limit, but at most kMaxOvershootSeconds past it (a
            // unit, 8 spp at 256x256, takes 1.2 s on lavapipe: rounding to the nearest had
            // `--time 2` write its image at 2.5-2.6 s, past the T + 0.5; now it stops
            // after one unit, at 1.3 s).
            double whole = std::floor(fit);
            if (fit - whole >= 0.5 && (whole + 1.0 - fit) * perUnit <= kMaxOvershootSeconds) whole += 1.0;
            m = std::min<uint64_t>(m, uint64_t(whole));
        }
        return m;
    };
    Communicator& comm = session.comm();
    // Step `step`'s size, agreed by the ranks; none when the render stops.
    auto agreeStepUnits = [&](uint64_t step, uint64_t running) -> std::optional<uint64_t> {
        const bool more = units + running < unitLimit && !session.interrupted();
        const uint64_t m = more ? nextStepUnits(step, running) : 0;
        if (comm.distributed()) {
            // The ranks step together, since their importance statistics are pooled at every
            // adaptation: rank 0's step size (it has the largest share of --spp, and its clock
            // rules under --time), cut to what is left of each rank's own share (a rank whose
            // share is spent joins with an empty step); all stop when rank 0 is done or any
            // rank is interrupted.
            std::vector<double> agreed{comm.rank() == 0 ? double(m) : 0.0,
                                       session.interrupted() ? 1.0 : 0.0};
            comm.allReduceSum(agreed);
            if (agreed[0] == 0.0 || agreed[1] > 0.0) return std::nullopt;
            return std::min<uint64_t>(uint64_t(agreed[0]), unitLimit - units - running);
        }
        if (m == 0) return std::nullopt;
        return m;
    };
    // Queues step-to-be's pool draws: points 0 .. stepPoolSpp - 1 of every pixel's sequence,
    // scrambled afresh with the step's own seed, pixels in Morton order (coherent rays).
    auto queuePool = [&](uint64_t stepUnits) {
        const auto hostStart = std::chrono::steady_clock::now();
        const uint32_t stepPoolSpp = poolSpp * uint32_t(stepUnits);
        requests.resize(size_t(stepPoolSpp) * pixels);
        size_t r = 0;
        for (uint32_t p : mortonPixels)
            for (uint32_t i = 0; i < stepPoolSpp; ++i) requests[r++] = {p, i, glm::vec2(0.0f)};
        const uint32_t seed = stepSeeds.nextUint();
        hostSeconds += since(hostStart);
        tracer.queue(StepTracer::kPool, requests, seed);
        return seed;
    };

    // The steps overlap on the device (issue 38): step t + 1's pool draws are queued behind
    // step t's members, so the device traces them while the host reduces step t, resamples
    // and writes step t + 1's member requests. That changes nothing in the estimator: the pool
    // draws' pixels and sequence points depend on the schedule alone, never on radiance values
    // or the population, and step t + 1's size is decided (from the schedule and the clock)
    // before they are queued, as it was before step t + 1 began.
    session.startClock();
    std::optional<uint64_t> nextUnits = agreeStepUnits(0, 0);
    uint32_t nextSeed = nextUnits && *nextUnits > 0 ? queuePool(*nextUnits) : 0;
    while (nextUnits) {
        uint64_t stepUnits = *nextUnits;
        const uint32_t seed = nextSeed;
        const uint32_t stepPoolSpp = poolSpp * uint32_t(stepUnits);
        uint64_t total = 0;
        uint32_t members = 0;
        bool traced = true;
        if (stepUnits > 0) {
            // The members' draws: every member's m TR mutations (pixels). How many land in each
            // pixel depends on the past and the host's random numbers only, never on this step's
            // radiance values. They are points stepPoolSpp .. count_p - 1 of the pixel's sequence,
            // in draw order.
            const auto hostStart = std::chrono::steady_clock::now();
            draws.clear();
            population.drawMutations(rng, draws, ps.mutations * uint32_t(stepUnits));
            std::fill(memberCount.begin(), memberCount.end(), 0u);
            for (const PositionDraw& d : draws) ++memberCount[d.pixel];
            for (uint32_t p = 0; p < pixels; ++p) {
                memberFirst[p] = members;
                members += memberCount[p];
            }
            requests.resize(members);
            drawOf.resize(members);
            std::copy(memberFirst.begin(), memberFirst.end(), next.begin());
            for (uint32_t j = 0; j < draws.size(); ++j) {
                const uint32_t p = draws[j].pixel;
                requests[next[p]] = {p, stepPoolSpp + (next[p] - memberFirst[p]), glm::vec2(0.0f)};
                drawOf[next[p]++] = j;
            }
            total = uint64_t(stepPoolSpp) * pixels + members;
            hostSeconds += since(hostStart);
            tracer.queue(StepTracer::kMembers, requests, seed);
            // Interrupted: an unfinished step is dropped whole. With several ranks this one still
            // joins the step's collectives; the loop then stops on every rank.
            traced = tracer.finish(StepTracer::kPool, poolResults);
            if (!traced && !comm.distributed()) break;
        }
        // The next step's size and pool draws, while the device traces this step's members.
        nextUnits = agreeStepUnits(steps + 1, traced ? stepUnits : 0);
        if (nextUnits && *nextUnits > 0) nextSeed = queuePool(*nextUnits);

        // Reduce pixel by pixel, in order: the step's estimate I_t(p), the average of the step's
        // samples in p (see the header), the plain sums, the tagged luminances and the strategy
        // counts. The pool's samples first, then the members' in draw order: the same sums, bit
        // for bit, however the samples were batched. Pixel p is reduced as soon as its members'
        // results are in (they are in pixel order), while the device traces the later pixels'.
        uint32_t reduced = 0;  // pixels
        auto reduceUpTo = [&](size_t memberResultsIn) {
            const auto hostStart = std::chrono::steady_clock::now();
            for (; reduced < pixels; ++reduced) {
                const uint32_t p = reduced;
                if (memberFirst[p] + memberCount[p] > memberResultsIn) break;
                glm::dvec3 sum(0.0);
                const glm::vec4* pooled = &poolResults[size_t(mortonRank[p]) * stepPoolSpp];
                for (uint32_t i = 0; i < stepPoolSpp; ++i) {
                    sum += glm::dvec3(pooled[i].x, pooled[i].y, pooled[i].z);
                    pixelLuminance[p].add(pooled[i].w);
                }
                for (uint32_t i = memberFirst[p]; i < memberFirst[p] + memberCount[p]; ++i) {
                    const glm::vec4 r = memberResults[i];
                    sum += glm::dvec3(r.x, r.y, r.z);
                    pixelLuminance[p].add(r.w);
                    const PositionDraw& d = draws[drawOf[i]];
                    population.record(d, r.w);
                    ++strategy[p][d.component];
                }
                stepSum[p] += double(stepUnits) * sum / double(stepPoolSpp + memberCount[p]);
                plainSum[p] += sum;
            }
            hostSeconds += since(hostStart);
        };
        if (stepUnits > 0 && traced) {
            traced = tracer.finish(StepTracer::kMembers, memberResults, reduceUpTo);
            if (!traced && !comm.distributed()) break;
            if (traced) reduceUpTo(members);
        }
        if (!traced) {
            stepUnits = 0;  // no weight and no samples
            total = 0;
        }
        samples += total;
        const auto hostStart = std::chrono::steady_clock::now();
        ++steps;
        units += stepUnits;
        population.endStep();
        // The population adapts and resamples for the next step; after the last there is none.
        if (nextUnits) {
            // Regeneration from the pool takes fresh pool positions (PMC-PT sec. 4.3.2).
            const std::vector<glm::dvec2> poolPositions =
                pool.next(population.poolReplacementsPerStep(!importance.empty()), rng);

            // Adapt alpha and beta after the first step and every adapt-every steps (sec. 4.3.3).
            if (steps == 1 || steps % o.adaptEvery == 0) {
                population.adapt();
                std::vector<double> luminance(pixels);
                for (uint32_t p = 0; p < pixels; ++p) {
                    const glm::dvec3 v = estimate(p);
                    luminance[p] = 0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z;
                }
                if (comm.distributed()) {
                    std::vector<RunningStats> pooled = pixelLuminance;
                    poolImportanceStatistics(comm, pooled, luminance);
                    importance.update(pooled, luminance);
                } else {
                    importance.update(pixelLuminance, luminance);
                }
                ++adaptations;
            }
            const ResampleCounts c = population.resample(rng, poolPositions, importance);
            resampled.eliminated += c.eliminated;
            resampled.fromPool += c.fromPool;
            resampled.fromImportance += c.fromImportance;
        }
        hostSeconds += since(hostStart);

        const double sppDone = double(samples) / double(pixels);
        const double fraction = unitLimit != std::numeric_limits<uint64_t>::max()
                                    ? double(units) / double(unitLimit)
                                    : session.elapsedSeconds() / settings.timeLimit;
        session.progress().update(fraction, sppDone, "spp");
        session.snapshotIfDue(samples, resolve);
    }
    session.progress().finish();

    RenderOutput out;
    out.image = resolve();
    // Diagnostics: the share of each radius among the mutations that landed in a pixel (red,
    // green, blue = radius 1, 2, 3; PMC-PT figs. 3-4) and the eye paths per pixel.
    Image strategyImage(width, height), densityImage(width, height);
    for (uint32_t p = 0; p < pixels; ++p) {
        const auto& s = strategy[p];
        const double total = double(s[0]) + double(s[1]) + double(s[2]);
        for (int c = 0; c < kMaxPopulationRadii; ++c)
            strategyImage.rgb[3 * p + size_t(c)] = total > 0.0 ? float(s[size_t(c)] / total) : 0.0f;
        const float n = float(pixelLuminance[p].count);
        densityImage.rgb[3 * p] = densityImage.rgb[3 * p + 1] = densityImage.rgb[3 * p + 2] = n;
    }
    out.diagnostics.push_back({"strategy", strategyImage});
    out.diagnostics.push_back({"density", densityImage});
    out.cameraSamples = samples;
    out.samplesPerPixel = double(samples) / double(pixels);

    std::array<double, kMaxPopulationRadii> meanAlpha{};
    for (const auto& m : population.members())
        for (int c = 0; c < k; ++c) meanAlpha[size_t(c)] += m.alpha[size_t(c)];
    nlohmann::json alpha = nlohmann::json::array(), radii = nlohmann::json::array();
    for (int c = 0; c < k; ++c) {
        alpha.push_back(meanAlpha[size_t(c)] / double(population.members().size()));
        radii.push_back(o.radii[size_t(c)]);
    }
    out.methodStats = {
        {"estimator", o.plainAverage ? "average (biased)" : "steps (average of step averages, unbiased)"},
        {"population", ps.size},
        {"mutations", ps.mutations},
        {"radii", radii},
        {"pool_spp", poolSpp},
        {"eye_paths_per_unit", drawsPerStep},
        {"step_growth", o.stepGrowth},
        {"units", units},
        {"resample_steps", steps},
        {"adaptations", adaptations},
        {"mean_alpha", alpha},
        {"eliminated", resampled.eliminated},
        {"regenerated_from_pool", resampled.fromPool},
        {"regenerated_from_beta", resampled.fromImportance},
        {"host_seconds", hostSeconds},
    };
    return out;
}

MethodInfo pmcPtMethod() {
    return {"pmc-pt", "population Monte Carlo path tracing: a population of pixels mutated in disks",
        true,
        {{"population", "auto", "members; auto = as many as make --defensive of each step's eye paths the pool's"},
         {"mutations", "16", "TR: mutations per member per resample step"},
         {"radii", "5,10,50", "disk radii in pixels, 1 to 3, separated by , or / (strategy image: red, green, blue)"},
         {"pool-spp", "4", "pool eye paths in every pixel per resample step, stratified with the step's other samples there"},
         {"step-growth", "1.5", "step t is round(G^t) times the first step (pool eye paths and mutations per member); weights ∝ size; 1 = equal steps"},
         {"adapt-every", "1", "resample steps between alpha and beta updates (the paper's 100-200 are steps 1/30 this size)"},
         {"resample-rate", "0.4", "share of the population replaced per step (half pool, half beta)"},
         {"epsilon", "0.01", "floor of the alpha weights"},
         {"defensive", "0.5", "share of each step's eye paths from the stratified pool (uniform)"},
         {"estimator", "steps", "steps: the average of each step's per-pixel averages (unbiased); average: the paper's per-pixel average over all steps", true},
         pixelSamplerOption(), misOption()},
        [](const RenderSettings& s) { return std::make_unique<PmcPt>(s); }, ""};
}

}  // namespace pmcr
