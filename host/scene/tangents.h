// Tangent frames for normal maps where a glTF mesh has no TANGENT attribute (glTF 2.0 sec.
// 3.7.2.1: "client implementations SHOULD calculate tangents using default MikkTSpace
// algorithms"). Per vertex the tangent is the direction of increasing u (dp/du) averaged over
// the triangles around it with their corner angles as weights (MikkTSpace's weighting), made
// orthogonal to the vertex normal; w = +-1 says whether the bitangent sign * cross(N, T) is the
// direction of decreasing v (glTF's v runs down the image, its normal maps' +y up it), as a
// MikkTSpace tangent of a mesh exported with glTF's uv has it. Unlike MikkTSpace, vertices
// shared by triangles with mirrored uv are not split: there the average may vanish and the
// interpolated normal is used (shaders/common/scene.glsl normalMapped).
#pragma once

#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "shared/host_device.h"

namespace pmcr {

// Tangents of `vertices` (world space, with uv and normal; a zero normal means the triangles'
// geometric one) for `triangles` (indices into `vertices`, counter-clockwise).
std::vector<glm::vec4> generateTangents(std::span<const gpu::Vertex> vertices,
                                        std::span<const glm::uvec3> triangles);

}  // namespace pmcr
