// A rendering method: takes a session (device, scene, film, budget) and produces an image.
#pragma once

#include "render/session.h"

namespace pmcr {

class Integrator {
public:
    virtual ~Integrator() = default;
    // Renders until the method's sample budget is spent, the time limit is reached or the user
    // interrupts; in the last two cases it returns the image so far. Contract with the session:
    // call session.startClock() when the first sample is about to be taken (after creating
    // kernels and buffers), stop at a batch boundary once session.shouldStop(), and call
    // session.snapshotIfDue(cameraSamples, resolve) at every batch boundary, `resolve` returning
    // the image so far exactly as the final image is resolved (for `pmcr bench`'s convergence
    // plots; it does nothing unless snapshots were asked for).
    virtual RenderOutput render(RenderSession& session) = 0;
    // Samples per pixel when neither --spp nor --time is given (the method's budget unit).
    virtual uint32_t defaultSpp() const = 0;
};

}  // namespace pmcr
