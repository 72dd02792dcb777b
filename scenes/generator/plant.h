// A procedural potted plant (no third-party data): a stem with arching fronds of thin leaflets,
// from a fixed-seed random number generator, so the output is the same on every platform.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "mesh.h"

namespace pmcr::scenegen {

struct Plant {
    Mesh stems;   // stem and frond midribs: thin flat-shaded tubes
    Mesh leaves;  // leaflets: flat, 4 triangles each, front faces up
};

// The plant rising from `base` (the top of its soil): about 0.8 tall and 1.6 across.
Plant makePlant(const glm::dvec3& base, uint64_t seed);

}  // namespace pmcr::scenegen
