// One Metropolis step of a PSSMLT chain (Kelemen et al. 2002 sec. 4; Veach 1997 sec. 11.3):
// the proposal y (a large or small step of the primary vector, pss_sampler.glsl) is path-traced,
// accepted with a = min(1, F(y) / F(x)), F = lum(L) (the steps are symmetric), and the step's
// deposit is replaced by its expected value (Veach 1997 sec. 11.3.4, "expected values"):
// a e_d L(y) / F(y) at y's pixel and (1 - a) e_d L(x) / F(x) at x's, with e_d = b / mutations.
// The host sets e_d when it resolves the splat film; here a deposit is in units of e_d.
#ifndef PMCR_PSSMLT_CHAIN_GLSL
#define PMCR_PSSMLT_CHAIN_GLSL

#include "methods/pssmlt/pss_deposit.glsl"
#include "methods/pssmlt/pss_sampler.glsl"
#include "methods/pt/path_tracer.glsl"
#include "methods/pssmlt/pss_path.glsl"

// The sampler of chain `chain` in state `st`.
Sampler pssChainSampler(uint chain, PssmltChain st) {
    return pssSampler(push, chain, st.rng, st.iteration, st.lastLargeStep, false);
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

#endif
