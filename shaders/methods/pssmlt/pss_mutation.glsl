// The mutations of primary sample space (Kelemen et al. 2002 sec. 3.3), one coordinate at a
// time: a large step draws the coordinate anew, uniform on [0, 1); a small step adds a Gaussian
// offset and wraps around to [0, 1) (pbrt-v3 MLTSampler's law in place of the paper's
// exponential one: n successive Gaussian steps of sigma add up to one of sigma sqrt(n), which
// lets coordinates be mutated lazily). Both are symmetric, T(x -> y) = T(y -> x): the offset's
// law is even and the wrap-around maps the circle onto itself, so the acceptance is
// min(1, F(y) / F(x)) (Kelemen et al. eq. 6).
#ifndef PMCR_PSS_MUTATION_GLSL
#define PMCR_PSS_MUTATION_GLSL

#include "common/math.glsl"
#include "common/rng.glsl"

// x mod 1, in [0, 1) (a float just below 0 would round to 1.0 after adding 1).
float wrapUnit(float x) {
    float v = x - floor(x);
    return v < 1.0 ? v : 0.0;
}

// A standard normal deviate (Box and Muller 1958), from two of the chain's random numbers.
float standardNormal(inout Rng rng) {
    float u1 = rngNext(rng);
    float u2 = rngNext(rng);
    return sqrt(-2.0 * log(1.0 - u1)) * cos(TWO_PI * u2);
}

// `n` successive small steps of standard deviation `sigma` from `value`, composed in closed form:
// one Gaussian offset of sigma sqrt(n), wrapped (the wrapped sum of wrapped offsets is the
// wrapped sum of the offsets).
float smallStep(float value, float sigma, uint n, inout Rng rng) {
    return wrapUnit(value + standardNormal(rng) * sigma * sqrt(float(n)));
}

// Coordinate `dimension` of bootstrap sample `sampleIndex` (a uniform primary vector): a hash of
// (render seed, sample, dimension), so a chain regenerates its start sample's vector exactly.
float bootstrapCoordinate(uint seed, uint sampleIndex, uint dimension) {
    return uintToUnitFloat(hash3(seed ^ 0x7055b007u, sampleIndex, dimension));
}

#endif
