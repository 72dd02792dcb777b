// The environment light (--env): radiance arriving from infinitely far, a constant or an
// equirectangular image (host/scene/environment.h has the mapping), and its importance
// sampling: uniform directions for a constant, for an image a pixel by the alias table over
// luminance * sin(theta) then a uniform point of it in (u, v) (pbrt-v4 ImageInfiniteLight, with
// an alias table in place of the piecewise-constant 2-D distribution). The density of a
// direction in pixel i is pmf_i * width * height / (2 pi^2 sin theta), the Jacobian of the
// (u, v) -> direction map being 2 pi^2 sin theta (pbrt-v4 section 12.5.2).
#ifndef PMCR_ENVIRONMENT_GLSL
#define PMCR_ENVIRONMENT_GLSL

#include "common/sampling.glsl"
#include "common/scene.glsl"

layout(set = SCENE_SET, binding = BINDING_ENV_TEXELS) uniform samplerBuffer envTexels;
layout(set = SCENE_SET, binding = BINDING_ENV_ALIAS) uniform usamplerBuffer envAliasTexels;

// Kernels compiled without PMCR_OTHER_LIGHTS (the variants the host picks for scenes lit by
// emitters alone) leave out the environment and the punctual lights: on lavapipe a kernel pays
// for every branch, taken or not (measured: pt 9% fewer samples/s with them compiled in).
bool hasEnvironment() {
#ifdef PMCR_OTHER_LIGHTS
    return sceneInfo.envKind != ENV_NONE;
#else
    return false;
#endif
}

// World direction -> the image's frame: rotated by -envRotation about +y.
vec3 envToLocal(vec3 d) {
    float c = cos(sceneInfo.envRotation);
    float s = sin(sceneInfo.envRotation);
    return vec3(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
}

vec3 envToWorld(vec3 l) {
    float c = cos(sceneInfo.envRotation);
    float s = sin(sceneInfo.envRotation);
    return vec3(c * l.x - s * l.z, l.y, s * l.x + c * l.z);
}

// The pixel a local direction falls in.
uvec2 envPixel(vec3 l) {
    float u = 0.5 + atan(l.x, -l.z) * (0.5 * INV_PI);
    float v = acos(clamp(l.y, -1.0, 1.0)) * INV_PI;
    return min(uvec2(vec2(u, v) * vec2(sceneInfo.envWidth, sceneInfo.envHeight)),
               uvec2(sceneInfo.envWidth - 1u, sceneInfo.envHeight - 1u));
}

uint envPixelIndex(uvec2 p) { return p.y * sceneInfo.envWidth + p.x; }

vec3 envTexel(uvec2 p) {
    return texelFetch(envTexels, int(envPixelIndex(p))).rgb * sceneInfo.envRadiance;
}

// Solid-angle density of a direction at sin(theta) in pixel `pixel` (the header's formula).
float envPixelPdf(uint pixel, float sinTheta) {
    if (!(sinTheta > 0.0)) return 0.0;
    float pmf = uintBitsToFloat(texelFetch(envAliasTexels, int(pixel)).y);
    return pmf * float(sceneInfo.envWidth) * float(sceneInfo.envHeight) / (2.0 * PI * PI * sinTheta);
}

// Radiance arriving along -d, i.e. seen looking in direction d.
vec3 envRadiance(vec3 d) {
    if (sceneInfo.envKind == ENV_CONSTANT) return sceneInfo.envRadiance;
    return envTexel(envPixel(envToLocal(d)));
}

// Solid-angle density of envSample drawing direction d (light selection not included).
float envPdf(vec3 d) {
    if (sceneInfo.envKind == ENV_CONSTANT) return 0.25 * INV_PI;
    vec3 l = envToLocal(d);
    return envPixelPdf(envPixelIndex(envPixel(l)), sqrt(max(0.0, 1.0 - l.y * l.y)));
}

struct EnvSample {
    vec3 wi;     // direction towards the environment
    vec3 Le;     // radiance arriving from it
    float pdf;   // solid-angle density (light selection not included); 0: no sample
};

// A direction drawn with uPixel (the alias table's pick) and uPoint (the point in the pixel).
EnvSample envSample(float uPixel, vec2 uPoint) {
    EnvSample e;
    if (sceneInfo.envKind == ENV_CONSTANT) {
        e.wi = sampleUniformSphere(uPoint);
        e.Le = sceneInfo.envRadiance;
        e.pdf = 0.25 * INV_PI;
        return e;
    }
    uint n = sceneInfo.envWidth * sceneInfo.envHeight;
    uint pixel = aliasTableTriangle(envAliasTexels, 0u, n, uPixel);
    uvec2 p = uvec2(pixel % sceneInfo.envWidth, pixel / sceneInfo.envWidth);
    vec2 uv = (vec2(p) + uPoint) / vec2(sceneInfo.envWidth, sceneInfo.envHeight);
    float phi = (uv.x - 0.5) * TWO_PI;
    float theta = uv.y * PI;
    float sinTheta = sin(theta);
    e.wi = envToWorld(vec3(sinTheta * sin(phi), cos(theta), -sinTheta * cos(phi)));
    e.pdf = envPixelPdf(pixel, sinTheta);
    e.Le = envTexel(p);
    return e;
}

#endif
