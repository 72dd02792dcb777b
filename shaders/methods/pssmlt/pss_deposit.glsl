// What every PSSMLT chain kernel counts, and its deposits on the splat film (in units of e_d):
// over pt (pssmlt_chain.glsl) and over bdpt (pssmlt_bdpt_step_kernel.glsl).
#ifndef PMCR_PSS_DEPOSIT_GLSL
#define PMCR_PSS_DEPOSIT_GLSL

#define COUNTERS_BINDING ERPT_BINDING_COUNTERS
#define FILM_BINDING ERPT_BINDING_SPLAT
#include "common/film.glsl"
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
