// Renders scenes in-process on the shared validated test context, exactly as `pmcr render` does.
#pragma once

#include <string>

#include "image/image.h"
#include "render/renderer.h"
#include "render/settings.h"
#include "scene/scene.h"

namespace pmcr::test {

// Loads a scene from the source tree once per test binary (cached by path).
const Scene& testScene(const std::string& relativePath);

// Renders `scene` with `settings` (size resolved from the scene when 0).
RenderResult renderForTest(const Scene& scene, RenderSettings settings);

// Mean of all pixels' luminance... and of each channel.
glm::dvec3 imageMean(const Image& image);

}  // namespace pmcr::test
