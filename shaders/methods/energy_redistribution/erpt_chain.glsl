// One step of an energy-redistribution chain (ERPT fig. 6 "equal deposition", PMC-ER fig. 2
// lines 9-12): choose a perturbation, propose, accept with probability a, deposit e_d at the
// (new) current path with its colour P / lum(P). With ERPT_FLAG_EXPECTED_VALUES the deposit is
// replaced by its expectation given the proposal, a e_d at y and (1 - a) e_d at x, which is
// also unbiased and less noisy.
#ifndef PMCR_ERPT_CHAIN_GLSL
#define PMCR_ERPT_CHAIN_GLSL

#include "common/film.glsl"
#include "methods/energy_redistribution/mutate_caustic.glsl"
#include "methods/energy_redistribution/mutate_lens.glsl"
#include "methods/energy_redistribution/splat.glsl"

layout(set = WORK_SET, binding = ERPT_BINDING_PIXEL_STATS, scalar) buffer PixelStatsBuffer {
    PixelChainStats pixelStats[];
};
layout(set = WORK_SET, binding = ERPT_BINDING_ENERGY, scalar) buffer EnergyBuffer { float energy[]; };

struct StepCounters {
    uint lensProposed;
    uint lensAccepted;
    uint causticProposed;
    uint causticAccepted;
    uint invalid;
    uint deposits;
    uint dropped;
    uint rays;
    float deposited;   // in units of e_d
};

StepCounters stepCountersCreate() {
    StepCounters c;
    c.lensProposed = c.lensAccepted = c.causticProposed = c.causticAccepted = 0u;
    c.invalid = c.deposits = c.dropped = c.rays = 0u;
    c.deposited = 0.0;
    return c;
}

void depositAt(inout ChainState st, uint pixel, vec3 throughput, float amount, inout Rng rng,
               uint consecutiveCap, inout StepCounters counters) {
    if (amount <= 0.0) return;
    counters.deposits += 1u;
    float y = luminance(throughput);
    // Consecutive-sample filter (ERPT sec. 4.4, biased, off unless consecutiveCap > 0).
    if (consecutiveCap > 0u && st.consecutive > consecutiveCap && pixel == st.lastPixel) {
        counters.dropped += 1u;
        return;
    }
    if (!(y > 0.0) || !splatDeposit(pixel, throughput / y, amount, rng)) {
        counters.dropped += 1u;
        return;
    }
    counters.deposited += amount;
}

// Advances the chain by one mutation, depositing `amount` e_d (1 in ERPT; a PMC-ER member's
// shares). `mode`, `lensRadius`, the angle laws and the flags come from the caller (ERPT push
// constants, or a PMC-ER member's chosen component).
void chainStep(uint chain, inout ChainState st, inout Rng rng, uint mode, float causticProbability,
               float lensRadius, AngleSampler lensAngle, AngleSampler causticAngle, uint flags,
               uint consecutiveCap, float amount, inout StepCounters counters,
               out float acceptProbability, out bool proposedCaustic) {
    uint xBase = pathBase(chain, st.slot);
    uint yBase = pathBase(chain, st.slot ^ 1u);
    uint k = st.vertexCount;
    uint head = causticHead(xBase, k);
    // ERPT 4.3: caustic perturbations exactly for paths L...S D E, lens otherwise.
    bool useCaustic = false;
    if (mode == MUTATION_ERPT) useCaustic = head > 1u;
    else if (mode == MUTATION_MIX) useCaustic = head > 0u && rngNext(rng) < causticProbability;
    else if (mode == MUTATION_CAUSTIC) useCaustic = true;
    proposedCaustic = useCaustic;

    MutationResult r;
    bool valid;
    if (useCaustic) {
        counters.causticProposed += 1u;
        valid = mutateCaustic(xBase, yBase, k, st.throughput, causticAngle, rng, counters.rays, r);
    } else {
        counters.lensProposed += 1u;
        valid = mutateLens(xBase, yBase, k, st.raster, st.throughput, lensRadius, lensAngle, rng,
                           counters.rays, r);
    }
    acceptProbability = valid ? acceptance(r) : 0.0;
    if (!valid) counters.invalid += 1u;
    else atomicAdd(pixelStats[rasterPixel(r.rasterY)].proposals, 1u);

    uint xPixel = rasterPixel(st.raster);
    if ((flags & ERPT_FLAG_EXPECTED_VALUES) != 0u) {
        if (valid) depositAt(st, rasterPixel(r.rasterY), r.throughputY, amount * acceptProbability, rng, 0u, counters);
        depositAt(st, xPixel, st.throughput, amount * (1.0 - acceptProbability), rng, 0u, counters);
    }
    if (valid && rngNext(rng) < acceptProbability) {
        st.slot ^= 1u;
        st.raster = r.rasterY;
        st.throughput = r.throughputY;
        if (useCaustic) counters.causticAccepted += 1u;
        else counters.lensAccepted += 1u;
    }
    if ((flags & ERPT_FLAG_EXPECTED_VALUES) == 0u) {
        uint pixel = rasterPixel(st.raster);
        st.consecutive = pixel == st.lastPixel ? st.consecutive + 1u : 1u;
        st.lastPixel = pixel;
        depositAt(st, pixel, st.throughput, amount, rng, consecutiveCap, counters);
    }
}

void flushStepCounters(StepCounters c) {
    counterAdd(COUNTER_LENS_PROPOSED, c.lensProposed);
    counterAdd(COUNTER_LENS_ACCEPTED, c.lensAccepted);
    counterAdd(COUNTER_CAUSTIC_PROPOSED, c.causticProposed);
    counterAdd(COUNTER_CAUSTIC_ACCEPTED, c.causticAccepted);
    counterAdd(COUNTER_INVALID_PROPOSALS, c.invalid);
    counterAdd(COUNTER_DEPOSITS, c.deposits);
    counterAdd(COUNTER_DEPOSITS_DROPPED, c.dropped);
    counterAdd(COUNTER_RAYS, c.rays);
    float total = subgroupAdd(c.deposited);
    if (subgroupElect() && total != 0.0) atomicAdd(energy[ENERGY_DEPOSITED], total);
}

#endif
