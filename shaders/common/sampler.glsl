// The path tracer's sample generator: per pixel, a padded (0,2)-sequence (pbrt-v4
// PaddedSobolSampler). Each dimension pair draws point `index` of the first two Sobol
// dimensions, with the index shuffled and the point Owen-scrambled by hashes of (pixel, pair)
// (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)). Any prefix of 2^k samples
// of a pixel is therefore a (0,k,2)-net in every pair: samples are stratified within the pixel
// whatever the sample count, which PMC-IP's varying per-pixel counts rely on.
#ifndef PMCR_SAMPLER_GLSL
#define PMCR_SAMPLER_GLSL

#include "common/rng.glsl"

// Laine-Karras style hash permutation: bit k of the result depends only on bits <= k of x
// (Burley 2020, listing 2 constants).
uint laineKarrasPermutation(uint x, uint seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

// Owen scrambling of a 32-bit fixed-point number in [0, 1) (Burley 2020, sec. 4).
uint nestedUniformScramble(uint x, uint seed) {
    return bitfieldReverse(laineKarrasPermutation(bitfieldReverse(x), seed));
}

// Sobol dimension 1: direction numbers v_1 = 1/2, v_{k+1} = v_k xor (v_k >> 1), i.e. the
// generator matrix is Pascal's triangle mod 2. By Lucas' theorem, entry (r, c) is 1 when the bits
// of r are a subset of those of c, so the product is a subset-XOR (zeta) transform of the
// bit-reversed index: five masked shift-XORs instead of one step per index bit.
uint sobolSecondDimension(uint index) {
    uint x = bitfieldReverse(index);
    x ^= (x << 1) & 0xAAAAAAAAu;
    x ^= (x << 2) & 0xCCCCCCCCu;
    x ^= (x << 4) & 0xF0F0F0F0u;
    x ^= (x << 8) & 0xFF00FF00u;
    x ^= (x << 16) & 0xFFFF0000u;
    return x;
}

struct Sampler {
    uint seed;       // hash of (pixel or stream, render seed)
    uint index;      // sample index within the pixel's sequence
    uint dimension;  // next dimension pair
};

Sampler samplerCreate(uint pixel, uint sampleIndex, uint renderSeed) {
    Sampler s;
    s.seed = hashCombine(pixel, renderSeed);
    s.index = sampleIndex;
    s.dimension = 0u;
    return s;
}

vec2 samplerGet2D(inout Sampler s) {
    uint dimSeed = hashCombine(s.seed, s.dimension);
    s.dimension += 1u;
    // Shuffle the index (an Owen scramble of the index keeps aligned blocks of 2^k samples
    // together, so prefixes stay nets), then scramble each coordinate.
    uint i = nestedUniformScramble(s.index, dimSeed);
    uint x = nestedUniformScramble(bitfieldReverse(i), hashPcg(dimSeed ^ 0x68bc21ebu));
    uint y = nestedUniformScramble(sobolSecondDimension(i), hashPcg(dimSeed ^ 0x02e5be93u));
    return vec2(uintToUnitFloat(x), uintToUnitFloat(y));
}

// In place of samplerGet2D, a point uniform in [0, 1)^2 and independent of every other sample's,
// with no stratification: a PCG stream seeded by a hash of (pixel or stream, render seed), the
// sample index and the dimension. It takes the dimension pair samplerGet2D would have taken, so
// the draws after it are the sequence's. The pixel sampler `independent` (--pixel-sampler; the
// uniform image-plane sampling of the PMC-IP and PMC-PT papers) draws raster positions with it.
vec2 samplerGetIndependent2D(inout Sampler s) {
    Rng r = rngCreate(hash3(s.seed, s.index, s.dimension));
    s.dimension += 1u;
    return rngNext2(r);
}

float samplerGet1D(inout Sampler s) {
    uint dimSeed = hashCombine(s.seed, s.dimension);
    s.dimension += 1u;
    uint i = nestedUniformScramble(s.index, dimSeed);
    return uintToUnitFloat(nestedUniformScramble(bitfieldReverse(i), hashPcg(dimSeed ^ 0x68bc21ebu)));
}

#endif
