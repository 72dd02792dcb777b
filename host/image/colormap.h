// False colour for scalar images (error maps in `pmcr compare` and reports).
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "image/image.h"

namespace pmcr {

// Linear RGB colour of t on a viridis-like, perceptually ordered colormap: dark purple at
// t = 0 to yellow at t = 1, luminance increasing. t is clamped to [0,1]; NaN maps to 0.
glm::vec3 viridis(float t);

// width x height values (row-major, top row first) mapped through viridis(value / maxValue).
// Throws pmcr::Error unless values.size() == width * height and maxValue is positive and finite.
Image falseColor(const std::vector<float>& values, int width, int height, float maxValue);

}  // namespace pmcr
