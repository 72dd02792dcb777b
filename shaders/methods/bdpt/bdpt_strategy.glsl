// The connection strategies of bidirectional path tracing over one camera sample's subpaths in
// the vertex buffers (Veach 1997 sec. 10.2; pbrt-v4 ConnectBDPT): SampleState walks through the
// strategies (s, t) of a sample, t = 1, 2, ... and s = 0, 1, ... for each, and evaluateStrategy
// gives each one's contribution and MIS weight (bdpt_mis.glsl). The kernel supplies the Sampler
// (the s = 1 light samples are read at bdptConnectDimension), points gCameraBase and gLightBase
// at the sample's subpaths, and decides where the contributions go (bdpt_connect_kernel.glsl,
// pssmlt_bdpt_connect_kernel.glsl). Its push constants have maxDepth.
#ifndef PMCR_BDPT_STRATEGY_GLSL
#define PMCR_BDPT_STRATEGY_GLSL

#include "methods/bdpt/bdpt_mis.glsl"
#include "methods/pt/path_tracer.glsl"

// The light vertex of next-event estimation's sample ls (s = 1): its position or direction and
// the density with which light sampling picks it (vertexPdfLightOrigin).
BdptVertex sampledLightVertex(LightSampleFrom ls) {
    BdptVertex v;
    if (ls.environment) {
        v = bdptVertex(BDPT_LIGHT_INFINITE);
        v.wo = ls.wi;
    } else if (ls.delta) {
#ifdef PMCR_OTHER_LIGHTS
        PunctualLight p = punctualLightAt(ls.punctual);
        if (p.type == PUNCTUAL_DIRECTIONAL) {
            v = bdptVertex(BDPT_LIGHT_INFINITE);
            v.flags = BDPT_VERTEX_DIRECTIONAL;
            v.wo = ls.wi;
        } else {
            v = bdptVertex(BDPT_LIGHT_POINT);
            v.position = p.position;
            v.triangle = ls.punctual;
        }
#else
        v = bdptVertex(BDPT_LIGHT_POINT);
#endif
    } else {
        v = bdptVertex(BDPT_LIGHT_AREA);
        v.position = ls.area.point.position;
        v.normal = ls.area.point.normal;
        v.triangle = ls.area.point.triangle;
        v.barycentrics = ls.area.barycentrics;
    }
    v.pdfFwd = ls.delta ? ls.pdf : ls.environment ? ls.pdf : ls.area.pdfArea;
    return v;
}

// The camera sample whose strategies an invocation is evaluating, and where it is: strategy
// (s, t), with what stays the same along s for its camera vertex t - 1.
struct SampleState {
    uint pixel;
    uvec2 counts;    // camera and light vertices
    uint t;
    uint s;
    Sampler smp;
    Rng rng;         // the splats' rounding
    vec3 L;          // the t >= 2 strategies so far
    float cameraTail;  // bdptMisWeight's tails for (s, t)
    float lightTail;
    BdptVertex pt;     // camera vertex t - 1
    ShadingPoint shPt;
    bool ptConnectible;
    float uLight;      // its s = 1 light sample's numbers
    vec2 uLightPoint;
};

// Moves st to camera vertex st.t - 1 and strategy (0, t).
void beginCameraVertex(inout SampleState st) {
    uint t = st.t;
    if (t >= 4u) st.cameraTail = tailStep(st.cameraTail, cameraVertex(t - 3u), vertexDelta(cameraVertex(t - 4u)));
    st.pt = cameraVertex(t - 1u);
    st.ptConnectible = false;
    if (st.pt.type == BDPT_SURFACE) {
        st.shPt = vertexShading(st.pt);
        st.ptConnectible = bsdfHasNonDelta(st.shPt.bsdf);
    }
    st.smp.dimension = bdptConnectDimension(push.maxDepth) + 2u * (t - 1u);
    st.uLight = samplerGet1D(st.smp);
    st.uLightPoint = samplerGet2D(st.smp);
    st.s = 0u;
    st.lightTail = 0.0;
}

// Moves st from strategy (s, t) to (s + 1, t), light vertex s existing.
void nextLightVertex(inout SampleState st) {
    st.s += 1u;
    if (st.s >= 3u) {
        BdptVertex v = lightVertex(st.s - 3u);
        bool deltaBefore = st.s >= 4u ? vertexDelta(lightVertex(st.s - 4u)) : vertexDeltaLight(v);
        st.lightTail = tailStep(st.lightTail, v, deltaBefore);
    }
}

// Moves st to its next strategy: s + 1, else the next camera vertex; false when none is left.
bool nextStrategy(inout SampleState st) {
    if (st.s + 1u > st.counts.y || st.s + 1u + st.t > push.maxDepth + 2u) {
        st.t += 1u;
        if (st.t > st.counts.x) return false;
        beginCameraVertex(st);
        return true;
    }
    nextLightVertex(st);
    return true;
}

// Starts st at strategy (0, 1) of its sample, then moves it to strategy (s, t), whose camera
// vertices 0 .. t - 1 and light vertices 0 .. s - 1 exist (mmlt: one strategy a sample).
void beginStrategy(inout SampleState st, uint s, uint t) {
    st.L = vec3(0.0);
    st.cameraTail = 0.0;
    st.t = 1u;
    beginCameraVertex(st);
    while (st.t < t) {
        st.t += 1u;
        beginCameraVertex(st);
    }
    while (st.s < s) nextLightVertex(st);
}

// Strategy (st.s, st.t): its unweighted contribution c and MIS weight w, and the pixel it lands
// on: the camera sample's (t >= 2) or the one light vertex s - 1 is seen through (t = 1). False
// when it contributes nothing.
bool evaluateStrategy(inout SampleState st, inout uint rays, out vec3 c, out float w, out uint target) {
    c = vec3(0.0);
    w = 0.0;
    target = st.pixel;
    uint s = st.s;
    uint t = st.t;
    if (s + t < 2u || (s == 1u && t == 1u)) return false;
    ShadingPoint none;
    if (s == 0u) {
        // The camera subpath found a light.
        if (st.pt.type == BDPT_LIGHT_INFINITE)
            c = st.pt.beta * envRadiance(st.pt.wo);
        else if (st.pt.type == BDPT_SURFACE)
            c = st.pt.beta * emittedRadiance(st.shPt.surface, st.pt.wo);
        if (maxComponent(c) > 0.0) w = bdptMisWeight(0u, t, st.pt, none, st.pt, st.shPt, st.cameraTail, st.lightTail);
    } else if (t == 1u) {
        // Light tracing: light vertex s - 1 seen by the pinhole, We cos / d^2
        // (pbrt-v4 PerspectiveCamera::SampleWi with a lens of area 1).
        BdptVertex qs = lightVertex(s - 1u);
        if (qs.type != BDPT_SURFACE) return false;
        ShadingPoint shQs = vertexShading(qs);
        if (!bsdfHasNonDelta(shQs.bsdf)) return false;
        vec3 toCamera = sceneInfo.cameraPosition - qs.position;
        float dist2 = dot(toCamera, toCamera);
        vec3 wCamera = toCamera * inversesqrt(dist2);
        vec2 raster;
        float cosCamera = cameraCosine(-wCamera);
        if (!(cosCamera > 0.0) || !cameraRasterPosition(-wCamera, raster)) return false;
        target = min(uint(raster.y), sceneInfo.height - 1u) * sceneInfo.width +
                 min(uint(raster.x), sceneInfo.width - 1u);
        float absCos;
        vec3 f = shadingEvalImportance(shQs, wCamera, absCos);
        float We = 1.0 / (cameraImageArea() * sqr(sqr(cosCamera)));
        c = qs.beta * f * absCos * We * cosCamera / dist2;
        if (maxComponent(c) > 0.0) {
            rays += 1u;
            ShadowRay r = shadowSegment(spawnOrigin(shQs, wCamera), sceneInfo.cameraPosition);
            if (traceAny(r.origin, r.dir, r.tMax)) c = vec3(0.0);
        }
        if (maxComponent(c) > 0.0) w = bdptMisWeight(s, 1u, qs, shQs, cameraVertex(0u), none, st.cameraTail, st.lightTail);
    } else if (s == 1u) {
        // Next-event estimation from camera vertex t - 1.
        if (!st.ptConnectible) return false;
        LightSampleFrom ls = sampleLightFrom(st.shPt, st.uLight, st.uLightPoint);
        if (!(maxComponent(ls.Le) > 0.0) || !(ls.pdf > 0.0)) return false;
        float pdfBsdf, absCos;
        vec3 f = shadingEval(st.shPt, ls.wi, pdfBsdf, absCos);
        c = st.pt.beta * f * absCos * ls.Le / ls.pdf;
        if (maxComponent(c) > 0.0) {
            rays += 1u;
            if (traceAny(ls.ray.origin, ls.ray.dir, ls.ray.tMax)) c = vec3(0.0);
        }
        if (maxComponent(c) > 0.0)
            w = bdptMisWeight(1u, t, sampledLightVertex(ls), none, st.pt, st.shPt, st.cameraTail, st.lightTail);
    } else {
        // Light vertex s - 1 and camera vertex t - 1 joined by a shadow ray.
        if (!st.ptConnectible) return false;
        BdptVertex qs = lightVertex(s - 1u);
        if (qs.type != BDPT_SURFACE) return false;
        ShadingPoint shQs = vertexShading(qs);
        if (!bsdfHasNonDelta(shQs.bsdf)) return false;
        vec3 d = qs.position - st.pt.position;
        float dist2 = dot(d, d);
        if (!(dist2 > 0.0)) return false;
        vec3 w1 = d * inversesqrt(dist2);
        float pdfBsdf, cosPt, cosQs;
        vec3 fPt = shadingEval(st.shPt, w1, pdfBsdf, cosPt);
        vec3 fQs = shadingEvalImportance(shQs, -w1, cosQs);
        c = qs.beta * fQs * fPt * st.pt.beta * (cosPt * cosQs / dist2);
        if (maxComponent(c) > 0.0) {
            rays += 1u;
            ShadowRay r = shadowSegment(spawnOrigin(st.shPt, w1), spawnOrigin(shQs, -w1));
            if (traceAny(r.origin, r.dir, r.tMax)) c = vec3(0.0);
        }
        if (maxComponent(c) > 0.0) w = bdptMisWeight(s, t, qs, shQs, st.pt, st.shPt, st.cameraTail, st.lightTail);
    }
    return maxComponent(c) > 0.0;
}

#endif
