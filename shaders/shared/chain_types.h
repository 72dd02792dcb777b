// Markov chains over light paths: the state energy redistribution (ERPT, PMC-ER) mutates.
//
// A chain holds its current path and a proposal in two slots of CHAIN_MAX_VERTICES vertices;
// accepting a proposal flips `slot`. A path x1..xk runs from the surface seen by the pinhole
// (x0, implied by the raster position) to a point on an emitter (xk). Vertices are stored as
// (triangle, barycentrics): positions, normals and materials are recomputed from the scene, so
// a vertex is 16 bytes and the two slots of a 17-vertex chain fit in 544 bytes.
//
// Vertex types: VERTEX_SPECULAR marks an S vertex (scattered by the delta lobe `lobe`, reflecting
// or, with VERTEX_TRANSMISSION, transmitting); other non-emitter vertices are D (any non-delta
// lobe); the last vertex has VERTEX_EMITTER. A mutation must reproduce the type sequence.

PMCR_CONST uint CHAIN_MAX_VERTICES = PATH_MAX_VERTICES + 1u;  // eye vertices + the light point
PMCR_CONST uint CHAIN_LOBE_SHIFT = 8u;                         // lobe id in flags bits 8..11

struct ChainVertex {
    uint triangle;
    float b1;
    float b2;
    uint flags;          // VERTEX_SPECULAR | VERTEX_TRANSMISSION | VERTEX_EMITTER | lobe << 8
};
PMCR_CHECK_SIZE(ChainVertex, 16);

struct ChainState {
    vec2 raster;         // film position of the current path's x1
    uint vertexCount;    // k: vertices x1..xk (both slots)
    uint slot;           // slot of the current path (0 or 1)
    vec3 throughput;     // P(x): product of the scattering factors and Le of the current path
    uint rng;            // Rng state
    uint lastPixel;      // for the consecutive-sample filter
    uint consecutive;    // deposits in a row on lastPixel
    uint origin;         // index of the seed path (record * 2 * PATH_MAX_VERTICES + ...) for stats
    uint pad;
};
PMCR_CHECK_SIZE(ChainState, 48);

// Work-set bindings of the ERPT kernels.
PMCR_CONST uint ERPT_BINDING_RECORDS = 0;         // PathRecord[] of the seed pass
PMCR_CONST uint ERPT_BINDING_RECORD_VERTICES = 1; // PathVertex[]
PMCR_CONST uint ERPT_BINDING_CHAIN_COUNTS = 2;    // uint[record]: chains the record starts
PMCR_CONST uint ERPT_BINDING_CHAIN_OFFSETS = 3;   // uint[record + 1]: exclusive prefix sums
PMCR_CONST uint ERPT_BINDING_CHAINS = 4;          // ChainState[]
PMCR_CONST uint ERPT_BINDING_CHAIN_VERTICES = 5;  // ChainVertex[chain * 2 * CHAIN_MAX_VERTICES]
PMCR_CONST uint ERPT_BINDING_SPLAT = 6;           // SplatPixel[] (fixed-point deposits)
PMCR_CONST uint ERPT_BINDING_COUNTERS = 7;        // uint[COUNTER_COUNT]
PMCR_CONST uint ERPT_BINDING_PIXEL_STATS = 8;     // PixelChainStats[] (diagnostics, filter)
PMCR_CONST uint ERPT_BINDING_ENERGY = 9;          // float[ENERGY_SLOTS], units of e_d:
PMCR_CONST uint ENERGY_SEED = 0;       // energy of the seed paths that start chains or members
PMCR_CONST uint ENERGY_DEPOSITED = 1;  // deposited by chains and members
PMCR_CONST uint ENERGY_DIRECT = 2;     // direct seed paths deposited at their pixel (--redistribute)
PMCR_CONST uint ENERGY_SLOTS = 3;

// Mutation statistics counters (shared/render_types.h COUNTER_* continue here).
PMCR_CONST uint COUNTER_LENS_PROPOSED = 4;
PMCR_CONST uint COUNTER_LENS_ACCEPTED = 5;
PMCR_CONST uint COUNTER_CAUSTIC_PROPOSED = 6;
PMCR_CONST uint COUNTER_CAUSTIC_ACCEPTED = 7;
PMCR_CONST uint COUNTER_INVALID_PROPOSALS = 8;  // signature changed, occluded, left the image
PMCR_CONST uint COUNTER_DEPOSITS = 9;
PMCR_CONST uint COUNTER_DEPOSITS_DROPPED = 10;  // non-finite or filtered away (filters are biased)
PMCR_CONST uint COUNTER_CHAINS_STARTED = 11;
// Metropolis light transport (mlt, pssmlt): independent / large-step and PSS small-step mutations.
PMCR_CONST uint COUNTER_LARGE_PROPOSED = 12;
PMCR_CONST uint COUNTER_LARGE_ACCEPTED = 13;
PMCR_CONST uint COUNTER_SMALL_PROPOSED = 14;
PMCR_CONST uint COUNTER_SMALL_ACCEPTED = 15;

// Deposits accumulate as 64-bit fixed point per channel (value * SPLAT_SCALE / e_d, rounded
// stochastically): order-independent, so a seed gives the same image bit for bit, and unbiased.
struct SplatPixel {
    uint64_t r;
    uint64_t g;
    uint64_t b;
};
PMCR_CHECK_SIZE(SplatPixel, 24);
PMCR_CONST float SPLAT_QUANTA_PER_DEPOSIT = 1048576.0;  // 2^20 quanta per e_d of luminance

struct PixelChainStats {
    uint chainsStarted;  // chains whose seed path lies in this pixel
    uint proposals;      // proposals that landed in this pixel (ERPT's proposed-mutations image)
};
PMCR_CHECK_SIZE(PixelChainStats, 8);

// Mutation selection (ErptPush.mutationMode).
PMCR_CONST uint MUTATION_ERPT = 0;     // caustic for paths ending ...S D E, lens otherwise (ERPT 4.3)
PMCR_CONST uint MUTATION_MIX = 1;      // caustic with causticProbability when applicable
PMCR_CONST uint MUTATION_LENS = 2;     // lens only
PMCR_CONST uint MUTATION_CAUSTIC = 3;  // caustic only (paths it does not apply to stay put)

PMCR_CONST uint ERPT_FLAG_EXPECTED_VALUES = 1u;  // deposit a*e_d at y and (1-a)*e_d at x
PMCR_CONST uint ERPT_FLAG_CAUSTIC_THETA_D = 2u;  // caustic angle from the lens radius (PMC-ER eq. 6)
PMCR_CONST uint ERPT_FLAG_DEPOSIT_DIRECT = 4u;   // seeds with one scattering vertex or none are
                                                 // deposited at their pixel, not redistributed

struct ErptPush {
    uint recordCount;        // seed kernels: records in this pass
    uint chainBase;          // chain kernels: first chain of this dispatch
    uint chainCount;
    uint steps;              // mutations per chain in this dispatch
    uint seed;
    uint pass;
    uint chainLength;        // m
    uint mutationMode;
    float depositEnergy;     // e_d (luminance, pixel-value units)
    float seedScale;         // seed energy = lum(contribution) * seedScale
    float lensRadius;        // pixels
    float causticThetaMin;   // radians (log-uniform between min and max, Veach 1997)
    float causticThetaMax;
    float causticProbability;
    uint flags;              // ERPT_FLAG_*
    uint consecutiveCap;     // 0 = off (biased filter)
    uint chainOffset;        // seed write kernel: chain index of chainBase in the pass
    uint pad0;
    uint pad1;
    uint pad2;
};
PMCR_CHECK_SIZE(ErptPush, 80);
