// The average pixel luminance of an image, estimated by a short path-traced pre-pass: ERPT's
// e_ave (ERPT eq. 7) and PMC-ER's image energy estimate (PMC-ER eq. 2-3). A poor estimate
// changes only the run time of those methods, not their expected image (ERPT sec. 3.2).
#pragma once

#include <cstdint>

#include "render/session.h"

namespace pmcr {

// Under --time without --spp, the pre-pass stops after the first sample per pixel that ends
// past this share of the budget (at 320x180 on lavapipe its 4 spp took up to 0.93 s of
// `--time 2`, and pmc-er's first pass, which always runs, 1.85 s more).
constexpr double kPrepassShareOfTime = 0.1;

// Renders `spp` samples per pixel of path tracing (seeded apart from the main render) into a
// scratch film and returns the mean over pixels of the per-pixel luminance estimate; with
// several ranks (session.comm()), the mean of every rank's pre-pass. A collective.
double estimateMeanLuminance(RenderSession& session, uint32_t spp);

}  // namespace pmcr
