// Scene buffers (set 0) and what kernels derive from a ray hit.
// Include once per kernel, before anything that reads the scene.
#ifndef PMCR_SCENE_GLSL
#define PMCR_SCENE_GLSL

#include "common/math.glsl"

layout(set = SCENE_SET, binding = BINDING_SCENE_INFO, scalar) uniform SceneInfoBlock {
    SceneInfo sceneInfo;
};

// The scene's features (SCENE_FEATURE_*), a specialization constant set when the host creates
// the pipeline (vk::Kernel): code under a feature the scene lacks is folded away, so a scene
// without normal maps, emissive textures, alpha masks or absorption pays nothing for them.
layout(constant_id = 0) const uint kSceneFeatures = 0u;
bool sceneHasNormalMaps() { return (kSceneFeatures & SCENE_FEATURE_NORMAL_MAPS) != 0u; }
bool sceneHasEmissiveTextures() { return (kSceneFeatures & SCENE_FEATURE_EMISSIVE_TEXTURES) != 0u; }
bool sceneHasAlphaMasks() { return (kSceneFeatures & SCENE_FEATURE_ALPHA_MASKS) != 0u; }
bool sceneHasAbsorption() { return (kSceneFeatures & SCENE_FEATURE_ABSORPTION) != 0u; }
bool sceneHasGlossy() { return (kSceneFeatures & SCENE_FEATURE_NO_GLOSSY) == 0u; }
bool sceneHasTransmission() { return (kSceneFeatures & SCENE_FEATURE_NO_TRANSMISSION) == 0u; }
bool sceneHasBlend() { return (kSceneFeatures & SCENE_FEATURE_NO_BLEND) == 0u; }
bool sceneHasThin() { return (kSceneFeatures & SCENE_FEATURE_NO_THIN) == 0u; }
bool sceneHasSpecular() { return (kSceneFeatures & SCENE_FEATURE_NO_SPECULAR) == 0u; }
bool sceneHasClearcoat() { return (kSceneFeatures & SCENE_FEATURE_NO_CLEARCOAT) == 0u; }
bool sceneHasSheen() { return (kSceneFeatures & SCENE_FEATURE_NO_SHEEN) == 0u; }
bool sceneHasClearcoatNormals() {
    return sceneHasClearcoat() && (kSceneFeatures & SCENE_FEATURE_NO_CLEARCOAT_NORMALS) == 0u;
}
// Vertices, triangles, materials and emitters are texel buffers, as the BVH is (bvh.glsl): on lavapipe a
// texel fetch is one gather of four words for all lanes, where a storage-buffer load with
// per-lane addresses is a loop over the lanes for every word. A Vertex is VERTEX_TEXELS float
// texels (position, u; normal, v), a Triangle one uint texel, a Material MATERIAL_TEXELS
// (shared/scene_types.h).
layout(set = SCENE_SET, binding = BINDING_VERTICES) uniform samplerBuffer vertexTexels;
layout(set = SCENE_SET, binding = BINDING_TRIANGLES) uniform usamplerBuffer triangleTexels;
layout(set = SCENE_SET, binding = BINDING_MATERIALS) uniform usamplerBuffer materialTexels;

Vertex vertexAt(uint i) {
    vec4 a = texelFetch(vertexTexels, int(VERTEX_TEXELS * i));
    vec4 b = texelFetch(vertexTexels, int(VERTEX_TEXELS * i + 1u));
    return Vertex(a.xyz, a.w, b.xyz, b.w);
}

vec3 vertexPosition(uint i) { return texelFetch(vertexTexels, int(VERTEX_TEXELS * i)).xyz; }

Triangle triangleAt(uint i) {
    uvec4 t = texelFetch(triangleTexels, int(i));
    return Triangle(t.x, t.y, t.z, t.w);
}

Material materialAt(uint i) {
    uvec4 a = texelFetch(materialTexels, int(MATERIAL_TEXELS * i));
    uvec4 b = texelFetch(materialTexels, int(MATERIAL_TEXELS * i + 1u));
    vec4 c = uintBitsToFloat(texelFetch(materialTexels, int(MATERIAL_TEXELS * i + 2u)));
    vec4 d = uintBitsToFloat(texelFetch(materialTexels, int(MATERIAL_TEXELS * i + 3u)));
    uvec4 e = texelFetch(materialTexels, int(MATERIAL_TEXELS * i + 4u));
    uvec4 f = texelFetch(materialTexels, int(MATERIAL_TEXELS * i + 5u));
    vec4 g = uintBitsToFloat(texelFetch(materialTexels, int(MATERIAL_TEXELS * i + 6u)));
    uvec4 h = texelFetch(materialTexels, int(MATERIAL_TEXELS * i + 7u));
    vec4 k = uintBitsToFloat(texelFetch(materialTexels, int(MATERIAL_TEXELS * i + 8u)));
    uvec4 l = texelFetch(materialTexels, int(MATERIAL_TEXELS * i + 9u));
    return Material(uintBitsToFloat(a.xyz), int(a.w), uintBitsToFloat(b.xyz), b.w, c.x, c.y, c.z,
                    c.w, d.xyz, d.w, e.x, e.y, e.z, e.w, uintBitsToFloat(f.x),
                    uintBitsToFloat(f.y), f.z, f.w, g.xyz, g.w, uintBitsToFloat(h.x),
                    uintBitsToFloat(h.y), h.z, h.w, k.xyz, k.w, l.x, l.y, l.z, uintBitsToFloat(l.w));
}
Emitter emitterFrom(uvec4 t) { return Emitter(t.x, uintBitsToFloat(t.y), uintBitsToFloat(t.z), t.w); }

// The triangle an alias table (Walker 1977; host/scene/scene.cpp buildAliasTable) picks with u:
// slot floor(u n) of the n entries from `first` in `table`, kept when the rest of u n is below
// its threshold, else its alias (relative to `first`).
uint aliasTableTriangle(usamplerBuffer table, uint first, uint n, float u) {
    if (n == 0u) return 0u;  // an empty table (a scene lit by its environment alone)
    float scaled = u * float(n);
    uint slot = min(uint(scaled), n - 1u);
    Emitter e = emitterFrom(texelFetch(table, int(first + slot)));
    return (scaled - float(slot)) < e.aliasThreshold
               ? e.triangle
               : emitterFrom(texelFetch(table, int(first + e.alias))).triangle;
}
// The textures: their TextureInfo, and their RGBA8 texels packed four to a uint texel (texel
// buffers, as the other scene tables: one gather for all lanes on lavapipe, where a storage
// buffer load is a loop over the lanes).
layout(set = SCENE_SET, binding = BINDING_TEXTURE_INFOS) uniform usamplerBuffer textureInfoTexels;
layout(set = SCENE_SET, binding = BINDING_TEXELS) uniform usamplerBuffer textureTexels;

TextureInfo textureInfoAt(int i) {
    uvec4 t = texelFetch(textureInfoTexels, i);
    return TextureInfo(t.x, t.y, t.z, t.w);
}

// sRGB EOTF (IEC 61966-2-1).
vec3 srgbToLinear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

// Texel coordinate x (an integer) of a texture n texels wide under wrap mode `mode` (glTF 2.0
// section 3.8.4.3). In float arithmetic, exact below 2^24: lavapipe has no vector integer
// division, so an integer % would be a loop over the lanes.
int wrapTexel(float x, float n, uint mode) {
    float repeat = x - n * floor(x / n);
    float period = x - 2.0 * n * floor(x / (2.0 * n));
    float mirror = period < n ? period : 2.0 * n - 1.0 - period;
    return int(mode == WRAP_CLAMP ? clamp(x, 0.0, n - 1.0) : mode == WRAP_MIRROR ? mirror : repeat);
}

// A texel as stored (8 bits per channel, in [0, 1]).
vec4 texelAt(TextureInfo info, float fx, float fy) {
    int x = wrapTexel(fx, float(info.width), info.wrap & 3u);
    int y = wrapTexel(fy, float(info.height), info.wrap >> 2);
    uint i = info.offset + uint(y) * info.width + uint(x);
    return unpackUnorm4x8(texelFetch(textureTexels, int(i >> 2))[i & 3u]);
}

// Bilinear lookup of a texture; uv (0,0) is the image's top-left (glTF). Colour textures are
// sRGB-encoded (decoded per texel, before filtering; alpha is linear), data textures
// (metallicRoughness, normal) linear. host/scene/texture_lookup.cpp does the same on the host.
vec4 sampleTextureRgba(int index, vec2 uv, bool srgb) {
    TextureInfo info = textureInfoAt(index);
    vec2 p = uv * vec2(info.width, info.height) - 0.5;
    vec2 f = p - floor(p);
    float x = floor(p.x);
    float y = floor(p.y);
    vec4 t00 = texelAt(info, x, y);
    vec4 t10 = texelAt(info, x + 1.0, y);
    vec4 t01 = texelAt(info, x, y + 1.0);
    vec4 t11 = texelAt(info, x + 1.0, y + 1.0);
    if (srgb) {
        t00.rgb = srgbToLinear(t00.rgb);
        t10.rgb = srgbToLinear(t10.rgb);
        t01.rgb = srgbToLinear(t01.rgb);
        t11.rgb = srgbToLinear(t11.rgb);
    }
    return mix(mix(t00, t10, f.x), mix(t01, t11, f.x), f.y);
}

vec3 sampleTexture(int index, vec2 uv, bool srgb) { return sampleTextureRgba(index, uv, srgb).rgb; }

// Texture coordinates of triangle `tri` at barycentrics (b1, b2).
vec2 triangleUv(uint tri, vec2 b) {
    Triangle t = triangleAt(tri);
    vec2 uv0 = vec2(texelFetch(vertexTexels, int(VERTEX_TEXELS * t.i0)).w,
                    texelFetch(vertexTexels, int(VERTEX_TEXELS * t.i0 + 1u)).w);
    vec2 uv1 = vec2(texelFetch(vertexTexels, int(VERTEX_TEXELS * t.i1)).w,
                    texelFetch(vertexTexels, int(VERTEX_TEXELS * t.i1 + 1u)).w);
    vec2 uv2 = vec2(texelFetch(vertexTexels, int(VERTEX_TEXELS * t.i2)).w,
                    texelFetch(vertexTexels, int(VERTEX_TEXELS * t.i2 + 1u)).w);
    return (1.0 - b.x - b.y) * uv0 + b.x * uv1 + b.y * uv2;
}

// Whether an alpha-masked triangle (glTF alphaMode MASK) is cut away at barycentrics (b1, b2):
// its base colour texture's alpha (`texture` + 1, as IsectTriangle's e1.w holds it) is below
// `cutoff` (Material::alphaCutoff). The traversal (bvh.glsl) calls it for every candidate hit
// on a masked triangle, closest-hit and shadow rays alike.
bool alphaCutAway(uint texturePlusOne, float cutoff, uint tri, float b1, float b2) {
    return sampleTextureRgba(int(texturePlusOne) - 1, triangleUv(tri, vec2(b1, b2)), false).a < cutoff;
}

#include "common/bvh.glsl"

// A point on a surface, as the integrators use it.
struct SurfacePoint {
    vec3 position;
    vec3 normal;         // geometric, unit, as wound (front face = CCW)
    vec3 shadingNormal;  // unit, on the same side as `normal`
    vec2 uv;
    vec2 barycentrics;   // (b1, b2) on `triangle`
    uint triangle;
    uint material;
};

// Twice the triangle's area times its unit normal.
vec3 triangleCross(uint tri) {
    Triangle t = triangleAt(tri);
    vec3 p0 = vertexPosition(t.i0);
    return cross(vertexPosition(t.i1) - p0, vertexPosition(t.i2) - p0);
}
float triangleArea(uint tri) { return 0.5 * length(triangleCross(tri)); }

// Surface point at barycentrics (b1, b2) of triangle `tri` (b0 = 1 - b1 - b2).
SurfacePoint surfaceAt(uint tri, vec2 b) {
    Triangle t = triangleAt(tri);
    Vertex v0 = vertexAt(t.i0);
    Vertex v1 = vertexAt(t.i1);
    Vertex v2 = vertexAt(t.i2);
    float b0 = 1.0 - b.x - b.y;
    SurfacePoint s;
    s.position = b0 * v0.position + b.x * v1.position + b.y * v2.position;
    s.normal = normalize(cross(v1.position - v0.position, v2.position - v0.position));
    vec3 ns = b0 * v0.normal + b.x * v1.normal + b.y * v2.normal;
    float len2 = dot(ns, ns);
    s.shadingNormal = len2 > 1e-12 ? ns * inversesqrt(len2) : s.normal;
    if (dot(s.shadingNormal, s.normal) < 0.0) s.shadingNormal = -s.shadingNormal;
    s.uv = b0 * vec2(v0.u, v0.v) + b.x * vec2(v1.u, v1.v) + b.y * vec2(v2.u, v2.v);
    s.barycentrics = b;
    s.triangle = tri;
    s.material = t.material;
    return s;
}

// The vertex tangents of normal-mapped scenes (SCENE_FEATURE_NORMAL_MAPS): xyz the tangent,
// w the bitangent's sign (host/scene/tangents.h).
layout(set = SCENE_SET, binding = BINDING_TANGENTS) uniform samplerBuffer tangentTexels;

// The shading normal a normal map gives at s: the texel's tangent-space normal (2 t - 1, x and y
// times the material's normalScale) in the frame (T, B, N) of the interpolated tangent T and
// normal N, B = sign * cross(N, T) (glTF 2.0 sec. 3.9.3; the MikkTSpace convention: T and the
// sign per vertex, B computed per point, the tangent not renormalised before interpolation).
// A mapped normal below the geometric surface is not used (the interpolated one is kept).
vec3 normalMapped(SurfacePoint s, vec3 texel, float scale) {
    Triangle t = triangleAt(s.triangle);
    vec4 t0 = texelFetch(tangentTexels, int(t.i0));
    vec4 t1 = texelFetch(tangentTexels, int(t.i1));
    vec4 t2 = texelFetch(tangentTexels, int(t.i2));
    vec2 b = s.barycentrics;
    vec3 T = (1.0 - b.x - b.y) * t0.xyz + b.x * t1.xyz + b.y * t2.xyz;
    vec3 N = s.shadingNormal;
    T -= N * dot(N, T);
    float len2 = dot(T, T);
    if (!(len2 > 1e-12)) return N;
    T *= inversesqrt(len2);
    vec3 B = (t0.w < 0.0 ? -1.0 : 1.0) * cross(N, T);
    vec3 tn = vec3((2.0 * texel.xy - 1.0) * scale, 2.0 * texel.z - 1.0);
    vec3 n = tn.x * T + tn.y * B + tn.z * N;
    float nLen2 = dot(n, n);
    if (!(nLen2 > 1e-12)) return N;
    n *= inversesqrt(nLen2);
    return dot(n, s.normal) > 1e-3 ? n : N;
}

// A material's base colour, metallic, roughness and transmission at s, and its shading normal:
// its factors, times its textures (glTF 2.0 section 3.9.2: baseColorTexture, sRGB;
// metallicRoughnessTexture's blue and green channels, linear; normalTexture, linear,
// normalMapped; KHR_materials_transmission's transmissionTexture, its red channel), and its
// coverage (alphaMode BLEND: Material::coverage times the base colour texture's alpha). The lookups
// run in a loop over the textures the material has, not under one if per texture: lavapipe runs
// both sides of an if whatever its lanes take, and a loop's body once (masked) and then only
// while a lane is still in it, so every vector pays for one lookup and only vectors with two
// textures for the second (measured on pt: two ifs cost 7% of its samples/s, the loop about
// 1%). The normal map is compiled in only for scenes that have one (sceneHasNormalMaps).
struct MaterialSample {
    vec3 baseColor;
    float metallic;
    float roughness;
    float transmission;
    vec3 shadingNormal;
    float coverage;  // 1 unless alphaMode BLEND
    float specular;        // KHR_materials_specular (MATERIAL_SPECULAR): weight and F0 tint,
    vec3 specularColor;    // times their textures
    float clearcoat;       // KHR_materials_clearcoat, times their textures
    float clearcoatRoughness;
    // The coat's normal (sceneHasClearcoatNormals): its clearcoatNormalTexture's, else the
    // interpolated vertex normal, not the normalTexture's (the extension's clearcoatNormal).
    vec3 clearcoatNormal;
    vec3 sheenColor;       // KHR_materials_sheen, times their textures
    float sheenRoughness;
};

MaterialSample materialTextures(Material m, SurfacePoint s) {
    MaterialSample r;
    r.baseColor = m.baseColor;
    r.metallic = m.metallic;
    r.roughness = m.roughness;
    r.transmission = m.transmission;
    r.shadingNormal = s.shadingNormal;
    r.specular = m.specular;
    r.specularColor = m.specularColor;
    r.clearcoat = m.clearcoat;
    r.clearcoatRoughness = m.clearcoatRoughness;
    r.clearcoatNormal = s.shadingNormal;
    r.sheenColor = m.sheenColor;
    r.sheenRoughness = m.sheenRoughness;
    float alpha = 1.0;
    int mrTexture = int(m.metallicRoughnessTexture) - 1;
    int normalTexture = sceneHasNormalMaps() ? int(m.normalTexture) - 1 : -1;
    int transmissionTexture = int(m.transmissionTexture) - 1;
    // The extensions' textures only in scenes with the extension (their texels not fetched else).
    int specularTexture = sceneHasSpecular() ? int(m.specularTexture) - 1 : -1;
    int specularColorTexture = sceneHasSpecular() ? int(m.specularColorTexture) - 1 : -1;
    int clearcoatTexture = sceneHasClearcoat() ? int(m.clearcoatTexture) - 1 : -1;
    int clearcoatRoughnessTexture = sceneHasClearcoat() ? int(m.clearcoatRoughnessTexture) - 1 : -1;
    int sheenColorTexture = sceneHasSheen() ? int(m.sheenColorTexture) - 1 : -1;
    int sheenRoughnessTexture = sceneHasSheen() ? int(m.sheenRoughnessTexture) - 1 : -1;
    int clearcoatNormalTexture =
        sceneHasClearcoatNormals() ? int(m.clearcoatNormalTexture) - 1 : -1;
    // Bit w set: the material has texture kind w (0 base colour, 1 metallicRoughness, 2 normal,
    // 3 transmission, 4 specular, 5 specular colour, 6 clearcoat, 7 clearcoat roughness, 8 sheen
    // colour, 9 sheen roughness, 10 clearcoat normal); each pass takes the lowest kind left.
    uint left = (m.baseColorTexture >= 0 ? 1u : 0u) | (mrTexture >= 0 ? 2u : 0u) |
                (normalTexture >= 0 ? 4u : 0u) | (transmissionTexture >= 0 ? 8u : 0u) |
                (specularTexture >= 0 ? 16u : 0u) | (specularColorTexture >= 0 ? 32u : 0u) |
                (clearcoatTexture >= 0 ? 64u : 0u) | (clearcoatRoughnessTexture >= 0 ? 128u : 0u) |
                (sheenColorTexture >= 0 ? 256u : 0u) | (sheenRoughnessTexture >= 0 ? 512u : 0u) |
                (clearcoatNormalTexture >= 0 ? 1024u : 0u);
    int count = bitCount(left);
    vec3 normalTexel = vec3(0.5, 0.5, 1.0);
    vec3 clearcoatNormalTexel = vec3(0.5, 0.5, 1.0);
    for (int k = 0; k < count; ++k) {
        int which = findLSB(left);
        left &= left - 1u;
        int index = which == 0   ? m.baseColorTexture
                    : which == 1 ? mrTexture
                    : which == 2 ? normalTexture
                    : which == 3 ? transmissionTexture
                    : which == 4 ? specularTexture
                    : which == 5 ? specularColorTexture
                    : which == 6 ? clearcoatTexture
                    : which == 7 ? clearcoatRoughnessTexture
                    : which == 8 ? sheenColorTexture
                    : which == 9 ? sheenRoughnessTexture
                                 : clearcoatNormalTexture;
        vec4 t = sampleTextureRgba(index, s.uv, which == 0 || which == 5 || which == 8);
        if (which == 0) {
            r.baseColor *= t.rgb;
            alpha = t.a;
        } else if (which == 1) {
            r.metallic *= t.b;
            r.roughness *= t.g;
        } else if (which == 2) {
            normalTexel = t.rgb;
        } else if (which == 3) {
            r.transmission *= t.r;
        } else if (which == 4) {
            r.specular *= t.a;
        } else if (which == 5) {
            r.specularColor *= t.rgb;
        } else if (which == 6) {
            r.clearcoat *= t.r;
        } else if (which == 7) {
            r.clearcoatRoughness *= t.g;
        } else if (which == 8) {
            r.sheenColor *= t.rgb;
        } else if (which == 9) {
            r.sheenRoughness *= t.a;
        } else {
            clearcoatNormalTexel = t.rgb;
        }
    }
    if (sceneHasNormalMaps() && normalTexture >= 0) {
        r.shadingNormal = normalMapped(s, normalTexel, m.normalScale);
    }
    if (clearcoatNormalTexture >= 0)
        r.clearcoatNormal = normalMapped(s, clearcoatNormalTexel, m.clearcoatNormalScale);
    r.coverage = sceneHasBlend() && (m.flags & MATERIAL_BLEND) != 0u ? m.coverage * alpha : 1.0;
    return r;
}

// Radiance emitted by a surface towards direction w (unit, away from the surface): area lights
// emit from their front face only unless the material is double-sided (pbrt, Mitsuba). Its
// emissiveTexture (sRGB) multiplies the emission (glTF 2.0 sec. 3.9.4).
vec3 emittedRadiance(SurfacePoint s, vec3 w) {
    Material m = materialAt(s.material);
    if (maxComponent(m.emission) <= 0.0) return vec3(0.0);
    if (!(dot(s.normal, w) > 0.0 || (m.flags & MATERIAL_DOUBLE_SIDED) != 0u)) return vec3(0.0);
    vec3 Le = m.emission;
    if (sceneHasEmissiveTextures() && m.emissiveTexture != 0u) {
        Le *= sampleTexture(int(m.emissiveTexture) - 1, s.uv, true);
    }
    return Le;
}

#endif
