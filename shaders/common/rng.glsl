// Random numbers: counter-based hashing for seeds, PCG for streams.
#ifndef PMCR_RNG_GLSL
#define PMCR_RNG_GLSL

// 32-bit integer hash (the PCG output permutation used as a hash; Jarzynski and Olano 2020,
// "Hash Functions for GPU Rendering", JCGT 9(3): "pcg").
uint hashPcg(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
uint hashCombine(uint a, uint b) { return hashPcg(a ^ (hashPcg(b) + 0x9e3779b9u + (a << 6) + (a >> 2))); }
uint hash3(uint a, uint b, uint c) { return hashCombine(hashCombine(a, b), c); }

// A 32-bit PCG stream (O'Neill 2014, PCG-RXS-M-XS 32/32): one uint of state per stream,
// small enough to live in path records and chain states.
struct Rng {
    uint state;
};

Rng rngCreate(uint seed) {
    Rng r;
    r.state = hashPcg(seed);
    return r;
}

uint rngNextUint(inout Rng r) {
    r.state = r.state * 747796405u + 2891336453u;
    uint word = ((r.state >> ((r.state >> 28u) + 4u)) ^ r.state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Uniform in [0, 1): the top 24 bits, exactly representable.
float uintToUnitFloat(uint x) { return float(x >> 8) * (1.0 / 16777216.0); }
float rngNext(inout Rng r) { return uintToUnitFloat(rngNextUint(r)); }
vec2 rngNext2(inout Rng r) { return vec2(rngNext(r), rngNext(r)); }

#endif
