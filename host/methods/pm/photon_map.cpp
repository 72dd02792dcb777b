#include "methods/pm/photon_map.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <glm/gtc/constants.hpp>

#include "core/error.h"
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
    cells.assign(hashSize, glm::uvec2(0u));
    std::vector<uint32_t> bucket(photons.size());
    for (size_t i = 0; i < photons.size(); ++i) {
        // The same float arithmetic as the lookup's floor((x +- r) / cellSize).
        const glm::vec3 c = glm::floor(photons[i].position / cellSize);
        bucket[i] = photonCellBucket(int32_t(c.x), int32_t(c.y), int32_t(c.z), hashSize);
        cells[bucket[i]].y += 1;
    }
    uint32_t first = 0;
    for (glm::uvec2& cell : cells) {
        cell.x = first;
        first += cell.y;
    }
    sorted.resize(photons.size());
    std::vector<uint32_t> next(hashSize);
    for (uint32_t b = 0; b < hashSize; ++b) next[b] = cells[b].x;
    for (size_t i = 0; i < photons.size(); ++i) sorted[next[bucket[i]]++] = photons[i];
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
    m_slots = vk::Buffer(session.context(), slotBytes,
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         "photon slots", vk::MemoryUsage::Readback);
    m_infoBuffer = vk::Buffer(session.context(), sizeof(gpu::PhotonMapInfo), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                              "photon map info");
    m_surfaceArea = surfaceArea(session.scene().scene());
    m_info.kernel = options.kernel;
    m_info.gatherRays = options.gatherRays;
    m_info.gatherDirect = options.gatherDirect ? 1u : 0u;
    m_info.maxLookup = options.maxLookup;
}

void PhotonMap::shoot(uint32_t pass) {
    const auto start = std::chrono::steady_clock::now();
    const GpuScene& scene = m_session.scene();
    const vk::Kernel& kernel = m_session.kernel(lightsKernelVariant(scene, "methods/pm/photon_shoot"));
    const RenderSettings& settings = m_session.settings();
    gpu::PhotonShootPush push{};
    push.seed = m_options.photonSeed >= 0 ? uint32_t(m_options.photonSeed) : settings.seed;
    push.pass = pass;
    push.slotsPerPath = m_slotsPerPath;
    push.maxDepth = settings.maxDepth;
    push.rrDepth = settings.rrDepth;
    push.pathScale = 1.0f / float(m_options.photonsPerPass);
    // Dispatches of at most 64k paths, one path per invocation.
    constexpr uint32_t kPathsPerDispatch = 65536;
    vk::CommandBatch batch(m_session.layout(), &m_session.timer());
    batch.fill(m_session.film().counters(), 0);
    batch.bind(scene.descriptorSet());
    batch.bind(*m_work);
    for (uint32_t offset = 0; offset < m_options.photonsPerPass; offset += kPathsPerDispatch) {
        push.pathOffset = offset;
        push.pathCount = std::min(kPathsPerDispatch, m_options.photonsPerPass - offset);
        batch.dispatch(kernel, push, push.pathCount);
    }
    batch.submitAndWait();
    m_session.film().addCounters(m_session.counters());
    m_shootSeconds += secondsSince(start);
    m_passesShot += 1;
}

void PhotonMap::build(uint32_t pass) {
    const auto start = std::chrono::steady_clock::now();
    // The stored photons in path order.
    const size_t slots = size_t(m_options.photonsPerPass) * m_slotsPerPath;
    const auto* slot = static_cast<const gpu::Photon*>(m_slots.mapped());
    std::vector<gpu::Photon> downloaded;
    if (!slot) {
        downloaded = m_slots.download<gpu::Photon>(slots);
        slot = downloaded.data();
    }
    m_photons.clear();
    for (size_t path = 0; path < m_options.photonsPerPass; ++path) {
        const gpu::Photon* p = slot + path * m_slotsPerPath;
        for (uint32_t k = 0; k < m_slotsPerPath && (p[k].flags & gpu::PHOTON_STORED); ++k) m_photons.push_back(p[k]);
    }
    m_photonsStored += m_photons.size();
    if (m_r0 == 0.0) {
        // Automatic: the radius whose disc would hold photonsPerDisc of the first pass's photons
        // spread evenly over the scene's surface, but at most kFootprintPixels pixels' footprint
        // at the scene's centre (scenes with a vast ground plane would otherwise blur by metres).
        constexpr double kFootprintPixels = 1.0;
        const gpu::SceneInfo& info = m_session.scene().info();
        const double spread = std::sqrt(m_options.photonsPerDisc * m_surfaceArea /
                                        (glm::pi<double>() * std::max<double>(1.0, double(m_photons.size()))));
        const double distance = glm::length(glm::dvec3(info.sceneCenter) - glm::dvec3(info.cameraPosition));
        const double footprint = kFootprintPixels * distance * 2.0 * info.tanHalfFovY / double(info.height);
        m_r0 = m_options.radius > 0.0 ? m_options.radius : std::min(spread, footprint > 0.0 ? footprint : spread);
        if (!(m_r0 > 0.0) || !std::isfinite(m_r0)) m_r0 = 1e-3 * info.sceneRadius;
    }
    const float radius = float(photonPassRadius(m_r0, pass, m_options.progressive, m_options.alpha));
    // The global grid (every photon), then the caustic grid (the caustic photons again), in one
    // photon buffer and one cells buffer (photon_types.h PhotonMapInfo).
    m_caustics.clear();
    for (const gpu::Photon& p : m_photons)
        if (p.flags & gpu::PHOTON_CAUSTIC) m_caustics.push_back(p);
    const uint32_t hashSize = nextPowerOfTwo(std::max<uint64_t>(1024, 2 * uint64_t(m_photons.size())));
    const uint32_t causticHashSize = nextPowerOfTwo(std::max<uint64_t>(1024, 2 * uint64_t(m_caustics.size())));
    std::vector<gpu::Photon> sortedCaustics;
    std::vector<glm::uvec2> causticCells;
    buildPhotonGrid(m_photons, 2.0f * radius, hashSize, m_sorted, m_cellData);
    buildPhotonGrid(m_caustics, 2.0f * radius, causticHashSize, sortedCaustics, causticCells);
    for (glm::uvec2& cell : causticCells) cell.x += uint32_t(m_sorted.size());
    m_sorted.insert(m_sorted.end(), sortedCaustics.begin(), sortedCaustics.end());
    m_cellData.insert(m_cellData.end(), causticCells.begin(), causticCells.end());
    const VkDeviceSize photonBytes = std::max<VkDeviceSize>(16, m_sorted.size() * sizeof(gpu::Photon));
    if (!m_photonBuffer.valid() || m_photonBuffer.size() < photonBytes) {
        m_photonBuffer = vk::Buffer(m_session.context(), photonBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "photons");
        m_work->bind(gpu::PM_BINDING_PHOTONS, m_photonBuffer);
    }
    const VkDeviceSize cellBytes = m_cellData.size() * sizeof(glm::uvec2);
    if (!m_cells.valid() || m_cells.size() < cellBytes) {
        m_cells = vk::Buffer(m_session.context(), cellBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "photon grid");
        m_work->bind(gpu::PM_BINDING_CELLS, m_cells);
    }
    m_cells.upload(m_cellData);
    if (!m_sorted.empty()) m_photonBuffer.upload(m_sorted);
    m_info.radius = radius;
    m_info.cellSize = 2.0f * radius;
    m_info.hashMask = hashSize - 1;
    m_info.photonCount = uint32_t(m_photons.size());
    m_info.causticCount = uint32_t(m_caustics.size());
    m_info.causticHashMask = causticHashSize - 1;
    m_info.causticCellOffset = hashSize;
    m_infoBuffer.upload(&m_info, sizeof(m_info));
    m_buildSeconds += secondsSince(start);
}

void PhotonMap::preparePass(uint32_t pass, vk::DescriptorSet& work) {
    if (m_work != &work) {
        m_work = &work;
        work.bind(gpu::PM_BINDING_SLOTS, m_slots);
        work.bind(gpu::PM_BINDING_INFO, m_infoBuffer);
        if (m_photonBuffer.valid()) work.bind(gpu::PM_BINDING_PHOTONS, m_photonBuffer);
        if (m_cells.valid()) work.bind(gpu::PM_BINDING_CELLS, m_cells);
    }
    if (m_passesShot > 0 && !m_options.progressive) return;
    shoot(pass);
    build(pass);
}

void PhotonMap::bindPass(vk::DescriptorSet& work) const {
    work.bind(gpu::PM_BINDING_SLOTS, m_slots);
    work.bind(gpu::PM_BINDING_INFO, m_infoBuffer);
    if (m_photonBuffer.valid()) work.bind(gpu::PM_BINDING_PHOTONS, m_photonBuffer);
    if (m_cells.valid()) work.bind(gpu::PM_BINDING_CELLS, m_cells);
}

nlohmann::json PhotonMap::stats() {
    const Counters& c = m_session.counters();
    nlohmann::json j;
    j["photon_passes"] = m_passesShot;
    j["photon_paths_per_pass"] = m_options.photonsPerPass;
    j["photons_stored"] = m_photonsStored;
    j["photons_per_pass"] = m_passesShot ? double(m_photonsStored) / m_passesShot : 0.0;
    j["caustic_photons_last_pass"] = m_info.causticCount;
    j["radius_initial"] = m_r0;
    j["radius_final"] = m_info.radius;
    j["progressive"] = m_options.progressive;
    j["gather_rays"] = m_options.gatherRays;
    j["gather_direct"] = m_options.gatherDirect;
    j["photon_shoot_seconds"] = m_shootSeconds;
    j["photon_build_seconds"] = m_buildSeconds;
    j["photon_paths_out_of_slots"] = c.values[gpu::COUNTER_PM_SLOTS_FULL];
    j["lookups"] = c.values[gpu::COUNTER_PM_LOOKUPS];
    j["lookups_strided"] = c.values[gpu::COUNTER_PM_LOOKUP_CUT];
    const double lookups = std::max<double>(1.0, double(c.values[gpu::COUNTER_PM_LOOKUPS]));
    j["photons_visited_per_lookup"] = double(c.values[gpu::COUNTER_PM_PHOTONS_VISITED]) / lookups;
    j["photons_used_per_lookup"] = double(c.values[gpu::COUNTER_PM_PHOTONS_USED]) / lookups;
    return j;
}

}  // namespace pmcr
