// PMC-HI, the adaptive direct-lighting sampler (Fan et al., sec. 5): its mixture's component
// slots, limits and dispatch parameters. The maths is in shaders/methods/pmc_hi/pmc_hi.glsl.

// Mixture components, by slot: the BSDF, the cone around important directions, then one per
// light (PMC_HI_LIGHT + l for light l), or a single one for all lights when they are shared,
// then, in a scene with an environment light (PMC_HI_FLAG_ENVIRONMENT), the environment's at
// PMC_HI_LIGHT + lightComponents: it takes one of the PMC_HI_MAX_LIGHTS light slots, so with an
// environment there are at most PMC_HI_MAX_LIGHTS - 1 light components (the host shares one
// among all lights beyond that). The slot count, and with it the kernel's arrays, stays what it
// is for emitters alone: with one slot more, pmc-hi on checkers-two-lights took 4-5% more CPU
// time on lavapipe (median and minimum of 8 interleaved runs; the machine was shared, so the
// evidence is weak), and this way its emitters-only images stay bit for bit. Punctual lights are no component: a delta distribution has no density to mix
// (pmc_hi.glsl pmcHiPunctualDirect).
PMCR_CONST uint PMC_HI_BSDF = 0;
PMCR_CONST uint PMC_HI_CONE = 1;
PMCR_CONST uint PMC_HI_LIGHT = 2;
PMCR_CONST uint PMC_HI_MAX_LIGHTS = 8;                            // --max-light-components limit
PMCR_CONST uint PMC_HI_MAX_COMPONENTS = PMC_HI_LIGHT + PMC_HI_MAX_LIGHTS;
PMCR_CONST uint PMC_HI_MAX_POPULATION_PER_COMPONENT = 8;
PMCR_CONST uint PMC_HI_MAX_ITERATIONS = 16;
// Indices per camera sample in the per-component sample streams (pmc_hi.glsl pmcHiStream): a
// power of two at least the largest population.
PMCR_CONST uint PMC_HI_STREAM_BLOCK = 128;
#ifdef __cplusplus
static_assert(PMC_HI_MAX_POPULATION_PER_COMPONENT * PMC_HI_MAX_COMPONENTS <= PMC_HI_STREAM_BLOCK);
#endif
// Smallest cone half-angle (radians): the cone of a population whose weight sits on one
// direction keeps some width.
PMCR_CONST float PMC_HI_CONE_MIN_ANGLE = 0.02f;

PMCR_CONST uint PMC_HI_FLAG_RAO_BLACKWELL = 1u;  // w = f / K (eq. 8); else f / h_k (sec. 7) [biased]
PMCR_CONST uint PMC_HI_FLAG_RECORD_ALPHA = 2u;   // add each pixel's final alpha to the alpha sums
PMCR_CONST uint PMC_HI_FLAG_FEEDBACK = 4u;       // start from the pixel's alpha, write each result's
PMCR_CONST uint PMC_HI_FLAG_INITIAL_ALPHA = 8u;  // iteration 0 without feedback: initialAlpha
// The environment is a component (its slot after the lights'); set only with the kernel variant
// that has the environment compiled in (pmc_hi_all_lights.comp).
PMCR_CONST uint PMC_HI_FLAG_ENVIRONMENT = 16u;

// Work-set binding of pmc_hi.comp beside the path tracer's (render_types.h PT_BINDING_*):
// per pixel PMC_HI_ALPHA_STRIDE floats: the sums of the final alpha of its estimates by slot,
// then the number of estimates summed (pixels whose first hit scatters through a non-delta lobe).
PMCR_CONST uint PMC_HI_BINDING_ALPHA = 6;
PMCR_CONST uint PMC_HI_ALPHA_STRIDE = PMC_HI_MAX_COMPONENTS + 1;
// PMC-IP feedback (sec. 6.1, PMC_HI_FLAG_FEEDBACK, request lists): per pixel the starting alpha
// (PMC_HI_MAX_COMPONENTS floats, all 0: none yet), and per request the final alpha of its
// first-hit estimate (all 0 when nothing was adapted).
PMCR_CONST uint PMC_HI_BINDING_ALPHA_START = 7;
PMCR_CONST uint PMC_HI_BINDING_ALPHA_OUT = 8;

struct PmcHiParams {
    uint lightComponents;        // number of light slots used (1 when shared)
    uint sharedLight;            // 1: the one light slot samples all emitters (lights.glsl)
    uint populationPerComponent; // N = populationPerComponent * m (slots in use)
    uint iterations;             // PMC iterations per estimate
    float coneInitial;           // alpha_cone after iteration 0 (the others scaled by 1 - it)
    float alphaFloor;            // defensive floor of the BSDF and light weights
    uint flags;                  // PMC_HI_FLAG_*
    uint initialPopulationPerComponent;  // the same for iteration 0
    // With PMC_HI_FLAG_INITIAL_ALPHA, iteration 0's weights (without feedback) by slot, before
    // the floor and normalisation; the cone's is ignored (it has no axis yet).
    float initialAlpha[PMC_HI_MAX_COMPONENTS];
    float adaptRate;             // a = (1 - rate) a + rate a(eq. 9); 1: eq. 9 (the paper)
};
PMCR_CHECK_SIZE(PmcHiParams, 76);

// Push constants of pmc_hi.comp: the path tracer's, then PMC-HI's.
struct PmcHiPush {
    PtPush pt;
    PmcHiParams hi;
};
PMCR_CHECK_SIZE(PmcHiPush, 128);  // the 128 bytes every device has

// Input of the PMC-HI test kernel (shaders/tests/pmc_hi_test.comp): a mixture and the shading
// point it samples at (triangle, barycentrics, wo), on the bound scene.
struct PmcHiTestSetup {
    PmcHiParams params;
    float alpha[PMC_HI_MAX_COMPONENTS];
    vec3 coneAxis;
    float coneOneMinusCos;
    vec3 wo;
    uint triangle;
    vec2 barycentrics;
    uint m;                // slots in use (DMS)
    uint N;                // population (DMS)
};
PMCR_CHECK_SIZE(PmcHiTestSetup, 164);
