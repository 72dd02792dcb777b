// The GGX (Trowbridge-Reitz) microfacet distribution, isotropic, in the local frame (n = +z).
// alpha = roughness^2 (glTF). Walter et al. 2007 ("Microfacet Models for Refraction through
// Rough Surfaces"), Heitz 2014 ("Understanding the Masking-Shadowing Function"), Heitz 2018
// ("Sampling the GGX Distribution of Visible Normals").
#ifndef PMCR_MICROFACET_GLSL
#define PMCR_MICROFACET_GLSL

#include "common/math.glsl"

// D(m) = alpha^2 / (pi ((n.m)^2 (alpha^2 - 1) + 1)^2)   (Walter 2007, eq. 33)
// The denominator's (n.m)^2 (alpha^2 - 1) + 1 is evaluated as sin^2 + alpha^2 cos^2 (equal
// for unit m): near the pole, where a sharp lobe (alpha = 0.0025) peaks, the first form cancels
// to about alpha^2 and loses most of its digits (float m.z^2 is good to 1e-7), and a GPU that
// contracts it into a fused multiply-add gets other digits than lavapipe (D's integral was 0.9986
// on an NVIDIA H200). pbrt-v4 writes D with tan^2(theta) for the same reason.
float ggxD(vec3 m, float alpha) {
    if (m.z <= 0.0) return 0.0;
    float a2 = alpha * alpha;
    float d = m.x * m.x + m.y * m.y + a2 * (m.z * m.z);
    return a2 / (PI * d * d);
}

// Smith Lambda for GGX: (-1 + sqrt(1 + alpha^2 tan^2(theta))) / 2   (Heitz 2014, eq. 72)
float ggxLambda(vec3 w, float alpha) {
    float cos2 = w.z * w.z;
    if (cos2 <= 0.0) return FLOAT_MAX;
    float tan2 = max(1.0 - cos2, 0.0) / cos2;
    return 0.5 * (-1.0 + sqrt(1.0 + alpha * alpha * tan2));
}

float ggxG1(vec3 w, float alpha) { return 1.0 / (1.0 + ggxLambda(w, alpha)); }

// Height-correlated masking-shadowing (Heitz 2014, eq. 99).
float ggxG2(vec3 wo, vec3 wi, float alpha) {
    return 1.0 / (1.0 + ggxLambda(wo, alpha) + ggxLambda(wi, alpha));
}

// Density of visible normals seen from wo (wo.z > 0): D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z
// (Heitz 2018, eq. 1).
float ggxVisibleNormalPdf(vec3 wo, vec3 m, float alpha) {
    if (wo.z <= 0.0) return 0.0;
    return ggxG1(wo, alpha) * max(dot(wo, m), 0.0) * ggxD(m, alpha) / wo.z;
}

// Samples m ~ D_wo (Heitz 2018, listing 1: stretch, sample the projected hemisphere, unstretch).
vec3 ggxSampleVisibleNormal(vec3 wo, float alpha, vec2 u) {
    vec3 wh = normalize(vec3(alpha * wo.x, alpha * wo.y, wo.z));
    float lensq = wh.x * wh.x + wh.y * wh.y;
    vec3 t1 = lensq > 0.0 ? vec3(-wh.y, wh.x, 0.0) * inversesqrt(lensq) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(wh, t1);
    float r = sqrt(u.x);
    float phi = TWO_PI * u.y;
    float p1 = r * cos(phi);
    float p2 = r * sin(phi);
    float s = 0.5 * (1.0 + wh.z);
    p2 = (1.0 - s) * safeSqrt(1.0 - p1 * p1) + s * p2;
    vec3 nh = p1 * t1 + p2 * t2 + safeSqrt(1.0 - p1 * p1 - p2 * p2) * wh;
    return normalize(vec3(alpha * nh.x, alpha * nh.y, max(1e-6, nh.z)));
}

// Unpolarised Fresnel reflectance of a dielectric interface (pbrt-v4 FrDielectric).
// cosThetaI: cosine between the incident direction and the normal; eta = eta_t / eta_i for light
// arriving on the side the normal points to. A negative cosThetaI means the light arrives from
// the other side, so eta is inverted.
float fresnelDielectric(float cosThetaI, float eta) {
    cosThetaI = clamp(cosThetaI, -1.0, 1.0);
    if (cosThetaI < 0.0) {
        eta = 1.0 / eta;
        cosThetaI = -cosThetaI;
    }
    float sin2ThetaT = (1.0 - cosThetaI * cosThetaI) / (eta * eta);
    if (sin2ThetaT >= 1.0) return 1.0;  // total internal reflection
    float cosThetaT = safeSqrt(1.0 - sin2ThetaT);
    float rParallel = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
    float rPerpendicular = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
    return 0.5 * (rParallel * rParallel + rPerpendicular * rPerpendicular);
}

// Schlick's approximation with colour F0 (glTF metallic-roughness conductor).
vec3 fresnelSchlick(vec3 f0, float cosTheta) {
    float m = clamp(1.0 - cosTheta, 0.0, 1.0);
    float m2 = m * m;
    return f0 + (1.0 - f0) * (m2 * m2 * m);
}

// Refracts w (pointing away from the surface, on the side n points to) through the interface
// with relative index eta = eta_t / eta_i. Returns false on total internal reflection.
bool refractDirection(vec3 w, vec3 n, float eta, out vec3 wt) {
    float cosThetaI = dot(n, w);
    float sin2ThetaI = max(0.0, 1.0 - cosThetaI * cosThetaI);
    float sin2ThetaT = sin2ThetaI / (eta * eta);
    if (sin2ThetaT >= 1.0) return false;
    float cosThetaT = safeSqrt(1.0 - sin2ThetaT);
    wt = -w / eta + (cosThetaI / eta - cosThetaT) * n;
    return true;
}

#endif
