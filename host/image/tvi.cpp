#include "image/tvi.h"

#include <algorithm>
#include <cmath>

namespace pmcr {

namespace {
// Below this adaptation luminance both branches are constant; it also avoids log10(0).
constexpr double kMinAdaptation = 1e-6;
}  // namespace

// Ferwerda et al. 1996, eq. for the cone threshold.
double tviPhotopic(double la) {
    const double logLa = std::log10(std::max(la, kMinAdaptation));
    double logDl;
    if (logLa <= -2.6)
        logDl = -0.72;
    else if (logLa >= 1.9)
        logDl = logLa - 1.255;
    else
        logDl = std::pow(0.249 * logLa + 0.65, 2.7) - 0.72;
    return std::pow(10.0, logDl);
}

// Ferwerda et al. 1996, eq. for the rod threshold.
double tviScotopic(double la) {
    const double logLa = std::log10(std::max(la, kMinAdaptation));
    double logDl;
    if (logLa <= -3.94)
        logDl = -2.86;
    else if (logLa >= -1.44)
        logDl = logLa - 0.395;
    else
        logDl = std::pow(0.405 * logLa + 1.6, 2.18) - 2.86;
    return std::pow(10.0, logDl);
}

double tviCdM2(double la) { return std::min(tviPhotopic(la), tviScotopic(la)); }

double tvi(double y, double displayWhite) { return tviCdM2(y * displayWhite) / displayWhite; }

}  // namespace pmcr
