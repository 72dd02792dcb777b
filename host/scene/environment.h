// The environment light (--env): what the command line names, how it is loaded, and the tables
// the kernels sample it with (shaders/common/environment.glsl).
//
// Directions map to the equirectangular image as in the kernels: with d rotated by -rotation
// about +y, u = 1/2 + atan2(d.x, -d.z) / (2 pi) (the image's centre column looks down -z, the
// glTF camera's default view) and v = acos(d.y) / pi (top row +y). Radiance is constant over a
// pixel (no filtering), so the pixel distribution below is exactly the density the kernels draw.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace pmcr {

// --env VALUE [--env-rotate DEGREES] [--env-scale S]. VALUE is "R,G,B" (a constant radiance)
// or an HDR image file (.exr, .pfm, or Radiance .hdr).
struct EnvironmentSpec {
    std::string value;           // empty: no environment light
    float rotateDegrees = 0.0f;
    float scale = 1.0f;
};

// Loads what `spec` names; throws pmcr::Error "<file or value>: <problem>" for a missing or
// unreadable file, a malformed value (R,G,B are decimal numbers), negative, NaN or infinite
// radiance, or radiance that overflows 32-bit floats once scaled by --env-scale. When `folder`
// is not empty (--restrict-paths), an image outside it is refused.
Environment loadEnvironment(const EnvironmentSpec& spec, const std::filesystem::path& folder = {});

// The importance-sampling table of an ENV_IMAGE environment: one alias-table entry per pixel
// (`triangle` = the pixel index), with weight luminance * sin(theta at the pixel's centre row)
// (pbrt-v4 ImageInfiniteLight), so that the solid-angle density of a direction in pixel i is
// pmf_i * width * height / (2 pi^2 sin theta). Empty for the other kinds.
std::vector<gpu::Emitter> environmentAliasTable(const Environment& env);

// The environment's power as pbrt-v4 estimates an infinite light's (Phi = pi R^2 times the
// integral of luminance over the sphere), R the scene's bounding-sphere radius: with the
// emitters' power, it sets how often light sampling picks the environment.
double environmentPower(const Environment& env, float sceneRadius);

}  // namespace pmcr
