// pmcr's one material model: the glTF metallic-roughness parameters as a mixture of lobes
// (see shared/scene_types.h `Material` and the material notes in docs/scenes.md):
//   conductor   weight metallic                        GGX, Schlick F0 = baseColor; mirror if smooth
//   dielectric  weight (1 - metallic) transmission     smooth or GGX rough glass (Walter 2007),
//                                                      transmission tinted by baseColor; or,
//                                                      thin-walled, a thin sheet (below)
//   base        weight (1 - metallic)(1 - transmission)
//       roughness == 1: Lambertian baseColor / pi
//       roughness  < 1: GGX dielectric coat (ior) over a Lambertian base attenuated by
//                       (1 - F(cos_i))(1 - F(cos_o)), which keeps it reciprocal and below 1;
//                       KHR_materials_specular weights and tints the coat's F (coatFresnel)
//                       and the base is attenuated by its largest channel, as the extension's
//                       fresnel_mix does with max_value(fr)
// under a clear coat (KHR_materials_clearcoat, factor c, its own GGX roughness, ior 1.5, on the
// front face only): the coat reflects c F_c(wo.m) D G / (4 cos cos) (LOBE_CLEARCOAT) and every
// lobe below is attenuated by (1 - c F_c(cos)) for each of wo and wi that lies on the front
// (the extension's fresnel_coat, taken at both ends as the dielectric coat above does, so
// that it stays reciprocal; a transmission crosses the coat once); the coat has a normal of its
// own (clearcoatNormal, below: its cosines and its F_c are taken about it),
// and between the two, a sheen (KHR_materials_sheen, colour C, roughness r): the Charlie lobe
// C D(h) V / max(1, E(cos_o), E(cos_i)) (LOBE_SHEEN, sampled cosine-weighted) over the lobes
// below, which keep
// min(1 - max(C) E(cos_o), 1 - max(C) E(cos_i)) of their value (the extension's albedo
// scaling, symmetric so reciprocal; E the lobe's directional albedo, sheenAlbedo),
// all of it times the coverage a (alphaMode BLEND; 1 otherwise), and
//   pass        weight 1 - a                           a delta: the ray goes on unchanged.
// BLEND is thus the mixture a * surface + (1 - a) * nothing (Mitsuba 3's `mask` BSDF): a pass
// is a specular transmission vertex with eta 1, which every method already handles (path
// tracing and photon mapping sample it, ERPT and MLT perturb through it as through glass),
// and a shadow ray stops at the surface as it does at glass: its expectation over the pass
// choice is the coverage-weighted sum every estimator and every Metropolis target evaluates.
//
// Thin-walled dielectric (KHR_materials_transmission without KHR_materials_volume): a sheet
// whose two parallel faces are close enough that light leaves it where it entered, in the
// direction it came (pbrt-v4 ThinDielectricBxDF; Pharr et al., PBR 4th ed., sec. 9.5.1):
// reflectance R' = R + T^2 R / (1 - R^2) summed over the bounces inside (R the interface's
// Fresnel reflectance, T = 1 - R), transmittance 1 - R', no change of eta (eta = 1 here). Rough
// (alpha >= SMOOTH_ALPHA), each GGX microfacet m acts as that sheet: the reflection about m with
// weight R'(wo.m), or its mirror image through the surface plane with weight 1 - R'(wo.m), the
// visible normal sampled as for the conductor. f_t(wo, wi) = f_r(wo, flip(wi)) (1 - R') / R',
// so it is reciprocal, tends to the smooth sheet as alpha -> 0 and holds energy at most 1.
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
const uint LOBE_PASS = 5u;        // BLEND coverage: the ray passes on unchanged (a delta)
const uint LOBE_CLEARCOAT = 6u;   // KHR_materials_clearcoat's reflection (smooth: a delta)
const uint LOBE_SHEEN = 7u;       // KHR_materials_sheen's Charlie lobe
const float CLEARCOAT_IOR = 1.5;  // the extension's fixed coat (F0 0.04)

struct Bsdf {
    vec3 baseColor;
    float alpha;         // GGX alpha = roughness^2
    float wConductor;    // lobe weights, sum to 1
    float wDielectric;
    float wBase;
    float ior;           // material ior, for the coat and the glass
    float eta;           // eta(wi side) / eta(wo side) for transmission (see header)
    bool coated;         // base lobe has the dielectric coat (roughness < 1)
    bool thin;           // the dielectric lobe is a thin sheet (eta is then 1)
    bool specularTinted; // KHR_materials_specular: the coat's F is weighted and tinted (coatFresnel)
    vec3 specularColor;  // its specularColorFactor times specularColorTexture
    float specularWeight;  // its specularFactor times specularTexture's alpha
    float clearcoat;     // KHR_materials_clearcoat factor (0: none; bsdfSetClearcoat)
    float clearcoatAlpha;  // its GGX alpha = clearcoatRoughness^2
    bool clearcoatFront;   // wo is on the coated (front) side
    // The coat's normal in this local frame, when clearcoatTilted (bsdfSetClearcoatNormal);
    // else the coat's normal is +z, the shading normal's, and the code takes w.z.
    vec3 clearcoatNormal;
    bool clearcoatTilted;
    bool adjoint;          // light-side walks: the coat's term is the adjoint (clearcoatNormal)
    vec3 sheenColor;       // KHR_materials_sheen colour (black: none; bsdfSetSheen)
    float sheenAlpha;      // its Charlie alpha = sheenRoughness^2, at least SHEEN_MIN_ALPHA
    float sheenAlbedoO;    // E(|wo.z|), the sheen lobe's directional albedo at wo (sheenAlbedo)
    float wPass;         // 1 - coverage (alphaMode BLEND): weight of the pass-through delta
};

struct BsdfSample {
    vec3 wi;      // local frame
    vec3 f;
    float pdf;    // solid angle, or discrete probability for a delta lobe
    uint lobe;
    bool delta;
    float eta;    // eta(wi side) / eta(wo side) of the event: b.eta for a refraction, else 1
};

// Builds the BSDF for a material; `frontSide` tells whether wo is on the front (outside) side,
// `thin` whether its transmission is thin-walled, `coverage` its BLEND alpha (1: opaque).
Bsdf makeBsdf(vec3 baseColor, float metallic, float roughness, float transmission, float ior,
              bool frontSide, bool thin, float coverage) {
    Bsdf b;
    b.baseColor = baseColor;
    b.alpha = max(roughness * roughness, 0.0);
    float a = clamp(coverage, 0.0, 1.0);
    float conductor = clamp(metallic, 0.0, 1.0);
    float dielectric = (1.0 - conductor) * clamp(transmission, 0.0, 1.0);
    b.wConductor = a * conductor;
    b.wDielectric = a * dielectric;
    b.wBase = a * max(0.0, 1.0 - conductor - dielectric);
    b.wPass = 1.0 - a;
    b.ior = max(ior, 1.0);
    b.thin = thin;
    b.specularTinted = false;
    b.specularColor = vec3(1.0);
    b.specularWeight = 1.0;
    b.clearcoat = 0.0;
    b.clearcoatAlpha = 0.0;
    b.clearcoatFront = frontSide;
    b.clearcoatNormal = vec3(0.0, 0.0, 1.0);
    b.clearcoatTilted = false;
    b.adjoint = false;
    b.sheenColor = vec3(0.0);
    b.sheenAlpha = 1.0;
    b.sheenAlbedoO = 0.0;
    b.eta = thin ? 1.0 : frontSide ? b.ior : 1.0 / b.ior;
    b.coated = roughness < 1.0;
    return b;
}

// Reflectance of a thin dielectric sheet of index ior seen at cosTheta, the light bouncing
// between its faces summed: R + T^2 R / (1 - R^2) (pbrt-v4 ThinDielectricBxDF, PBR 4th ed.
// sec. 9.5.1). From air an interface never reflects totally, so R < 1.
float thinDielectricReflectance(float cosTheta, float ior) {
    float R = fresnelDielectric(abs(cosTheta), ior);
    float T = 1.0 - R;
    return R < 1.0 ? R + T * T * R / (1.0 - R * R) : 1.0;
}

// The glass lobe's reflectance at cos(wo, m): the sheet's or the interface's Fresnel factor.
float dielectricReflectance(Bsdf b, float cosTheta) {
    return b.thin ? thinDielectricReflectance(cosTheta, b.ior) : fresnelDielectric(cosTheta, b.eta);
}

// eta of the event `lobe` (transmitting or not) makes: the ratio radiance transport divides by
// squared, and etendue through a specular vertex multiplies by (mutate_caustic.glsl). Only a
// refraction by solid glass changes it; a thin sheet and a BLEND pass leave it at 1.
float bsdfLobeEta(Bsdf b, uint lobe, bool transmit) {
    return transmit && lobe == LOBE_DIELECTRIC ? b.eta : 1.0;
}

bool bsdfSmooth(Bsdf b) { return b.alpha < SMOOTH_ALPHA; }

// True when some lobe is not a delta, i.e. light sampling can contribute.
bool bsdfHasNonDelta(Bsdf b) {
    if (b.wBase > 0.0) return true;  // the Lambertian part is never a delta (0 at coverage 0)
    if (maxComponent(b.sheenColor) > 0.0 && b.wPass < 1.0) return true;  // the sheen
    // A rough clear coat (its alpha not below SMOOTH_ALPHA, clearcoatSmooth) on the side seen.
    if (b.clearcoat > 0.0 && b.clearcoatFront && b.clearcoatAlpha >= SMOOTH_ALPHA && b.wPass < 1.0)
        return true;
    return !bsdfSmooth(b) && (b.wConductor > 0.0 || b.wDielectric > 0.0);
}

// KHR_materials_specular on a material made by makeBsdf: specularFactor (times its texture's
// alpha) and specularColorFactor (times its texture).
void bsdfSetSpecular(inout Bsdf b, float weight, vec3 color) {
    b.specularTinted = true;
    b.specularWeight = clamp(weight, 0.0, 1.0);
    b.specularColor = max(color, vec3(0.0));
}

// KHR_materials_clearcoat on a material made by makeBsdf: clearcoatFactor and roughness (times
// their textures).
void bsdfSetClearcoat(inout Bsdf b, float factor, float roughness) {
    b.clearcoat = clamp(factor, 0.0, 1.0);
    b.clearcoatAlpha = sqr(clamp(roughness, 0.0, 1.0));
}

bool clearcoatSmooth(Bsdf b) { return b.clearcoatAlpha < SMOOTH_ALPHA; }

// ---- The clear coat's own normal n_c (KHR_materials_clearcoat's clearcoatNormal) ----------------
// The coat reflects about n_c (its clearcoatNormalTexture, else the interpolated normal) while
// the lobes below take the shading normal n_s (+z here, the normalTexture's) and every
// integrator weights a BSDF by |cos_i| about n_s. Its lobe, f_c = c F D G / (4 cos'_o cos'_i)
// (primes: cosines about n_c), scatters f_c cos'_i dw_i, so in pmcr's terms it is
//   f(wo, wi) = f_c cos'_i / |cos_i| = c F D G / (4 cos'_o |cos_i|),
// the same step as Veach's shading normal (1997 sec. 5.3, eq. 5.17: a BSDF about n_s written
// for cosines about n_g) taken one layer further, from n_c to n_s. It is not symmetric: walks
// that carry importance from the lights (bdpt's light subpaths and their t = 1 connections,
// photons) need the adjoint f*(wo, wi) = f(wi, wo) = c F D G / (4 cos'_i |cos_o|) (Veach 1997
// sec. 5.3.2; wo is then the light's side), and they apply eq. 5.19's correction from n_s to
// n_g on top as for any BSDF (bdpt_vertex.glsl shadingEvalImportance). A smooth coat mirrors
// about n_c with f |cos_i| = c F(cos'_o) for radiance and, since the mirror maps solid angle to
// itself, f* |cos_i| = c F |cos_i| / |cos_o| for importance. The attenuation of the lobes below,
// (1 - c F(|cos'_o|)) (1 - c F(|cos'_i|)), is symmetric and the same both ways. Sampling draws
// visible normals about n_c; every density is the sampler's whatever the adjoint.
void bsdfSetClearcoatNormal(inout Bsdf b, vec3 n) {
    b.clearcoatNormal = normalize(n);
    b.clearcoatTilted = true;
}

// cos of w about the coat's normal.
float clearcoatCos(Bsdf b, vec3 w) { return b.clearcoatTilted ? dot(w, b.clearcoatNormal) : w.z; }

// ---- The sheen (KHR_materials_sheen) ----------------------------------------------------------
// Charlie distribution D(h) = (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi) (Estevez and Kulla
// 2017, "Production Friendly Microfacet Sheen BRDF", eq. 2; the extension's sheen_D) with
// Ashikhmin's visibility V = 1 / (4 (cos_i + cos_o - cos_i cos_o)) (Neubelt and Pettineo 2013;
// the extension's V for implementations without the Charlie visibility fit).
// The roughness is kept at 0.07 or more, as the Khronos sample viewer does: below it the lobe is
// a sliver at grazing that no sampler or quadrature here resolves.
const float SHEEN_MIN_ALPHA = 0.0049;

bool bsdfHasSheen(Bsdf b) { return maxComponent(b.sheenColor) > 0.0; }

// D V of the sheen for wo and wi above the surface, without the colour.
float sheenDV(float alpha, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    vec3 h = normalize(wo + wi);
    float sin2 = max(1.0 - h.z * h.z, 0.0);
    float D = (2.0 + 1.0 / alpha) * pow(sin2, 0.5 / alpha) * INV_TWO_PI;
    return D / (4.0 * (wi.z + wo.z - wi.z * wo.z));
}

// E(cos): the sheen's directional albedo, the integral of D V cos_i over the hemisphere, by
// Gauss-Legendre quadrature of 8 nodes in cos_i and the midpoint rule of 16 in phi over [0, pi]
// (the lobe is symmetric about the plane of wo). The quadrature is pmcr's E (the sample viewer
// reads a table of the same integral): the albedo scaling uses it on both sides, so the BSDF
// stays reciprocal whatever its error, and test_bsdf.cpp checks it against sampling.
float sheenAlbedo(float alpha, float cosTheta) {
    const float x[4] = float[4](0.1834346425, 0.5255324099, 0.7966664774, 0.9602898565);
    const float w[4] = float[4](0.3626837834, 0.3137066459, 0.2223810345, 0.1012285363);
    float c = clamp(cosTheta, 1e-4, 1.0);
    vec3 wo = vec3(sqrt(1.0 - c * c), 0.0, c);
    float sum = 0.0;
    for (int i = 0; i < 8; ++i) {
        float mu = 0.5 * (1.0 + (i < 4 ? -x[3 - i] : x[i - 4]));
        float weight = 0.5 * (i < 4 ? w[3 - i] : w[i - 4]);
        float s = sqrt(max(1.0 - mu * mu, 0.0));
        for (int k = 0; k < 16; ++k) {
            float phi = (float(k) + 0.5) * (PI / 16.0);
            vec3 wi = vec3(s * cos(phi), s * sin(phi), mu);
            sum += weight * sheenDV(alpha, wo, wi) * mu;
        }
    }
    return 2.0 * (PI / 16.0) * sum;
}

// KHR_materials_sheen on a material made by makeBsdf (wo given for the albedo it takes there).
void bsdfSetSheen(inout Bsdf b, vec3 color, float roughness, vec3 wo) {
    b.sheenColor = clamp(color, vec3(0.0), vec3(1.0));
    b.sheenAlpha = max(sqr(clamp(roughness, 0.0, 1.0)), SHEEN_MIN_ALPHA);
    b.sheenAlbedoO = sheenAlbedo(b.sheenAlpha, abs(wo.z));
}

// The same material seen from direction wo on side frontSide, for callers that reuse a Bsdf
// made for another wo (a bidirectional method turning a vertex around): what makeBsdf,
// bsdfSetClearcoat and bsdfSetSheen derived from the side and from wo follows it (eta, the
// clear coat's side, the sheen's albedo at wo).
void bsdfSetOutgoing(inout Bsdf b, bool frontSide, vec3 wo) {
    b.eta = b.thin ? 1.0 : frontSide ? b.ior : 1.0 / b.ior;
    b.clearcoatFront = frontSide;
    if (bsdfHasSheen(b)) b.sheenAlbedoO = sheenAlbedo(b.sheenAlpha, abs(wo.z));
}

// The share of the lobes below the sheen kept for (wo, wi): min(1 - max(C) E(|cos_o|),
// 1 - max(C) E(|cos_i|)) (the extension's sheen albedo scaling), at least 0.
float sheenScaling(Bsdf b, float albedoI) {
    float c = maxComponent(b.sheenColor);
    return max(min(1.0 - c * b.sheenAlbedoO, 1.0 - c * albedoI), 0.0);
}

// The sheen lobe C D V / max(1, E(cos_o), E(cos_i)): with Ashikhmin's visibility the lobe's
// albedo passes 1 near grazing at low roughness; dividing by the larger albedo of the two
// directions (symmetric, so still reciprocal) keeps it at most 1.
vec3 evalSheen(Bsdf b, vec3 wo, vec3 wi, float albedoI) {
    return b.sheenColor * (sheenDV(b.sheenAlpha, wo, wi) / max(1.0, max(b.sheenAlbedoO, albedoI)));
}

// Probability of sampling the sheen among the lobes under the clear coat: q / (q + (1 - q) / 2),
// q = max(C) min(E(wo.z), 1).
float sheenSelect(Bsdf b) {
    if (!bsdfHasSheen(b)) return 0.0;
    float q = maxComponent(b.sheenColor) * min(b.sheenAlbedoO, 1.0);
    return q / (q + 0.5 * (1.0 - q));
}

// The share of light at w the clear coat leaves to the lobes below: 1 - c F_c(|cos|) when w is
// on the coated side, else 1 (the coat is crossed once by a transmission).
float clearcoatAttenuation(Bsdf b, vec3 w) {
    if (b.clearcoat <= 0.0) return 1.0;
    bool coatedSide = b.clearcoatFront ? w.z > 0.0 : w.z < 0.0;
    return coatedSide ? 1.0 - b.clearcoat * fresnelDielectric(abs(clearcoatCos(b, w)), CLEARCOAT_IOR)
                      : 1.0;
}

// Probability of sampling the clear coat (rather than the lobes below; within the coverage),
// from its reflectance q = c F_c(wo.z) and an even guess for what lies below: q / (q + (1 - q) / 2).
float clearcoatSelect(Bsdf b, vec3 wo) {
    if (b.clearcoat <= 0.0 || !b.clearcoatFront) return 0.0;
    float cosC = clearcoatCos(b, wo);
    if (cosC <= 0.0) return 0.0;  // below the coat's horizon: it reflects nothing
    // A smooth coat whose mirror about n_c leaves below the shading normal's horizon: neither.
    if (b.clearcoatTilted && clearcoatSmooth(b) && 2.0 * cosC * b.clearcoatNormal.z <= wo.z)
        return 0.0;
    float q = b.clearcoat * fresnelDielectric(cosC, CLEARCOAT_IOR);
    return q / (q + 0.5 * (1.0 - q));
}

// The probabilities bsdfSampleDirection picks the clear coat with and the pass with:
// (1 - wPass) clearcoatSelect and wPass; the sheen (1 - wPass) (1 - clearcoatSelect) sheenSelect;
// the lobes below share the rest.
float clearcoatLobeProbability(Bsdf b, vec3 wo) { return (1.0 - b.wPass) * clearcoatSelect(b, wo); }
float sheenLobeProbability(Bsdf b, vec3 wo) {
    return (1.0 - b.wPass) * (1.0 - clearcoatSelect(b, wo)) * sheenSelect(b);
}

// The coat's Fresnel reflectance at cosTheta, per channel: the dielectric's F(ior), or under
// KHR_materials_specular its fresnel_mix form, weight * (f0 + (1 - f0) w) with
// f0 = min(F0(ior) * specularColor, 1) (the extension's dielectric_f0: tinted at normal
// incidence, white at grazing), where pmcr takes the rise w from F itself,
// w = (F - F0) / (1 - F0), in place of Schlick's (1 - cos)^5, so that weight 1 and colour 1 give
// F exactly.
vec3 coatFresnel(Bsdf b, float cosTheta) {
    float F = fresnelDielectric(cosTheta, b.ior);
    if (!b.specularTinted) return vec3(F);
    float F0 = sqr((b.ior - 1.0) / (b.ior + 1.0));
    float w = F0 < 1.0 ? clamp((F - F0) / (1.0 - F0), 0.0, 1.0) : 1.0;
    vec3 f0 = min(F0 * b.specularColor, vec3(1.0));
    return b.specularWeight * (f0 + (1.0 - f0) * w);
}

// The share of light the coat takes from the base at cosTheta: F, or the largest channel of the
// tinted F (the extension's max_value(fr)), so no channel of base and coat exceeds 1.
float coatReflectance(Bsdf b, float cosTheta) {
    return maxComponent(coatFresnel(b, cosTheta));
}

// Probability of sampling the coat (rather than the diffuse base) inside the base lobe: its share
// of the expected reflectance seen from wo (fr = coatReflectance, frLum its luminance; equal
// without KHR_materials_specular).
float coatSelectProbabilityFromFresnel(Bsdf b, float fr, float frLum) {
    float diffuse = (1.0 - fr) * luminance(b.baseColor);
    return frLum / (frLum + diffuse);
}

float coatSelectProbability(Bsdf b, float cosThetaO) {
    vec3 fc = coatFresnel(b, cosThetaO);
    return coatSelectProbabilityFromFresnel(b, maxComponent(fc),
                                            b.specularTinted ? luminance(fc) : fc.x);
}

// Lobe selection probabilities (diffuse, coat, conductor, dielectric) for a given wo: their
// mixture weights, the base's split between diffuse and coat, all shrunk by the clear coat's
// share (clearcoatSelect; the clear coat and the pass take the rest).
vec4 lobeSelectProbabilities(Bsdf b, vec3 wo) {
    float pCoat = b.coated ? coatSelectProbability(b, wo.z) : 0.0;
    return vec4(b.wBase * (1.0 - pCoat), b.wBase * pCoat, b.wConductor, b.wDielectric) *
           ((1.0 - clearcoatSelect(b, wo)) * (1.0 - sheenSelect(b)));
}

// w in the coat's frame (n_c = +z); w itself when the coat takes the shading normal.
vec3 clearcoatLocal(Bsdf b, vec3 w) {
    return b.clearcoatTilted ? toLocal(frameFromNormal(b.clearcoatNormal), w) : w;
}

// The clear coat's rough reflection, without its weight (1 - wPass) c: D G F_c / (4 cos'_o |cos_i|),
// or its adjoint D G F_c / (4 cos'_i |cos_o|) (primes about n_c; equal without a tilt).
float evalClearcoat(Bsdf b, vec3 wo, vec3 wi) {
    if (wi.z <= 0.0 || wo.z <= 0.0 || clearcoatSmooth(b)) return 0.0;
    vec3 o = clearcoatLocal(b, wo), i = clearcoatLocal(b, wi);
    if (b.clearcoatTilted && (o.z <= 0.0 || i.z <= 0.0)) return 0.0;
    vec3 m = normalize(o + i);
    float cosines = b.clearcoatTilted && b.adjoint ? i.z * wo.z : o.z * wi.z;
    return ggxD(m, b.clearcoatAlpha) * ggxG2(o, i, b.clearcoatAlpha) *
           fresnelDielectric(dot(o, m), CLEARCOAT_IOR) / (4.0 * cosines);
}

// The density of the coat's visible-normal sampling about n_c (bsdfSampleDirection), which
// fails below either horizon.
float pdfClearcoat(Bsdf b, vec3 wo, vec3 wi) {
    if (wi.z <= 0.0 || clearcoatSmooth(b)) return 0.0;
    vec3 o = clearcoatLocal(b, wo), i = clearcoatLocal(b, wi);
    if (b.clearcoatTilted && (o.z <= 0.0 || i.z <= 0.0)) return 0.0;
    vec3 m = normalize(o + i);
    return ggxVisibleNormalPdf(o, m, b.clearcoatAlpha) / (4.0 * abs(dot(o, m)));
}

// ---- Individual non-delta lobes ------------------------------------------------------------

vec3 evalCoat(Bsdf b, vec3 wo, vec3 wi) {
    if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);
    vec3 diffuse = b.baseColor * INV_PI * (1.0 - coatReflectance(b, wi.z)) *
                   (1.0 - coatReflectance(b, wo.z));
    if (bsdfSmooth(b)) return diffuse;
    vec3 m = normalize(wo + wi);
    vec3 spec = ggxD(m, b.alpha) * ggxG2(wo, wi, b.alpha) * coatFresnel(b, dot(wo, m)) /
                (4.0 * wo.z * wi.z);
    return diffuse + spec;
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
// A thin sheet's transmission is the reflection mirrored through the surface plane, so its half
// vector (and its facing test) is that of wo and wi's mirror image.
bool dielectricHalfVector(Bsdf b, vec3 wo, vec3 wi, out vec3 m, out bool reflect) {
    reflect = wi.z > 0.0;
    // A thin sheet's transmission is the reflection towards wi mirrored: work with that.
    if (!reflect && b.thin) wi.z = -wi.z;
    m = reflect || b.thin ? wo + wi : wo + wi * b.eta;
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
    float F = dielectricReflectance(b, dot(wo, m));
    float DG = ggxD(m, b.alpha) * ggxG2(wo, wi, b.alpha);
    if (reflect) return vec3(DG * F / (4.0 * wo.z * wi.z));
    // The thin sheet's mirrored reflection (header), tinted by baseColor.
    if (b.thin) return b.baseColor * (DG * (1.0 - F) / (4.0 * wo.z * abs(wi.z)));
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
    float F = dielectricReflectance(b, dot(wo, m));
    float pm = ggxVisibleNormalPdf(wo, m, b.alpha);
    if (reflect) return pm * F / (4.0 * abs(dot(wo, m)));
    if (b.thin) return pm * (1.0 - F) / (4.0 * abs(dot(wo, m)));
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
    if (bsdfHasSheen(b)) {
        float albedoI = sheenAlbedo(b.sheenAlpha, abs(wi.z));
        f *= sheenScaling(b, albedoI);
        f += (1.0 - b.wPass) * evalSheen(b, wo, wi, albedoI);
    }
    if (b.clearcoat > 0.0) {
        f *= clearcoatAttenuation(b, wo) * clearcoatAttenuation(b, wi);
        if (b.clearcoatFront) f += vec3((1.0 - b.wPass) * b.clearcoat * evalClearcoat(b, wo, wi));
    }
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
    float pClearcoat = clearcoatLobeProbability(b, wo);
    if (pClearcoat > 0.0) pdf += pClearcoat * pdfClearcoat(b, wo, wi);
    float pSheen = sheenLobeProbability(b, wo);
    if (pSheen > 0.0) pdf += pSheen * cosineHemispherePdf(wi.z);
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
    vec3 coatO = b.coated ? coatFresnel(b, wo.z) : vec3(0.0);
    float fresnelO = maxComponent(coatO);
    float pCoat = b.coated ? coatSelectProbabilityFromFresnel(
                                 b, fresnelO, b.specularTinted ? luminance(coatO) : coatO.x)
                           : 0.0;
    float pClearcoatShare = clearcoatSelect(b, wo);
    vec4 p = vec4(b.wBase * (1.0 - pCoat), b.wBase * pCoat, b.wConductor, b.wDielectric) *
             ((1.0 - pClearcoatShare) * (1.0 - sheenSelect(b)));
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
                vec3 coat = b.baseColor * INV_PI * (1.0 - coatReflectance(b, wi.z)) * (1.0 - fresnelO);
                if (rough)
                    coat += dR * G2 * coatFresnel(b, dot(wo, mR)) / (4.0 * wo.z * wi.z);
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
            float F = dielectricReflectance(b, dot(wo, m));
            float D = ggxD(m, b.alpha);
            float DG = D * G2;
            float pm = G1o * max(dot(wo, m), 0.0) * D / wo.z;
            if (reflect) {
                f += b.wDielectric * vec3(DG * F / (4.0 * wo.z * wi.z));
                pdf += p.w * (pm * F / (4.0 * abs(dot(wo, m))));
            } else if (b.thin) {
                f += b.wDielectric * (b.baseColor * (DG * (1.0 - F) / (4.0 * wo.z * abs(wi.z))));
                pdf += p.w * (pm * (1.0 - F) / (4.0 * abs(dot(wo, m))));
            } else {
                float denom = sqr(dot(wi, m) + dot(wo, m) / b.eta);
                float ft = DG * (1.0 - F) * abs(dot(wi, m) * dot(wo, m) / (wi.z * wo.z * denom)) / sqr(b.eta);
                f += b.wDielectric * (b.baseColor * ft);
                pdf += p.w * (pm * (1.0 - F) * abs(dot(wi, m)) / denom);
            }
        }
    }
    if (bsdfHasSheen(b)) {
        // The sheen over the lobes above (sheenScaling, sheenDV; sampled cosine-weighted).
        float albedoI = sheenAlbedo(b.sheenAlpha, abs(wi.z));
        f *= sheenScaling(b, albedoI);
        f += (1.0 - b.wPass) * evalSheen(b, wo, wi, albedoI);
        pdf += (1.0 - b.wPass) * (1.0 - pClearcoatShare) * sheenSelect(b) * cosineHemispherePdf(wi.z);
    }
    if (b.clearcoat > 0.0) {
        // The clear coat over all of it (evalClearcoat, pdfClearcoat).
        f *= clearcoatAttenuation(b, wo) * clearcoatAttenuation(b, wi);
        if (b.clearcoatFront) {
            f += vec3((1.0 - b.wPass) * b.clearcoat * evalClearcoat(b, wo, wi));
            pdf += (1.0 - b.wPass) * pClearcoatShare * pdfClearcoat(b, wo, wi);
        }
    }
    return f;
}

// The delta lobes. For a specular `lobe` (LOBE_COAT, LOBE_CONDUCTOR or LOBE_DIELECTRIC, the
// latter reflecting or transmitting, or LOBE_PASS, transmitting), the direction it scatters wo
// into and its weight f * |cos(wi)| (the lobe's Fresnel factor times its mixture weight;
// transmission tinted by baseColor and divided by eta^2; a thin sheet's straight through with
// its 1 - R'; a pass's 1 - coverage; LOBE_CLEARCOAT's (1 - wPass) c F_c; every lobe below the
// clear coat times its attenuation at wo and wi). False when the material has no such delta lobe or the
// direction does not exist (total internal reflection). Path mutations use this to follow
// specular chains; bsdfSample divides the weight by the lobe's probability.
bool bsdfSpecular(Bsdf b, vec3 wo, uint lobe, bool transmit, out vec3 wi, out vec3 weight) {
    wi = vec3(-wo.x, -wo.y, wo.z);
    weight = vec3(0.0);
    if (wo.z <= 0.0) return false;
    if (lobe == LOBE_PASS) {
        if (!transmit) return false;
        wi = -wo;
        weight = vec3(b.wPass);
        return b.wPass > 0.0;
    }
    if (lobe == LOBE_CLEARCOAT) {
        if (transmit || !clearcoatSmooth(b) || !b.clearcoatFront) return false;
        float cosC = clearcoatCos(b, wo);
        if (b.clearcoatTilted) {
            // The mirror about n_c, which must leave on the front (clearcoatNormal).
            if (cosC <= 0.0) return false;
            wi = 2.0 * cosC * b.clearcoatNormal - wo;
            if (wi.z <= 0.0) return false;
        }
        weight = vec3((1.0 - b.wPass) * b.clearcoat * fresnelDielectric(cosC, CLEARCOAT_IOR));
        if (b.clearcoatTilted && b.adjoint) weight *= wi.z / wo.z;
        return maxComponent(weight) > 0.0;
    }
    if (!bsdfSmooth(b)) return false;
    if (lobe == LOBE_COAT && !transmit && b.wBase > 0.0 && b.coated) {
        weight = b.wBase * coatFresnel(b, wo.z);
    } else if (lobe == LOBE_CONDUCTOR && !transmit && b.wConductor > 0.0) {
        weight = b.wConductor * fresnelSchlick(b.baseColor, wo.z);
    } else if (lobe == LOBE_DIELECTRIC && b.wDielectric > 0.0) {
        float F = dielectricReflectance(b, wo.z);
        if (!transmit) {
            weight = vec3(b.wDielectric * F);
        } else if (b.thin) {
            wi = -wo;
            weight = b.wDielectric * b.baseColor * (1.0 - F);
        } else {
            if (!refractDirection(wo, vec3(0.0, 0.0, 1.0), b.eta, wi)) return false;
            weight = b.wDielectric * b.baseColor * ((1.0 - F) / sqr(b.eta));
        }
    } else {
        return false;
    }
    if (bsdfHasSheen(b)) weight *= sheenScaling(b, sheenAlbedo(b.sheenAlpha, abs(wi.z)));
    weight *= clearcoatAttenuation(b, wo) * clearcoatAttenuation(b, wi);
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
    s.eta = 1.0;
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
    } else if (p.w > 0.0 && ((b.wPass == 0.0 && b.clearcoat == 0.0 && !bsdfHasSheen(b)) ||
                             uLobe < p.x + p.y + p.z + p.w)) {
        s.lobe = LOBE_DIELECTRIC;
        // Re-use the lobe sample's remainder to choose reflection or transmission.
        float uChoice = clamp((uLobe - (p.x + p.y + p.z)) / p.w, 0.0, ONE_MINUS_EPSILON);
        if (isSmooth) {
            // Reflect with probability F, else transmit (total internal reflection: F = 1).
            float F = dielectricReflectance(b, wo.z);
            bool transmit = uChoice >= F;
            vec3 weight;
            if (!bsdfSpecular(b, wo, LOBE_DIELECTRIC, transmit, s.wi, weight)) return false;
            s.f = weight / abs(s.wi.z);
            s.pdf = p.w * (transmit ? 1.0 - F : F);
            s.delta = true;
            s.eta = bsdfLobeEta(b, LOBE_DIELECTRIC, transmit);
            return s.pdf > 0.0;
        }
        vec3 m = ggxSampleVisibleNormal(wo, b.alpha, u);
        float F = dielectricReflectance(b, dot(wo, m));
        if (uChoice < F) {
            s.wi = reflect(-wo, m);
            if (s.wi.z <= 0.0) return false;
        } else if (b.thin) {
            // The reflection mirrored through the surface plane (header).
            vec3 r = reflect(-wo, m);
            if (r.z <= 0.0) return false;
            s.wi = vec3(r.xy, -r.z);
        } else {
            vec3 wt;
            if (!refractDirection(wo, m, b.eta, wt) || wt.z >= 0.0) return false;
            s.wi = wt;
            s.eta = b.eta;
        }
    } else if (bsdfHasSheen(b) && uLobe < p.x + p.y + p.z + p.w + sheenLobeProbability(b, wo)) {
        s.lobe = LOBE_SHEEN;
        s.wi = sampleCosineHemisphere(u);
    } else if (b.clearcoat > 0.0 && (b.wPass == 0.0 || uLobe < 1.0 - b.wPass)) {
        s.lobe = LOBE_CLEARCOAT;
        if (clearcoatSmooth(b)) {
            vec3 weight;
            if (!bsdfSpecular(b, wo, LOBE_CLEARCOAT, false, s.wi, weight)) return false;
            s.f = weight / s.wi.z;
            s.pdf = clearcoatLobeProbability(b, wo);
            s.delta = true;
            return s.pdf > 0.0;
        }
        // Visible normals about n_c: a reflection below either horizon fails (pdfClearcoat).
        vec3 o = clearcoatLocal(b, wo);
        if (o.z <= 0.0) return false;
        vec3 i = reflect(-o, ggxSampleVisibleNormal(o, b.clearcoatAlpha, u));
        if (b.clearcoatTilted && i.z <= 0.0) return false;
        s.wi = b.clearcoatTilted ? toWorld(frameFromNormal(b.clearcoatNormal), i) : i;
        if (s.wi.z <= 0.0) return false;
    } else if (b.wPass > 0.0) {
        // BLEND: the ray passes on with probability 1 - coverage, weight 1.
        s.lobe = LOBE_PASS;
        vec3 weight;
        if (!bsdfSpecular(b, wo, LOBE_PASS, true, s.wi, weight)) return false;
        s.f = weight / wo.z;
        s.pdf = b.wPass;
        s.delta = true;
        return true;
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
