// The path of a primary vector (PSSMLT): its first two coordinates place the camera sample
// anywhere on the image, u * (width, height); the rest drive the path tracer
// (methods/pt/path_tracer.glsl, included before this file with the kernel's Sampler).
#ifndef PMCR_PSS_PATH_GLSL
#define PMCR_PSS_PATH_GLSL

vec2 pssRaster(inout Sampler s) {
    vec2 size = vec2(sceneInfo.width, sceneInfo.height);
    return min(samplerGet2D(s) * size, size * ONE_MINUS_EPSILON);
}

uint pssPixel(vec2 raster) { return uint(raster.y) * sceneInfo.width + uint(raster.x); }

// The target function F(u) = lum(L(u)) (Kelemen et al. 2002 sec. 4: the luminance of the
// contribution), 0 for a non-finite estimate, which the caller counts as dropped.
float pssTarget(vec3 L) { return isFinite(L) ? max(luminance(L), 0.0) : 0.0; }

#endif
