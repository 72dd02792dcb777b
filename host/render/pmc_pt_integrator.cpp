#include "render/pmc_pt_integrator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "core/error.h"
#include "image/image.h"
#include "vk/command_batch.h"
#include "vk/context.h"

namespace pmcr {

namespace {

constexpr uint32_t kSlots = 8;              // dispatches per batch, each with its own buffers
constexpr uint32_t kSlotCapacity = 16384;   // camera samples per dispatch at most
constexpr double kPaperMembersPerPixel = 5000.0 / (640.0 * 480.0);
// Step t is weighted min(t, kRampSteps): the first steps' control variates come from few samples.
constexpr uint64_t kRampSteps = 8;

// The pixel a raster position lands in, as camera_sample_kernel.glsl computes it.
uint32_t pixelOf(glm::vec2 raster, int width, int height) {
    constexpr float oneMinusEpsilon = 0.99999994f;
    const float x = std::clamp(raster.x, 0.0f, float(width) * oneMinusEpsilon);
    const float y = std::clamp(raster.y, 0.0f, float(height) * oneMinusEpsilon);
    return uint32_t(y) * uint32_t(width) + uint32_t(x);
}

// Interleaves the bits of a pixel's coordinates (Morton order), so that sorting by it keeps
// neighbouring camera rays in neighbouring invocations.
uint32_t mortonCode(uint32_t x, uint32_t y) {
    auto spread = [](uint32_t v) {
        v &= 0xffffu;
        v = (v | (v << 8)) & 0x00ff00ffu;
        v = (v | (v << 4)) & 0x0f0f0f0fu;
        v = (v | (v << 2)) & 0x33333333u;
        v = (v | (v << 1)) & 0x55555555u;
        return v;
    };
    return spread(x) | (spread(y) << 1);
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
    const int adaptEvery = s.optionInt("adapt-every", int(o.adaptEvery));
    if (adaptEvery < 1) throw Error("--adapt-every: expected a positive number of resample steps");
    o.adaptEvery = uint32_t(adaptEvery);
    o.resampleRate = s.optionDouble("resample-rate", o.resampleRate);
    if (!(o.resampleRate >= 0.0 && o.resampleRate <= 1.0))
        throw Error("--resample-rate: expected a share of the population, 0..1");
    o.epsilon = s.optionDouble("epsilon", o.epsilon);
    if (!(o.epsilon >= 0.0 && o.epsilon < 1.0)) throw Error("--epsilon: expected 0 <= epsilon < 1");
    const std::string estimator = s.optionString("estimator", "weighted");
    if (estimator != "weighted" && estimator != "average")
        throw Error("--estimator: expected weighted or average, got '" + estimator + "'");
    o.plainAverage = estimator == "average";
    o.defensive = s.optionDouble("defensive", o.defensive);
    if (!(o.defensive >= 0.0 && o.defensive < 1.0))
        throw Error("--defensive: expected a share of the eye paths, 0 <= share < 1");
    if (!o.plainAverage && !(o.defensive > 0.0))
        throw Error("--defensive: the weighted estimator needs a positive share (it keeps the "
                    "proposal density positive on the whole image)");
    return o;
}

uint32_t PmcPtOptions::populationFor(uint64_t pixels) const {
    if (population > 0) return population;
    return uint32_t(std::max<double>(16.0, std::round(kPaperMembersPerPixel * double(pixels))));
}

PmcPt::PmcPt(const RenderSettings& settings) : m_options(PmcPtOptions::fromSettings(settings)) {}

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
    // A step's draws: TR per member plus the defensive pool draws, `defensive` of the total.
    const uint64_t mutationDraws = uint64_t(ps.size) * ps.mutations;
    const uint32_t poolDraws =
        o.defensive > 0.0
            ? uint32_t(std::max<double>(1.0, std::round(o.defensive * double(mutationDraws) /
                                                         (1.0 - o.defensive))))
            : 0u;
    const uint64_t drawsPerStep = mutationDraws + poolDraws;
    if (drawsPerStep > std::numeric_limits<uint32_t>::max() / 2)
        throw Error("pmc-pt: --population times --mutations is too large");
    // --spp N: N eye paths per pixel on average in all, in whole steps of equal size (the step
    // count is fixed in advance, so the steps' weights are deterministic).
    const uint64_t stepLimit =
        settings.spp > 0
            ? std::max<uint64_t>(1, uint64_t(std::llround(double(settings.spp) * pixels /
                                                          double(drawsPerStep))))
        : settings.timeLimit > 0.0
            ? std::numeric_limits<uint64_t>::max()
            : std::max<uint64_t>(1, uint64_t(std::llround(double(kDefaultSpp) * pixels /
                                                          double(drawsPerStep))));

    // Pipelines and buffers before the clock starts.
    const vk::Kernel& kernel = session.kernel("pt");
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
    push.source = gpu::PT_SOURCE_POINTS;
    push.flags = gpu::PT_FLAG_WRITE_RESULTS;
    push.seed = settings.seed;
    push.maxDepth = settings.maxDepth;
    push.rrDepth = settings.rrDepth;
    push.lightSamples = 1;
    vk::CommandBatch batch(session.layout(), &session.timer());
    DispatchSizer sizer(2048, kSlotCapacity, session.targetDispatchSeconds());

    // Path traces `requests` into `results` in dispatches of the sizer's size, a few per batch;
    // false when asked to stop first.
    auto trace = [&](const std::vector<gpu::SampleRequest>& requests,
                     std::vector<glm::vec4>& results) {
        results.resize(requests.size());
        const uint32_t perBatch = uint32_t(std::clamp(
            session.targetBatchSeconds() / session.targetDispatchSeconds(), 1.0, double(kSlots)));
        size_t done = 0;
        while (done < requests.size()) {
            if (session.shouldStop()) return false;
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
                batch.dispatch(kernel, push, count);
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
    PixelPopulation population(ps, width, height, rng);
    PositionPool pool(width, height);
    PixelImportance importance;
    const int k = population.components();

    // Per pixel: the weighted estimator's sum over steps of I_t, the plain sums, the luminance
    // statistics beta needs, and the strategy counts.
    std::vector<glm::dvec3> weightedSum(pixels, glm::dvec3(0.0));
    std::vector<glm::dvec3> plainSum(pixels, glm::dvec3(0.0));
    std::vector<glm::dvec3> control(pixels, glm::dvec3(0.0));
    std::vector<RunningStats> pixelLuminance(pixels);
    std::vector<std::array<uint32_t, kMaxPopulationRadii>> strategy(pixels, {0u, 0u, 0u});
    uint64_t steps = 0, samples = 0, adaptations = 0;
    double weightTotal = 0.0;  // sum of the steps' weights, which depend only on their number
    ResampleCounts resampled;

    auto estimate = [&](uint32_t p) {
        if (o.plainAverage)
            return pixelLuminance[p].count > 0 ? plainSum[p] / double(pixelLuminance[p].count)
                                               : glm::dvec3(0.0);
        return weightTotal > 0.0 ? weightedSum[p] / weightTotal : glm::dvec3(0.0);
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
    std::vector<double> density;
    std::vector<uint32_t> order, keys;
    std::vector<gpu::SampleRequest> sortedRequests;
    std::vector<glm::vec4> sortedResults;
    double hostSeconds = 0.0;  // population, densities and reduction: the method's own overhead
    auto since = [](std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    session.startClock();
    while (steps < stepLimit && !session.shouldStop()) {
        // The step's positions: every member's TR mutations, then the defensive pool draws.
        auto hostStart = std::chrono::steady_clock::now();
        draws.clear();
        population.drawMutations(rng, draws);
        const std::vector<glm::dvec2> poolPositions = pool.next(poolDraws, rng);
        for (const glm::dvec2& p : poolPositions) draws.push_back({p, PositionDraw::kPool, 0});
        // Their density Q_t, known before any of them is traced.
        const ProposalDensity proposal(population, poolDraws);
        requests.resize(draws.size());
        density.resize(draws.size());
        for (size_t j = 0; j < draws.size(); ++j) {
            const PositionDraw& d = draws[j];
            gpu::SampleRequest& r = requests[j];
            r.raster = glm::vec2(d.position);
            // Each path gets a sampler sequence of its own (stream = the draw's number in the
            // render). Sharing one across a member's mutations would stratify them, and then a
            // path's random numbers would depend on earlier paths' whose values decided where
            // this one goes: the estimator would no longer be unbiased given the past.
            const uint64_t draw = samples + j;
            r.pixel = uint32_t(draw);
            r.sampleIndex = uint32_t(draw >> 32);
            density[j] = proposal(d.position);
        }
        // Trace in Morton order of the pixels (coherent rays), results back in draw order.
        order.resize(draws.size());
        keys.resize(draws.size());
        for (uint32_t j = 0; j < order.size(); ++j) {
            order[j] = j;
            keys[j] = mortonCode(uint32_t(requests[j].raster.x), uint32_t(requests[j].raster.y));
        }
        std::stable_sort(order.begin(), order.end(),
                         [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
        sortedRequests.resize(draws.size());
        for (size_t i = 0; i < order.size(); ++i) sortedRequests[i] = requests[order[i]];
        hostSeconds += since(hostStart);
        if (!trace(sortedRequests, sortedResults)) break;  // an unfinished step is dropped whole
        hostStart = std::chrono::steady_clock::now();
        results.resize(draws.size());
        for (size_t i = 0; i < order.size(); ++i) results[order[i]] = sortedResults[i];

        // Reduce in draw order: I_t(pixel) = c + sum (L - c) / Q_t with c the plain average of
        // the pixel's earlier samples (see the header; the image's while it has none), the plain
        // sums, the tagged luminances and the strategy counts.
        glm::dvec3 imageSum(0.0);
        for (uint32_t p = 0; p < pixels; ++p) imageSum += plainSum[p];
        const glm::dvec3 imageMean = samples > 0 ? imageSum / double(samples) : glm::dvec3(0.0);
        for (uint32_t p = 0; p < pixels; ++p) {
            const uint32_t n = pixelLuminance[p].count;
            control[p] = n > 0 ? plainSum[p] / double(n) : imageMean;
        }
        const double stepWeight = double(std::min(steps + 1, kRampSteps));
        for (uint32_t p = 0; p < pixels; ++p) weightedSum[p] += stepWeight * control[p];
        for (size_t j = 0; j < draws.size(); ++j) {
            const uint32_t p = pixelOf(requests[j].raster, width, height);
            const glm::vec4 r = results[j];
            const glm::dvec3 radiance(r.x, r.y, r.z);
            weightedSum[p] += stepWeight * (radiance - control[p]) / density[j];
            plainSum[p] += radiance;
            pixelLuminance[p].add(r.w);
            population.record(draws[j], r.w);
            if (draws[j].member != PositionDraw::kPool) ++strategy[p][draws[j].component];
        }
        ++steps;
        weightTotal += stepWeight;
        samples += draws.size();
        population.endStep();

        // Adapt alpha and beta after the first step and every adapt-every steps (sec. 4.3.3).
        if (steps == 1 || steps % o.adaptEvery == 0) {
            population.adapt();
            std::vector<double> luminance(pixels);
            for (uint32_t p = 0; p < pixels; ++p) {
                const glm::dvec3 v = estimate(p);
                luminance[p] = 0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z;
            }
            importance.update(pixelLuminance, luminance);
            ++adaptations;
        }
        // Resample; pool replacements reuse positions this step already traced.
        const ResampleCounts c = population.resample(rng, poolPositions, importance);
        resampled.eliminated += c.eliminated;
        resampled.fromPool += c.fromPool;
        resampled.fromImportance += c.fromImportance;
        hostSeconds += since(hostStart);

        const double sppDone = double(samples) / double(pixels);
        const double fraction = stepLimit != std::numeric_limits<uint64_t>::max()
                                    ? double(steps) / double(stepLimit)
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
        {"estimator", o.plainAverage ? "average (biased)" : "weighted (D-kernel, unbiased)"},
        {"population", ps.size},
        {"mutations", ps.mutations},
        {"radii", radii},
        {"pool_draws_per_step", poolDraws},
        {"eye_paths_per_step", drawsPerStep},
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

}  // namespace pmcr
