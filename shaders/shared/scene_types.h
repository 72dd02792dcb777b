// Scene data as the kernels see it. Built on the host by scene/ (glTF loader, BVH builder).

// Vertex in world space. normal == (0,0,0) means "no shading normal: use the geometric one".
struct Vertex {
    vec3 position;
    float u;
    vec3 normal;
    float v;
};
PMCR_CHECK_SIZE(Vertex, 32);

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
struct IsectTriangle {
    vec4 v0;
    vec4 e1;
    vec4 e2;
};
PMCR_CHECK_SIZE(IsectTriangle, 48);

// Flattened binary BVH node. Interior (count == 0): children are nodes leftOrFirst and
// leftOrFirst + 1. Leaf (count > 0): IsectTriangles [leftOrFirst, leftOrFirst + count).
// axis (bits 30..31 of count for interiors) is the split axis, used for front-to-back order.
struct BvhNode {
    vec3 boundsMin;
    uint leftOrFirst;
    vec3 boundsMax;
    uint count;
};
PMCR_CHECK_SIZE(BvhNode, 32);

// Material flags.
PMCR_CONST uint MATERIAL_DOUBLE_SIDED = 1u;   // emits from both faces; two-sided shading

// The glTF metallic-roughness model as pmcr interprets it (see host/scene/material.h):
// a mixture of up to three lobes with weights
//   conductor  = metallic                         (GGX, Schlick F0 = baseColor; mirror at roughness 0)
//   dielectric = (1 - metallic) * transmission    (smooth or GGX rough glass, tinted by baseColor)
//   base       = (1 - metallic) * (1 - transmission):
//                Lambertian when roughness == 1, else Lambertian under a GGX dielectric coat.
struct Material {
    vec3 baseColor;
    int baseColorTexture;  // index into TextureInfo[], -1 for none
    vec3 emission;         // emitted radiance (emissiveFactor * KHR_materials_emissive_strength)
    uint flags;
    float metallic;
    float roughness;       // perceptual; GGX alpha = roughness^2
    float transmission;
    float ior;
};
PMCR_CHECK_SIZE(Material, 48);

// One emissive triangle, in an alias table (Walker 1977) over emitted power:
// pick slot i uniformly, keep it when u < aliasThreshold, else take emitter `alias`.
struct Emitter {
    uint triangle;
    float pmf;             // probability of selecting this emitter (power / total power)
    float aliasThreshold;
    uint alias;
};
PMCR_CHECK_SIZE(Emitter, 16);

struct TextureInfo {
    uint offset;           // first texel in the texel buffer
    uint width;
    uint height;
    uint pad;
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
    uint emitterCount;
    uint nodeCount;
    float totalEmitterPower;
};
PMCR_CHECK_SIZE(SceneInfo, 96);
