// Warps from [0,1)^2 to the domains the integrators sample, with their densities.
#ifndef PMCR_SAMPLING_GLSL
#define PMCR_SAMPLING_GLSL

#include "common/math.glsl"

// Concentric map to the unit disk (Shirley and Chiu 1997); uniform, density 1/pi.
vec2 sampleUniformDiskConcentric(vec2 u) {
    vec2 o = 2.0 * u - 1.0;
    if (o.x == 0.0 && o.y == 0.0) return vec2(0.0);
    float r, theta;
    if (abs(o.x) > abs(o.y)) {
        r = o.x;
        theta = (PI / 4.0) * (o.y / o.x);
    } else {
        r = o.y;
        theta = (PI / 2.0) - (PI / 4.0) * (o.x / o.y);
    }
    return r * vec2(cos(theta), sin(theta));
}

// Cosine-weighted hemisphere around +z (Malley's method); pdf = cos(theta) / pi.
vec3 sampleCosineHemisphere(vec2 u) {
    vec2 d = sampleUniformDiskConcentric(u);
    float z = safeSqrt(1.0 - dot(d, d));
    return vec3(d, z);
}
float cosineHemispherePdf(float cosTheta) { return max(cosTheta, 0.0) * INV_PI; }

// Uniform direction on the sphere; pdf = 1 / (4 pi).
vec3 sampleUniformSphere(vec2 u) {
    float z = 1.0 - 2.0 * u.x;
    float r = safeSqrt(1.0 - z * z);
    float phi = TWO_PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), z);
}

// Uniform direction in the cone of half-angle acos(cosThetaMax) around +z;
// pdf = 1 / (2 pi (1 - cosThetaMax)).
vec3 sampleUniformCone(vec2 u, float cosThetaMax) {
    float cosTheta = (1.0 - u.x) + u.x * cosThetaMax;
    float sinTheta = safeSqrt(1.0 - cosTheta * cosTheta);
    float phi = TWO_PI * u.y;
    return vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta);
}
float uniformConePdf(float cosThetaMax) { return 1.0 / (TWO_PI * (1.0 - cosThetaMax)); }

// Two barycentrics (b1, b2; b0 = 1 - b1 - b2) of a point uniform on a triangle, area-preserving
// (Heitz 2019, "A Low-Distortion Map Between Triangle and Square"). Any two of the three
// barycentrics of a uniform point are identically distributed, so the labelling is free.
vec2 sampleUniformTriangle(vec2 u) {
    vec2 b;
    if (u.x < u.y) {
        b.x = u.x / 2.0;
        b.y = u.y - b.x;
    } else {
        b.y = u.y / 2.0;
        b.x = u.x - b.y;
    }
    return b;
}

// Veach's power heuristic with beta = 2 (Veach 1997, eq. 9.13), for one sample of each strategy.
float powerHeuristic(float pdfA, float pdfB) {
    float a = pdfA * pdfA;
    float b = pdfB * pdfB;
    if (isinf(a)) return 1.0;
    return a + b > 0.0 ? a / (a + b) : 0.0;
}
// Power heuristic for nA samples of strategy A against nB samples of B.
float powerHeuristic(float nA, float pdfA, float nB, float pdfB) {
    return powerHeuristic(nA * pdfA, nB * pdfB);
}

// Veach's balance heuristic (Veach 1997, eq. 9.8), for one sample of each strategy: the weights
// of a pair of strategies sum to one as the power heuristic's do (tests/gpu/test_sampling.cpp).
float balanceHeuristic(float pdfA, float pdfB) {
    if (isinf(pdfA)) return 1.0;
    return pdfA + pdfB > 0.0 ? pdfA / (pdfA + pdfB) : 0.0;
}
// Balance heuristic for nA samples of strategy A against nB samples of B.
float balanceHeuristic(float nA, float pdfA, float nB, float pdfB) {
    return balanceHeuristic(nA * pdfA, nB * pdfB);
}

#endif
