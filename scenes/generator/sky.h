// A clear-sky environment map for pmcr's --env: the Preetham, Shirley and Smits (1999) daylight
// model ("A Practical Analytic Model for Daylight", SIGGRAPH 99) with a sun disk, as an
// equirectangular image in pmcr's mapping (host/scene/environment.h).
#pragma once

#include "image/image.h"

namespace pmcr::scenegen {

struct SkyParams {
    int width = 512;
    int height = 256;
    double turbidity = 3.0;        // T: 2 very clear, 3 clear, 6 hazy (Preetham et al. sec. 3)
    double sunElevation = 35.0;    // degrees above the horizon
    double sunAzimuth = 45.0;      // degrees from -z (the default view) towards +x
    double sunRadius = 1.0;        // degrees: larger than the real 0.27, for softer shadows
    double sunToSky = 5.0;         // the sun's irradiance at normal incidence over pi * zenith
                                   // luminance: a clear afternoon's sun gives several times the
                                   // sky's light
    double groundAlbedo = 0.3;     // below the horizon: this times the sky's mean luminance
    double zenithLuminance = 0.3;  // the scale: a white Lambertian floor then sees about 1
};

// The sky's radiance (linear Rec. 709 RGB), scaled so that the zenith's luminance is
// zenithLuminance.
Image preethamSky(const SkyParams& params);

}  // namespace pmcr::scenegen
