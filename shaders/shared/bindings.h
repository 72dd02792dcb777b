// Descriptor bindings and workgroup sizes. All compute pipelines share one pipeline layout:
//   set 0: the scene (read-only, uploaded once);
//   set 1: the integrator's working buffers (film, sample lists, path records, statistics);
//   push constants: at most PUSH_CONSTANT_BYTES per dispatch.
// A kernel declares only the bindings it uses; unused ones may stay unwritten.

PMCR_CONST uint SCENE_SET = 0;
PMCR_CONST uint BINDING_SCENE_INFO = 0;      // SceneInfo (uniform)
PMCR_CONST uint BINDING_VERTICES = 1;        // Vertex[] as a float texel buffer, VERTEX_TEXELS each
PMCR_CONST uint BINDING_TRIANGLES = 2;       // Triangle[] as a uint texel buffer (original order)
PMCR_CONST uint BINDING_PUNCTUAL_LIGHTS = 3;  // PunctualLight[] as a uint texel buffer, PUNCTUAL_LIGHT_TEXELS each
PMCR_CONST uint BINDING_BVH = 4;             // uvec4 texel buffer: nodes and triangles (Bvh::deviceTexels)
PMCR_CONST uint BINDING_MATERIALS = 5;       // Material[] as a uint texel buffer, MATERIAL_TEXELS each
PMCR_CONST uint BINDING_PUNCTUAL_ALIAS = 6;   // Emitter[] as a uint texel buffer: an alias table over
                                             // the punctual lights' power (`triangle`: the light)
PMCR_CONST uint BINDING_TEXTURE_INFOS = 7;   // TextureInfo[] as a uint texel buffer
PMCR_CONST uint BINDING_TEXELS = 8;          // the textures' RGBA8 texels, four to a uint texel
PMCR_CONST uint BINDING_LIGHT_GROUPS = 9;     // LightGroup[] as a uint texel buffer: the lights
                                              // (connected emitters, PMC-HI), then all emitters
PMCR_CONST uint BINDING_LIGHT_EMITTERS = 10;  // Emitter[] as a uint texel buffer (their alias tables)
PMCR_CONST uint BINDING_TRIANGLE_LIGHTS = 11; // uint[] per triangle: its LightGroup, or LIGHT_NONE
PMCR_CONST uint BINDING_ENV_TEXELS = 12;      // vec4[] float texel buffer: the environment image's RGB, row-major, top row first
PMCR_CONST uint BINDING_ENV_ALIAS = 13;       // Emitter[] as a uint texel buffer: an alias table over its pixels
PMCR_CONST uint BINDING_TANGENTS = 14;        // vec4[] float texel buffer: per vertex its tangent
                                              // (xyz, world space) and bitangent sign (w); only
                                              // with SCENE_FEATURE_NORMAL_MAPS
PMCR_CONST uint BINDING_TRIANGLE_EMISSION = 15;  // float[] four to a float texel: per triangle the
                                              // luminance of its mean emitted radiance; only with
                                              // SCENE_FEATURE_EMISSIVE_TEXTURES
PMCR_CONST uint SCENE_BINDING_COUNT = 16;

PMCR_CONST uint WORK_SET = 1;
PMCR_CONST uint WORK_BINDING_COUNT = 16;     // storage buffers 0..15, meaning set per kernel

PMCR_CONST uint PUSH_CONSTANT_BYTES = 128;

// 1D workgroup size of every kernel. 64 = 8 subgroups of 8 on lavapipe, 2 warps on NVIDIA.
PMCR_CONST uint WORKGROUP_SIZE = 64;
