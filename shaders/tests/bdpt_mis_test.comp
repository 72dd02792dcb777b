#version 460
// The MIS weights of bidirectional path tracing (methods/bdpt/bdpt_mis.glsl) on real paths: for
// each camera subpath written by bdpt_subpaths (same push constants, one sample per pixel of a
// pass) and each of its vertices x_k that is on a light (an emitter seen from x_k-1, or the
// environment), the path x_0 .. x_k is split every way (s, t), s + t = k + 1, its last s
// vertices reversed into a light subpath with the densities a light walk would have recorded
// (Veach 1997 sec. 10.2; pbrt-v4 Vertex pdfFwd / pdfRev); the weights of the strategies that
// can make it (none joins at a delta vertex; (1, 1) is not one) must sum to 1, and each must
// equal the weight summed plainly over the vertices (referenceWeight), the definition that
// bdptMisWeight's tails shorten. results[sample * resultStride + k] = (sum of the weights,
// largest |weight - reference|, strategies, 1); w = 0 where x_k is not on a light.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#define PMCR_OTHER_LIGHTS
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { BdptPush push; };

#include "methods/bdpt/bdpt_mis.glsl"

layout(set = WORK_SET, binding = 9, scalar) writeonly buffer ResultBuffer { vec4 results[]; };

// The weight of (s, t) summed over every vertex, as pbrt-v4's MISWeight does it.
float referenceWeight(uint s, uint t, BdptVertex qs, ShadingPoint shQs, BdptVertex pt, ShadingPoint shPt) {
    if (s + t == 2u) return 1.0;
    bool hasQsMinus = s > 1u;
    bool hasPtMinus = t > 1u;
    BdptVertex qsMinus = hasQsMinus ? lightVertex(s - 2u) : bdptVertex(BDPT_CAMERA);
    BdptVertex ptMinus = hasPtMinus ? cameraVertex(t - 2u) : bdptVertex(BDPT_CAMERA);
    float ptRev = s > 0u ? vertexPdf(qs, shQs, hasQsMinus, qsMinus, pt) : vertexPdfLightOrigin(pt);
    float ptMinusRev = 0.0;
    if (hasPtMinus) ptMinusRev = s > 0u ? vertexPdf(pt, shPt, true, qs, ptMinus) : vertexPdfLight(pt, ptMinus);
    float qsRev = s > 0u ? vertexPdf(pt, shPt, hasPtMinus, ptMinus, qs) : 0.0;
    float qsMinusRev = hasQsMinus ? vertexPdf(qs, shQs, true, pt, qsMinus) : 0.0;
    float sum = 0.0;
    float ri = 1.0;
    for (uint i = t - 1u; i > 0u; --i) {
        BdptVertex v = i == t - 1u ? pt : cameraVertex(i);
        float rev = i == t - 1u ? ptRev : i + 2u == t ? ptMinusRev : v.pdfRev;
        ri *= remap0(rev) / remap0(v.pdfFwd);
        bool delta = i != t - 1u && vertexDelta(v);
        if (!delta && !vertexDelta(cameraVertex(i - 1u))) sum += misTerm(ri);
    }
    ri = 1.0;
    for (uint k = 0u; k < s; ++k) {
        uint i = s - 1u - k;
        BdptVertex v = i == s - 1u ? qs : lightVertex(i);
        float rev = i == s - 1u ? qsRev : i + 2u == s ? qsMinusRev : v.pdfRev;
        ri *= remap0(rev) / remap0(v.pdfFwd);
        bool delta = i != s - 1u && vertexDelta(v);
        bool deltaBefore = i > 0u ? vertexDelta(lightVertex(i - 1u)) : vertexDeltaLight(v);
        if (!delta && !deltaBefore) sum += misTerm(ri);
    }
    return 1.0 / (1.0 + sum);
}

// bdptMisWeight's tails, from their definitions.
float cameraTailOf(uint t) {
    float tail = 0.0;
    for (uint i = 4u; i <= t; ++i) tail = tailStep(tail, cameraVertex(i - 3u), vertexDelta(cameraVertex(i - 4u)));
    return tail;
}
float lightTailOf(uint s) {
    float tail = 0.0;
    for (uint i = 3u; i <= s; ++i) {
        BdptVertex v = lightVertex(i - 3u);
        tail = tailStep(tail, v, i >= 4u ? vertexDelta(lightVertex(i - 4u)) : vertexDeltaLight(v));
    }
    return tail;
}

// Whether vertex v (with sh) can be joined by a shadow ray: a surface with a non-delta lobe.
bool connectible(BdptVertex v, ShadingPoint sh) { return v.type == BDPT_SURFACE && bsdfHasNonDelta(sh.bsdf); }

void main() {
    uint sampleIndex = gl_GlobalInvocationID.x;
    if (sampleIndex >= push.count) return;
    uint resultStride = push.cameraStride;
    gCameraBase = sampleIndex * push.cameraStride;
    uint nc = vertexCounts[sampleIndex].x;
    for (uint k = 0u; k < push.cameraStride; ++k) results[sampleIndex * resultStride + k] = vec4(0.0);
    for (uint k = 2u; k < nc && k <= push.maxDepth + 1u; ++k) {
        // x_k on a light, seen from x_k-1?
        BdptVertex xk = cameraVertex(k);
        BdptVertex light;
        if (xk.type == BDPT_LIGHT_INFINITE) {
            light = xk;
        } else {
            if (maxComponent(emittedRadiance(surfaceAt(xk.triangle, xk.barycentrics), xk.wo)) <= 0.0) continue;
            light = xk;
            light.type = BDPT_LIGHT_AREA;
            light.flags = 0u;
        }
        // Its last vertices reversed: light vertex j is x_k-j, in this sampleIndex's light slot.
        gLightBase = sampleIndex * push.lightStride;
        uint maxS = min(k, push.lightStride);
        light.pdfFwd = vertexPdfLightOrigin(light);
        light.pdfRev = xk.pdfFwd;
        lightVertices[gLightBase] = light;
        for (uint j = 1u; j < maxS; ++j) {
            BdptVertex v = cameraVertex(k - j);
            BdptVertex towardsLight = cameraVertex(k - j + 1u);
            float unused;
            v.wo = j == 1u ? vertexDirection(v, light, unused) : vertexDirection(v, towardsLight, unused);
            v.pdfRev = v.pdfFwd;  // from x_k-j-1, the camera's side
            v.pdfFwd = j == 1u ? vertexPdfLight(light, v) : cameraVertex(k - j).pdfRev;
            lightVertices[gLightBase + j] = v;
        }
        float sum = 0.0;
        float worst = 0.0;
        uint strategies = 0u;
        for (uint t = 1u; t <= k + 1u; ++t) {
            uint s = k + 1u - t;
            if (s > maxS || (s == 1u && t == 1u)) continue;
            ShadingPoint none;
            BdptVertex pt = cameraVertex(t - 1u);
            ShadingPoint shPt;
            if (pt.type == BDPT_SURFACE) shPt = vertexShading(pt);
            BdptVertex qs = s > 0u ? lightVertex(s - 1u) : pt;
            ShadingPoint shQs;
            if (s > 1u) shQs = vertexShading(qs);
            // Can strategy (s, t) make this path?
            bool possible = s == 0u || (t == 1u ? connectible(qs, shQs)
                                        : s == 1u ? connectible(pt, shPt) && !vertexDeltaLight(qs)
                                                  : connectible(qs, shQs) && connectible(pt, shPt));
            if (!possible) continue;
            if (t == 1u) pt = cameraVertex(0u);
            float w = bdptMisWeight(s, t, qs, shQs, pt, shPt, cameraTailOf(t), lightTailOf(s));
            float reference = referenceWeight(s, t, qs, shQs, pt, shPt);
            sum += w;
            worst = max(worst, abs(w - reference));
            strategies += 1u;
        }
        results[sampleIndex * resultStride + k] = vec4(sum, worst, float(strategies), 1.0);
    }
}
