// The photon map of `pm` and `pm-pmc` (Jensen 2001; the PMC paper's sec. 6 builds its final
// gather on it): each pass shoots photon paths on the device (shaders/methods/pm/
// photon_shoot.comp), then the host sorts the stored photons into a hashed uniform grid of cell
// size 2 r (a counting sort by bucket, in path order, so a seed gives the same map bit for bit)
// and uploads it for the gather kernels (shaders/methods/pm/photon_map.glsl).
//
// Keeping the device busy (issue 38): the map holds two passes, on alternate buffer sets (pass
// p on set p % 2). While the device gathers pass p, it has already shot pass p + 1's photons,
// and the host sorts them on a thread of its own (buildNextInBackground), its sort spread over
// the cores; the device never waits for the host's sort once the first pass is built. A pass
// is a function of its index alone (seed, pass, and the first pass's radius), so shooting it
// early changes no photon, and a pass prepared but never gathered (the clock ran out) adds
// nothing to the image.
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

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/method_info.h"
#include "render/session.h"
#include "vk/buffer.h"
#include "vk/command_batch.h"
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
// each bucket's (first, count) into `cells` (hashSize entries). Spread over the cores in fixed
// blocks (core/parallel.h): the result is the same as one thread's, photons in path order
// within each bucket.
void buildPhotonGrid(const std::vector<gpu::Photon>& photons, float cellSize, uint32_t hashSize,
                     std::vector<gpu::Photon>& sorted, std::vector<glm::uvec2>& cells);

class PhotonMap {
public:
    // `sppPerPass`: the camera samples per pixel each pass serves, for the default photon count
    // (as many photon paths as camera samples). Checks the memory a pass needs against the
    // device's limits (pmcr::Error when over).
    PhotonMap(RenderSession& session, const PhotonMapOptions& options, double sppPerPass);
    ~PhotonMap();  // waits for a sort and a shoot in progress

    // Makes pass `pass`'s map ready for the gather kernels: shoots its photons and builds their
    // grid at this pass's radius when the map is progressive (or not built yet), or takes the
    // grid built in the background, and uploads it to set pass % 2. With `next` Yes, the next
    // pass's photons are then shot on the device (ahead of the gathers the caller submits next);
    // IfLikelyGathered (under --time) shoots it while the host sorts this pass only if this
    // pass's gathers, guessed from its shoot's time, would end before the clock (otherwise the
    // caller decides later, with shootAhead).
    // The caller guarantees that no batch in flight reads set pass % 2 (pass - 2's gathers are
    // done); passes are prepared in order.
    enum class Next { No, Yes, IfLikelyGathered };
    void preparePass(uint32_t pass, Next next);
    // The same, then points `work`'s photon bindings at the pass's map.
    void preparePass(uint32_t pass, vk::DescriptorSet& work);
    // Shoots pass `pass` now (on the device, ahead of the batches submitted next) unless it is
    // shot or built already: for a caller that decides late whether the next pass will be
    // gathered (under --time, a pass shot and never gathered costs the device its shoot).
    void shootAhead(uint32_t pass);
    // Whether pass `pass` is shot (or being shot) or built.
    bool shotAhead(uint32_t pass) const;
    // Once a batch is queued behind the next pass's shoot: waits for the shoot (the device goes
    // on with that batch) and sorts its photons on a thread of its own. Does nothing when no
    // shoot is pending.
    void buildNextInBackground();
    // Points `work`'s photon bindings at pass `pass`'s map (prepared, or being gathered).
    void bindPass(uint32_t pass, vk::DescriptorSet& work) const;

    double radius() const { return m_info.radius; }
    // The last prepared pass's photons in path order (as shot, before the grid sort).
    const std::vector<gpu::Photon>& photons() const;
    // Passes gathered, photons stored, host and device seconds, lookup statistics.
    nlohmann::json stats();

private:
    // One pass's map, on one of the two buffer sets.
    struct PassSet {
        vk::Buffer slots;   // what shooting stores
        vk::Buffer photonBuffer;  // the pass's photons sorted by bucket, then its caustic ones
        vk::Buffer cells;
        vk::Buffer infoBuffer;
        gpu::PhotonMapInfo info{};
        std::vector<gpu::Photon> photons, sorted;  // path order; the grid's order
        std::vector<glm::uvec2> cellData;
        std::atomic<uint32_t> builtPass{UINT32_MAX};  // the pass whose grid the vectors hold
    };
    uint32_t setOf(uint32_t pass) const { return m_options.progressive ? pass % 2 : 0; }
    void submitShoot(uint32_t pass);
    void waitShoot();
    void build(uint32_t pass);  // the host's sort of a shot pass into its set's vectors
    void joinBuild();
    void upload(PassSet& set);

    RenderSession& m_session;
    PhotonMapOptions m_options;
    uint32_t m_slotsPerPath = 0;
    uint32_t m_passesPrepared = 0;  // passes whose map was made ready (gathered, or about to be)
    uint32_t m_passesShot = 0;
    double m_gatherShoots = 0.0;  // a pass's gathers guessed in shoots (IfLikelyGathered)
    double m_r0 = 0.0;
    double m_surfaceArea = 0.0;
    gpu::PhotonMapInfo m_info{};  // the last prepared pass's
    std::array<PassSet, 2> m_sets;
    uint32_t m_lastSet = 0;
    // The shoot: its own batch, work set and counters, so it runs beside the gathers.
    const vk::Kernel* m_shootKernel = nullptr;
    std::unique_ptr<vk::CommandBatch> m_shootBatch;
    std::unique_ptr<vk::DescriptorSet> m_shootWork;
    vk::Buffer m_shootCounters;
    uint32_t m_shootPending = UINT32_MAX;  // the pass whose shoot is submitted, not waited
    uint32_t m_shot = UINT32_MAX;          // the last pass shot and waited for, not built
    std::chrono::steady_clock::time_point m_shootStart{};
    std::future<void> m_build;            // the background sort
    uint32_t m_building = UINT32_MAX;     // the pass it sorts
    uint64_t m_photonsStored = 0;
    double m_shootSeconds = 0.0;  // host time from submitting a shoot to its end
    double m_buildSeconds = 0.0;  // host time sorting (on the background thread too)
    double m_buildWaitSeconds = 0.0;  // time the render's thread waited for a sort
};

}  // namespace pmcr
