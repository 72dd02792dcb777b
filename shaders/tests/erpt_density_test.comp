#version 460
// Test kernel for the densities of ERPT's mutations (tests/gpu/test_erpt_densities.cpp): runs the
// renderer's own mutateLens / mutateCaustic and path-space factors on recorded paths.
//   mode 0 (lens proposals): invocation i copies the template path (binding 1) into its chain's
//          slot 0, proposes y into slot 1 and writes
//          results[4i]   = (rasterY, valid, transitionRatio)
//          results[4i+1] = (targetX, targetY, y1 position.x, .y)   [y1 = the new x1]
//          results[4i+2] = (y1 position.z, rasterDensity(y1), rasterDensity(x1), 0)
//          results[4i+3] = (x1 position, y1's triangle)
//   mode 1 (caustic proposals): the same with mutateCaustic, and
//          results[4i+1] = (theta drawn, phi drawn, thetaMax(x), thetaMax(y) or 0)
//          results[4i+2] = (unit direction head -> y_h-1, valid)
//          results[4i+3] = (unit direction head -> x_h-1 (the centre), h)
//          With a mixture, the component is drawn first (alpha_j = mixtureWeights) and
//          results[4i+1].zw = (thetaMax(x), thetaMax(y)) per unit theta(d), uncapped.
//   mode 2 (Jacobians by finite differences): invocation j takes path j at chain j, slot 0
//          (binding 5), with (k, h) = pathInfo[j], and writes results[64j ...]:
//          [0]  (rasterDensity(x1), reconnectionFactor(x1, x2), |cos_s(x1 -> x2)|, causticGamma)
//          [1]  (raster of x1, eps, epsAngle)
//          [2..5]  raster of x1 + s eps t_a, (s, a) = (+,1) (-,1) (+,2) (-,2), t the x1 tangents
//          [6..9]  unit direction x1 -> x2 + s eps t_a, t the tangents at x2
//          [10..27] (raster of x1', valid) and (x1' -> x2' direction) after retracing the specular
//                   chain from the head moved by +-eps along its tangents, or its direction
//                   turned by +-epsAngle towards its basis vectors, then the unperturbed one.
//                   At a point light head "its tangents" span the plane normal to the
//                   direction x_h -> x_h-1, so the determinant is Gamma / |cos_s(x1 -> x2)| with
//                   no |cos_g| at the head, what causticGamma has there (path_space.glsl).
// Compiled with the other lights (punctual, environment): scenes without them read the same.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#define PMCR_OTHER_LIGHTS
#include "shared/host_device.h"

#include "methods/energy_redistribution/mutate_caustic.glsl"
#include "methods/energy_redistribution/mutate_lens.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(set = WORK_SET, binding = 0, scalar) writeonly buffer Results { vec4 results[]; };
layout(set = WORK_SET, binding = 1, scalar) readonly buffer Template { ChainVertex templateVertices[]; };
layout(set = WORK_SET, binding = 2, scalar) readonly buffer PathInfo { uvec2 pathInfo[]; };
layout(push_constant, scalar) uniform Push {
    uint mode;
    uint count;
    uint seed;
    uint k;              // modes 0, 1: vertices of the template path
    vec2 raster;         // modes 0, 1: its raster position
    float lensRadius;
    float thetaMin;
    float thetaMax;
    uint uniformLaw;
    float eps;           // mode 2: position step (scene units)
    float epsAngle;      // mode 2: direction step (radians)
    uint mixtureCount;   // mode 1, uniform law: a mixture over theta(d_j) (PMC-ER eq. 8), 0: none
    vec3 mixtureWeights;
    vec3 mixtureThetas;
    uint pad;
} push;

// Retraces the specular chain x_h-1 .. x2 from a ray leaving the head at `headPosition` with
// geometric normal `headNormal` along `dir`, as mutateCaustic does, to the new x1: its raster
// position and the unit direction x1 -> x2. False on a miss or a lost specular lobe.
bool retraceToEye(uint base, uint h, vec3 headPosition, vec3 headNormal, vec3 dir,
                  out vec2 raster, out vec3 w12) {
    raster = vec2(-1.0);
    w12 = vec3(0.0);
    uint rays = 0u;
    vec3 origin = vertexPunctual(chainVertices[base + h])
                      ? headPosition
                      : offsetRayOrigin(headPosition, dot(dir, headNormal) > 0.0 ? headNormal : -headNormal);
    SurfacePoint s;
    for (int i = int(h) - 1; i >= 0; --i) {
        vec2 b;
        if (!traceToSurface(origin, dir, rays, s, b)) return false;
        if (i > 0 && !followSpecular(s, dir, chainVertices[base + uint(i)], dir, origin)) return false;
    }
    w12 = -dir;
    vec3 toX1 = s.position - sceneInfo.cameraPosition;
    cameraRasterPosition(normalize(toX1), raster);
    return true;
}

void jacobians(uint j) {
    uint base = pathBase(j, 0u);
    uint h = pathInfo[j].y;
    uint o = 64u * j;
    SurfacePoint x1 = pathPoint(base, 0u);
    SurfacePoint x2 = pathPoint(base, 1u);
    vec3 toEye = normalize(sceneInfo.cameraPosition - x1.position);
    ShadingPoint sh1 = makeShadingPoint(x1, toEye);
    float cosS12 = abs(dot(sh1.frame.n, normalize(x2.position - x1.position)));
    results[o] = vec4(rasterDensity(x1), reconnectionFactor(x1, toEye, x2), cosS12,
                      h > 0u ? causticGamma(base, h) : 0.0);
    vec2 r;
    cameraRasterPosition(normalize(x1.position - sceneInfo.cameraPosition), r);
    results[o + 1u] = vec4(r, push.eps, push.epsAngle);

    vec3 t[2];
    orthonormalBasis(x1.normal, t[0], t[1]);
    for (uint m = 0u; m < 4u; ++m) {
        vec3 p = x1.position + (m % 2u == 0u ? 1.0 : -1.0) * push.eps * t[m / 2u];
        cameraRasterPosition(normalize(p - sceneInfo.cameraPosition), r);
        results[o + 2u + m] = vec4(r, 0.0, 0.0);
    }
    orthonormalBasis(x2.normal, t[0], t[1]);
    for (uint m = 0u; m < 4u; ++m) {
        vec3 p = x2.position + (m % 2u == 0u ? 1.0 : -1.0) * push.eps * t[m / 2u];
        results[o + 6u + m] = vec4(normalize(p - x1.position), 0.0);
    }
    if (h == 0u) return;

    SurfacePoint head = pathPoint(base, h);
    vec3 center = normalize(pathPoint(base, h - 1u).position - head.position);
    vec3 tHead[2], tDir[2];
    orthonormalBasis(vertexPunctual(chainVertices[base + h]) ? center : head.normal, tHead[0], tHead[1]);
    orthonormalBasis(center, tDir[0], tDir[1]);
    for (uint m = 0u; m < 9u; ++m) {
        float s = m % 2u == 0u ? 1.0 : -1.0;
        vec3 position = head.position;
        vec3 dir = center;
        if (m < 4u) position += s * push.eps * tHead[m / 2u];
        else if (m < 8u) dir = normalize(center + s * push.epsAngle * tDir[(m - 4u) / 2u]);
        vec3 w12;
        bool ok = retraceToEye(base, h, position, head.normal, dir, r, w12);
        results[o + 10u + 2u * m] = vec4(r, ok ? 1.0 : 0.0, 0.0);
        results[o + 11u + 2u * m] = vec4(w12, 0.0);
    }
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    if (push.mode == 2u) {
        jacobians(i);
        return;
    }
    uint xBase = pathBase(i, 0u);
    uint yBase = pathBase(i, 1u);
    for (uint v = 0u; v < push.k; ++v) chainVertices[xBase + v] = templateVertices[v];
    vec3 throughputX = pathThroughput(xBase, push.k);
    Rng rng = rngCreate(hashCombine(i, push.seed));
    AngleSampler angle = angleSampler(push.thetaMin, push.thetaMax, push.uniformLaw != 0u);
    uint rays = 0u;
    MutationResult r;
    bool valid;
    if (push.mode == 0u) {
        valid = mutateLens(xBase, yBase, push.k, push.raster, throughputX, push.lensRadius, angle,
                           rng, rays, r);
        vec3 y1 = pathPoint(yBase, 0u).position;
        results[4u * i] = vec4(r.rasterY, valid ? 1.0 : 0.0, r.transitionRatio);
        results[4u * i + 1u] = vec4(r.targetX, r.targetY, y1.xy);
        results[4u * i + 2u] = vec4(y1.z, valid ? rasterDensity(pathPoint(yBase, 0u)) : 0.0,
                                    rasterDensity(pathPoint(xBase, 0u)), 0.0);
        results[4u * i + 3u] = vec4(pathPoint(xBase, 0u).position, float(chainVertices[yBase].triangle));
        return;
    }
    if (push.mixtureCount > 0u) {
        // The component, by its weight; mutateCaustic gets the whole mixture.
        float u = rngNext(rng);
        uint j = 0u;
        for (; j + 1u < push.mixtureCount && u >= push.mixtureWeights[j]; ++j) u -= push.mixtureWeights[j];
        angle.thetaMax = push.mixtureThetas[j];
        angle.mixtureCount = push.mixtureCount;
        angle.mixtureWeights = push.mixtureWeights;
        angle.mixtureThetas = push.mixtureThetas;
    }
    // The angles mutateCaustic draws: its first two random numbers.
    Rng drawn = rng;
    uint h = causticHead(xBase, push.k);
    AngleSampler law = angle;
    float thetaMaxX = 0.0;
    if (angle.uniformLaw) {
        thetaMaxX = causticThetaMax(xBase, h, angle.thetaMax);
        law.thetaMax = thetaMaxX;
    }
    vec2 u = rngNext2(drawn);
    valid = mutateCaustic(xBase, yBase, push.k, throughputX, angle, rng, rays, r);
    SurfacePoint head = pathPoint(xBase, h);
    vec3 toY = normalize(pathPoint(yBase, h - 1u).position - head.position);
    vec3 toX = normalize(pathPoint(xBase, h - 1u).position - head.position);
    float thetaMaxY = valid && angle.uniformLaw ? causticThetaMax(yBase, h, angle.thetaMax) : 0.0;
    results[4u * i] = vec4(r.rasterY, valid ? 1.0 : 0.0, r.transitionRatio);
    if (push.mixtureCount > 0u) {
        const float unit = 1e-4;  // small enough for the pi / 2 cap not to apply
        thetaMaxX = causticThetaMax(xBase, h, unit) / unit;
        thetaMaxY = valid ? causticThetaMax(yBase, h, unit) / unit : 0.0;
    }
    results[4u * i + 1u] = vec4(sampleTheta(law, u.x), TWO_PI * u.y, thetaMaxX, thetaMaxY);
    results[4u * i + 2u] = vec4(toY, valid ? 1.0 : 0.0);
    results[4u * i + 3u] = vec4(toX, float(h));
}
