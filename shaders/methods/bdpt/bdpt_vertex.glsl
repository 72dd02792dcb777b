// The vertices of bidirectional path tracing (shared/bdpt_types.h BdptVertex) and the densities
// between them (Veach 1997 sec. 10.2; pbrt-v4 Vertex::Pdf, PdfLight, PdfLightOrigin,
// ConvertDensity): what the subpath kernel records and the MIS weights of the connection kernel
// read. Densities are per unit area at the vertex they reach (times |cos| there), or per unit
// solid angle towards an infinite light (the environment, a directional light), whose vertex is
// a direction: `wo`, from the scene towards the light.
#ifndef PMCR_BDPT_VERTEX_GLSL
#define PMCR_BDPT_VERTEX_GLSL

#include "common/camera.glsl"
#include "common/environment.glsl"
#include "common/lights.glsl"
#include "common/punctual_sampling.glsl"
#include "common/shading.glsl"

// The vertex buffers' bindings: bdpt's unless the kernel names others (pssmlt over bdpt).
#ifndef CAMERA_VERTICES_BINDING
#define CAMERA_VERTICES_BINDING BDPT_BINDING_CAMERA_VERTICES
#define LIGHT_VERTICES_BINDING BDPT_BINDING_LIGHT_VERTICES
#define VERTEX_COUNTS_BINDING BDPT_BINDING_COUNTS
#endif
layout(set = WORK_SET, binding = CAMERA_VERTICES_BINDING, scalar) buffer CameraVertexBuffer {
    BdptVertex cameraVertices[];
};
layout(set = WORK_SET, binding = LIGHT_VERTICES_BINDING, scalar) buffer LightVertexBuffer {
    BdptVertex lightVertices[];
};
layout(set = WORK_SET, binding = VERTEX_COUNTS_BINDING, scalar) buffer CountBuffer { uvec2 vertexCounts[]; };

// The sampler dimensions of a camera sample (shared/bdpt_types.h BDPT_LIGHT_DIMENSION): the
// raster position (0), the camera walk from 1, the light subpath from bdptLightDimension, and
// the light samples of the s = 1 connections from bdptConnectDimension (two apart per camera
// vertex), so that no part's numbers depend on another part's length.
uint bdptLightDimension(uint maxDepth) { return BDPT_LIGHT_DIMENSION(maxDepth); }
uint bdptConnectDimension(uint maxDepth) { return BDPT_CONNECT_DIMENSION(maxDepth); }

BdptVertex bdptVertex(uint type) {
    return BdptVertex(vec3(0.0), type, vec3(0.0), 0u, vec3(0.0), 0.0, vec3(0.0), 0.0, vec2(0.0), 0u, 0.0);
}

bool vertexInfinite(BdptVertex v) { return v.type == BDPT_LIGHT_INFINITE; }
bool vertexOnSurface(BdptVertex v) { return v.type == BDPT_SURFACE || v.type == BDPT_LIGHT_AREA; }
bool vertexDelta(BdptVertex v) { return (v.flags & BDPT_VERTEX_DELTA) != 0u; }
// A light with a delta in position or direction: no path can reach it by scattering.
bool vertexDeltaLight(BdptVertex v) {
    return v.type == BDPT_LIGHT_POINT ||
           (v.type == BDPT_LIGHT_INFINITE && (v.flags & BDPT_VERTEX_DIRECTIONAL) != 0u);
}

// Unit direction from a towards b, and the squared distance (1 to or from an infinite light).
vec3 vertexDirection(BdptVertex a, BdptVertex b, out float dist2) {
    dist2 = 1.0;
    if (vertexInfinite(b)) return b.wo;
    if (vertexInfinite(a)) return -a.wo;
    vec3 d = b.position - a.position;
    dist2 = dot(d, d);
    return dist2 > 0.0 ? d * inversesqrt(dist2) : vec3(0.0);
}

// A solid-angle density at v of the direction towards `next`, as a density at next: times
// |cos| at next over the squared distance, unless next is an infinite light (pbrt-v4
// Vertex::ConvertDensity).
float convertDensity(BdptVertex v, float pdf, BdptVertex next) {
    if (vertexInfinite(next)) return pdf;
    float dist2;
    vec3 w = vertexDirection(v, next, dist2);
    if (!(dist2 > 0.0)) return 0.0;
    pdf /= dist2;
    if (vertexOnSurface(next)) pdf *= abs(dot(next.normal, w));
    return pdf;
}

// The pinhole's importance and the density of its rays (pbrt-v4 PerspectiveCamera::We, PDF_We,
// with a lens of area 1): We = 1 / (A cos^4) and p = 1 / (A cos^3) per unit solid angle for a
// direction through the image (A: the image's area on the plane at distance 1), else 0.
float cameraCosine(vec3 w) { return dot(w, sceneInfo.cameraForward); }
float cameraImageArea() {
    return cameraPixelArea() * float(sceneInfo.width) * float(sceneInfo.height);
}
float cameraDirectionPdf(vec3 w) {
    vec2 raster;
    float c = cameraCosine(w);
    if (!(c > 0.0) || !cameraRasterPosition(w, raster)) return 0.0;
    return 1.0 / (cameraImageArea() * c * c * c);
}

// The shading point of surface vertex v, with wo its recorded direction.
ShadingPoint vertexShading(BdptVertex v) {
    return makeShadingPoint(surfaceAt(v.triangle, v.barycentrics), v.wo);
}

// sh seen from direction wo instead: the side (and so the frame, the geometric normal and what
// the BSDF derives from them) follows wo (shading.glsl makeShadingPoint), without reading the
// material again.
ShadingPoint shadingFrom(ShadingPoint sh, vec3 wo) {
    bool front = dot(sh.surface.normal, wo) > 0.0;
    if (front != sh.front) {
        sh.front = front;
        sh.ng = -sh.ng;
        vec3 coatNormal = toWorld(sh.frame, sh.bsdf.clearcoatNormal);
        sh.frame = frameFromNormal(-sh.frame.n);
        if (sh.bsdf.clearcoatTilted) sh.bsdf.clearcoatNormal = toLocal(sh.frame, coatNormal);
    }
    sh.woLocal = toLocal(sh.frame, wo);
    // What the BSDF derived from wo's side and direction (eta, the clear coat's side, the
    // sheen's albedo at wo) follows it.
    bsdfSetOutgoing(sh.bsdf, front, sh.woLocal);
    return sh;
}

// Solid-angle density with which BSDF sampling at sh, arriving from direction wo, draws wi.
float shadingPdf(ShadingPoint sh, vec3 wo, vec3 wi) {
    ShadingPoint r = shadingFrom(sh, wo);
    vec3 wiLocal = toLocal(r.frame, wi);
    if ((dot(wi, r.ng) > 0.0) != (wiLocal.z > 0.0)) return 0.0;
    return bsdfPdf(r.bsdf, r.woLocal, wiLocal);
}

// The adjoint BSDF at sh (light subpaths, pbrt-v4 TransportMode::Importance) towards wi, times
// the shading normal's correction |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|) (Veach 1997 eq. 5.19): no
// 1 / eta^2 on transmission (bsdf.glsl divides by it for radiance; the non-delta transmission
// is the rough dielectric's, whose eta is the material's, 1 for a thin sheet), and the clear
// coat's adjoint term about its own normal (bsdf.glsl clearcoatNormal; every other lobe is
// symmetric). absCos = |wi.ns|.
vec3 shadingEvalImportance(ShadingPoint sh, vec3 wi, out float absCos) {
    sh.bsdf.adjoint = true;
    float pdf;
    vec3 f = shadingEval(sh, wi, pdf, absCos);
    if (dot(wi, sh.ng) < 0.0) f *= sqr(sh.bsdf.eta);
    float denom = abs(dot(toWorld(sh.frame, sh.woLocal), sh.ng)) * absCos;
    return denom > 0.0 ? f * (abs(sh.woLocal.z) * abs(dot(wi, sh.ng)) / denom) : vec3(0.0);
}

// Solid-angle density of an emitter point's emission towards w (photon_emission.glsl: cosine-
// distributed on its emitting side, either side with probability 1/2 when double-sided).
float emitterDirectionPdf(uint triangle, vec3 normal, vec3 w) {
    Material m = materialAt(triangleAt(triangle).material);
    float c = dot(normal, w);
    if ((m.flags & MATERIAL_DOUBLE_SIDED) != 0u) return 0.5 * abs(c) * INV_PI;
    return max(c, 0.0) * INV_PI;
}

#ifdef PMCR_OTHER_LIGHTS
// Solid-angle density of a point or spot light's emission towards w: uniform on the sphere, or
// in a spot's outer cone.
float punctualDirectionPdf(uint index, vec3 w) {
    PunctualLight l = punctualLightAt(index);
    if (l.type == PUNCTUAL_SPOT)
        return dot(w, l.direction) >= l.cosOuter ? uniformConePdf(l.cosOuter) : 0.0;
    return 0.25 * INV_PI;
}
#endif

// Density with which light v's emission reaches `next` (pbrt-v4 Vertex::PdfLight): an emitting
// surface vertex of a camera subpath counts as its emitter. Infinite lights emit from a disc of
// the scene's radius (photonDiscOrigin), so their density is per unit area of that disc.
float vertexPdfLight(BdptVertex v, BdptVertex next) {
    float dist2;
    vec3 w = vertexDirection(v, next, dist2);
    float pdf;
    if (vertexInfinite(v)) {
        pdf = 1.0 / (PI * sqr(sceneInfo.sceneRadius));
    } else {
        if (!(dist2 > 0.0)) return 0.0;
#ifdef PMCR_OTHER_LIGHTS
        if (v.type == BDPT_LIGHT_POINT)
            pdf = punctualDirectionPdf(v.triangle, w) / dist2;
        else
#endif
            pdf = emitterDirectionPdf(v.triangle, v.normal, w) / dist2;
    }
    if (vertexOnSurface(next)) pdf *= abs(dot(next.normal, w));
    return pdf;
}

// Density with which light sampling picks light vertex v (pbrt-v4 Vertex::PdfLightOrigin): the
// light's selection probability times its density in position (area for an emitter; per unit
// solid angle for the environment; a delta for punctual lights, whose value never enters a
// weight).
float vertexPdfLightOrigin(BdptVertex v) {
#ifdef PMCR_OTHER_LIGHTS
    if (vertexInfinite(v)) {
        if ((v.flags & BDPT_VERTEX_DIRECTIONAL) != 0u || !hasEnvironment()) return 0.0;
        return sceneInfo.envSelectPmf * envPdf(v.wo);
    }
    if (v.type == BDPT_LIGHT_POINT) return punctualLightPmf(v.triangle) * sceneInfo.punctualSelectPmf;
#endif
    return emitterAreaPdf(v.triangle);
}

// Density with which v's subpath, having arrived from `prev` (hasPrev), samples `next`
// (pbrt-v4 Vertex::Pdf). sh is v's shading point when v is a surface.
float vertexPdf(BdptVertex v, ShadingPoint sh, bool hasPrev, BdptVertex prev, BdptVertex next) {
    if (v.type >= BDPT_LIGHT_AREA) return vertexPdfLight(v, next);
    float dist2;
    vec3 wn = vertexDirection(v, next, dist2);
    if (!(dist2 > 0.0)) return 0.0;
    float pdf = 0.0;
    if (v.type == BDPT_CAMERA) {
        pdf = cameraDirectionPdf(wn);
    } else if (hasPrev) {
        float unused;
        pdf = shadingPdf(sh, vertexDirection(v, prev, unused), wn);
    }
    return convertDensity(v, pdf, next);
}

#endif
