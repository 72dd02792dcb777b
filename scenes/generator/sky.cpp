#include "sky.h"

#include <cmath>
#include <numbers>

#include <glm/glm.hpp>

namespace pmcr::scenegen {

namespace {

constexpr double kPi = std::numbers::pi;

// The Perez et al. luminance distribution, F(theta, gamma) = (1 + A e^(B / cos theta))
// (1 + C e^(D gamma) + E cos^2 gamma) (Preetham et al. eq. 3).
struct Perez {
    double A, B, C, D, E;
    double operator()(double cosTheta, double gamma) const {
        const double c = std::max(cosTheta, 1e-3);
        return (1.0 + A * std::exp(B / c)) * (1.0 + C * std::exp(D * gamma) + E * std::cos(gamma) * std::cos(gamma));
    }
};

// Zenith chromaticity: [T^2 T 1] M [theta_s^3 theta_s^2 theta_s 1]^T (Preetham et al.,
// appendix A.2).
double zenithChromaticity(const double m[3][4], double T, double thetaS) {
    const double t[3] = {T * T, T, 1.0};
    const double s[4] = {thetaS * thetaS * thetaS, thetaS * thetaS, thetaS, 1.0};
    double sum = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) sum += t[i] * m[i][j] * s[j];
    return sum;
}

// CIE xyY to linear Rec. 709 RGB (IEC 61966-2-1 matrix, D65 white).
glm::dvec3 xyYToRgb(double x, double y, double Y) {
    const double X = x / y * Y, Z = (1.0 - x - y) / y * Y;
    return {3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z, -0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z,
            0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z};
}

// A direction of pmcr's equirectangular mapping: theta from +y, phi from -z towards +x.
glm::dvec3 direction(double theta, double phi) {
    return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

}  // namespace

Image preethamSky(const SkyParams& p) {
    const double T = p.turbidity;
    const double thetaS = kPi / 2.0 - p.sunElevation * kPi / 180.0;
    const glm::dvec3 sun = direction(thetaS, p.sunAzimuth * kPi / 180.0);
    // Distribution coefficients (Preetham et al., appendix A.2).
    const Perez fY{0.1787 * T - 1.4630, -0.3554 * T + 0.4275, -0.0227 * T + 5.3251, 0.1206 * T - 2.5771,
                   -0.0670 * T + 0.3703};
    const Perez fx{-0.0193 * T - 0.2592, -0.0665 * T + 0.0008, -0.0004 * T + 0.2125, -0.0641 * T - 0.8989,
                   -0.0033 * T + 0.0452};
    const Perez fy{-0.0167 * T - 0.2608, -0.0950 * T + 0.0092, -0.0079 * T + 0.2102, -0.0441 * T - 1.6537,
                   -0.0109 * T + 0.0529};
    // Zenith chromaticity (appendix A.2). Luminance is relative to the zenith's (its absolute
    // value, eq. A.2's Y_z, would only scale the image).
    const double mx[3][4] = {{0.00166, -0.00375, 0.00209, 0.0},
                             {-0.02903, 0.06377, -0.03202, 0.00394},
                             {0.11693, -0.21196, 0.06052, 0.25886}};
    const double my[3][4] = {{0.00275, -0.00610, 0.00317, 0.0},
                             {-0.04214, 0.08970, -0.04153, 0.00516},
                             {0.15346, -0.26756, 0.06670, 0.26688}};
    const double xz = zenithChromaticity(mx, T, thetaS), yz = zenithChromaticity(my, T, thetaS);

    Image sky(p.width, p.height);
    const double pixelArea = 2.0 * kPi * kPi / (double(p.width) * p.height);  // times sin theta
    double skyLuminance = 0.0, skyArea = 0.0, sunArea = 0.0;
    for (int y = 0; y < p.height; ++y) {
        const double theta = kPi * (y + 0.5) / p.height;
        for (int x = 0; x < p.width; ++x) {
            const double phi = 2.0 * kPi * ((x + 0.5) / p.width - 0.5);
            const glm::dvec3 d = direction(theta, phi);
            const double gamma = std::acos(std::clamp(glm::dot(d, sun), -1.0, 1.0));
            const double solidAngle = pixelArea * std::sin(theta);
            if (gamma < p.sunRadius * kPi / 180.0) sunArea += solidAngle;
            if (theta >= kPi / 2.0) continue;  // the ground, below
            // Relative to the zenith (eq. 2): value = zenith * F(theta, gamma) / F(0, theta_s).
            const double cosTheta = std::cos(theta);
            const double Y = fY(cosTheta, gamma) / fY(1.0, thetaS);
            const double cx = xz * fx(cosTheta, gamma) / fx(1.0, thetaS);
            const double cy = yz * fy(cosTheta, gamma) / fy(1.0, thetaS);
            sky.set(x, y, glm::vec3(glm::max(xyYToRgb(cx, cy, Y), glm::dvec3(0.0))));
            skyLuminance += Y * solidAngle;
            skyArea += solidAngle;
        }
    }
    // The ground: a grey plain lit by the sky, groundAlbedo times its mean luminance.
    const float ground = float(p.groundAlbedo * skyLuminance / skyArea);
    for (int y = p.height / 2; y < p.height; ++y)
        for (int x = 0; x < p.width; ++x)
            if (kPi * (y + 0.5) / p.height >= kPi / 2.0) sky.set(x, y, glm::vec3(ground));
    // The sun: its pixels share E = sunToSky * pi (zenith luminance 1) at normal incidence, in
    // the sky's colour near the sun, so that its light does not depend on how many pixels the
    // disk covers.
    if (sunArea > 0.0) {
        const glm::dvec3 sunColor = glm::dvec3(1.0, 0.93, 0.85) / 0.939;  // luminance 1, warm
        const double radiance = p.sunToSky * kPi / sunArea;
        for (int y = 0; y < p.height; ++y) {
            const double theta = kPi * (y + 0.5) / p.height;
            for (int x = 0; x < p.width; ++x) {
                const double phi = 2.0 * kPi * ((x + 0.5) / p.width - 0.5);
                const double gamma = std::acos(std::clamp(glm::dot(direction(theta, phi), sun), -1.0, 1.0));
                if (gamma < p.sunRadius * kPi / 180.0)
                    sky.set(x, y, sky.at(x, y) + glm::vec3(radiance * sunColor));
            }
        }
    }
    for (float& v : sky.rgb) v *= float(p.zenithLuminance);
    return sky;
}

}  // namespace pmcr::scenegen
