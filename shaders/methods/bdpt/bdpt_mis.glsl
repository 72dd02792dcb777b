// The MIS weights of bidirectional path tracing's strategies (bdpt_connect_kernel.glsl), over
// the subpaths of one camera sample in the vertex buffers (bdpt_vertex.glsl): the caller points
// gCameraBase and gLightBase at them. tests/gpu/test_bdpt_mis.cpp checks that the weights of
// all the strategies that make one path sum to 1, and equal the plain sum over vertices.
#ifndef PMCR_BDPT_MIS_GLSL
#define PMCR_BDPT_MIS_GLSL

#include "common/kernel_options.glsl"
#include "methods/bdpt/bdpt_vertex.glsl"

uint gCameraBase;
uint gLightBase;
BdptVertex cameraVertex(uint i) { return cameraVertices[gCameraBase + i]; }
BdptVertex lightVertex(uint i) { return lightVertices[gLightBase + i]; }

float remap0(float f) { return f != 0.0 ? f : 1.0; }
// A ratio of densities p_i / p_s as it enters the weight: squared for the power heuristic
// (w_s = p_s^2 / sum_i p_i^2), as is for the balance heuristic (--mis balance).
float misTerm(float r) { return balanceHeuristicMis() ? r : r * r; }

// The MIS weight of strategy (s, t) for the path it made (Veach 1997 sec. 10.2.1; pbrt-v4
// BDPTIntegrator MISWeight): w = 1 / (1 + sum over the other strategies i of (p_i / p_s)^k),
// the ratios built vertex by vertex from the forward and reverse densities recorded along both
// subpaths, with the densities at the four vertices around the connection evaluated for this
// path, and no strategy that would have to connect at a delta vertex or hit a delta light.
// qs (with shQs) is the light end (the sampled light for s = 1), pt (shPt) the camera end.
//
// Only the two vertices next to the connection on each side have densities of this path's own;
// beyond them the terms are the recorded ones, whose sums the caller keeps as it steps through
// t and s (cameraTail, lightTail: see tailStep), so a weight costs O(1) instead of O(s + t).
// With r_i = rev_i / fwd_i and m_i = 1 when neither vertex i nor the one before it is a delta,
// the camera side's terms below vertex t - 2 sum to k(r_{t-1} r_{t-2}) * cameraTail(t),
// cameraTail(t) = sum_{i=1}^{t-3} m_i prod_{j=i}^{t-3} k(r_j), and likewise for the light side
// from vertex 0 (k: misTerm, multiplicative for both heuristics).
float bdptMisWeight(uint s, uint t, BdptVertex qs, ShadingPoint shQs, BdptVertex pt, ShadingPoint shPt,
                    float cameraTail, float lightTail) {
    if (s + t == 2u) return 1.0;
    bool hasQsMinus = s > 1u;
    bool hasPtMinus = t > 1u;
    BdptVertex qsMinus = hasQsMinus ? lightVertex(s - 2u) : bdptVertex(BDPT_CAMERA);
    BdptVertex ptMinus = hasPtMinus ? cameraVertex(t - 2u) : bdptVertex(BDPT_CAMERA);
    float ptRev = s > 0u ? vertexPdf(qs, shQs, hasQsMinus, qsMinus, pt) : vertexPdfLightOrigin(pt);
    float ptMinusRev = 0.0;
    if (hasPtMinus)
        ptMinusRev = s > 0u ? vertexPdf(pt, shPt, true, qs, ptMinus) : vertexPdfLight(pt, ptMinus);
    float qsRev = s > 0u ? vertexPdf(pt, shPt, hasPtMinus, ptMinus, qs) : 0.0;
    float qsMinusRev = hasQsMinus ? vertexPdf(qs, shQs, true, pt, qsMinus) : 0.0;

    float sum = 0.0;
    // Strategies with fewer camera vertices: camera vertex i >= 1 sampled by the light subpath
    // (pt itself counts as no delta: it is connected).
    if (t >= 2u) {
        float r1 = remap0(ptRev) / remap0(pt.pdfFwd);
        if (!vertexDelta(ptMinus)) sum += misTerm(r1);
        if (t >= 3u) {
            float r2 = r1 * remap0(ptMinusRev) / remap0(ptMinus.pdfFwd);
            bool deltaBefore = (cameraVertices[gCameraBase + t - 3u].flags & BDPT_VERTEX_DELTA) != 0u;
            if (!vertexDelta(ptMinus) && !deltaBefore) sum += misTerm(r2);
            sum += misTerm(r2) * cameraTail;
        }
    }
    // Strategies with fewer light vertices: light vertex i sampled by the camera subpath.
    if (s >= 1u) {
        float r1 = remap0(qsRev) / remap0(qs.pdfFwd);
        if (!(hasQsMinus ? vertexDelta(qsMinus) : vertexDeltaLight(qs))) sum += misTerm(r1);
        if (hasQsMinus) {
            float r2 = r1 * remap0(qsMinusRev) / remap0(qsMinus.pdfFwd);
            bool deltaBefore = s >= 3u ? (lightVertices[gLightBase + s - 3u].flags & BDPT_VERTEX_DELTA) != 0u
                                       : vertexDeltaLight(qsMinus);
            if (!vertexDelta(qsMinus) && !deltaBefore) sum += misTerm(r2);
            sum += misTerm(r2) * lightTail;
        }
    }
    return 1.0 / (1.0 + sum);
}

// One step of a tail sum of bdptMisWeight: the tail with vertex v (recorded densities) added
// below it, tail' = k(r_v) (tail + m_v), where deltaBefore tells whether the vertex before v (or
// v's light, for light vertex 0) is a delta.
float tailStep(float tail, BdptVertex v, bool deltaBefore) {
    float m = !vertexDelta(v) && !deltaBefore ? 1.0 : 0.0;
    return misTerm(remap0(v.pdfRev) / remap0(v.pdfFwd)) * (tail + m);
}

#endif
