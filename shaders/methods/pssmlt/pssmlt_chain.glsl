// One Metropolis step of a PSSMLT chain (Kelemen et al. 2002 sec. 4; Veach 1997 sec. 11.3):
// the proposal y (a large or small step of the primary vector, pss_sampler.glsl) is path-traced,
// accepted with a = min(1, F(y) / F(x)), F = lum(L) (the steps are symmetric), and the step's
// deposit is replaced by its expected value (Veach 1997 sec. 11.3.4, "expected values"):
// a e_d L(y) / F(y) at y's pixel and (1 - a) e_d L(x) / F(x) at x's, with e_d = b / mutations.
// The host sets e_d when it resolves the splat film; here a deposit is in units of e_d.
#ifndef PMCR_PSSMLT_CHAIN_GLSL
#define PMCR_PSSMLT_CHAIN_GLSL

#define COUNTERS_BINDING ERPT_BINDING_COUNTERS
#define FILM_BINDING ERPT_BINDING_SPLAT
#include "common/film.glsl"
#include "methods/pssmlt/pss_sampler.glsl"
#include "methods/pt/path_tracer.glsl"
#include "methods/pssmlt/pss_path.glsl"
#include "methods/energy_redistribution/splat.glsl"

layout(set = WORK_SET, binding = ERPT_BINDING_ENERGY, scalar) buffer EnergyBuffer { float energy[]; };

struct PssCounters {
    uint largeProposed;
    uint largeAccepted;
    uint smallProposed;
    uint smallAccepted;
    uint deposits;
    uint dropped;      // deposits not made: non-finite or zero target
    uint nanPaths;     // proposals whose estimate was not finite (F = 0: rejected)
    uint rays;
    uint paths;
    float deposited;   // in units of e_d
};

PssCounters pssCountersCreate() {
    PssCounters c;
    c.largeProposed = c.largeAccepted = c.smallProposed = c.smallAccepted = 0u;
    c.deposits = c.dropped = c.nanPaths = c.rays = c.paths = 0u;
    c.deposited = 0.0;
    return c;
}

// The sampler of chain `chain` in state `st`.
Sampler pssChainSampler(uint chain, PssmltChain st) {
    Sampler s;
    s.chain = chain;
    s.stride = push.chainStride;
    s.dimensions = push.dimensions;
    s.dimension = 0u;
    s.iteration = st.iteration;
    s.lastLargeStep = st.lastLargeStep;
    s.largeStep = false;
    s.sigma = push.sigma;
    s.rng.state = st.rng;
    return s;
}

// Deposits `amount` e_d with colour L / F at `pixel`.
void pssDeposit(uint pixel, vec3 L, float F, float amount, inout Rng rng, inout PssCounters c) {
    if (!(amount > 0.0)) return;
    c.deposits += 1u;
    if (!(F > 0.0) || !splatDeposit(pixel, L / F, amount, rng)) {
        c.dropped += 1u;
        return;
    }
    c.deposited += amount;
}

// Ends the proposal whose estimate is Ly at pixel yPixel: deposits, then accepts or rejects.
void pssStep(inout PssmltChain st, inout Sampler s, vec3 Ly, uint yPixel, inout PssCounters c) {
    c.paths += 1u;
    if (!isFinite(Ly)) c.nanPaths += 1u;
    float Fy = pssTarget(Ly);
    float Fx = pssTarget(st.radiance);
    // Kelemen et al. 2002 eq. 6 with T(x -> y) = T(y -> x).
    float a = Fx > 0.0 ? min(1.0, Fy / Fx) : 1.0;
    pssDeposit(yPixel, Ly, Fy, a, s.rng, c);
    pssDeposit(st.pixel, st.radiance, Fx, 1.0 - a, s.rng, c);
    bool accept = rngNext(s.rng) < a;
    if (s.largeStep) {
        c.largeProposed += 1u;
        if (accept) c.largeAccepted += 1u;
    } else {
        c.smallProposed += 1u;
        if (accept) c.smallAccepted += 1u;
    }
    if (accept) {
        pssAccept(s);
        st.radiance = Ly;
        st.pixel = yPixel;
    } else {
        pssReject(s);
    }
}

void flushPssCounters(PssCounters c) {
    counterAdd(COUNTER_LARGE_PROPOSED, c.largeProposed);
    counterAdd(COUNTER_LARGE_ACCEPTED, c.largeAccepted);
    counterAdd(COUNTER_SMALL_PROPOSED, c.smallProposed);
    counterAdd(COUNTER_SMALL_ACCEPTED, c.smallAccepted);
    counterAdd(COUNTER_DEPOSITS, c.deposits);
    counterAdd(COUNTER_DEPOSITS_DROPPED, c.dropped);
    counterAdd(COUNTER_NAN_DROPPED, c.nanPaths);
    counterAdd(COUNTER_RAYS, c.rays);
    counterAdd(COUNTER_PATHS, c.paths);
    float total = subgroupAdd(c.deposited);
    if (subgroupElect() && total != 0.0) atomicAdd(energy[ENERGY_DEPOSITED], total);
}

#endif
