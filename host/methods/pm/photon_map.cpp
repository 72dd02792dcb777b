#include "methods/pm/photon_map.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <glm/gtc/constants.hpp>

#include "core/error.h"
#include "core/parallel.h"
#include "methods/pt/pt_integrator.h"
#include "vk/command_batch.h"
#include "vk/context.h"

namespace pmcr {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

uint32_t kernelByName(const std::string& name) {
    if (name == "box") return gpu::PM_KERNEL_BOX;
    if (name == "cone") return gpu::PM_KERNEL_CONE;
    if (name == "epanechnikov") return gpu::PM_KERNEL_EPANECHNIKOV;
    throw Error("--kernel " + name + ": expected box, cone or epanechnikov");
}

// Every triangle's area: the surface the automatic radius spreads the photons over.
double surfaceArea(const Scene& scene) {
    double area = 0.0;
    for (const gpu::Triangle& t : scene.triangles) {
        const glm::dvec3 a(scene.vertices[t.i0].position), b(scene.vertices[t.i1].position),
            c(scene.vertices[t.i2].position);
        area += 0.5 * glm::length(glm::cross(b - a, c - a));
    }
    return area;
}

uint32_t nextPowerOfTwo(uint64_t n) {
    uint64_t p = 1;
    while (p < n) p <<= 1;
    return uint32_t(std::min<uint64_t>(p, uint64_t(1) << 31));
}

}  // namespace

PhotonMapOptions PhotonMapOptions::fromSettings(const RenderSettings& settings) {
    PhotonMapOptions o;
    const int photons = settings.optionInt("photons", int(o.photonsPerPass));
    if (photons < 0 || photons > 16 * 1000 * 1000)
        throw Error("--photons: expected 0..16000000 photon paths per pass (0: one per camera sample)");
    o.photonsPerPass = uint32_t(photons);
    const int photonSeed = settings.optionInt("photon-seed", -1);
    if (photonSeed < -1) throw Error("--photon-seed: expected a seed >= 0 (-1: the render seed)");
    o.photonSeed = photonSeed;
    o.radius = settings.optionDouble("radius", o.radius);
    if (!(o.radius >= 0.0) || !std::isfinite(o.radius)) throw Error("--radius: expected a radius >= 0 in scene units (0: automatic)");
    o.photonsPerDisc = settings.optionDouble("photons-per-disc", o.photonsPerDisc);
    if (!(o.photonsPerDisc >= 1.0 && o.photonsPerDisc <= 1e6)) throw Error("--photons-per-disc: expected 1..1000000");
    o.progressive = settings.optionBool("progressive", o.progressive);
    o.alpha = settings.optionDouble("alpha", o.alpha);
    if (!(o.alpha > 0.0 && o.alpha < 1.0)) throw Error("--alpha: expected a number in (0, 1)");
    const int gather = settings.optionInt("gather-rays", int(o.gatherRays));
    if (gather < 0 || gather > 32) throw Error("--gather-rays: expected 0..32");
    o.gatherRays = uint32_t(gather);
    o.gatherDirect = settings.optionBool("gather-direct", o.gatherDirect);
    o.kernel = kernelByName(settings.optionString("kernel", "epanechnikov"));
    const int lookup = settings.optionInt("max-lookup", int(o.maxLookup));
    if (lookup < 16 || lookup > 1024) throw Error("--max-lookup: expected 16..1024 photons");
    o.maxLookup = uint32_t(lookup);
    return o;
}

std::vector<MethodOption> PhotonMapOptions::methodOptions() {
    return {
        {"photons", "0", "photon paths shot per pass (0: as many as the pass's camera samples)"},
        {"photon-seed", "-1", "seed of the photon paths (-1: the render seed); fixed, renders of other seeds share the photon maps"},
        {"radius", "0", "initial gather radius in scene units (0: from --photons-per-disc)"},
        {"photons-per-disc", "32", "automatic radius: the first pass's photons per disc, spread evenly over the scene's surface"},
        {"progressive", "on", "on: new photons and a smaller radius every pass (consistent); off: one photon map at a fixed radius"},
        {"alpha", "0.7", "progressive radius reduction: r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1)"},
        {"gather-rays", "4", "final gather rays per gather point (0: read the photon map at the gather point)"},
        {"gather-direct", "off", "on: direct light at the final gather's hits by light sampling, their non-direct photons only; off: all their photons"},
        {"kernel", "epanechnikov", "density estimation kernel: box, cone or epanechnikov"},
        {"max-lookup", "1024", "photons one density lookup reads at most; fuller cells are read strided (unbiased, noisier)"},
    };
}

double photonPassRadius(double r0, uint32_t pass, bool progressive, double alpha) {
    if (!progressive) return r0;
    double r2 = r0 * r0;
    for (uint32_t i = 1; i <= pass; ++i) r2 *= (double(i) + alpha) / (double(i) + 1.0);
    return std::sqrt(r2);
}

uint32_t photonCellBucket(int32_t x, int32_t y, int32_t z, uint32_t hashSize) {
    return ((uint32_t(x) * 73856093u) ^ (uint32_t(y) * 19349663u) ^ (uint32_t(z) * 83492791u)) &
           (hashSize - 1u);
}

void buildPhotonGrid(const std::vector<gpu::Photon>& photons, float cellSize, uint32_t hashSize,
                     std::vector<gpu::Photon>& sorted, std::vector<glm::uvec2>& cells) {
    // A stable counting sort in two levels, each spread over the cores: the photons are first
    // partitioned (stably, block by block) into kRanges ranges of buckets by the buckets' high
    // bits, then each range is sorted by bucket on its own. Within a bucket the photons keep
    // their path order, as one thread's counting sort would leave them.
    constexpr size_t kBlock = 16384;
    const size_t n = photons.size();
    cells.assign(hashSize, glm::uvec2(0u));
    sorted.resize(n);
    if (n == 0) return;
    uint32_t bits = 0;
    while ((1u << bits) < hashSize) ++bits;
    const uint32_t rangeBits = std::min<uint32_t>(bits, 6);
    const uint32_t ranges = 1u << rangeBits, shift = bits - rangeBits;
    const size_t blocks = (n + kBlock - 1) / kBlock;
    std::vector<uint32_t> bucket(n);
    std::vector<uint32_t> histogram(blocks * ranges, 0u);
    parallelFor(n, kBlock, [&](size_t begin, size_t end) {
        uint32_t* h = &histogram[(begin / kBlock) * ranges];
        for (size_t i = begin; i < end; ++i) {
            // The same float arithmetic as the lookup's floor((x +- r) / cellSize).
            const glm::vec3 c = glm::floor(photons[i].position / cellSize);
            bucket[i] = photonCellBucket(int32_t(c.x), int32_t(c.y), int32_t(c.z), hashSize);
            ++h[bucket[i] >> shift];
        }
    });
    // Each block's first position in each range (ranges in order, blocks in order within one).
    std::vector<uint32_t> rangeFirst(ranges + 1, 0u);
    {
        uint32_t first = 0;
        for (uint32_t r = 0; r < ranges; ++r) {
            rangeFirst[r] = first;
            for (size_t b = 0; b < blocks; ++b) {
                const uint32_t count = histogram[b * ranges + r];
                histogram[b * ranges + r] = first;
                first += count;
            }
        }
        rangeFirst[ranges] = first;
    }
    std::vector<uint32_t> order(n);
    parallelFor(n, kBlock, [&](size_t begin, size_t end) {
        uint32_t* next = &histogram[(begin / kBlock) * ranges];
        for (size_t i = begin; i < end; ++i) order[next[bucket[i] >> shift]++] = uint32_t(i);
    });
    // Each range's buckets: counts, firsts, then the photons in order.
    const uint32_t bucketsPerRange = 1u << shift;
    parallelFor(ranges, 1, [&](size_t r0, size_t r1) {
        for (size_t r = r0; r < r1; ++r) {
            for (uint32_t j = rangeFirst[r]; j < rangeFirst[r + 1]; ++j) cells[bucket[order[j]]].y += 1;
            uint32_t first = rangeFirst[r];
            glm::uvec2* range = &cells[r * bucketsPerRange];
            for (uint32_t b = 0; b < bucketsPerRange; ++b) {
                range[b].x = first;
                first += range[b].y;
            }
            std::vector<uint32_t> next(bucketsPerRange);
            for (uint32_t b = 0; b < bucketsPerRange; ++b) next[b] = range[b].x;
            for (uint32_t j = rangeFirst[r]; j < rangeFirst[r + 1]; ++j) {
                const uint32_t i = order[j];
                sorted[next[bucket[i] - r * bucketsPerRange]++] = photons[i];
            }
        }
    });
}

PhotonMap::PhotonMap(RenderSession& session, const PhotonMapOptions& options, double sppPerPass)
    : m_session(session), m_options(options) {
    const RenderSettings& settings = session.settings();
    m_slotsPerPath = std::clamp<uint32_t>(settings.maxDepth, 1, gpu::PM_MAX_SLOTS_PER_PATH);
    const uint64_t limit = session.context().limits().maxStorageBufferRange;
    if (m_options.photonsPerPass == 0) {
        // As many paths as camera samples, at most what one slot buffer holds (lavapipe: 128 MiB,
        // 262144 paths of 16 slots).
        const double fit = double(limit / (uint64_t(m_slotsPerPath) * sizeof(gpu::Photon)));
        m_options.photonsPerPass = uint32_t(std::clamp(
            double(session.film().pixelCount()) * sppPerPass, 1024.0, std::min(fit, 16e6)));
    }
    const uint64_t slotBytes = uint64_t(m_options.photonsPerPass) * m_slotsPerPath * sizeof(gpu::Photon);
    const uint64_t cellBytes = uint64_t(nextPowerOfTwo(2 * uint64_t(m_options.photonsPerPass) * m_slotsPerPath)) *
                               sizeof(glm::uvec2);
    if (slotBytes > limit || cellBytes > limit)
        throw Error("--photons " + std::to_string(m_options.photonsPerPass) + ": a pass needs " +
                    std::to_string((std::max(slotBytes, cellBytes) + (1u << 20) - 1) >> 20) +
                    " MiB in one buffer (32 bytes per photon slot, " + std::to_string(m_slotsPerPath) +
                    " slots per path), above the device's storage buffer range of " +
                    std::to_string(limit >> 20) + " MiB; use fewer --photons or a lower --max-depth");
    // Two sets when progressive (the next pass is shot and sorted while this one is gathered).
    const size_t sets = m_options.progressive ? 2 : 1;
    for (size_t i = 0; i < sets; ++i) {
        const std::string tag = std::to_string(i);
        m_sets[i].slots = vk::Buffer(session.context(), slotBytes,
                                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                     "photon slots " + tag, vk::MemoryUsage::Readback);
        m_sets[i].infoBuffer = vk::Buffer(session.context(), sizeof(gpu::PhotonMapInfo),
                                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "photon map info " + tag);
    }
    m_surfaceArea = surfaceArea(session.scene().scene());
    m_info.kernel = options.kernel;
    m_info.gatherRays = options.gatherRays;
    m_info.gatherDirect = options.gatherDirect ? 1u : 0u;
    m_info.maxLookup = options.maxLookup;
    // A pass's gathers against its shoot, for IfLikelyGathered: a camera sample traces about
    // 1 + gather-rays paths as long as a photon path, doubled for direct light and PMC-HI
    // (measured on lavapipe: 4.8 shoots for pm's pass on cornell-glass; more than 8 for
    // pm-pmc's first iteration).
    m_gatherShoots = 2.0 * (1.0 + double(m_options.gatherRays)) * double(session.film().pixelCount()) * sppPerPass /
                     double(m_options.photonsPerPass);
    // Taken now, so that the render's warm-up creates it off the clock (startClock).
    m_shootKernel = &session.kernel(lightsKernelVariant(session.scene(), "methods/pm/photon_shoot"));
    m_shootCounters = Film::makeCounters(session.context(), "photon shoot counters");
    m_shootWork = std::make_unique<vk::DescriptorSet>(session.layout(), vk::DescriptorSet::Kind::Work, "photon shoot work");
    for (uint32_t b = 0; b < gpu::WORK_BINDING_COUNT; ++b) m_shootWork->bind(b, session.placeholder());
    m_shootWork->bind(gpu::PT_BINDING_FILM, session.film().pixels());
    m_shootWork->bind(gpu::PT_BINDING_COUNTERS, m_shootCounters);
    m_shootBatch = std::make_unique<vk::CommandBatch>(session.layout(), &session.timer());
}

PhotonMap::~PhotonMap() {
    if (m_build.valid()) m_build.wait();
    if (m_shootBatch) m_shootBatch->wait();
}

void PhotonMap::submitShoot(uint32_t pass) {
    m_shootStart = std::chrono::steady_clock::now();
    const GpuScene& scene = m_session.scene();
    const vk::Kernel& kernel = *m_shootKernel;
    const RenderSettings& settings = m_session.settings();
    gpu::PhotonShootPush push{};
    push.seed = m_options.photonSeed >= 0 ? uint32_t(m_options.photonSeed) : settings.seed;
    push.pass = pass;
    push.slotsPerPath = m_slotsPerPath;
    push.maxDepth = settings.maxDepth;
    push.rrDepth = settings.rrDepth;
    push.pathScale = 1.0f / float(m_options.photonsPerPass);
    // (The set's slots were last read by the host's sort of pass - 2, finished.)
    m_shootWork->bind(gpu::PM_BINDING_SLOTS, m_sets[setOf(pass)].slots);
    // Dispatches of at most 64k paths, one path per invocation.
    constexpr uint32_t kPathsPerDispatch = 65536;
    vk::CommandBatch& batch = *m_shootBatch;
    batch.fill(m_shootCounters, 0);
    batch.bind(scene.descriptorSet());
    batch.bind(*m_shootWork);
    for (uint32_t offset = 0; offset < m_options.photonsPerPass; offset += kPathsPerDispatch) {
        push.pathOffset = offset;
        push.pathCount = std::min(kPathsPerDispatch, m_options.photonsPerPass - offset);
        batch.dispatch(kernel, push, push.pathCount);
    }
    batch.submit();
    m_shootPending = pass;
}

void PhotonMap::waitShoot() {
    if (m_shootPending == UINT32_MAX) return;
    m_shootBatch->wait();
    Film::addCounters(m_shootCounters, m_session.counters());
    m_shootSeconds += secondsSince(m_shootStart);
    m_passesShot += 1;
    m_shot = m_shootPending;
    m_shootPending = UINT32_MAX;
}

void PhotonMap::build(uint32_t pass) {
    const auto start = std::chrono::steady_clock::now();
    PassSet& set = m_sets[setOf(pass)];
    // The stored photons in path order (a path's stored slots come first).
    const size_t slots = size_t(m_options.photonsPerPass) * m_slotsPerPath;
    const auto* slot = static_cast<const gpu::Photon*>(set.slots.mapped());
    std::vector<gpu::Photon> downloaded;
    if (!slot) {  // (never: the slots are host-visible, so a sort on its own thread submits nothing)
        downloaded = set.slots.download<gpu::Photon>(slots);
        slot = downloaded.data();
    }
    // (A path's photons are its slots up to the first one not stored: the slots after it may
    // hold an earlier pass's photons.)
    const uint32_t slotsPerPath = m_slotsPerPath;
    auto storedOf = [slot, slotsPerPath](size_t path) {
        const gpu::Photon* p = slot + path * slotsPerPath;
        uint32_t k = 0;
        while (k < slotsPerPath && (p[k].flags & gpu::PHOTON_STORED)) ++k;
        return k;
    };
    parallelConcat(size_t(m_options.photonsPerPass), 4096, set.photons, storedOf,
                   [&](size_t path, gpu::Photon* out) { return std::copy_n(slot + path * slotsPerPath, storedOf(path), out); });
    if (m_r0 == 0.0) {
        // Automatic: the radius whose disc would hold photonsPerDisc of the first pass's photons
        // spread evenly over the scene's surface, but at most kFootprintPixels pixels' footprint
        // at the scene's centre (scenes with a vast ground plane would otherwise blur by metres).
        constexpr double kFootprintPixels = 1.0;
        const gpu::SceneInfo& info = m_session.scene().info();
        const double spread = std::sqrt(m_options.photonsPerDisc * m_surfaceArea /
                                        (glm::pi<double>() * std::max<double>(1.0, double(set.photons.size()))));
        const double distance = glm::length(glm::dvec3(info.sceneCenter) - glm::dvec3(info.cameraPosition));
        const double footprint = kFootprintPixels * distance * 2.0 * info.tanHalfFovY / double(info.height);
        m_r0 = m_options.radius > 0.0 ? m_options.radius : std::min(spread, footprint > 0.0 ? footprint : spread);
        if (!(m_r0 > 0.0) || !std::isfinite(m_r0)) m_r0 = 1e-3 * info.sceneRadius;
    }
    const float radius = float(photonPassRadius(m_r0, pass, m_options.progressive, m_options.alpha));
    // The global grid (every photon), then the caustic grid (the caustic photons again), in one
    // photon buffer and one cells buffer (photon_types.h PhotonMapInfo).
    std::vector<gpu::Photon> caustics, sortedCaustics;
    auto caustic = [&](size_t i) -> size_t { return (set.photons[i].flags & gpu::PHOTON_CAUSTIC) != 0; };
    parallelConcat(set.photons.size(), 8192, caustics, caustic, [&](size_t i, gpu::Photon* out) {
        if (caustic(i)) *out++ = set.photons[i];
        return out;
    });
    const uint32_t hashSize = nextPowerOfTwo(std::max<uint64_t>(1024, 2 * uint64_t(set.photons.size())));
    const uint32_t causticHashSize = nextPowerOfTwo(std::max<uint64_t>(1024, 2 * uint64_t(caustics.size())));
    std::vector<glm::uvec2> causticCells;
    // Room for both grids, so that appending the caustic one moves nothing (a first pass's
    // 552k photons and 2^21 cells took 25 ms to move on lavapipe's 2-core machine).
    set.sorted.reserve(set.photons.size() + caustics.size());
    set.cellData.reserve(size_t(hashSize) + causticHashSize);
    buildPhotonGrid(set.photons, 2.0f * radius, hashSize, set.sorted, set.cellData);
    buildPhotonGrid(caustics, 2.0f * radius, causticHashSize, sortedCaustics, causticCells);
    for (glm::uvec2& cell : causticCells) cell.x += uint32_t(set.sorted.size());
    set.sorted.insert(set.sorted.end(), sortedCaustics.begin(), sortedCaustics.end());
    set.cellData.insert(set.cellData.end(), causticCells.begin(), causticCells.end());
    set.info = gpu::PhotonMapInfo{};
    set.info.kernel = m_options.kernel;
    set.info.gatherRays = m_options.gatherRays;
    set.info.gatherDirect = m_options.gatherDirect ? 1u : 0u;
    set.info.maxLookup = m_options.maxLookup;
    set.info.radius = radius;
    set.info.cellSize = 2.0f * radius;
    set.info.hashMask = hashSize - 1;
    set.info.photonCount = uint32_t(set.photons.size());
    set.info.causticCount = uint32_t(caustics.size());
    set.info.causticHashMask = causticHashSize - 1;
    set.info.causticCellOffset = hashSize;
    set.builtPass = pass;
    m_buildSeconds += secondsSince(start);
}

void PhotonMap::joinBuild() {
    if (!m_build.valid()) return;
    const auto start = std::chrono::steady_clock::now();
    m_build.get();  // rethrows what the sort threw
    m_buildWaitSeconds += secondsSince(start);
    m_building = UINT32_MAX;
}

void PhotonMap::upload(PassSet& set) {
    const VkDeviceSize photonBytes = std::max<VkDeviceSize>(16, set.sorted.size() * sizeof(gpu::Photon));
    if (!set.photonBuffer.valid() || set.photonBuffer.size() < photonBytes)
        set.photonBuffer = vk::Buffer(m_session.context(), photonBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "photons");
    const VkDeviceSize cellBytes = set.cellData.size() * sizeof(glm::uvec2);
    if (!set.cells.valid() || set.cells.size() < cellBytes)
        set.cells = vk::Buffer(m_session.context(), cellBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "photon grid");
    set.cells.upload(set.cellData);
    if (!set.sorted.empty()) set.photonBuffer.upload(set.sorted);
    set.infoBuffer.upload(&set.info, sizeof(set.info));
}

void PhotonMap::preparePass(uint32_t pass, Next next) {
    const bool shootNext = next == Next::Yes && m_options.progressive;
    if (m_passesPrepared > 0 && !m_options.progressive) {  // one map for every pass
        m_passesPrepared += 1;
        return;
    }
    PassSet& set = m_sets[setOf(pass)];
    if (m_building == pass) joinBuild();
    if (set.builtPass != pass) {
        // Not shot ahead (the first pass, or a caller that does not overlap): shoot it now, and
        // while the host sorts it, the device shoots the next one.
        if (m_shootPending != pass && m_shot != pass) {
            waitShoot();
            submitShoot(pass);
        }
        const double shootStart = m_shootSeconds;
        waitShoot();
        const double shootSeconds = m_shootSeconds - shootStart;
        const double limit = m_session.settings().timeLimit;
        // IfLikelyGathered: this pass's gathers guessed at m_gatherShoots shoots, the next
        // shoot itself at one.
        if (shootNext || (next == Next::IfLikelyGathered && m_options.progressive &&
                          (limit <= 0.0 ||
                           m_session.elapsedSeconds() + (1.0 + m_gatherShoots) * shootSeconds < limit)))
            submitShoot(pass + 1);
        build(pass);
    } else if (shootNext) {
        shootAhead(pass + 1);
    }
    upload(set);
    m_info = set.info;
    m_lastSet = setOf(pass);
    m_photonsStored += set.photons.size();
    m_passesPrepared += 1;
}

void PhotonMap::preparePass(uint32_t pass, vk::DescriptorSet& work) {
    preparePass(pass, Next::No);
    bindPass(pass, work);
}

void PhotonMap::shootAhead(uint32_t pass) {
    if (!m_options.progressive || shotAhead(pass)) return;
    waitShoot();
    submitShoot(pass);
}

bool PhotonMap::shotAhead(uint32_t pass) const {
    return m_shootPending == pass || m_shot == pass || m_building == pass || m_sets[setOf(pass)].builtPass == pass;
}

void PhotonMap::buildNextInBackground() {
    if (m_shootPending == UINT32_MAX || m_build.valid()) return;
    waitShoot();
    const uint32_t pass = m_shot;
    m_building = pass;
    m_build = std::async(std::launch::async, [this, pass] { build(pass); });
}

void PhotonMap::bindPass(uint32_t pass, vk::DescriptorSet& work) const {
    const PassSet& set = m_sets[setOf(pass)];
    work.bind(gpu::PM_BINDING_SLOTS, set.slots);
    work.bind(gpu::PM_BINDING_INFO, set.infoBuffer);
    if (set.photonBuffer.valid()) work.bind(gpu::PM_BINDING_PHOTONS, set.photonBuffer);
    if (set.cells.valid()) work.bind(gpu::PM_BINDING_CELLS, set.cells);
}

const std::vector<gpu::Photon>& PhotonMap::photons() const { return m_sets[m_lastSet].photons; }

nlohmann::json PhotonMap::stats() {
    // A pass shot or sorted ahead and never gathered (the clock ran out): its device work
    // (queued before the last gathers, so done) and its host seconds join the totals.
    waitShoot();
    if (m_build.valid()) m_build.wait();
    const Counters& c = m_session.counters();
    nlohmann::json j;
    j["photon_passes"] = m_passesPrepared;
    j["photon_passes_shot"] = m_passesShot;
    j["photon_paths_per_pass"] = m_options.photonsPerPass;
    j["photons_stored"] = m_photonsStored;
    j["photons_per_pass"] = m_passesPrepared ? double(m_photonsStored) / m_passesPrepared : 0.0;
    j["caustic_photons_last_pass"] = m_info.causticCount;
    j["radius_initial"] = m_r0;
    j["radius_final"] = m_info.radius;
    j["progressive"] = m_options.progressive;
    j["gather_rays"] = m_options.gatherRays;
    j["gather_direct"] = m_options.gatherDirect;
    j["photon_shoot_seconds"] = m_shootSeconds;
    j["photon_build_seconds"] = m_buildSeconds;
    j["photon_build_wait_seconds"] = m_buildWaitSeconds;
    j["photon_paths_out_of_slots"] = c.values[gpu::COUNTER_PM_SLOTS_FULL];
    j["lookups"] = c.values[gpu::COUNTER_PM_LOOKUPS];
    j["lookups_strided"] = c.values[gpu::COUNTER_PM_LOOKUP_CUT];
    const double lookups = std::max<double>(1.0, double(c.values[gpu::COUNTER_PM_LOOKUPS]));
    j["photons_visited_per_lookup"] = double(c.values[gpu::COUNTER_PM_PHOTONS_VISITED]) / lookups;
    j["photons_used_per_lookup"] = double(c.values[gpu::COUNTER_PM_PHOTONS_USED]) / lookups;
    return j;
}

}  // namespace pmcr
