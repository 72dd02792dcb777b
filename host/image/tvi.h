// Threshold-versus-intensity: the smallest luminance difference a viewer adapted to luminance
// La can see. Used by the perceptual error metric (P-Err, P-Eff) and by PMC-IP / PMC-PT's
// perceptually weighted variance (Fan et al., "Population Monte Carlo Samplers for Rendering",
// sec. 4.2 and 4.4).
//
// Ferwerda, Pattanaik, Shirley and Greenberg 1996, "A Model of Visual Adaptation for Realistic
// Image Synthesis", give threshold luminance (cd/m^2) against adaptation luminance (cd/m^2),
// both in log10, for the cones (photopic) and the rods (scotopic):
//   cones: log dL = -0.72                            if log La <= -2.6
//                   (0.249 log La + 0.65)^2.7 - 0.72 if -2.6 < log La < 1.9
//                   log La - 1.255                   if log La >= 1.9
//   rods:  log dL = -2.86                            if log La <= -3.94
//                   (0.405 log La + 1.6)^2.18 - 2.86 if -3.94 < log La < -1.44
//                   log La - 0.395                   if log La >= -1.44
// The visible threshold is the lower of the two (the more sensitive system wins).
//
// Rendered images have no absolute unit, so pixel luminance Y is read as Y * displayWhite cd/m^2
// (default 100, a typical display's white), and the threshold is returned in pixel units.
#pragma once

namespace pmcr {

constexpr double kDefaultDisplayWhite = 100.0;  // cd/m^2 that pixel luminance 1 stands for

double tviPhotopic(double adaptationCdM2);   // cd/m^2 -> cd/m^2
double tviScotopic(double adaptationCdM2);   // cd/m^2 -> cd/m^2
double tviCdM2(double adaptationCdM2);       // min of the two

// Threshold in pixel units for pixel luminance y (y <= 0 treated as the darkest level).
double tvi(double y, double displayWhite = kDefaultDisplayWhite);

}  // namespace pmcr
