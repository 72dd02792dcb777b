// Photon mapping (`pm`): the two-pass renderer of Jensen 2001 ch. 9 that the PMC paper's sec. 6
// starts from, with progressive radius reduction by default. Each photon pass (photon_map.h)
// serves --spp-per-pass camera samples per pixel, each traced by the gather kernel
// (shaders/methods/pm/pm_gather_kernel.glsl: MIS direct lighting, caustic photons seen directly,
// a final gather of the photon map); the image is the average of all camera samples, so with
// --progressive on the passes' shrinking radii make it converge to the path tracer's image
// (consistent, not unbiased), and at a fixed radius (--progressive off, one photon pass) it is
// biased. `pm-pmc` (methods/pmc_ip/pmc_ip_integrator.h) drives the same gather with PMC-IP and
// PMC-HI.
#pragma once

#include "methods/pm/photon_map.h"
#include "render/integrator.h"
#include "render/method_info.h"

namespace pmcr {

class PhotonMapper : public Integrator {
public:
    explicit PhotonMapper(const RenderSettings& settings);
    RenderOutput render(RenderSession& session) override;

    static constexpr uint32_t kDefaultSpp = 16;
    uint32_t defaultSpp() const override { return kDefaultSpp; }

private:
    PhotonMapOptions m_photons;
    uint32_t m_lightSamples = 1;
    uint32_t m_sppPerPass = 1;
};

// The gather kernel (under shaders/methods/pm/) for `scene`: pm_gather, or pm_gather_hi with
// PMC-HI direct lighting, each in the variant for the scene's lights (lightsKernelVariant).
std::string photonGatherKernel(const GpuScene& scene, bool pmcHi);

// The registry entry (render/methods.cpp) of `pm`.
MethodInfo pmMethod();

}  // namespace pmcr
