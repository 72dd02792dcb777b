#include "methods/pmc_ip/pmc_ip_integrator.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>

#include "core/error.h"
#include "core/parallel.h"
#include "core/random.h"
#include "methods/pm/pm_integrator.h"
#include "methods/pt/pixel_order.h"
#include "methods/pt/pt_integrator.h"
#include "vk/command_batch.h"
#include "vk/context.h"

namespace pmcr {

namespace {

constexpr uint32_t kMaxRequestsInFlight = 1u << 20;  // per batch: 16 MiB of requests and results
// The host's per-request work spread over the cores in blocks of this many results, or pixel
// runs of requests (core/parallel.h).
constexpr size_t kReduceBlock = 4096;
constexpr size_t kRunBlock = 1024;

// A pixel's next `count` samples from sample `index` of its iteration, at `offset` in a batch.
struct Run {
    uint32_t pixel, index, count;
    size_t offset;
};

std::vector<MethodOption> pmcIpOptions(bool direct) {
    std::vector<MethodOption> options = {
        {"iterations", "0", "adaptive iterations after the first (0: as many as --spp or --time allow)"},
        {"initial-spp", "4", "samples per pixel of the first, uniform iteration"},
        {"spp-per-iteration", "4", "average samples per pixel of each adaptive iteration (N / pixels; on a GPU at least 2^23 / pixels unless given)"},
        {"epsilon", "0.01", "defensive weight: every pixel's mixture weight is at least epsilon / pixels"},
        {"min-spp", "1", "pilot samples every pixel gets in every iteration; they alone drive the adaptation"},
        {"variance-radius", "2", "a pixel's weight comes from its neighbours' pilot variance within this radius"},
        {"host-threads", "0", "threads adding the results and writing the requests (0: 1 on a CPU device, whose kernels need the cores, else every core); the image is the same for any count"},
    };
    if (direct)
        options.push_back({"light-samples", "1", "light samples (and as many BSDF samples) per camera sample"});
    options.push_back(pixelSamplerOption());
    return options;
}

// pmc-ip and pmc-ip-direct: the image-plane options, --pixel-sampler, and --mis for the MIS of
// the path tracer or direct lighting under them.
std::vector<MethodOption> pmcIpMisOptions(bool direct) {
    std::vector<MethodOption> options = pmcIpOptions(direct);
    options.push_back(misOption());
    return options;
}

// pmc-ip-hi: no --mis (PMC-HI weighs by its mixture, not MIS).
std::vector<MethodOption> pmcIpHiOptions() {
    std::vector<MethodOption> options = pmcIpOptions(false);
    for (MethodOption& o : pmcHiMethodOptions()) {
        // PMC-IP's --iterations counts image-plane iterations; PMC-HI's is per estimate.
        if (o.name == "iterations") o.name = "hi-iterations";
        options.push_back(o);
    }
    options.push_back({"feedback", "on", "seed each pixel's PMC-HI weights from its previous iteration (sec. 6.1)"});
    return options;
}

}  // namespace

PmcIp::PmcIp(const RenderSettings& settings, Estimator estimator)
    : m_estimator(estimator), m_baseline(parseBaselineOptions(settings)) {
    m_options.samplesPerIteration = settings.optionDouble("spp-per-iteration", 4.0);
    m_samplesPerIterationGiven = settings.options.count("spp-per-iteration") > 0;
    if (!(m_options.samplesPerIteration > 0.0 && m_options.samplesPerIteration <= 4096.0))
        throw Error("--spp-per-iteration: expected a number of samples per pixel in (0, 4096]");
    const int initial = settings.optionInt("initial-spp", 4);
    if (initial < 2 || initial > 4096) throw Error("--initial-spp: expected 2..4096");
    m_options.initialSpp = uint32_t(initial);
    m_options.epsilon = settings.optionDouble("epsilon", 0.01);
    if (!(m_options.epsilon > 0.0 && m_options.epsilon <= 1.0))
        throw Error("--epsilon: expected 0 < epsilon <= 1 (the defensive weight must be positive)");
    const int minSamples = settings.optionInt("min-spp", 1);
    if (minSamples < 0 || double(minSamples) > m_options.samplesPerIteration)
        throw Error("--min-spp: expected 0..spp-per-iteration");
    m_options.minSamples = uint32_t(minSamples);
    m_options.radius = settings.optionInt("variance-radius", 2);
    if (m_options.radius < 1 || m_options.radius > 16) throw Error("--variance-radius: expected 1..16 pixels");
    const int iterations = settings.optionInt("iterations", 0);
    if (iterations < 0) throw Error("--iterations: expected a count (0 = from --spp or --time)");
    m_iterations = uint32_t(iterations);
    const int hostThreads = settings.optionInt("host-threads", 0);
    if (hostThreads < 0 || hostThreads > 256) throw Error("--host-threads: expected 0..256 (0: from the device)");
    m_hostThreads = uint32_t(hostThreads);
    if (estimator == Estimator::Direct) {
        const int n = settings.optionInt("light-samples", 1);
        if (n < 1 || n > 1024) throw Error("--light-samples: expected 1..1024");
        m_lightSamples = uint32_t(n);
    }
    if (estimator == Estimator::PmcHi || estimator == Estimator::PhotonGather) {
        m_hi = parsePmcHiOptions(settings, "hi-iterations");
        m_feedback = settings.optionBool("feedback", true);
    }
    if (estimator == Estimator::PhotonGather) m_photons = PhotonMapOptions::fromSettings(settings);
}

RenderOutput PmcIp::render(RenderSession& session) {
    const RenderSettings& settings = session.settings();
    vk::Context& context = session.context();
    const vk::Kernel& kernel =
        session.kernel(m_estimator == Estimator::Full     ? pathTracingKernel(session.scene(), "pt")
                       : m_estimator == Estimator::Direct ? pathTracingKernel(session.scene(), "direct")
                       : m_estimator == Estimator::PmcHi  ? pmcHiKernel(session.scene())
                                                          : photonGatherKernel(session.scene(), true),
                       m_baseline.kernelOptions());
    Film& film = session.film();
    const uint32_t pixels = film.pixelCount();
    // Iterations sized to the device (issue 38): 4 spp at 256x256 keep an H200 busy for 2 ms,
    // less than the host takes to adapt; on a GPU an iteration takes at least 2^23 samples
    // unless --spp-per-iteration says otherwise (a function of the device and the image size
    // only, so the same seed on the same device gives the same image). pm-pmc keeps its
    // iterations: each is also a photon pass.
    ImagePlaneOptions options = m_options;
    if (!m_samplesPerIterationGiven && !context.isCpuDevice() && m_estimator != Estimator::PhotonGather)
        options.samplesPerIteration =
            std::clamp(std::floor(double(1u << 23) / double(pixels)), options.samplesPerIteration, 4096.0);
    ImagePlaneSampler sampler(film.width(), film.height(), options);
    // Several ranks adapt as one population: the pilot statistics are summed over them before
    // every allocation, PMC-HI's feedback sums after every iteration (core/communicator.h).
    Communicator& comm = session.comm();
    if (comm.distributed()) sampler.setPilotReduction([&comm](std::vector<double>& v) { comm.allReduceSum(v); });

    // Adaptive iterations after the first: asked for, or what --spp allows, or unbounded
    // under --time alone.
    uint64_t iterations = m_iterations;
    if (iterations == 0) {
        const double spp = settings.spp > 0 ? double(settings.spp)
                           : settings.timeLimit > 0.0 ? std::numeric_limits<double>::infinity()
                                                      : double(kDefaultSpp);
        const double rest = spp - double(options.initialSpp);
        iterations = std::isinf(rest) ? std::numeric_limits<uint32_t>::max()
                     : rest > 0.0    ? uint64_t(std::ceil(rest / options.samplesPerIteration - 1e-9))
                                     : 0;
    }
    const uint64_t totalIterations = iterations + 1;
    // Samples per pixel in all: --spp exactly (the last iteration takes what is left), or what
    // --iterations asks for.
    const double budgetSpp = m_iterations == 0 && settings.spp > 0
                                 ? std::max(double(settings.spp), double(options.initialSpp))
                                 : double(options.initialSpp) + double(iterations) * options.samplesPerIteration;

    // Two batches in flight (issue 38): while the device traces one, the host reduces the
    // other's results and writes the next one's requests. Each has its own requests, results,
    // counters and (PMC-HI) final weights, bound by its own descriptor set.
    const uint32_t capacity = kMaxRequestsInFlight / 2;
    struct BatchSlot {
        vk::Buffer requests, results, counters, alphaOut;
        std::unique_ptr<vk::DescriptorSet> work;
        std::unique_ptr<vk::CommandBatch> batch;
        std::vector<gpu::SampleRequest> list;
        std::vector<uint8_t> pilot;  // whether each request is a pilot sample of its iteration
        uint32_t dispatches = 0;
        uint64_t sequence = 0;       // submission order
        uint64_t iteration = 0;      // the iteration its requests belong to
        std::chrono::steady_clock::time_point submitted;
        bool pending = false;
    };
    std::array<BatchSlot, 2> slots;
    for (size_t i = 0; i < slots.size(); ++i) {
        BatchSlot& slot = slots[i];
        const std::string tag = " " + std::to_string(i);
        slot.requests = vk::Buffer(context, uint64_t(capacity) * sizeof(gpu::SampleRequest),
                                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pmc-ip requests" + tag, vk::MemoryUsage::Upload);
        slot.results = vk::Buffer(context, uint64_t(capacity) * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                  "pmc-ip results" + tag, vk::MemoryUsage::Readback);
        slot.counters = Film::makeCounters(context, "pmc-ip counters" + tag);
        slot.work = std::make_unique<vk::DescriptorSet>(session.layout(), vk::DescriptorSet::Kind::Work, "pmc-ip work" + tag);
        slot.work->bind(gpu::PT_BINDING_FILM, film.pixels());
        slot.work->bind(gpu::PT_BINDING_COUNTERS, slot.counters);
        slot.work->bind(gpu::PT_BINDING_REQUESTS, slot.requests);
        slot.work->bind(gpu::PT_BINDING_RESULTS, slot.results);
        slot.batch = std::make_unique<vk::CommandBatch>(session.layout(), &session.timer());
    }

    // PMC-HI feedback: the auxiliary image of starting weights (per pixel), each request's final
    // weights, and this iteration's per-pixel sums of them (count last).
    const bool pmcHi = m_estimator == Estimator::PmcHi || m_estimator == Estimator::PhotonGather;
    gpu::PmcHiPush hiPush{};
    // The starting weights of even and odd iterations: iteration t + 1's are written while the
    // device may still trace iteration t's last requests.
    std::array<vk::Buffer, 2> alphaStart;
    std::vector<float> auxiliary, iterationSums, requestAlpha;
    if (pmcHi) {
        hiPush.hi = pmcHiParamsForScene(m_hi, session.scene());
        if (m_feedback) hiPush.hi.flags |= gpu::PMC_HI_FLAG_FEEDBACK;
        auxiliary.assign(size_t(pixels) * gpu::PMC_HI_ALPHA_STRIDE, 0.0f);
        iterationSums.assign(size_t(pixels) * gpu::PMC_HI_ALPHA_STRIDE, 0.0f);
        for (vk::Buffer& a : alphaStart) {
            // Written at every iteration's cut, with batches in flight: mapped (through a
            // staging copy it would wait for them; issue 38).
            a = vk::Buffer(context, VkDeviceSize(pixels) * gpu::PMC_HI_MAX_COMPONENTS * sizeof(float),
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pmc-ip-hi starting alpha", vk::MemoryUsage::Upload);
            a.fill(0);
        }
        for (BatchSlot& slot : slots) {
            slot.alphaOut = vk::Buffer(context, VkDeviceSize(capacity) * gpu::PMC_HI_MAX_COMPONENTS * sizeof(float),
                                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pmc-ip-hi final alpha",
                                       vk::MemoryUsage::Readback);
            slot.alphaOut.fill(0);  // the kernel writes the slots in use only
            slot.work->bind(gpu::PMC_HI_BINDING_ALPHA, session.placeholder());
            slot.work->bind(gpu::PMC_HI_BINDING_ALPHA_START, alphaStart[0]);
            slot.work->bind(gpu::PMC_HI_BINDING_ALPHA_OUT, slot.alphaOut);
        }
    }

    gpu::PtPush push{};
    push.source = gpu::PT_SOURCE_LIST;
    push.flags = gpu::PT_FLAG_WRITE_RESULTS;
    push.maxDepth = m_estimator == Estimator::Full || m_estimator == Estimator::PhotonGather ? settings.maxDepth : 1;
    push.rrDepth = settings.rrDepth;
    push.lightSamples = m_lightSamples;

    DispatchSizer sizer(std::min<uint32_t>(pixels, 4096), capacity, session.targetDispatchSeconds());
    const uint32_t dispatchesPerBatch =
        uint32_t(std::max(1.0, session.targetBatchSeconds() / session.targetDispatchSeconds()));
    // The residual passes' offsets, and the render seed that scrambles every pixel's sequence
    // once for the whole render (see image_plane_sampler.h).
    Pcg32 rng(settings.seed, 0x504d432d4950ULL);  // "PMC-IP"
    push.seed = rng.nextUint();
    std::vector<glm::vec4> results;
    const std::vector<uint32_t> pixelOrder = mortonPixelOrder(film.width(), film.height());
    auto resolve = [&] { return sampler.image(); };

    // Host time spent adapting (alpha, DMS) and reducing results, to weigh against the GPU's.
    double adaptSeconds = 0.0;
    double reduceSeconds = 0.0;
    double requestWriteSeconds = 0.0;  // writing the requests (host_request_seconds)
    auto since = [](std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };

    // pm-pmc: a photon pass per image-plane iteration (photon_map.h).
    std::unique_ptr<PhotonMap> photonMap;
    if (m_estimator == Estimator::PhotonGather) photonMap = std::make_unique<PhotonMap>(session, m_photons, options.samplesPerIteration);

    // The iterations allocated and not yet fully reduced, oldest first, each with what its
    // requests need once the sampler has moved on to the next one: counts, first sequence
    // indices, pilots, and its request numbers over the whole render. Iteration t + 1 is
    // allocated when the results of iteration t's requests before `cut` are in; with the
    // overlap (pmc-ip, pmc-ip-direct on one process) the cut leaves out the last quarter of
    // t's requests, which the device traces meanwhile, so it never waits for the allocation.
    // The cut is a request number, so the same seed still gives the same image; the weights
    // still depend on no sample of their own pixel (image_plane_sampler.h), so the estimator
    // stays unbiased. PMC-HI's feedback (pmc-ip-hi) is taken at the cut too, from the final
    // weights of the requests reduced by then: it only seeds each estimate's mixture, which
    // any start leaves unbiased. pm-pmc's photon pass for iteration t + 1 is prepared at the
    // cut too: it was shot and sorted while t was traced, and goes to the buffers of t - 1's,
    // whose batches are all in (photon_map.h). No overlap across MPI ranks (whose collectives
    // run at iteration boundaries).
    struct Iteration {
        uint64_t number = 0;
        std::vector<uint32_t> counts, start;
        uint32_t pilots = 0;
        uint64_t first = 0, cut = 0, end = 0;
        uint32_t next = 0, index = 0;  // the next request: position in pixelOrder, sample
    };
    std::deque<Iteration> open;
    const bool overlap = !comm.distributed();
    bool done = false;          // no iteration after the last one allocated
    uint64_t allocations = 0;   // iterations allocated
    uint64_t issued = 0, reduced = 0, allocatedEnd = 0;

    // PMC-HI's feedback (sec. 6.1): the auxiliary image takes each sampled pixel's mean final
    // weights since the last feedback (pixels without an adapted estimate keep theirs) and
    // seeds iteration `number`'s estimates.
    auto feedback = [&](uint64_t number) {
        if (comm.distributed()) comm.allReduceSum(iterationSums);
        const auto feedbackStart = std::chrono::steady_clock::now();
        std::vector<float> start(size_t(pixels) * gpu::PMC_HI_MAX_COMPONENTS);
        for (uint32_t p = 0; p < pixels; ++p) {
            float* sum = &iterationSums[size_t(p) * gpu::PMC_HI_ALPHA_STRIDE];
            float* aux = &auxiliary[size_t(p) * gpu::PMC_HI_ALPHA_STRIDE];
            const float count = sum[gpu::PMC_HI_MAX_COMPONENTS];
            if (count > 0.0f) {
                for (uint32_t c = 0; c < gpu::PMC_HI_MAX_COMPONENTS; ++c) aux[c] = sum[c] / count;
                aux[gpu::PMC_HI_MAX_COMPONENTS] = 1.0f;
            }
            std::copy(aux, aux + gpu::PMC_HI_MAX_COMPONENTS, &start[size_t(p) * gpu::PMC_HI_MAX_COMPONENTS]);
            std::fill(sum, sum + gpu::PMC_HI_ALPHA_STRIDE, 0.0f);
        }
        // (No batch of iteration number - 2, which used this buffer, is still in flight.)
        if (m_feedback) alphaStart[number % 2].upload(start);
        adaptSeconds += since(feedbackStart);
    };
    bool feedbackDue = false;  // an iteration was allocated since the last feedback

    auto allocateNext = [&](uint64_t number) {
        if (pmcHi && feedbackDue) {
            feedback(number);
            feedbackDue = false;
        }
        // The ranks run each iteration together: on while any has budget left (a rank whose
        // budget is spent takes no samples), all stop when any must (time, Ctrl-C).
        if (session.shouldStopTogether() || !comm.anyTrue(number < totalIterations)) {
            done = true;
            return;
        }
        // The iteration's photon pass, shot and sorted while the iteration before it was traced
        // (photon_map.h), and the next one shot now. (No batch of iteration number - 2, which
        // read the buffers this pass goes to, is in flight.)
        if (photonMap)
            photonMap->preparePass(uint32_t(number), number + 1 >= totalIterations ? PhotonMap::Next::No
                                                     : settings.timeLimit > 0.0   ? PhotonMap::Next::IfLikelyGathered
                                                                                  : PhotonMap::Next::Yes);
        const auto adaptStart = std::chrono::steady_clock::now();
        // The last iteration of a --spp budget takes only what is left of it.
        // (None once it is spent: a rank whose share ends sooner still joins the iterations.)
        const double spp = number == 0 ? double(options.initialSpp)
                                       : std::clamp(budgetSpp - double(options.initialSpp) -
                                                        double(number - 1) * options.samplesPerIteration,
                                                    0.0, options.samplesPerIteration);
        Iteration it;
        it.number = number;
        it.counts = sampler.allocate(rng.nextDouble(), spp);
        it.start = sampler.sequenceStarts();
        it.pilots = number == 0 ? std::numeric_limits<uint32_t>::max() : sampler.iterationPilots();
        uint64_t requests = 0;
        for (uint32_t c : it.counts) requests += c;
        it.first = allocatedEnd;
        it.end = it.first + requests;
        it.cut = overlap && requests >= 4 ? it.end - requests / 4 : it.end;
        allocatedEnd = it.end;
        open.push_back(std::move(it));
        ++allocations;
        feedbackDue = true;
        adaptSeconds += since(adaptStart);
    };
    // The end of an iteration (all its results in, or the render stopping).
    auto completeIteration = [&]() {
        open.pop_front();
        sampler.finishIteration();
        session.snapshotIfDue(sampler.samplesTaken(), resolve);
    };
    // After `reduced` moved: completes the iterations whose results are all in and allocates
    // the next iteration once the newest one's results before its cut are.
    auto settle = [&]() {
        for (;;) {
            if (!open.empty() && open.front().end <= reduced && open.front().end <= issued) {
                completeIteration();
            } else if (!done && (open.empty() || open.back().cut <= reduced)) {
                allocateNext(allocations);
            } else {
                break;
            }
        }
    };

    // A batch that completed: its counters and results join the totals and the sampler, in
    // request order (the same seed gives the same sums), and the sizer learns from its time on
    // the device (from when it could start: submitted, and the batch before it done).
    InFlightTimer inFlight;
    // The per-request work (adding results, writing requests) on every core when the device is
    // not the CPU (--host-threads 0): on lavapipe its threads took the cores from the kernels,
    // and pmc-ip ran 15% slower (three pairs, cornell-glass 256x256, --spp 40).
    const size_t hostThreads = m_hostThreads > 0 ? m_hostThreads : context.isCpuDevice() ? 1 : 0;
    double requestSeconds = 0.0;  // the device's, over the requests reduced
    auto finishBatch = [&](BatchSlot& slot) {
        if (!slot.pending) return;
        const double seconds = inFlight.wait(*slot.batch, slot.submitted);
        slot.pending = false;
        const uint32_t n = uint32_t(slot.list.size());
        sizer.record(n / slot.dispatches, seconds / slot.dispatches);
        requestSeconds += seconds;
        Film::addCounters(slot.counters, session.counters());
        const auto reduceStart = std::chrono::steady_clock::now();
        double settleSeconds = 0.0;  // adapting, counted apart
        results.resize(n);
        slot.results.download(results.data(), uint64_t(n) * sizeof(glm::vec4));
        if (pmcHi) {
            requestAlpha.resize(size_t(n) * gpu::PMC_HI_MAX_COMPONENTS);
            slot.alphaOut.download(requestAlpha.data(), requestAlpha.size() * sizeof(float));
        }
        // The next request number at which settle() has something to do.
        auto nextEvent = [&] {
            uint64_t e = std::numeric_limits<uint64_t>::max();
            if (!open.empty()) e = std::min(e, open.front().end);
            if (!done && !open.empty()) e = std::min(e, open.back().cut);
            return e;
        };
        // Results [begin, end) added on the cores (a GPU's batches hold millions; issue 38). A
        // batch holds each of its pixels' samples in one run (nextRequests), and a block takes
        // the runs that begin in it, to their ends: every pixel's results are added in request
        // order by one thread, the sums the same bit for bit as one thread's.
        auto addResults = [&](uint32_t begin, uint32_t end) {
            parallelFor(end - begin, kReduceBlock, [&](size_t blockBegin, size_t blockEnd) {
                size_t k = begin + blockBegin, stop = begin + blockEnd;
                while (k > begin && k < stop && slot.list[k].pixel == slot.list[k - 1].pixel) ++k;
                while (stop < end && slot.list[stop].pixel == slot.list[stop - 1].pixel) ++stop;
                for (; k < stop; ++k) {
                    sampler.addPixelResult(slot.list[k].pixel, slot.pilot[k] != 0, glm::vec3(results[k]));
                    if (pmcHi) {
                        // Each pixel's sum of its samples' final weights this iteration.
                        const float* a = &requestAlpha[k * gpu::PMC_HI_MAX_COMPONENTS];
                        float* sum = &iterationSums[size_t(slot.list[k].pixel) * gpu::PMC_HI_ALPHA_STRIDE];
                        float total = 0.0f;
                        for (uint32_t c = 0; c < gpu::PMC_HI_MAX_COMPONENTS; ++c) total += a[c];
                        if (total > 0.0f) {
                            for (uint32_t c = 0; c < gpu::PMC_HI_MAX_COMPONENTS; ++c) sum[c] += a[c];
                            sum[gpu::PMC_HI_MAX_COMPONENTS] += 1.0f;
                        }
                    }
                }
            }, hostThreads);
            sampler.countResults(end - begin);
        };
        // In spans that end where settle() has something to do.
        uint64_t event = nextEvent();
        for (uint32_t k = 0; k < n;) {
            const uint64_t toEvent = event > reduced ? event - reduced : 1;
            const uint32_t end = toEvent < n - k ? uint32_t(k + toEvent) : n;
            addResults(k, end);
            reduced += end - k;
            k = end;
            if (reduced >= event) {
                const auto settleStart = std::chrono::steady_clock::now();
                settle();
                settleSeconds += since(settleStart);
                event = nextEvent();
            }
        }
        reduceSeconds += since(reduceStart) - settleSeconds;
        const double sppDone = double(sampler.samplesTaken()) / double(pixels);
        const double fraction = settings.timeLimit > 0.0 && !(settings.spp > 0 || m_iterations > 0)
                                    ? session.elapsedSeconds() / settings.timeLimit
                                    : sppDone / budgetSpp;
        session.progress().update(fraction, sppDone, "spp");
        session.snapshotIfDue(sampler.samplesTaken(), resolve);
    };

    // The next batch's requests: the open iterations' in order, walking the pixels in Morton
    // order (coherent rays), each pixel's samples the next points of its sequence. A batch ends
    // at an iteration's cut, so the batch before the cut can be reduced (and the next iteration
    // allocated) while the one after it runs.
    std::vector<Run> runs;
    auto nextRequests = [&](BatchSlot& slot, uint64_t wanted) {
        slot.list.clear();
        slot.pilot.clear();
        for (Iteration& it : open) {
            if (issued >= it.end) continue;
            const uint64_t limit = issued < it.cut ? it.cut : it.end;
            // The runs first (a pixel's next samples, at most what is wanted), then their
            // requests written on the cores.
            runs.clear();
            size_t size = 0;
            while (size < wanted && issued < limit) {
                const uint32_t pixel = pixelOrder[it.next];
                if (it.index >= it.counts[pixel]) {
                    ++it.next;
                    it.index = 0;
                    continue;
                }
                const uint32_t count = uint32_t(std::min<uint64_t>(
                    {it.counts[pixel] - it.index, wanted - size, limit - issued}));
                runs.push_back({pixel, it.index, count, size});
                size += count;
                it.index += count;
                issued += count;
            }
            slot.list.resize(size);
            slot.pilot.resize(size);
            parallelFor(runs.size(), kRunBlock, [&](size_t begin, size_t end) {
                for (size_t r = begin; r < end; ++r) {
                    const Run& run = runs[r];
                    for (uint32_t i = 0; i < run.count; ++i) {
                        slot.list[run.offset + i] = {run.pixel, it.start[run.pixel] + run.index + i, glm::vec2(0.0f)};
                        slot.pilot[run.offset + i] = run.index + i < it.pilots ? 1 : 0;
                    }
                }
            }, hostThreads);
            slot.iteration = it.number;
            break;  // one iteration (and one side of its cut) per batch
        }
    };

    session.startClock();
    settle();  // allocates the first iteration
    uint64_t sequence = 0;
    for (size_t turn = 0;; ++turn) {
        if (session.shouldStop()) break;
        BatchSlot& slot = slots[turn % 2];
        BatchSlot& other = slots[(turn + 1) % 2];
        finishBatch(slot);  // its results are needed before its buffers are written again
        // Under --time, another batch only if it ends the render nearer the limit (the one in
        // flight, unless finished, is taken as just begun; the next as many requests as it may
        // hold; both about as long per request as the batches so far; one rank alone: the
        // ranks stop together otherwise). pmc-ip-hi had written `--time 2` at 2.54 s on
        // lavapipe. The first two batches go untimed: one render of pm-pmc in about seven on
        // room still writes at 2.54-2.60 s (its first two took 0.8 s each), but smaller or
        // serialised first batches cost it more idle time.
        const uint32_t units = sizer.units();
        const uint64_t wanted = std::min<uint64_t>(capacity, uint64_t(units) * dispatchesPerBatch);
        if (settings.timeLimit > 0.0 && reduced > 0 && !session.comm().distributed()) {
            const double perRequest = requestSeconds / double(reduced);
            const bool running = other.pending && !other.batch->finished();
            if (!session.queueAnotherBatch(running ? double(other.list.size()) * perRequest : 0.0,
                                           double(wanted) * perRequest))
                break;
        }
        const auto requestStart = std::chrono::steady_clock::now();
        nextRequests(slot, wanted);
        requestWriteSeconds += since(requestStart);
        if (slot.list.empty()) {
            // Nothing to issue until the batch in flight is in (its results may allocate the
            // next iteration); with none in flight, the render is done.
            if (other.pending) {
                finishBatch(other);
                continue;
            }
            break;
        }
        // pm-pmc under --time: the next iteration's photons are shot once this one looks like
        // ending before the clock (from the device's seconds per request so far); a pass shot
        // and never gathered would cost the device its shoot.
        if (photonMap && settings.timeLimit > 0.0 && !done && allocations < totalIterations &&
            !photonMap->shotAhead(uint32_t(allocations)) && reduced > 0 &&
            session.elapsedSeconds() + double(allocatedEnd - reduced) * requestSeconds / double(reduced) <
                settings.timeLimit)
            photonMap->shootAhead(uint32_t(allocations));
        slot.requests.upload(slot.list);
        if (pmcHi) slot.work->bind(gpu::PMC_HI_BINDING_ALPHA_START, alphaStart[slot.iteration % 2]);
        if (photonMap) photonMap->bindPass(uint32_t(slot.iteration), *slot.work);
        vk::CommandBatch& batch = *slot.batch;
        batch.fill(slot.counters, 0);
        batch.bind(session.scene().descriptorSet());
        batch.bind(*slot.work);
        const uint32_t n = uint32_t(slot.list.size());
        for (uint32_t offset = 0; offset < n; offset += units) {
            push.requestOffset = offset;
            push.recordOffset = offset;  // pmc_hi.comp: request i's final alpha at i
            push.invocationCount = std::min(units, n - offset);
            if (pmcHi) {
                hiPush.pt = push;
                batch.dispatch(kernel, hiPush, push.invocationCount);
            } else {
                // pt.comp takes several requests per invocation in turn on a CPU device.
                const uint32_t perInvocation =
                    m_estimator == Estimator::Full ? ptItemsPerInvocation(context, push.invocationCount) : 1;
                push.itemsPerInvocation = perInvocation;
                batch.dispatch(kernel, push, (push.invocationCount + perInvocation - 1) / perInvocation);
            }
        }
        slot.dispatches = std::max<uint32_t>(batch.dispatchCount(), 1);
        slot.submitted = std::chrono::steady_clock::now();
        slot.sequence = sequence++;
        batch.submit();
        slot.pending = true;
        // The next photon pass, queued ahead of this batch, is sorted while it runs.
        if (photonMap) photonMap->buildNextInBackground();
        // While it runs: the batch before it.
        finishBatch(other);
    }
    // Stopped (time, Ctrl-C) or done: the batches in flight, oldest first; an iteration cut
    // short still ends (PMC-HI's feedback, the ranks' collectives), and a rank that stopped on
    // its own joins the others' decision to stop.
    if (slots[0].pending && slots[1].pending && slots[1].sequence < slots[0].sequence) finishBatch(slots[1]);
    for (BatchSlot& slot : slots) finishBatch(slot);
    while (!open.empty()) completeIteration();
    if (!done) {
        if (pmcHi && feedbackDue) feedback(allocations);  // the figure 7 maps; the ranks' collectives
        session.shouldStopTogether();
    }
    session.progress().finish();

    RenderOutput out;
    if (photonMap) out.methodStats = photonMap->stats();
    out.image = sampler.image();
    out.cameraSamples = sampler.samplesTaken();
    out.samplesPerPixel = double(out.cameraSamples) / double(pixels);
    out.diagnostics.emplace_back("alpha", sampler.alphaImage());
    out.diagnostics.emplace_back("samples", sampler.sampleCountImage());
    out.diagnostics.emplace_back("variance", sampler.varianceImage());
    out.methodStats["iterations_completed"] = sampler.iteration();
    out.methodStats["initial_spp"] = options.initialSpp;
    out.methodStats["host_adapt_seconds"] = adaptSeconds;
    out.methodStats["host_reduce_seconds"] = reduceSeconds;
    out.methodStats["host_request_seconds"] = requestWriteSeconds;
    out.methodStats["spp_per_iteration"] = options.samplesPerIteration;
    out.methodStats["epsilon"] = options.epsilon;
    out.methodStats["min_spp"] = options.minSamples;
    if (m_estimator == Estimator::Direct) out.methodStats["light_samples"] = m_lightSamples;
    if (pmcHi) {
        // The figure 7 maps from the auxiliary image after the last iteration.
        addPmcHiOutputs(out, hiPush.hi, session.scene(), auxiliary, film.width(), film.height());
        out.methodStats["feedback"] = m_feedback;
    }
    uint32_t maxCount = 0;
    for (float c : out.diagnostics[1].second.rgb) maxCount = std::max(maxCount, uint32_t(c));
    out.methodStats["max_samples_in_a_pixel"] = maxCount;
    return out;
}

MethodInfo pmPmcMethod() {
    std::vector<MethodOption> options = pmcIpHiOptions();
    for (MethodOption& o : PhotonMapOptions::methodOptions()) options.push_back(o);
    return {"pm-pmc",
            "photon mapping with its final gather driven by PMC-IP and PMC-HI with feedback (sec. 6) "
            "[BIASED]: consistent with --progressive on (the default)",
            false, options,
            [](const RenderSettings& s) { return std::make_unique<PmcIp>(s, PmcIp::Estimator::PhotonGather); },
            ""};
}

MethodInfo pmcIpMethod() {
    return {"pmc-ip", "PMC-IP adaptive image-plane sampling over path tracing", true,
        pmcIpMisOptions(false),
        [](const RenderSettings& s) { return std::make_unique<PmcIp>(s, PmcIp::Estimator::Full); },
        ""};
}

MethodInfo pmcIpDirectMethod() {
    return {"pmc-ip-direct", "PMC-IP adaptive image-plane sampling over MIS direct lighting", true,
        pmcIpMisOptions(true),
        [](const RenderSettings& s) { return std::make_unique<PmcIp>(s, PmcIp::Estimator::Direct); },
        ""};
}

MethodInfo pmcIpHiMethod() {
    return {"pmc-ip-hi", "PMC-IP adaptive image-plane sampling over PMC-HI direct lighting, with feedback",
        true, pmcIpHiOptions(),
        [](const RenderSettings& s) { return std::make_unique<PmcIp>(s, PmcIp::Estimator::PmcHi); },
        ""};
}

}  // namespace pmcr
