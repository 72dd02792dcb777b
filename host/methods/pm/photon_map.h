// The photon map of `pm` and `pm-pmc` (Jensen 2001; the PMC paper's sec. 6 builds its final
// gather on it): each pass shoots photon paths on the device (shaders/methods/pm/
// photon_shoot.comp), then the host sorts the stored photons into a hashed uniform grid of cell
// size 2 r (a counting sort by bucket, in path order, so a seed gives the same map bit for bit)
// and uploads it for the gather kernels (shaders/methods/pm/photon_map.glsl).
//
// Radius: --radius in scene units, or (0, the default) the radius whose disc would hold
// --photons-per-disc of the first pass's photons were they spread evenly over the scene's
// surface area, at most 1 pixel's footprint at the distance of the scene's centre (docs/methods/
// pm.md: the cap that brings lamp-room's and room's block means within 1% of pt's). Progressive
// (the default) shrinks it from pass to pass, r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1)
// (Hachisuka and Jensen 2009's SPPM radius reduction in the probabilistic form of Knaus and
// Zwicker 2011, eq. 19, one radius for every point so that the final gather's hit points, new
// every pass, can share it): the average of the passes' images
// converges to the path tracer's; at a fixed radius (--progressive off: one photon pass, the
// classic two-pass renderer) the image keeps density estimation's bias.
//
// Two grids: every photon (the global map, read by the final gather) and the caustic photons
// alone (the caustic map, read at the gather point), so a caustic lookup reads no other photon.
//
// Memory: a pass needs 32 bytes per photon slot (paths x min(max-depth, 16) slots), 32 per
// stored photon (and again per caustic photon) sorted, and 8 bytes per grid bucket (2 buckets
// per photon, rounded up to a power of two): a pass whose slots or buckets would exceed the
// device's storage buffer range fails up front with a one-line error.
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/method_info.h"
#include "render/session.h"
#include "vk/buffer.h"
#include "vk/pipeline.h"

namespace pmcr {

struct PhotonMapOptions {
    uint32_t photonsPerPass = 0;       // photon paths shot per pass; 0: pixels x camera samples per pass
    int64_t photonSeed = -1;           // seed of the photon paths; -1: the render seed
    double radius = 0.0;               // initial radius in scene units; 0: from photonsPerDisc
    double photonsPerDisc = 32.0;      // the automatic radius's target
    bool progressive = true;           // new photons and a smaller radius every pass
    double alpha = 0.7;                // progressive radius reduction (SPPM's alpha)
    uint32_t gatherRays = 4;           // final gather rays per gather point (0: read the map there)
    bool gatherDirect = false;         // direct light at the gather rays' hits by light sampling
    uint32_t kernel = 2;               // gpu::PM_KERNEL_*
    uint32_t maxLookup = 1024;         // photons one lookup reads at most

    static PhotonMapOptions fromSettings(const RenderSettings& settings);
    // The registry's option list (defaults and help) of the options above.
    static std::vector<MethodOption> methodOptions();
};

// The radius of pass `pass` (0-based) from the first pass's r0: r0 at a fixed radius, else
// r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1) with i = pass + 1.
double photonPassRadius(double r0, uint32_t pass, bool progressive, double alpha);

// The hash bucket of grid cell (x, y, z) among `hashSize` (a power of two): the same function as
// photon_map.glsl's photonCellBucket.
uint32_t photonCellBucket(int32_t x, int32_t y, int32_t z, uint32_t hashSize);

// Sorts `photons` by grid bucket (cells of size cellSize), stably, into `sorted`, and writes
// each bucket's (first, count) into `cells` (hashSize entries).
void buildPhotonGrid(const std::vector<gpu::Photon>& photons, float cellSize, uint32_t hashSize,
                     std::vector<gpu::Photon>& sorted, std::vector<glm::uvec2>& cells);

class PhotonMap {
public:
    // `sppPerPass`: the camera samples per pixel each pass serves, for the default photon count
    // (as many photon paths as camera samples). Checks the memory a pass needs against the
    // device's limits (pmcr::Error when over).
    PhotonMap(RenderSession& session, const PhotonMapOptions& options, double sppPerPass);

    // Pass `pass`'s map: shoots new photons and builds their grid at this pass's radius when the
    // map is progressive or not built yet, then points `work`'s photon bindings at it.
    void preparePass(uint32_t pass, vk::DescriptorSet& work);
    // Points another work set (a second batch in flight) at this pass's photon buffers too.
    void bindPass(vk::DescriptorSet& work) const;

    double radius() const { return m_info.radius; }
    // The last pass's photons in path order (as shot, before the grid sort).
    const std::vector<gpu::Photon>& photons() const { return m_photons; }
    // Passes shot, photons stored, host and device seconds, lookup statistics.
    nlohmann::json stats();

private:
    void shoot(uint32_t pass);
    void build(uint32_t pass);

    RenderSession& m_session;
    PhotonMapOptions m_options;
    vk::DescriptorSet* m_work = nullptr;  // the work set the photon bindings point into
    uint32_t m_slotsPerPath = 0;
    uint32_t m_passesShot = 0;
    double m_r0 = 0.0;
    double m_surfaceArea = 0.0;
    gpu::PhotonMapInfo m_info{};
    vk::Buffer m_slots;         // what shooting stores
    vk::Buffer m_photonBuffer;  // this pass's photons sorted by bucket, then its caustic ones
    vk::Buffer m_cells;
    vk::Buffer m_infoBuffer;
    uint64_t m_photonsStored = 0;
    double m_shootSeconds = 0.0;
    double m_buildSeconds = 0.0;
    std::vector<gpu::Photon> m_photons, m_caustics, m_sorted;
    std::vector<glm::uvec2> m_cellData;
};

}  // namespace pmcr
