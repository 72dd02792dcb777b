// Photon mapping (`pm`, `pm-pmc`; host/methods/pm/): photons shot from the lights, stored at
// every non-specular hit, sorted into a hashed uniform grid between dispatches, and read back by
// density estimation in the gather kernel (shaders/methods/pm/).

// Work-set bindings of photon_shoot.comp and the gather kernels (pm_gather*.comp), beside the
// path tracer's PT_BINDING_* (0..3) and PMC-HI's feedback bindings (6..8).
PMCR_CONST uint PM_BINDING_SLOTS = 9;     // Photon[path * slotsPerPath + k]: what shooting stores
PMCR_CONST uint PM_BINDING_PHOTONS = 10;  // Photon[]: this pass's photons sorted by grid bucket,
                                          // then its caustic photons again, sorted by theirs
PMCR_CONST uint PM_BINDING_CELLS = 11;    // uvec2[]: (first photon, count) per bucket, the
                                          // global grid's buckets then the caustic grid's
PMCR_CONST uint PM_BINDING_INFO = 12;     // PhotonMapInfo: this pass's radius and grid

// Photon.flags
PMCR_CONST uint PHOTON_STORED = 1u;   // a photon (a slot without it ends the path's photons)
PMCR_CONST uint PHOTON_DIRECT = 2u;   // the light's first hit: light -> here
PMCR_CONST uint PHOTON_CAUSTIC = 4u;  // light -> one or more delta scatterings -> here (L S+ D)
PMCR_CONST uint PHOTON_HIT_SHIFT = 8u;  // flags >> PHOTON_HIT_SHIFT: the path's hit index h >= 1
                                        // (h - 1 bounces since the light), for the depth limit

// One photon, 32 bytes: where it landed, the direction back along its last segment
// (octahedral, two 16-bit halves), and its flux (power, in W for the whole pass's photons: the
// pass's emitted power divided by its path count is already in it).
struct Photon {
    vec3 position;
    uint direction;  // octEncode(wi), wi pointing back towards where the photon came from
    vec3 power;
    uint flags;      // PHOTON_* | hit index << PHOTON_HIT_SHIFT
};
PMCR_CHECK_SIZE(Photon, 32);

// The most photons one path stores (one slot each); a path ends at maxDepth hits, so the host
// gives each path min(maxDepth, PM_MAX_SLOTS_PER_PATH) slots and shooting stops when they are
// full (counted, COUNTER_PM_SLOTS_FULL).
PMCR_CONST uint PM_MAX_SLOTS_PER_PATH = 16;

// Density estimation kernels (PhotonMapInfo.kernel), 2D over the disc of radius r.
PMCR_CONST uint PM_KERNEL_BOX = 0;           // 1 / (pi r^2)
PMCR_CONST uint PM_KERNEL_CONE = 1;          // 3 / (pi r^2) (1 - d / r)       (Jensen 2001, k = 1)
PMCR_CONST uint PM_KERNEL_EPANECHNIKOV = 2;  // 2 / (pi r^2) (1 - d^2 / r^2)   (Silverman 1986)

// Counters the photon kernels add to (render_types.h COUNTER_*; 3..15 are free in these kernels).
PMCR_CONST uint COUNTER_PM_SLOTS_FULL = 4;       // photon paths that ran out of slots
PMCR_CONST uint COUNTER_PM_LOOKUP_CUT = 5;       // density lookups that read a bucket strided (maxLookup)
PMCR_CONST uint COUNTER_PM_LOOKUPS = 6;          // density lookups
PMCR_CONST uint COUNTER_PM_PHOTONS_VISITED = 7;  // photons read by lookups
PMCR_CONST uint COUNTER_PM_PHOTONS_USED = 8;     // of which within the radius

// One pass's photon map, as the gather kernels read it.
// Two grids of the same cells: every photon (the global map), and the caustic photons alone (the
// caustic map, so that its lookups read no other photon).
struct PhotonMapInfo {
    float radius;      // r of this pass (progressive: shrinks from pass to pass)
    float cellSize;    // 2 r: a disc of radius r around a point meets at most 2 x 2 x 2 cells
    uint hashMask;     // the global grid's bucket count - 1 (a power of two)
    uint kernel;       // PM_KERNEL_*
    uint gatherRays;   // final gather rays per gather point (0: read the map at the gather point)
    uint maxLookup;    // photons one lookup reads at most, maxLookup / 8 per bucket (lavapipe's loop budget)
    uint photonCount;  // photons in the global map
    uint causticCount;       // photons in the caustic map
    uint causticHashMask;    // the caustic grid's bucket count - 1
    uint causticCellOffset;  // its first bucket in the cells buffer
    uint gatherDirect;       // 1: the final gather estimates direct light at its hits by light
                             // sampling and reads their non-direct photons; 0: all their photons
};
PMCR_CHECK_SIZE(PhotonMapInfo, 44);

// Push constants of photon_shoot.comp.
struct PhotonShootPush {
    uint seed;          // render seed
    uint pass;          // photon pass: every pass draws new paths
    uint pathOffset;    // first path of this dispatch
    uint pathCount;     // paths of this dispatch
    uint slotsPerPath;  // photon slots per path (<= PM_MAX_SLOTS_PER_PATH)
    uint maxDepth;      // hits a photon path may have (stores at hits 1..maxDepth)
    uint rrDepth;       // Russian roulette from this hit on
    float pathScale;    // 1 / (paths of the pass): each photon's share of the emitted power
};
PMCR_CHECK_SIZE(PhotonShootPush, 32);
