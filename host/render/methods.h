// The methods pmcr knows, their options and how to create them. One registry for the CLI's
// `render --method`, `--help` and `bench --methods`.
#pragma once

#include <string>
#include <vector>

#include "render/method_info.h"
#include "render/settings.h"
#include "scene/scene.h"

namespace pmcr {

const std::vector<MethodInfo>& methods();
const MethodInfo* findMethod(const std::string& name);

// Checks settings.options against the method's options; throws pmcr::Error naming an unknown
// option or an unimplemented method.
void validateMethodOptions(const RenderSettings& settings);

}  // namespace pmcr
