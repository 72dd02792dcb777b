// Scene data as the kernels see it. Built on the host by scene/ (glTF loader, BVH builder).

// Vertex, Triangle, Material, Emitter and LightGroup are read by the kernels as 16-byte texels
// (VERTEX_TEXELS, 1, MATERIAL_TEXELS, 1 and 1 each; shaders/common/scene.glsl vertexAt,
// triangleAt, materialAt, aliasTableTriangle and light_groups.glsl lightGroupAt): keep their
// fields in that order.

// Vertex in world space. normal == (0,0,0) means "no shading normal: use the geometric one".
struct Vertex {
    vec3 position;
    float u;
    vec3 normal;
    float v;
};
PMCR_CHECK_SIZE(Vertex, 32);
PMCR_CONST uint VERTEX_TEXELS = 2;

// Triangle in the scene's original order: vertex indices and material.
struct Triangle {
    uint i0;
    uint i1;
    uint i2;
    uint material;
};
PMCR_CHECK_SIZE(Triangle, 16);

// Intersection-ready triangle in BVH leaf order (Moller-Trumbore form):
// v0.xyz = first vertex, v0.w = uintBitsToFloat(original triangle index), e1 = v1 - v0, e2 = v2 - v0.
// An alpha-masked triangle (Material::alphaCutoff > 0) has e1.w = uintBitsToFloat(its base colour
// texture + 1) and e2.w = its alphaCutoff (Bvh::build(const Scene&)); others have 0 and 0.
struct IsectTriangle {
    vec4 v0;
    vec4 e1;
    vec4 e2;
};
PMCR_CHECK_SIZE(IsectTriangle, 48);

// Flattened binary BVH (host/scene/bvh.h), as the host's traversal reads it; the kernels read
// its 4-wide form (below). Node 0 is the root. Interior (count == 0): children are nodes
// leftOrFirst and leftOrFirst + 1. Leaf (count > 0): IsectTriangles [leftOrFirst, leftOrFirst + count).
struct BvhNode {
    vec3 boundsMin;
    uint leftOrFirst;
    vec3 boundsMax;
    uint count;
};
PMCR_CHECK_SIZE(BvhNode, 32);

// The kernels read the BVH as one texel buffer of uvec4 (Bvh::deviceTexels, BINDING_BVH), the
// binary tree collapsed to 4-wide nodes (each binary interior node with its two children
// opened: two SAH splits per node, as Dammertz et al. 2008 build their 4-wide QBVH):
//   wide node k: texels BVH_NODE_TEXELS k + {0..6}: the bounds of its four children as
//                structure of arrays, minimum x, y, z then maximum x, y, z (child c in
//                component c), then the children's refs: texel address << 3 | count, where
//                count == 0 is a wide node and 1..BVH_MAX_LEAF_TRIANGLES a leaf's triangles,
//                or BVH_EMPTY_CHILD for an unused slot. Wide node 0 (address 0) is the root.
//   triangle j:  texels BVH_NODE_TEXELS * wideNodeCount + 3j + {0, 1, 2} = IsectTriangle j's
//                v0, e1, e2.
// A texel fetch is a vector gather on lavapipe, where SSBO loads with per-lane addresses loop
// over the lanes (shaders/common/bvh.glsl). Addresses stay below BVH_MAX_TEXELS so that a ref
// packs address and count into one uint.
PMCR_CONST uint BVH_MAX_TEXELS = 1u << 29;
PMCR_CONST uint BVH_WIDTH = 4;
PMCR_CONST uint BVH_NODE_TEXELS = 7;
PMCR_CONST uint BVH_NODE_REFS_TEXEL = 6;  // of a wide node's texels, the one with its refs
PMCR_CONST uint BVH_TRIANGLE_TEXELS = 3;  // v0, e1, e2
PMCR_CONST uint BVH_EMPTY_CHILD = 0xFFFFFFFFu;

// Build limits. Leaves hold at most BVH_MAX_LEAF_TRIANGLES; the root has depth 0 and every
// leaf of the binary tree has depth <= BVH_MAX_DEPTH, so below at most BVH_MAX_DEPTH / 2 wide
// nodes. Near-child-first traversal pushes at most three children per wide node it enters,
// so a stack of BVH_STACK_SIZE entries never overflows (shaders/common/bvh.glsl). 48 is far
// above the 26 levels that 4-triangle leaves need for the most triangles the texel addresses
// allow (BVH_MAX_TEXELS / 3), and keeps the stack in Vulkan's minimum of shared memory.
PMCR_CONST uint BVH_MAX_DEPTH = 48;
PMCR_CONST uint BVH_MAX_LEAF_TRIANGLES = 4;
PMCR_CONST uint BVH_STACK_SIZE = 3 * (BVH_MAX_DEPTH / 2);
// Ray/box exit distances are scaled by 1 + 2 gamma(3) (pbrt-v4 section 6.8.7, Bounds3::IntersectP)
// so that rounding never culls a box the ray actually crosses.
PMCR_CONST float BVH_BOX_EXIT_SCALE = 1.00000036f;
// Direction components smaller than this in magnitude are replaced by +-BVH_MIN_DIRECTION
// before taking the reciprocal, so slab distances are finite and never 0 * inf = NaN.
PMCR_CONST float BVH_MIN_DIRECTION = 1e-30f;
// The builder pads node bounds outwards by at least this much (host/scene/bvh.cpp), so a ray
// on a face plane of the unpadded box with a zero direction component is never culled.
PMCR_CONST float BVH_MIN_BOUNDS_PAD = 1e-15f;

PMCR_CONST uint BVH_NO_HIT = 0xFFFFFFFFu;  // Hit.triangle of a miss

// Closest hit of a ray origin + t * direction (direction need not be unit length):
// hit point = (1 - b1 - b2) * v0 + b1 * v1 + b2 * v2 of original triangle `triangle`.
struct Hit {
    float t;
    uint triangle;
    float b1;
    float b2;
};
PMCR_CHECK_SIZE(Hit, 16);

// One ray of the BVH test kernel (shaders/tests/bvh_trace_test.comp).
struct BvhQuery {
    vec3 origin;
    float tMax;
    vec3 direction;
    uint pad;
};
PMCR_CHECK_SIZE(BvhQuery, 32);

// Material flags.
PMCR_CONST uint MATERIAL_DOUBLE_SIDED = 1u;   // emits from both faces; two-sided shading
// Transmission is thin-walled (KHR_materials_transmission without KHR_materials_volume): the
// glass lobe is a thin sheet, light leaves it where it entered (bsdf.glsl header).
PMCR_CONST uint MATERIAL_THIN_WALLED = 2u;
// alphaMode BLEND: coverage (alpha) = Material::coverage times the base colour texture's alpha;
// the ray passes through with probability 1 - coverage (bsdf.glsl LOBE_PASS).
PMCR_CONST uint MATERIAL_BLEND = 4u;
// KHR_materials_specular: the coat's Fresnel is weighted by `specular` and its F0 tinted by
// `specularColor` (bsdf.glsl coatFresnel); without the flag both are ignored (and may be 0).
PMCR_CONST uint MATERIAL_SPECULAR = 8u;

// The glTF metallic-roughness model as pmcr interprets it (shaders/common/bsdf.glsl makeBsdf):
// a mixture of up to three lobes with weights
//   conductor  = metallic                         (GGX, Schlick F0 = baseColor; mirror at roughness 0)
//   dielectric = (1 - metallic) * transmission    (smooth or GGX rough glass, tinted by baseColor)
//   base       = (1 - metallic) * (1 - transmission):
//                Lambertian when roughness == 1, else Lambertian under a GGX dielectric coat,
// all times the BLEND coverage, beside a pass-through delta of weight 1 - coverage.
// Textures are numbered from 0 (baseColorTexture, -1 for none) or from 1 (the others, 0 for
// none, so that a zero-initialised Material has none). All of a material's textures read the
// same texture coordinates (the vertices' uv).
struct Material {
    vec3 baseColor;
    int baseColorTexture;  // index into TextureInfo[], -1 for none
    vec3 emission;         // emitted radiance (emissiveFactor * KHR_materials_emissive_strength)
    uint flags;            // MATERIAL_* bits
    float metallic;        // times the metallicRoughnessTexture's blue channel, when it has one
    float roughness;       // perceptual; GGX alpha = roughness^2; times the texture's green
    float transmission;
    float ior;
    // Absorption coefficient (per unit length) of the medium inside a transmissive material
    // (KHR_materials_volume: -ln(attenuationColor) / attenuationDistance; Beer-Lambert); 0: none.
    vec3 absorption;
    // alphaMode MASK: the surface is cut away where the base colour texture's alpha is below
    // alphaCutoff (alphaCutoff / baseColorFactor's alpha, so that it compares with the texture
    // alone). 0: opaque. Applied in traversal (IsectTriangle).
    float alphaCutoff;
    uint metallicRoughnessTexture;  // index + 1, 0 for none (linear; blue metal, green rough)
    uint normalTexture;    // index + 1, 0 for none (tangent space, MikkTSpace convention)
    uint emissiveTexture;  // index + 1, 0 for none (sRGB; emission is multiplied by it)
    uint transmissionTexture;  // index + 1, 0 for none (linear; transmission times its red)
    float normalScale;     // normalTexture.scale: the tangent-space normal's x and y scale
    float coverage;        // alphaMode BLEND (MATERIAL_BLEND): baseColorFactor's alpha
    uint specularTexture;  // index + 1, 0 for none (KHR_materials_specular; its alpha, linear)
    uint specularColorTexture;  // index + 1, 0 for none (sRGB; specularColor times its rgb)
    vec3 specularColor;    // KHR_materials_specular specularColorFactor (MATERIAL_SPECULAR)
    float specular;        // its specularFactor
    // KHR_materials_clearcoat: a GGX coat of ior 1.5 over everything (bsdf.glsl); 0: none.
    float clearcoat;       // clearcoatFactor (times clearcoatTexture's red)
    float clearcoatRoughness;  // clearcoatRoughnessFactor (times its texture's green)
    uint clearcoatTexture;     // index + 1, 0 for none (linear)
    uint clearcoatRoughnessTexture;  // index + 1, 0 for none (linear)
    // KHR_materials_sheen: the Charlie sheen lobe over the base (bsdf.glsl); black: none.
    vec3 sheenColor;       // sheenColorFactor (times sheenColorTexture, sRGB)
    float sheenRoughness;  // sheenRoughnessFactor (times its texture's alpha)
    uint sheenColorTexture;      // index + 1, 0 for none
    uint sheenRoughnessTexture;  // index + 1, 0 for none (linear; alpha)
    // KHR_materials_clearcoat's clearcoatNormalTexture: the coat's own normal map (index + 1,
    // 0 for none: the coat then takes the interpolated vertex normal), and its scale.
    uint clearcoatNormalTexture;
    float clearcoatNormalScale;
};
PMCR_CHECK_SIZE(Material, 160);
PMCR_CONST uint MATERIAL_TEXELS = 10;
// Below this GGX alpha (roughness^2) a lobe is perfectly smooth, a delta, as pbrt-v4 does.
PMCR_CONST float SMOOTH_ALPHA = 1e-3f;

// Scene features the kernels are specialized for (specialization constant 0, kSceneFeatures in
// shaders/common/scene.glsl; host/scene/scene.h sceneFeatures): code for a feature the scene
// lacks is compiled out when the pipeline is created, so scenes without it pay nothing.
PMCR_CONST uint SCENE_FEATURE_NORMAL_MAPS = 1u;        // a material has a normalTexture
PMCR_CONST uint SCENE_FEATURE_EMISSIVE_TEXTURES = 2u;  // an emitter has an emissiveTexture
PMCR_CONST uint SCENE_FEATURE_ALPHA_MASKS = 4u;        // a triangle is cut by an alpha mask
PMCR_CONST uint SCENE_FEATURE_ABSORPTION = 8u;         // a material absorbs inside (volume)
// Set when no material has a GGX lobe (every lobe is Lambertian or smooth, a delta; see
// SMOOTH_ALPHA): the kernels then compile the microfacet evaluation and sampling out. Unlike the
// bits above it marks a lack, so that a kernel made without features keeps every lobe.
PMCR_CONST uint SCENE_FEATURE_NO_GLOSSY = 16u;
// Set when no material transmits (transmission 0): the glass lobe's code is compiled out.
PMCR_CONST uint SCENE_FEATURE_NO_TRANSMISSION = 32u;
// Set when no material has the issue 41 material features: BLEND coverage, thin-walled
// transmission, KHR_materials_specular, _clearcoat, _sheen. Their code is then compiled out
// (lavapipe runs both sides of a branch, so a sheen's quadrature would cost every scene).
PMCR_CONST uint SCENE_FEATURE_NO_BLEND = 64u;
PMCR_CONST uint SCENE_FEATURE_NO_THIN = 128u;
PMCR_CONST uint SCENE_FEATURE_NO_SPECULAR = 256u;
PMCR_CONST uint SCENE_FEATURE_NO_CLEARCOAT = 512u;
PMCR_CONST uint SCENE_FEATURE_NO_SHEEN = 1024u;
// Set when no clear-coated material's coat normal can differ from its shading normal: none has
// a clearcoatNormalTexture, or a normalTexture (which the coat does not take). The coat's own
// normal and the adjoint of its lobe (bsdf.glsl clearcoatTilted) are then compiled out.
PMCR_CONST uint SCENE_FEATURE_NO_CLEARCOAT_NORMALS = 2048u;
PMCR_CONST uint SCENE_FEATURES_LACKS = SCENE_FEATURE_NO_GLOSSY | SCENE_FEATURE_NO_TRANSMISSION |
                                       SCENE_FEATURE_NO_BLEND | SCENE_FEATURE_NO_THIN |
                                       SCENE_FEATURE_NO_SPECULAR | SCENE_FEATURE_NO_CLEARCOAT |
                                       SCENE_FEATURE_NO_SHEEN | SCENE_FEATURE_NO_CLEARCOAT_NORMALS;

// One emissive triangle, in an alias table (Walker 1977) over emitted power:
// pick slot i uniformly, keep it when u < aliasThreshold, else take emitter `alias`.
struct Emitter {
    uint triangle;
    float pmf;             // probability of selecting this emitter (power / total power)
    float aliasThreshold;
    uint alias;
};
PMCR_CHECK_SIZE(Emitter, 16);

// A light of the adaptive direct-lighting sampler (PMC-HI): a connected group of emissive
// triangles (sharing vertex positions), sampled by its own alias table over its triangles'
// power. Its table is LightGroupEmitter entries [firstEmitter, firstEmitter + emitterCount);
// their `alias` indices are relative to firstEmitter and their `pmf` is within the light.
struct LightGroup {
    uint firstEmitter;
    uint emitterCount;
    float power;           // sum of emitterPower over its triangles
    uint pad;
};
PMCR_CHECK_SIZE(LightGroup, 16);
#ifdef __cplusplus
static_assert(sizeof(Vertex) == 16 * VERTEX_TEXELS && sizeof(Material) == 16 * MATERIAL_TEXELS &&
              sizeof(Triangle) == 16 && sizeof(Emitter) == 16 && sizeof(LightGroup) == 16,
              "scene tables are read as whole 16-byte texels");
#endif

PMCR_CONST uint LIGHT_NONE = 0xFFFFFFFFu;  // triangleLight of a triangle that does not emit

// Texture wrap modes (glTF samplers), two bits per axis: wrap & 3 along u, wrap >> 2 along v.
PMCR_CONST uint WRAP_REPEAT = 0;
PMCR_CONST uint WRAP_CLAMP = 1;     // CLAMP_TO_EDGE
PMCR_CONST uint WRAP_MIRROR = 2;    // MIRRORED_REPEAT

struct TextureInfo {
    uint offset;           // first texel in the texel buffer
    uint width;
    uint height;
    uint wrap;             // WRAP_* along u | (WRAP_* along v) << 2
};
PMCR_CHECK_SIZE(TextureInfo, 16);

// Pinhole camera and scene-wide constants (uniform buffer).
// Raster (px, py) in [0, width) x [0, height), y down, maps to the direction
//   normalize(forward + ((2 px / width - 1) * tanHalfFovY * aspect) * right
//                     + ((1 - 2 py / height) * tanHalfFovY) * up).
struct SceneInfo {
    vec3 cameraPosition;
    float tanHalfFovY;
    vec3 cameraRight;
    float aspect;
    vec3 cameraUp;
    uint width;
    vec3 cameraForward;
    uint height;
    vec3 sceneCenter;
    float sceneRadius;
    uint triangleCount;
    uint pad3;             // unused (the emitter count is the last light group's)
    uint nodeCount;
    float totalEmitterPower;
    uint lightCount;       // PMC-HI's lights (LightGroup[]); the group of all emitters follows them
    uint punctualCount;    // PunctualLight[] (KHR_lights_punctual)
    float punctualSelectPmf;  // probability that light sampling picks a punctual light (chooseLights)
    uint pad2;
    // The environment light (--env; shaders/common/environment.glsl).
    vec3 envRadiance;      // ENV_CONSTANT: the radiance; ENV_IMAGE: the scale of the image's texels
    uint envKind;          // ENV_*
    float envSelectPmf;    // probability that light sampling picks the environment (chooseLights)
    float envRotation;     // radians about +y (--env-rotate)
    uint envWidth;         // ENV_IMAGE: the equirectangular image's size
    uint envHeight;
};
PMCR_CHECK_SIZE(SceneInfo, 144);

// A punctual light (KHR_lights_punctual): a point, a spot (a point with a cone) or a directional
// light, each a delta in position or direction, reached by light sampling only. Three texels.
PMCR_CONST uint PUNCTUAL_POINT = 0;
PMCR_CONST uint PUNCTUAL_SPOT = 1;
PMCR_CONST uint PUNCTUAL_DIRECTIONAL = 2;
struct PunctualLight {
    vec3 position;         // point, spot: world position
    uint type;             // PUNCTUAL_*
    vec3 direction;        // spot, directional: the unit direction the light shines in
    float cosOuter;        // spot: cos of the outer cone angle
    vec3 intensity;        // point, spot: radiant intensity (colour * intensity, per sr);
                           // directional: irradiance on a surface facing it
    float cosInner;        // spot: cos of the inner cone angle
};
PMCR_CHECK_SIZE(PunctualLight, 48);
PMCR_CONST uint PUNCTUAL_LIGHT_TEXELS = 3;
#ifdef __cplusplus
static_assert(sizeof(PunctualLight) == 16 * PUNCTUAL_LIGHT_TEXELS, "read as whole 16-byte texels");
#endif

// The environment light: radiance arriving from infinitely far in every direction.
PMCR_CONST uint ENV_NONE = 0;
PMCR_CONST uint ENV_CONSTANT = 1;  // the same radiance from every direction
PMCR_CONST uint ENV_IMAGE = 2;     // an equirectangular (latitude-longitude) image, +y up
