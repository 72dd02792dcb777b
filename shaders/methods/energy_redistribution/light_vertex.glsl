// The light vertex x_k of a light path in a chain (ERPT, PMC-ER): the point of an emitter
// triangle, or, in kernels compiled with PMCR_OTHER_LIGHTS, a punctual light or the environment
// (shared/path_types.h VERTEX_PUNCTUAL, VERTEX_ENVIRONMENT). What the path-space factors need
// of it: where it is seen from a point, what it emits there, and the measure it lives in.
//
// Measures (what replaces dA(x_k) in the path measure, Veach 1997 sec. 8.1):
//  - an emitter point: area, dA(x_k);
//  - a point or spot light: a position with no area (a delta in position). Its "Le dA" is
//    I(w) delta(x_k - p): the path's contribution carries I(w) / d^2 in place of
//    Le |cos_g(x_k)| / d^2 dA, so P takes the radiant intensity I(w) (times the spot falloff)
//    and the geometric factor of the segment into the light loses |cos_g(x_k)|, keeping the
//    1 / d^2 (pbrt-v4 PointLight::SampleLi: Li = I / d^2);
//  - the environment: a direction w, in solid angle dw. The segment into it is a direction from
//    x_k-1, so its geometric factor is |cos_s(x_k-1, w)| alone (no 1 / d^2, no cos at the light),
//    and P takes L_env(w);
//  - a directional light: a fixed direction (a delta in direction), P takes its irradiance E
//    and the segment factor is |cos_s(x_k-1, w)| as for the environment.
// These factors are reconnectionFactor's and causticGamma's (path_space.glsl, mutate_caustic.glsl).
// The code that handles these light vertices sits in #ifdef PMCR_OTHER_LIGHTS blocks, so that the
// kernels for emitters alone are the code they were (measured: with the branches folded only at
// run time, the chain kernel's SPIR-V grew by 40%).
#ifndef PMCR_LIGHT_VERTEX_GLSL
#define PMCR_LIGHT_VERTEX_GLSL

#include "common/lights.glsl"
#include "common/octahedral.glsl"

bool vertexPunctual(ChainVertex v) { return hasPunctualLights() && (v.flags & VERTEX_PUNCTUAL) != 0u; }
bool vertexEnvironment(ChainVertex v) { return hasEnvironment() && (v.flags & VERTEX_ENVIRONMENT) != 0u; }

// A light vertex that is a direction (the environment, a directional light), not a position.
bool vertexIsDirection(ChainVertex v) {
    return vertexEnvironment(v) ||
           (vertexPunctual(v) && punctualLightAt(v.triangle).type == PUNCTUAL_DIRECTIONAL);
}

// The unit direction towards a direction vertex, from anywhere.
vec3 vertexDirection(ChainVertex v) {
    if (vertexEnvironment(v)) return octDecode(vec2(v.b1, v.b2));
    return -punctualLightAt(v.triangle).direction;
}

// A light vertex that is not on a surface as a SurfacePoint: a point or spot light's position
// with a zero normal; a direction vertex has no position (its fields are zero and unused).
SurfacePoint lightVertexPoint(ChainVertex v) {
    SurfacePoint s;
    s.position = vec3(0.0);
    if (vertexPunctual(v)) {
        PunctualLight l = punctualLightAt(v.triangle);
        if (l.type != PUNCTUAL_DIRECTIONAL) s.position = l.position;
    }
    s.normal = vec3(0.0);
    s.shadingNormal = vec3(0.0);
    s.uv = vec2(0.0);
    s.triangle = v.triangle;
    s.material = 0u;
    return s;
}

// What light vertex v (at s) sends towards `previous`, the vertex before it: Le for an emitter
// point, the intensity I (times the spot falloff) for a point or spot light, E for a directional
// light, L_env for the environment (the header's measures).
vec3 lightVertexEmission(ChainVertex v, SurfacePoint s, vec3 previous) {
#ifdef PMCR_OTHER_LIGHTS
    if (vertexEnvironment(v)) return envRadiance(vertexDirection(v));
    if (vertexPunctual(v)) {
        PunctualLight l = punctualLightAt(v.triangle);
        if (l.type == PUNCTUAL_DIRECTIONAL) return l.intensity;
        if (l.type == PUNCTUAL_SPOT)
            return l.intensity * spotFalloff(l, dot(normalize(previous - l.position), l.direction));
        return l.intensity;
    }
#endif
    return emittedRadiance(s, normalize(previous - s.position));
}

#endif
