#include "methods/erpt/erpt_integrator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "methods/energy_redistribution/energy_estimate.h"
#include "methods/energy_redistribution/path_records.h"
#include "methods/energy_redistribution/redistribution.h"
#include "methods/energy_redistribution/splat_film.h"
#include "methods/pt/pt_integrator.h"
#include "vk/command_batch.h"
#include "vk/context.h"

namespace pmcr {

namespace {

// Records (seed paths) held at once and chains alive at once: on a CPU device what keeps the
// buffers in its caches; on a GPU enough chains to fill it (hundreds of thousands of threads;
// issue 38), with the passes run together that it takes.
constexpr uint32_t kRecordChunkCpu = 16384;
constexpr uint32_t kChainCapacityCpu = 65536;
constexpr uint32_t kRecordChunkGpu = 1u << 18;
constexpr uint32_t kChainCapacityGpu = 1u << 18;

}  // namespace

ErptOptions ErptOptions::fromSettings(const RenderSettings& s) {
    ErptOptions o;
    const int chainLength = s.optionInt("chain-length", int(o.chainLength));
    if (chainLength < 1 || chainLength > 100000) throw Error("--chain-length: expected 1..100000");
    o.chainLength = uint32_t(chainLength);
    o.mutationsPerPixel = s.optionDouble("mutations-per-pixel", o.mutationsPerPixel);
    if (!(o.mutationsPerPixel > 0.0)) throw Error("--mutations-per-pixel: expected a positive number");
    const int prepass = s.optionInt("prepass-spp", int(o.prepassSpp));
    if (prepass < 1 || prepass > 4096) throw Error("--prepass-spp: expected 1..4096");
    o.prepassSpp = uint32_t(prepass);
    o.perturbation = PerturbationOptions::fromSettings(s);
    o.expectedValues = s.optionBool("expected-values", false);
    const std::string redistribute = s.optionString("redistribute", "indirect");
    if (redistribute != "all" && redistribute != "indirect")
        throw Error("--redistribute: expected all or indirect, got '" + redistribute + "'");
    o.depositDirect = redistribute == "indirect";
    o.filterProposalsRadius = s.optionInt("filter-proposals", 0);
    if (o.filterProposalsRadius < 0 || o.filterProposalsRadius > 32)
        throw Error("--filter-proposals: expected a box radius 0..32 (0 = off)");
    const int cap = s.optionInt("filter-consecutive", 0);
    if (cap < 0) throw Error("--filter-consecutive: expected a count (0 = off)");
    o.filterConsecutive = uint32_t(cap);
    const int together = s.optionInt("passes-per-batch", 0);
    if (together < 0 || together > 1024) throw Error("--passes-per-batch: expected 0..1024 (0 = from the device)");
    o.passesPerBatch = uint32_t(together);
    const int steps = s.optionInt("steps-per-dispatch", int(o.stepsPerDispatch));
    if (steps < 1 || steps > 64) throw Error("--steps-per-dispatch: expected 1..64");
    o.stepsPerDispatch = uint32_t(steps);
    return o;
}

Erpt::Erpt(const RenderSettings& settings) : m_options(ErptOptions::fromSettings(settings)) {}

void applyProposalFilter(Image& image, const std::vector<uint32_t>& proposals, int radius) {
    const int w = image.width, h = image.height;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const uint32_t own = proposals[size_t(y) * w + x];
            if (own == 0) continue;
            double sum = 0.0;
            int count = 0;
            for (int dy = -radius; dy <= radius; ++dy)
                for (int dx = -radius; dx <= radius; ++dx) {
                    const int px = x + dx, py = y + dy;
                    if (px < 0 || py < 0 || px >= w || py >= h) continue;
                    sum += proposals[size_t(py) * w + px];
                    ++count;
                }
            image.set(x, y, image.at(x, y) * float(sum / count / own));
        }
}

RenderOutput Erpt::render(RenderSession& session) {
    const RenderSettings& settings = session.settings();
    vk::Context& context = session.context();
    const ErptOptions& o = m_options;
    const uint32_t pixels = uint32_t(session.width()) * uint32_t(session.height());
    const uint32_t spp = settings.spp > 0 ? settings.spp
                         : settings.timeLimit > 0.0 ? std::numeric_limits<uint32_t>::max()
                                                    : kDefaultSpp;
    // Build the pipelines before the clock starts (compilation is not rendering).
    // Each kernel in the variant for the scene's lights (punctual lights, an environment).
    auto kernel = [&](const std::string& path) -> const vk::Kernel& {
        return session.kernel(lightsKernelVariant(session.scene(), path));
    };
    const vk::Kernel& recordKernel = kernel("methods/pt/pt_record");
    const vk::Kernel& countKernel = session.kernel("methods/erpt/erpt_count");
    const vk::Kernel& seedKernel = kernel("methods/erpt/erpt_seed");
    const vk::Kernel& chainKernel = kernel("methods/erpt/erpt_chains");
    session.kernel(pathTracingKernel(session.scene(), "pt"));  // the pre-pass
    session.startClock();

    // e_d = e_ave / k (ERPT eq. 7).
    const double meanLuminance = estimateMeanLuminance(session, o.prepassSpp);
    const float depositEnergy = float(meanLuminance / o.mutationsPerPixel);

    Film& film = session.film();
    SplatFilm splat(context, session.width(), session.height());
    const bool gpu = !context.isCpuDevice();
    const uint32_t chainCapacity = gpu ? kChainCapacityGpu : kChainCapacityCpu;
    // Seed passes run together, S: their seed paths are traced in one set of records and their
    // chains run side by side, into the same splat film; the image is the film over the passes
    // either way. The number of chains a pass starts is about pixels k / m: the seed energy,
    // pixels e_ave, over the m e_d each chain deposits, with e_d = e_ave / k (ERPT eq. 7 and
    // sec. 3.2; less with --redistribute indirect), so a GPU takes as many passes as fill
    // chainCapacity. A deterministic function of the options, the image size and the device.
    const double chainsPerPass = std::max(1.0, double(pixels) * o.mutationsPerPixel / double(o.chainLength));
    const uint32_t together =
        o.passesPerBatch > 0 ? o.passesPerBatch
        : gpu ? uint32_t(std::clamp(std::floor(double(chainCapacity) / chainsPerPass), 1.0, 64.0))
              : 1u;
    // Records: whole pixels' S samples each.
    const uint32_t recordLimit = gpu ? kRecordChunkGpu : kRecordChunkCpu;
    const uint32_t chunkPixels = std::max(1u, std::min(pixels, recordLimit / together));
    const uint32_t recordChunk = chunkPixels * together;
    PathRecords records(context, recordChunk, "erpt seed");
    vk::Buffer counts(context, recordChunk * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      "chain counts", vk::MemoryUsage::Readback);
    vk::Buffer offsets(context, (recordChunk + 1) * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "chain offsets");
    vk::Buffer chains(context, VkDeviceSize(chainCapacity) * sizeof(gpu::ChainState), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "chains");
    vk::Buffer chainVertices(context, VkDeviceSize(chainCapacity) * 2 * gpu::CHAIN_MAX_VERTICES * sizeof(gpu::ChainVertex),
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "chain vertices");
    vk::Buffer pixelStats(context, pixels * sizeof(gpu::PixelChainStats), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "pixel chain stats");
    pixelStats.fill(0);

    vk::DescriptorSet ptWork(session.layout(), vk::DescriptorSet::Kind::Work, "erpt seed pass");
    records.bindTracer(ptWork, session, session.placeholder());
    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "erpt chains");
    records.bindSeeds(work);
    work.bind(gpu::ERPT_BINDING_CHAIN_COUNTS, counts);
    work.bind(gpu::ERPT_BINDING_CHAIN_OFFSETS, offsets);
    work.bind(gpu::ERPT_BINDING_CHAINS, chains);
    work.bind(gpu::ERPT_BINDING_CHAIN_VERTICES, chainVertices);
    work.bind(gpu::ERPT_BINDING_SPLAT, splat.pixels());
    work.bind(gpu::ERPT_BINDING_COUNTERS, film.counters());
    work.bind(gpu::ERPT_BINDING_PIXEL_STATS, pixelStats);
    RedistributionBatch batches(session);
    vk::CommandBatch& batch = batches.batch();
    work.bind(gpu::ERPT_BINDING_ENERGY, batches.energy());

    gpu::PtPush ptPush{};
    ptPush.source = gpu::PT_SOURCE_TILE;
    ptPush.flags = 0;  // records only: the seed samples reach the image through their chains
    ptPush.seed = settings.seed;
    ptPush.maxDepth = std::min(settings.maxDepth, gpu::PATH_MAX_VERTICES - 1);
    ptPush.rrDepth = settings.rrDepth;

    gpu::ErptPush push{};
    push.seed = settings.seed;
    push.chainLength = o.chainLength;
    push.mutationMode = o.perturbation.mutationMode;
    push.depositEnergy = depositEnergy;
    push.seedScale = 1.0f;  // one seed sample per pixel per pass; passes are averaged
    push.lensRadius = o.perturbation.lensRadius;
    push.causticThetaMin = o.perturbation.causticThetaMin;
    push.causticThetaMax = o.perturbation.causticThetaMax;
    push.causticProbability = o.perturbation.causticProbability;
    push.flags = (o.expectedValues ? gpu::ERPT_FLAG_EXPECTED_VALUES : 0u) |
                 (o.depositDirect ? gpu::ERPT_FLAG_DEPOSIT_DIRECT : 0u);
    push.consecutiveCap = o.filterConsecutive;

    uint64_t chainsStarted = 0;
    uint64_t chainSteps = 0;  // mutations run, each depositing e_d in total (equal deposition)
    uint64_t submissions = 0;
    DispatchSizer sizer(4096, chainCapacity, session.targetDispatchSeconds());
    // Dispatches per submission: a batch lasts about targetBatchSeconds.
    const uint32_t dispatchesPerBatch =
        uint32_t(std::max(1.0, session.targetBatchSeconds() / session.targetDispatchSeconds()));
    auto submit = [&]() {
        batches.submit();
        ++submissions;
    };
    auto beginBatch = [&]() { batches.begin(); };
    if (depositEnergy > 0.0f && std::isfinite(depositEnergy)) {
        PassClock clock(session);
        for (uint32_t pass = 0; pass < spp && clock.startPass();) {
            // This batch of passes: S, or what --spp leaves.
            const uint32_t passesNow = std::min(together, spp - pass);
            push.pass = pass;
            ptPush.samplesPerPixel = passesNow;  // record i S + k: the pixel's sample of pass + k
            bool interrupted = false;
            for (uint32_t first = 0; first < pixels && !interrupted; first += chunkPixels) {
                const uint32_t nPixels = std::min(chunkPixels, pixels - first);
                const uint32_t n = nPixels * passesNow;  // records
                // Seed samples and their chain counts.
                beginBatch();
                batch.bind(ptWork);
                ptPush.pixelOffset = first;
                ptPush.invocationCount = nPixels;
                ptPush.sampleBase = pass;
                ptPush.recordOffset = 0;
                // pt_record.comp takes several paths per invocation in turn on a CPU device.
                // (Tile mode: the items are the pixels, each with all its S samples.)
                ptPush.itemsPerInvocation = ptItemsPerInvocation(session.context(), nPixels);
                batch.dispatch(recordKernel, ptPush,
                               (nPixels + ptPush.itemsPerInvocation - 1) / ptPush.itemsPerInvocation);
                batch.bind(work);
                push.recordCount = n;
                batch.dispatch(countKernel, push, n);
                submit();
                auto chainCounts = counts.download<uint32_t>(n);
                std::vector<uint32_t> prefix(n + 1, 0);
                uint64_t total = 0;
                for (uint32_t r = 0; r < n; ++r) {
                    prefix[r] = uint32_t(total);
                    total += chainCounts[r];
                }
                if (total > std::numeric_limits<uint32_t>::max())
                    throw Error("erpt: more than 2^32 chains in one pass; raise --chain-length or lower --mutations-per-pixel");
                prefix[n] = uint32_t(total);
                offsets.upload(prefix.data(), prefix.size() * sizeof(uint32_t));
                chainsStarted += total;

                // Run the chains, chainCapacity at a time, a few mutations per dispatch and a
                // few dispatches per submission.
                for (uint64_t start = 0; start < total && !interrupted; start += chainCapacity) {
                    const uint32_t group = uint32_t(std::min<uint64_t>(chainCapacity, total - start));
                    beginBatch();
                    batch.bind(work);
                    push.chainOffset = uint32_t(start);
                    push.chainBase = 0;
                    push.chainCount = group;
                    batch.dispatch(seedKernel, push, group);
                    uint32_t inBatch = 0;
                    uint64_t batchUnits = 0;
                    auto batchStart = std::chrono::steady_clock::now();
                    for (uint32_t done = 0; done < o.chainLength;) {
                        push.steps = std::min(o.stepsPerDispatch, o.chainLength - done);
                        for (uint32_t c = 0; c < group;) {
                            push.chainBase = c;
                            push.chainCount = std::min(sizer.units(), group - c);
                            batch.dispatch(chainKernel, push, push.chainCount);
                            chainSteps += uint64_t(push.chainCount) * push.steps;
                            batchUnits += push.chainCount;
                            c += push.chainCount;
                            if (++inBatch < dispatchesPerBatch) continue;
                            submit();
                            const double seconds = std::chrono::duration<double>(
                                std::chrono::steady_clock::now() - batchStart).count();
                            sizer.record(batchUnits / inBatch, seconds / inBatch);
                            inBatch = 0;
                            batchUnits = 0;
                            beginBatch();
                            batch.bind(work);
                            batchStart = std::chrono::steady_clock::now();
                        }
                        done += push.steps;
                        if (clock.abandon()) {
                            interrupted = true;
                            break;
                        }
                    }
                    submit();
                }
            }
            if (interrupted) break;
            pass += passesNow;
            completeRedistributionPass(session, splat, depositEnergy, pixels, pass - 1, spp, passesNow);
            clock.passDone();
        }
    }
    session.progress().finish();

    RenderOutput out;
    out.image = splat.resolve(depositEnergy);
    auto stats = pixelStats.download<gpu::PixelChainStats>(pixels);
    std::vector<uint32_t> proposals(pixels);
    Image chainsImage(session.width(), session.height()), proposalsImage(session.width(), session.height());
    for (uint32_t i = 0; i < pixels; ++i) {
        proposals[i] = stats[i].proposals;
        const float c = float(stats[i].chainsStarted), p = float(stats[i].proposals);
        chainsImage.rgb[3 * i] = chainsImage.rgb[3 * i + 1] = chainsImage.rgb[3 * i + 2] = c;
        proposalsImage.rgb[3 * i] = proposalsImage.rgb[3 * i + 1] = proposalsImage.rgb[3 * i + 2] = p;
    }
    if (o.filterProposalsRadius > 0) applyProposalFilter(out.image, proposals, o.filterProposalsRadius);
    out.diagnostics.push_back({"chains", chainsImage});
    out.diagnostics.push_back({"proposals", proposalsImage});
    const int passes = splat.completedPasses();
    out.cameraSamples = uint64_t(passes) * pixels;
    out.samplesPerPixel = passes;

    const double seedEnergy = batches.seedEnergy(), depositedEnergy = batches.depositedEnergy();
    const double directEnergy = batches.directEnergy();
    out.methodStats = {
        {"passes", passes},
        {"mean_luminance_prepass", meanLuminance},
        {"deposit_energy", depositEnergy},
        {"chain_length", o.chainLength},
        {"mutations_per_pixel_per_pass", o.mutationsPerPixel},
        {"chains_started", chainsStarted},
        {"seed_energy", seedEnergy},        // in units of e_d, all passes
        {"deposited_energy", depositedEnergy},
        {"chain_steps", chainSteps},
        {"passes_per_batch", together},
        {"submissions", submissions},
        // The chains' energy that did not land, relative to the e_d per step they carry: zero by
        // construction (a rejected or invalid proposal still deposits at the current path), up
        // to float rounding of the sums; only dropped deposits (NaN, biased filters) make it
        // positive.
        {"energy_not_deposited", chainSteps > 0 ? 1.0 - depositedEnergy / double(chainSteps) : 0.0},
        // Deposited relative to seed energy, minus one: zero in expectation only (ERPT sec. 3.2),
        // it is the noise of the floor(U + e / (m e_d)) chain counts.
        {"deposited_vs_seed_energy", seedEnergy > 0.0 ? depositedEnergy / seedEnergy - 1.0 : 0.0},
        // The share of the image's energy deposited straight from direct seed paths
        // (--redistribute indirect), not by chains.
        {"direct_energy_share", directEnergy + seedEnergy > 0.0 ? directEnergy / (directEnergy + seedEnergy) : 0.0},
        {"biased_filters", o.filterProposalsRadius > 0 || o.filterConsecutive > 0},
    };
    out.methodStats.update(mutationStatistics(session.counters()));
    return out;
}

MethodInfo erptMethod() {
    std::vector<MethodOption> options = {
        {"chain-length", "100", "mutations per chain, m"},
        {"mutations-per-pixel", "4", "k: e_d = mean pixel luminance / k, per seed pass (--spp passes)"},
        {"prepass-spp", "4", "path-traced samples per pixel estimating the mean luminance"}};
    for (const MethodOption& o : PerturbationOptions::help()) options.push_back(o);
    for (const MethodOption& o : std::vector<MethodOption>{
             {"expected-values", "off", "deposit a e_d at the proposal and (1-a) e_d at the current path"},
             {"redistribute", "indirect", "all seed paths, or indirect: the emitter seen directly and direct light at the first hit are deposited at their pixel"},
             {"steps-per-dispatch", "4", "mutations per chain per dispatch"},
             {"passes-per-batch", "0", "seed passes whose chains run together (0: 1 on a CPU device, enough to fill a GPU)"},
             {"filter-proposals", "0", "proposed-mutation filter box radius (ERPT 4.4)", true},
             {"filter-consecutive", "0", "cap on consecutive deposits per pixel (ERPT 4.4)", true}})
        options.push_back(o);
    return {"erpt", "energy redistribution path tracing (equal deposition, lens and caustic perturbations)",
            true, options, [](const RenderSettings& s) { return std::make_unique<Erpt>(s); }, ""};
}

}  // namespace pmcr
