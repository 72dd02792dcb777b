// Path records: what the path generation kernel writes so that later kernels (ERPT, PMC-ER)
// can split a path tracer sample into its light paths, perturb them and re-evaluate them.
//
// A path tracer sample with next-event estimation is a tree: the eye subpath x1..xn (x0 is the
// pinhole, implied by the record's raster position) and, at every non-specular vertex xk, one
// explicit connection to a light point. It therefore holds up to two light paths per vertex:
//   implicit path  x0 x1 .. xk          (xk is an emitter hit by BSDF sampling)
//   explicit path  x0 x1 .. xk  y_k     (y_k sampled on an emitter from xk)
// each with its MIS-weighted contribution (ERPT eq. 9 and 10, weighted by the power heuristic).
// Each becomes a seed path of energy lum(contribution) in equal deposition (ERPT fig. 7).
//
// Lights other than emitter triangles (kernels compiled with PMCR_OTHER_LIGHTS):
//  - an explicit connection to a punctual light sets VERTEX_SAMPLED_PUNCTUAL and stores the
//    light's index in lightTriangle; one to the environment sets VERTEX_SAMPLED_ENVIRONMENT and
//    stores the unit direction towards it, octahedral-encoded (octEncode), in lightB1, lightB2;
//  - a ray that escapes to the environment after xk adds one more record vertex x_k+1 that is
//    not a surface: flags VERTEX_EMITTER | VERTEX_ENVIRONMENT, the direction octahedral-encoded
//    in barycentrics, its MIS-weighted contribution in implicitContribution. So the implicit
//    path x0 .. xk (environment) is seed path 2 (k + 1) like any emitter hit.

PMCR_CONST uint PATH_MAX_VERTICES = 16;   // eye vertices stored per record (x1..x16)

// PathVertex.flags
PMCR_CONST uint VERTEX_SPECULAR = 1u;          // the lobe sampled here is a delta lobe (S); else D
PMCR_CONST uint VERTEX_EMITTER = 2u;           // the surface emits towards the previous vertex
PMCR_CONST uint VERTEX_HAS_LIGHT_SAMPLE = 4u;  // lightPosition/explicitContribution are valid
PMCR_CONST uint VERTEX_BACKFACE = 8u;          // the previous vertex sees the back of the surface
PMCR_CONST uint VERTEX_TRANSMISSION = 16u;     // the direction sampled here crosses the surface
PMCR_CONST uint VERTEX_PUNCTUAL = 32u;         // not a surface: punctual light `triangle` (chains)
PMCR_CONST uint VERTEX_ENVIRONMENT = 64u;      // not a surface: the environment in direction
                                               // octDecode(b1, b2) from the previous vertex
PMCR_CONST uint VERTEX_SAMPLED_PUNCTUAL = 4096u;     // the light sample is a punctual light
PMCR_CONST uint VERTEX_SAMPLED_ENVIRONMENT = 8192u;  // the light sample is the environment

struct PathVertex {
    vec3 position;
    uint triangle;               // original triangle index
    vec3 normal;                 // geometric normal (unit, as wound)
    uint flags;                  // VERTEX_*
    vec3 shadingNormal;          // unit, on the same side as `normal`
    uint material;
    vec2 barycentrics;           // (b1, b2) on `triangle`
    float pdfForward;            // solid-angle pdf of the direction sampled here (0 for delta)
    uint lobe;                   // which lobe was sampled here (see shaders/common/bsdf.glsl)
    vec3 lightPosition;          // explicit connection from this vertex
    uint lightTriangle;
    vec3 explicitContribution;   // MIS-weighted contribution of x0..xk y_k
    float lightB1;               // barycentrics of the light point on lightTriangle
    vec3 implicitContribution;   // MIS-weighted contribution of x0..xk when xk is an emitter
    float lightB2;
};
PMCR_CHECK_SIZE(PathVertex, 112);

struct PathRecord {
    vec2 raster;                 // film position of x1 (raster coordinates)
    uint pixel;                  // linear pixel index of raster
    uint vertexCount;            // eye vertices stored (x1..x_vertexCount)
    vec3 radiance;               // the sample's full estimate (sum of all its contributions)
    uint firstVertex;            // index of x1 in the PathVertex buffer
};
PMCR_CHECK_SIZE(PathRecord, 32);
