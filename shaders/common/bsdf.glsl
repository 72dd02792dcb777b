// pmcr's one material model: the glTF metallic-roughness parameters as a mixture of lobes
// (see shared/scene_types.h `Material` and the material notes in docs/scenes.md):
//   conductor   weight metallic                        GGX, Schlick F0 = baseColor; mirror if smooth
//   dielectric  weight (1 - metallic) transmission     smooth or GGX rough glass (Walter 2007),
//                                                      transmission tinted by baseColor
//   base        weight (1 - metallic)(1 - transmission)
//       roughness == 1: Lambertian baseColor / pi
//       roughness  < 1: GGX dielectric coat (ior) over a Lambertian base attenuated by
//                       (1 - F(cos_i))(1 - F(cos_o)), which keeps it reciprocal and below 1.
//
// Everything is evaluated in a local frame whose +z is the shading normal turned to the side of
// wo (the direction towards the previous vertex), so wo.z > 0 for valid queries; wi.z > 0 is
// reflection and wi.z < 0 transmission. `eta` = eta(wi's side) / eta(wo's side) for a
// transmission: the material's ior when wo is outside (front side), 1/ior when inside.
//
// Conventions as pbrt-v4: f is the BSDF value; a delta lobe's sample carries f = weight / |cos|
// and pdf = its discrete probability, so f |cos| / pdf is the throughput either way. Radiance
// transport (camera paths): transmission is divided by eta^2.
#ifndef PMCR_BSDF_GLSL
#define PMCR_BSDF_GLSL

#include "common/math.glsl"
#include "common/microfacet.glsl"
#include "common/sampling.glsl"

const uint LOBE_NONE = 0u;
const uint LOBE_DIFFUSE = 1u;
const uint LOBE_COAT = 2u;        // GGX (or smooth) dielectric coat reflection over diffuse
const uint LOBE_CONDUCTOR = 3u;
const uint LOBE_DIELECTRIC = 4u;  // reflection or transmission of the glass lobe

struct Bsdf {
    vec3 baseColor;
    float alpha;         // GGX alpha = roughness^2
    float wConductor;    // lobe weights, sum to 1
    float wDielectric;
    float wBase;
    float ior;           // material ior, for the coat and the glass
    float eta;           // eta(wi side) / eta(wo side) for transmission (see header)
    bool coated;         // base lobe has the dielectric coat (roughness < 1)
};

struct BsdfSample {
    vec3 wi;      // local frame
    vec3 f;
    float pdf;    // solid angle, or discrete probability for a delta lobe
    uint lobe;
    bool delta;
};

// Builds the BSDF for a material; `frontSide` tells whether wo is on the front (outside) side.
Bsdf makeBsdf(vec3 baseColor, float metallic, float roughness, float transmission, float ior,
              bool frontSide) {
    Bsdf b;
    b.baseColor = baseColor;
    b.alpha = max(roughness * roughness, 0.0);
    b.wConductor = clamp(metallic, 0.0, 1.0);
    b.wDielectric = (1.0 - b.wConductor) * clamp(transmission, 0.0, 1.0);
    b.wBase = max(0.0, 1.0 - b.wConductor - b.wDielectric);
    b.ior = max(ior, 1.0);
    b.eta = frontSide ? b.ior : 1.0 / b.ior;
    b.coated = roughness < 1.0;
    return b;
}

bool bsdfSmooth(Bsdf b) { return b.alpha < SMOOTH_ALPHA; }

// True when some lobe is not a delta, i.e. light sampling can contribute.
bool bsdfHasNonDelta(Bsdf b) {
    if (b.wBase > 0.0) return true;  // the Lambertian part is never a delta
    return !bsdfSmooth(b) && (b.wConductor > 0.0 || b.wDielectric > 0.0);
}

// Probability of sampling the coat (rather than the diffuse base) inside the base lobe: its share
// of the expected reflectance seen from wo.
float coatSelectProbabilityFromFresnel(Bsdf b, float fr) {
    float diffuse = (1.0 - fr) * luminance(b.baseColor);
    return fr / (fr + diffuse);
}

float coatSelectProbability(Bsdf b, float cosThetaO) {
    return coatSelectProbabilityFromFresnel(b, fresnelDielectric(cosThetaO, b.ior));
}

// Lobe selection probabilities (diffuse, coat, conductor, dielectric) for a given wo.
vec4 lobeSelectProbabilities(Bsdf b, vec3 wo) {
    float pCoat = b.coated ? coatSelectProbability(b, wo.z) : 0.0;
    return vec4(b.wBase * (1.0 - pCoat), b.wBase * pCoat, b.wConductor, b.wDielectric);
}

// ---- Individual non-delta lobes ------------------------------------------------------------

vec3 evalCoat(Bsdf b, vec3 wo, vec3 wi) {
    if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);
    vec3 diffuse = b.baseColor * INV_PI * (1.0 - fresnelDielectric(wi.z, b.ior)) *
                   (1.0 - fresnelDielectric(wo.z, b.ior));
    if (bsdfSmooth(b)) return diffuse;
    vec3 m = normalize(wo + wi);
    float spec = ggxD(m, b.alpha) * ggxG2(wo, wi, b.alpha) * fresnelDielectric(dot(wo, m), b.ior) /
                 (4.0 * wo.z * wi.z);
    return diffuse + vec3(spec);
}

float pdfCoatSpecular(Bsdf b, vec3 wo, vec3 wi) {
    if (wi.z <= 0.0 || bsdfSmooth(b)) return 0.0;
    vec3 m = normalize(wo + wi);
    return ggxVisibleNormalPdf(wo, m, b.alpha) / (4.0 * abs(dot(wo, m)));
}

vec3 evalConductor(Bsdf b, vec3 wo, vec3 wi) {
    if (wi.z <= 0.0 || wo.z <= 0.0 || bsdfSmooth(b)) return vec3(0.0);
    vec3 m = normalize(wo + wi);
    return fresnelSchlick(b.baseColor, dot(wo, m)) * ggxD(m, b.alpha) * ggxG2(wo, wi, b.alpha) /
           (4.0 * wo.z * wi.z);
}

float pdfConductor(Bsdf b, vec3 wo, vec3 wi) {
    if (wi.z <= 0.0 || bsdfSmooth(b)) return 0.0;
    vec3 m = normalize(wo + wi);
    return ggxVisibleNormalPdf(wo, m, b.alpha) / (4.0 * abs(dot(wo, m)));
}

// Generalised half vector of the rough dielectric (Walter 2007, eq. 16), facing +z; false for
// configurations no microfacet produces.
bool dielectricHalfVector(Bsdf b, vec3 wo, vec3 wi, out vec3 m, out bool reflect) {
    reflect = wi.z > 0.0;
    m = reflect ? wo + wi : wo + wi * b.eta;
    if (dot(m, m) == 0.0 || wi.z == 0.0) return false;
    m = normalize(m);
    if (m.z < 0.0) m = -m;
    // Discard back-facing microfacets (Walter 2007, sec. 5.3).
    return dot(m, wi) * wi.z > 0.0 && dot(m, wo) * wo.z > 0.0;
}

vec3 evalDielectric(Bsdf b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || bsdfSmooth(b)) return vec3(0.0);
    vec3 m;
    bool reflect;
    if (!dielectricHalfVector(b, wo, wi, m, reflect)) return vec3(0.0);
    float F = fresnelDielectric(dot(wo, m), b.eta);
    float DG = ggxD(m, b.alpha) * ggxG2(wo, wi, b.alpha);
    if (reflect) return vec3(DG * F / (4.0 * wo.z * wi.z));
    // Walter 2007, eq. 21, divided by eta^2 for radiance transport.
    float denom = sqr(dot(wi, m) + dot(wo, m) / b.eta);
    float ft = DG * (1.0 - F) * abs(dot(wi, m) * dot(wo, m) / (wi.z * wo.z * denom)) / sqr(b.eta);
    return b.baseColor * ft;
}

float pdfDielectric(Bsdf b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || bsdfSmooth(b)) return 0.0;
    vec3 m;
    bool reflect;
    if (!dielectricHalfVector(b, wo, wi, m, reflect)) return 0.0;
    float F = fresnelDielectric(dot(wo, m), b.eta);
    float pm = ggxVisibleNormalPdf(wo, m, b.alpha);
    if (reflect) return pm * F / (4.0 * abs(dot(wo, m)));
    // Jacobian of the refraction half vector (Walter 2007, eq. 17).
    float denom = sqr(dot(wi, m) + dot(wo, m) / b.eta);
    return pm * (1.0 - F) * abs(dot(wi, m)) / denom;
}

// ---- The mixture -----------------------------------------------------------------------------
// bsdfEval and bsdfPdf sum the lobes above one by one: the plain statement of the mixture, which
// tests/gpu/test_bsdf.cpp checks against integrals and sampled directions. The kernels call
// bsdfEvalPdf, the same sums with the terms the lobes share computed once, and the test checks
// it against these two at every sampled direction.

// f(wo, wi) of all non-delta lobes.
vec3 bsdfEval(Bsdf b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0) return vec3(0.0);
    vec3 f = vec3(0.0);
    if (b.wBase > 0.0) {
        if (b.coated)
            f += b.wBase * evalCoat(b, wo, wi);
        else if (wi.z > 0.0)
            f += b.wBase * b.baseColor * INV_PI;
    }
    if (b.wConductor > 0.0) f += b.wConductor * evalConductor(b, wo, wi);
    if (b.wDielectric > 0.0) f += b.wDielectric * evalDielectric(b, wo, wi);
    return f;
}

// Solid-angle density with which bsdfSample draws wi through its non-delta lobes.
float bsdfPdf(Bsdf b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0) return 0.0;
    vec4 p = lobeSelectProbabilities(b, wo);
    float pdf = 0.0;
    if (p.x > 0.0) pdf += p.x * cosineHemispherePdf(wi.z);
    if (p.y > 0.0) pdf += p.y * pdfCoatSpecular(b, wo, wi);
    if (p.z > 0.0) pdf += p.z * pdfConductor(b, wo, wi);
    if (p.w > 0.0) pdf += p.w * pdfDielectric(b, wo, wi);
    return pdf;
}

// bsdfEval and bsdfPdf in one pass, for callers that need both: the coat's Fresnel factor at wo
// (its selection probability and the base's attenuation), the reflection half vector, D and the
// masking terms are computed once for all the lobes that share them. Each term is the same
// expression, in the same order, as in the separate functions.
vec3 bsdfEvalPdf(Bsdf b, vec3 wo, vec3 wi, out float pdf) {
    pdf = 0.0;
    if (wo.z <= 0.0) return vec3(0.0);
    const bool rough = !bsdfSmooth(b);
    float fresnelO = b.coated ? fresnelDielectric(wo.z, b.ior) : 0.0;
    float pCoat = b.coated ? coatSelectProbabilityFromFresnel(b, fresnelO) : 0.0;
    vec4 p = vec4(b.wBase * (1.0 - pCoat), b.wBase * pCoat, b.wConductor, b.wDielectric);
    // Smith masking of wo and wi (Heitz 2014): G1(wo) = 1 / (1 + L(wo)), G2 = 1 / (1 + L(wo) + L(wi)).
    float lambdaO = rough ? ggxLambda(wo, b.alpha) : 0.0;
    float G2 = rough ? 1.0 / (1.0 + lambdaO + ggxLambda(wi, b.alpha)) : 0.0;
    float G1o = 1.0 / (1.0 + lambdaO);

    // Reflection half vector of the coat and the conductor; density of the visible normal
    // (Heitz 2018) times the reflection Jacobian 1 / (4 |wo.m|).
    const bool coatSpecular = b.wBase > 0.0 && b.coated && rough;
    const bool conductor = b.wConductor > 0.0 && rough;
    vec3 mR = vec3(0.0, 0.0, 1.0);
    float dR = 0.0;
    float pdfReflect = 0.0;
    if ((coatSpecular || conductor) && wi.z > 0.0) {
        mR = normalize(wo + wi);
        dR = ggxD(mR, b.alpha);
        pdfReflect = G1o * max(dot(wo, mR), 0.0) * dR / wo.z / (4.0 * abs(dot(wo, mR)));
    }

    vec3 f = vec3(0.0);
    if (b.wBase > 0.0) {
        if (b.coated) {
            // evalCoat
            if (wi.z > 0.0) {
                vec3 coat = b.baseColor * INV_PI * (1.0 - fresnelDielectric(wi.z, b.ior)) * (1.0 - fresnelO);
                if (rough)
                    coat += vec3(dR * G2 * fresnelDielectric(dot(wo, mR), b.ior) / (4.0 * wo.z * wi.z));
                f += b.wBase * coat;
            }
        } else if (wi.z > 0.0) {
            f += b.wBase * b.baseColor * INV_PI;
        }
    }
    if (p.x > 0.0) pdf += p.x * cosineHemispherePdf(wi.z);
    if (p.y > 0.0 && wi.z > 0.0 && rough) pdf += p.y * pdfReflect;
    if (b.wConductor > 0.0 && wi.z > 0.0 && rough) {
        // evalConductor, pdfConductor
        f += b.wConductor * (fresnelSchlick(b.baseColor, dot(wo, mR)) * dR * G2 / (4.0 * wo.z * wi.z));
        pdf += p.z * pdfReflect;
    }
    if (b.wDielectric > 0.0 && rough) {
        // evalDielectric, pdfDielectric (Walter 2007, eqs. 16, 17, 21)
        vec3 m;
        bool reflect;
        if (dielectricHalfVector(b, wo, wi, m, reflect)) {
            float F = fresnelDielectric(dot(wo, m), b.eta);
            float D = ggxD(m, b.alpha);
            float DG = D * G2;
            float pm = G1o * max(dot(wo, m), 0.0) * D / wo.z;
            if (reflect) {
                f += b.wDielectric * vec3(DG * F / (4.0 * wo.z * wi.z));
                pdf += p.w * (pm * F / (4.0 * abs(dot(wo, m))));
            } else {
                float denom = sqr(dot(wi, m) + dot(wo, m) / b.eta);
                float ft = DG * (1.0 - F) * abs(dot(wi, m) * dot(wo, m) / (wi.z * wo.z * denom)) / sqr(b.eta);
                f += b.wDielectric * (b.baseColor * ft);
                pdf += p.w * (pm * (1.0 - F) * abs(dot(wi, m)) / denom);
            }
        }
    }
    return f;
}

// The delta lobes. For a specular `lobe` (LOBE_COAT, LOBE_CONDUCTOR or LOBE_DIELECTRIC, the
// latter reflecting or transmitting), the direction it scatters wo into and its weight
// f * |cos(wi)| (the lobe's Fresnel factor times its mixture weight; transmission tinted by
// baseColor and divided by eta^2). False when the material has no such delta lobe or the
// direction does not exist (total internal reflection). Path mutations use this to follow
// specular chains; bsdfSample divides the weight by the lobe's probability.
bool bsdfSpecular(Bsdf b, vec3 wo, uint lobe, bool transmit, out vec3 wi, out vec3 weight) {
    wi = vec3(-wo.x, -wo.y, wo.z);
    weight = vec3(0.0);
    if (!bsdfSmooth(b) || wo.z <= 0.0) return false;
    if (lobe == LOBE_COAT && !transmit && b.wBase > 0.0 && b.coated) {
        weight = vec3(b.wBase * fresnelDielectric(wo.z, b.ior));
    } else if (lobe == LOBE_CONDUCTOR && !transmit && b.wConductor > 0.0) {
        weight = b.wConductor * fresnelSchlick(b.baseColor, wo.z);
    } else if (lobe == LOBE_DIELECTRIC && b.wDielectric > 0.0) {
        float F = fresnelDielectric(wo.z, b.eta);
        if (!transmit) {
            weight = vec3(b.wDielectric * F);
        } else {
            if (!refractDirection(wo, vec3(0.0, 0.0, 1.0), b.eta, wi)) return false;
            weight = b.wDielectric * b.baseColor * ((1.0 - F) / sqr(b.eta));
        }
    } else {
        return false;
    }
    return maxComponent(weight) > 0.0;
}

// Draws wi: uLobe picks the lobe, u the direction. Returns false when no direction results. A
// delta lobe's sample is complete; a non-delta one has only wi and lobe, its f and pdf (those
// of the whole non-delta mixture) left to bsdfEvalPdf, so that a caller that evaluates other
// directions too can do it at one call site (bsdfSample does it here).
bool bsdfSampleDirection(Bsdf b, vec3 wo, float uLobe, vec2 u, out BsdfSample s) {
    s.wi = vec3(0.0, 0.0, 1.0);
    s.f = vec3(0.0);
    s.pdf = 0.0;
    s.lobe = LOBE_NONE;
    s.delta = false;
    if (wo.z <= 0.0) return false;
    vec4 p = lobeSelectProbabilities(b, wo);
    const bool isSmooth = bsdfSmooth(b);

    if (uLobe < p.x) {
        s.lobe = LOBE_DIFFUSE;
        s.wi = sampleCosineHemisphere(u);
    } else if (uLobe < p.x + p.y) {
        s.lobe = LOBE_COAT;
        if (isSmooth) {
            // Mirror reflection off the smooth coat, chosen with probability pCoat.
            vec3 weight;
            if (!bsdfSpecular(b, wo, LOBE_COAT, false, s.wi, weight)) return false;
            s.f = weight / wo.z;
            s.pdf = p.y;
            s.delta = true;
            return true;
        }
        vec3 m = ggxSampleVisibleNormal(wo, b.alpha, u);
        s.wi = reflect(-wo, m);
        // bsdfEval and bsdfPdf tell reflection from transmission by the side of wi, so a
        // reflection below the surface (or a refraction above it) would be scored with another
        // lobe's value and density: such samples fail, as in pbrt-v4, and bsdfPdf leaves them out.
        if (s.wi.z <= 0.0) return false;
    } else if (uLobe < p.x + p.y + p.z) {
        s.lobe = LOBE_CONDUCTOR;
        if (isSmooth) {
            vec3 weight;
            if (!bsdfSpecular(b, wo, LOBE_CONDUCTOR, false, s.wi, weight)) return false;
            s.f = weight / wo.z;
            s.pdf = p.z;
            s.delta = true;
            return true;
        }
        vec3 m = ggxSampleVisibleNormal(wo, b.alpha, u);
        s.wi = reflect(-wo, m);
        if (s.wi.z <= 0.0) return false;
    } else if (p.w > 0.0) {
        s.lobe = LOBE_DIELECTRIC;
        // Re-use the lobe sample's remainder to choose reflection or transmission.
        float uChoice = clamp((uLobe - (p.x + p.y + p.z)) / p.w, 0.0, ONE_MINUS_EPSILON);
        if (isSmooth) {
            // Reflect with probability F, else transmit (total internal reflection: F = 1).
            float F = fresnelDielectric(wo.z, b.eta);
            bool transmit = uChoice >= F;
            vec3 weight;
            if (!bsdfSpecular(b, wo, LOBE_DIELECTRIC, transmit, s.wi, weight)) return false;
            s.f = weight / abs(s.wi.z);
            s.pdf = p.w * (transmit ? 1.0 - F : F);
            s.delta = true;
            return s.pdf > 0.0;
        }
        vec3 m = ggxSampleVisibleNormal(wo, b.alpha, u);
        float F = fresnelDielectric(dot(wo, m), b.eta);
        if (uChoice < F) {
            s.wi = reflect(-wo, m);
            if (s.wi.z <= 0.0) return false;
        } else {
            vec3 wt;
            if (!refractDirection(wo, m, b.eta, wt) || wt.z >= 0.0) return false;
            s.wi = wt;
        }
    } else {
        return false;
    }
    return true;
}

bool bsdfSample(Bsdf b, vec3 wo, float uLobe, vec2 u, out BsdfSample s) {
    if (!bsdfSampleDirection(b, wo, uLobe, u, s)) return false;
    if (s.delta) return true;
    // Non-delta: value and density of the whole non-delta mixture at wi.
    s.f = bsdfEvalPdf(b, wo, s.wi, s.pdf);
    return s.pdf > 0.0 && maxComponent(s.f) > 0.0;
}

#endif
