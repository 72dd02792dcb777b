// Texture lookups on the host, the same as the kernels' (shaders/common/scene.glsl
// sampleTexture: glTF wrap modes, bilinear, sRGB decoded per texel before filtering), for what
// the host precomputes from textures: an emitter's mean emission (light selection by power).
#pragma once

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace pmcr {

// Bilinear lookup at uv ((0,0) the image's top-left); colour textures (srgb) decoded to linear.
glm::vec4 sampleTexture(const Texture& texture, glm::vec2 uv, bool srgb);

// The mean of sampleTexture over the triangle with texture coordinates uv0, uv1, uv2 (uniform in
// its area): the centroids of a k x k subdivision of the triangle, k growing with the texels the
// triangle covers (at least 4, at most 64).
glm::vec3 meanOverTriangle(const Texture& texture, glm::vec2 uv0, glm::vec2 uv1, glm::vec2 uv2,
                           bool srgb);

}  // namespace pmcr
