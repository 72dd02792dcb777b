// Scene buffers (set 0) and what kernels derive from a ray hit.
// Include once per kernel, before anything that reads the scene.
#ifndef PMCR_SCENE_GLSL
#define PMCR_SCENE_GLSL

#include "common/math.glsl"

layout(set = SCENE_SET, binding = BINDING_SCENE_INFO, scalar) uniform SceneInfoBlock {
    SceneInfo sceneInfo;
};
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
    return Material(uintBitsToFloat(a.xyz), int(a.w), uintBitsToFloat(b.xyz), b.w, c.x, c.y, c.z, c.w);
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

#include "common/bvh.glsl"

// A point on a surface, as the integrators use it.
struct SurfacePoint {
    vec3 position;
    vec3 normal;         // geometric, unit, as wound (front face = CCW)
    vec3 shadingNormal;  // unit, on the same side as `normal`
    vec2 uv;
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
    s.triangle = tri;
    s.material = t.material;
    return s;
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
vec3 texelAt(TextureInfo info, float fx, float fy) {
    int x = wrapTexel(fx, float(info.width), info.wrap & 3u);
    int y = wrapTexel(fy, float(info.height), info.wrap >> 2);
    uint i = info.offset + uint(y) * info.width + uint(x);
    return unpackUnorm4x8(texelFetch(textureTexels, int(i >> 2))[i & 3u]).rgb;
}

// Bilinear lookup of a texture; uv (0,0) is the image's top-left (glTF). Colour textures are
// sRGB-encoded (decoded per texel, before filtering), data textures (metallicRoughness) linear.
vec3 sampleTexture(int index, vec2 uv, bool srgb) {
    TextureInfo info = textureInfoAt(index);
    vec2 p = uv * vec2(info.width, info.height) - 0.5;
    vec2 f = p - floor(p);
    float x = floor(p.x);
    float y = floor(p.y);
    vec3 t00 = texelAt(info, x, y);
    vec3 t10 = texelAt(info, x + 1.0, y);
    vec3 t01 = texelAt(info, x, y + 1.0);
    vec3 t11 = texelAt(info, x + 1.0, y + 1.0);
    if (srgb) {
        t00 = srgbToLinear(t00);
        t10 = srgbToLinear(t10);
        t01 = srgbToLinear(t01);
        t11 = srgbToLinear(t11);
    }
    return mix(mix(t00, t10, f.x), mix(t01, t11, f.x), f.y);
}

// A material's base colour, metallic and roughness at uv: its factors, times its textures
// (glTF 2.0 section 3.9.2: baseColorTexture, sRGB; metallicRoughnessTexture's blue and green
// channels, linear). The lookups run in a loop over the textures the material has, not under
// one if per texture: lavapipe runs both sides of an if whatever its lanes take, and a loop's
// body once (masked) and then only while a lane is still in it, so every vector pays for one
// lookup and only vectors with two textures for the second (measured on pt: two ifs cost 7% of
// its samples/s, the loop about 1%).
void materialTextures(Material m, vec2 uv, out vec3 baseColor, out vec2 metallicRoughness) {
    baseColor = m.baseColor;
    metallicRoughness = vec2(m.metallic, m.roughness);
    int mrTexture = int(m.flags >> MATERIAL_MR_TEXTURE_SHIFT) - 1;
    int count = (m.baseColorTexture >= 0 ? 1 : 0) + (mrTexture >= 0 ? 1 : 0);
    for (int k = 0; k < count; ++k) {
        bool base = k == 0 && m.baseColorTexture >= 0;
        vec3 t = sampleTexture(base ? m.baseColorTexture : mrTexture, uv, base);
        if (base) {
            baseColor *= t;
        } else {
            metallicRoughness *= t.bg;
        }
    }
}

// Radiance emitted by a surface towards direction w (unit, away from the surface): area lights
// emit from their front face only unless the material is double-sided (pbrt, Mitsuba).
vec3 emittedRadiance(SurfacePoint s, vec3 w) {
    Material m = materialAt(s.material);
    if (maxComponent(m.emission) <= 0.0) return vec3(0.0);
    if (dot(s.normal, w) > 0.0 || (m.flags & MATERIAL_DOUBLE_SIDED) != 0u) return m.emission;
    return vec3(0.0);
}

#endif
