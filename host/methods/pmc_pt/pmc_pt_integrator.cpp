#include "methods/pmc_pt/pmc_pt_integrator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "core/error.h"
#include "image/image.h"
#include "methods/pt/pixel_order.h"
#include "methods/pt/pt_integrator.h"
#include "vk/command_batch.h"
#include "vk/context.h"

namespace pmcr {

namespace {

constexpr uint32_t kSlots = 8;              // dispatches per batch, each with its own buffers
constexpr uint32_t kSlotCapacity = 16384;   // camera samples per dispatch at most
constexpr uint64_t kMaxStepDraws = 1u << 22;  // eye paths in a grown step at most

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
    Film& film = session.film();
    struct Slot {
        vk::Buffer requests;
        vk::Buffer results;
        std::unique_ptr<vk::DescriptorSet> set;
    };
    std::vector<Slot> slots(kSlots);
    for (uint32_t i = 0; i < kSlots; ++i) {
        Slot& s = slots[i];
        s.requests = vk::Buffer(session.context(), kSlotCapacity * sizeof(gpu::SampleRequest),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pmc-pt requests");
        s.results = vk::Buffer(session.context(), kSlotCapacity * sizeof(glm::vec4),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pmc-pt results",
                               vk::MemoryUsage::Readback);
        s.set = std::make_unique<vk::DescriptorSet>(session.layout(), vk::DescriptorSet::Kind::Work,
                                                    "pmc-pt work");
        s.set->bind(gpu::PT_BINDING_FILM, film.pixels());
        s.set->bind(gpu::PT_BINDING_COUNTERS, film.counters());
        s.set->bind(gpu::PT_BINDING_REQUESTS, s.requests);
        s.set->bind(gpu::PT_BINDING_RESULTS, s.results);
    }
    gpu::PtPush push{};
    push.source = gpu::PT_SOURCE_LIST;
    push.flags = gpu::PT_FLAG_WRITE_RESULTS;
    push.seed = settings.seed;
    push.maxDepth = settings.maxDepth;
    push.rrDepth = settings.rrDepth;
    push.lightSamples = 1;
    vk::CommandBatch batch(session.layout(), &session.timer());
    DispatchSizer sizer(2048, kSlotCapacity, session.targetDispatchSeconds());

    // Path traces `requests` into `results` in dispatches of the sizer's size, a few per batch;
    // false when interrupted first. The time limit does not stop a step midway (an unfinished
    // step is dropped whole, so its time would be spent for nothing): the loop below decides
    // before each step whether it is to run.
    auto trace = [&](const std::vector<gpu::SampleRequest>& requests,
                     std::vector<glm::vec4>& results) {
        results.resize(requests.size());
        const uint32_t perBatch = uint32_t(std::clamp(
            session.targetBatchSeconds() / session.targetDispatchSeconds(), 1.0, double(kSlots)));
        size_t done = 0;
        while (done < requests.size()) {
            if (session.interrupted()) return false;
            batch.fill(film.counters(), 0);
            batch.bind(session.scene().descriptorSet());
            struct Pending {
                size_t first;
                uint32_t count;
            };
            std::vector<Pending> pending;
            uint64_t batchSamples = 0;
            for (uint32_t d = 0; d < perBatch && done < requests.size(); ++d) {
                const uint32_t count =
                    uint32_t(std::min<size_t>(sizer.units(), requests.size() - done));
                slots[d].requests.upload(&requests[done], count * sizeof(gpu::SampleRequest));
                batch.bind(*slots[d].set);
                push.invocationCount = count;
                // pt.comp takes several requests per invocation in turn on a CPU device.
                push.itemsPerInvocation = ptItemsPerInvocation(session.context(), count);
                batch.dispatch(kernel, push, (count + push.itemsPerInvocation - 1) / push.itemsPerInvocation);
                pending.push_back({done, count});
                done += count;
                batchSamples += count;
            }
            const auto t0 = std::chrono::steady_clock::now();
            batch.submitAndWait();
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            for (size_t d = 0; d < pending.size(); ++d)
                slots[d].results.download(&results[pending[d].first],
                                          pending[d].count * sizeof(glm::vec4));
            sizer.record(batchSamples / pending.size(), seconds / double(pending.size()));
            film.addCounters(session.counters());
        }
        return true;
    };

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

    std::vector<PositionDraw> draws;
    std::vector<gpu::SampleRequest> requests;
    std::vector<glm::vec4> results;
    std::vector<uint32_t> count(pixels), first(pixels), next(pixels), drawOf;
    double hostSeconds = 0.0;  // population, requests and reduction: the method's own overhead
    auto since = [](std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    const std::vector<uint32_t> mortonPixels = mortonPixelOrder(width, height);
    // The next step's size in units: the schedule's, at most what is left of --spp, and with
    // --time at most the units expected (from the time per unit so far) to end nearest the
    // limit; 0 when the render is done.
    auto nextStepUnits = [&]() -> uint64_t {
        uint64_t m = std::min(scheduled(steps), unitLimit - units);
        if (settings.timeLimit > 0.0 && units > 0) {
            const double elapsed = session.elapsedSeconds();
            const double fit = (settings.timeLimit - elapsed) / (elapsed / double(units));
            m = std::min<uint64_t>(m, uint64_t(std::max(0.0, std::floor(fit + 0.5))));
        }
        return m;
    };
    session.startClock();
    Communicator& comm = session.comm();
    for (;;) {
        uint64_t stepUnits = units < unitLimit && !session.interrupted() ? nextStepUnits() : 0;
        if (comm.distributed()) {
            // The ranks step together, since their importance statistics are pooled at every
            // adaptation: rank 0's step size (it has the largest share of --spp, and its clock
            // rules under --time), cut to what is left of each rank's own share (a rank whose
            // share is spent joins with an empty step); all stop when rank 0 is done or any
            // rank is interrupted.
            std::vector<double> agreed{comm.rank() == 0 ? double(stepUnits) : 0.0,
                                       session.interrupted() ? 1.0 : 0.0};
            comm.allReduceSum(agreed);
            if (agreed[0] == 0.0 || agreed[1] > 0.0) break;
            stepUnits = std::min<uint64_t>(uint64_t(agreed[0]), unitLimit - units);
        } else if (stepUnits == 0) {
            break;
        }
        if (stepUnits > 0) {
            // The step's draws: every member's m TR mutations (pixels), then m poolSpp pool draws in
            // every pixel. How many land in each pixel depends on the past and the host's random
            // numbers only, never on this step's radiance values.
            auto hostStart = std::chrono::steady_clock::now();
            const uint32_t stepPoolSpp = poolSpp * uint32_t(stepUnits);
            draws.clear();
            population.drawMutations(rng, draws, ps.mutations * uint32_t(stepUnits));
            std::fill(count.begin(), count.end(), stepPoolSpp);
            for (const PositionDraw& d : draws) ++count[d.pixel];
            // Pixel p's samples are points 0 .. count_p - 1 of its sequence, scrambled afresh for the
            // step (the step's seed): the pool draws first, then the members' in draw order.
            uint32_t total = 0;
            for (uint32_t p : mortonPixels) {
                first[p] = total;
                total += count[p];
            }
            requests.resize(total);
            drawOf.assign(total, PositionDraw::kPool);
            for (uint32_t p = 0; p < pixels; ++p) next[p] = first[p] + stepPoolSpp;
            for (uint32_t j = 0; j < draws.size(); ++j) drawOf[next[draws[j].pixel]++] = j;
            for (uint32_t p : mortonPixels)
                for (uint32_t i = 0; i < count[p]; ++i) requests[first[p] + i] = {p, i, glm::vec2(0.0f)};
            push.seed = stepSeeds.nextUint();
            hostSeconds += since(hostStart);
            // Interrupted: an unfinished step is dropped whole. With several ranks this one still
            // joins the step's collectives; the loop then stops on every rank.
            const bool traced = trace(requests, results);
            if (!traced && !comm.distributed()) break;
            hostStart = std::chrono::steady_clock::now();
            if (!traced) {
                stepUnits = 0;  // no weight and no samples
                total = 0;
            }

            // Reduce pixel by pixel: the step's estimate I_t(p), the average of the step's samples
            // in p (see the header), the plain sums, the tagged luminances and the strategy counts.
            if (traced) {
                for (uint32_t p = 0; p < pixels; ++p) {
                    glm::dvec3 sum(0.0);
                    for (uint32_t i = first[p]; i < first[p] + count[p]; ++i) {
                        const glm::vec4 r = results[i];
                        sum += glm::dvec3(r.x, r.y, r.z);
                        pixelLuminance[p].add(r.w);
                        const uint32_t j = drawOf[i];
                        if (j != PositionDraw::kPool) {
                            population.record(draws[j], r.w);
                            ++strategy[p][draws[j].component];
                        }
                    }
                    stepSum[p] += double(stepUnits) * sum / double(count[p]);
                    plainSum[p] += sum;
                }
            }
            samples += total;
            hostSeconds += since(hostStart);
        }
        const auto hostStart = std::chrono::steady_clock::now();
        // Regeneration from the pool takes fresh pool positions (PMC-PT sec. 4.3.2).
        const std::vector<glm::dvec2> poolPositions =
            pool.next(population.poolReplacementsPerStep(!importance.empty()), rng);
        ++steps;
        units += stepUnits;
        population.endStep();

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
