// A rendering method: takes a session (device, scene, film, budget) and produces an image.
#pragma once

#include "render/session.h"

namespace pmcr {

class Integrator {
public:
    virtual ~Integrator() = default;
    // Renders until the method's sample budget is spent, the time limit is reached or the user
    // interrupts; in the last two cases it returns the image so far.
    virtual RenderOutput render(RenderSession& session) = 0;
};

}  // namespace pmcr
