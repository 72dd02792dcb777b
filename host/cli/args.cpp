#include "cli/args.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/decimal.h"
#include "core/error.h"

namespace pmcr::cli {

Args::Args(int argc, char** argv, int first) {
    for (int i = first; i < argc; ++i) m_tokens.emplace_back(argv[i]);
}

std::string Args::next() {
    m_inlineValue.reset();
    std::string token = m_tokens[m_pos++];
    if (token.rfind("--", 0) == 0) {
        auto eq = token.find('=');
        if (eq != std::string::npos) {
            m_inlineValue = token.substr(eq + 1);
            token = token.substr(0, eq);
        }
    }
    return token;
}

std::string Args::value(const std::string& option) {
    if (m_inlineValue) {
        std::string v = *m_inlineValue;
        m_inlineValue.reset();
        return v;
    }
    if (done()) throw Error(option + ": missing value");
    return m_tokens[m_pos++];
}

namespace {

// A bound in an error message as it would be typed: "0.001" and "1e+30", not "0.001000" and
// 31 digits.
std::string boundText(double v) {
    char text[32];
    std::snprintf(text, sizeof(text), "%g", v);
    return text;
}

}  // namespace

// Numbers are decimal only (core/decimal.h): "0x10", "inf" or " 5" are errors naming the option,
// not values strtol or strtod would read some other way.
uint32_t parseUint(const std::string& option, const std::string& text, uint32_t min, uint32_t max) {
    errno = 0;
    const bool decimal = isDecimalInteger(text);
    const long long v = decimal ? std::strtoll(text.c_str(), nullptr, 10) : 0;  // holds a uint32_t
    if (!decimal || errno == ERANGE || v < (long long)min || v > (long long)max)
        throw Error(option + ": expected an integer in [" + std::to_string(min) + ", " +
                    std::to_string(max) + "], got '" + text + "'");
    return uint32_t(v);
}

int parseInt(const std::string& option, const std::string& text, int min, int max) {
    errno = 0;
    const bool decimal = isDecimalInteger(text);
    const long long v = decimal ? std::strtoll(text.c_str(), nullptr, 10) : 0;
    if (!decimal || errno == ERANGE || v < min || v > max)
        throw Error(option + ": expected an integer in [" + std::to_string(min) + ", " +
                    std::to_string(max) + "], got '" + text + "'");
    return int(v);
}

double parseDouble(const std::string& option, const std::string& text, double min, double max) {
    errno = 0;
    const bool decimal = isDecimalNumber(text);
    const double v = decimal ? std::strtod(text.c_str(), nullptr) : 0.0;
    if (!decimal || errno == ERANGE || !std::isfinite(v) || v < min || v > max)
        throw Error(option + ": expected a number in [" + boundText(min) + ", " + boundText(max) +
                    "], got '" + text + "'");
    return v;
}

bool parseEnvironmentOption(const std::string& a, Args& args, EnvironmentSpec& env) {
    if (a == "--env") env.value = args.value(a);
    else if (a == "--env-rotate") env.rotateDegrees = float(parseDouble(a, args.value(a), -36000, 36000));
    else if (a == "--env-scale") env.scale = float(parseDouble(a, args.value(a), 0, 1e30));
    else return false;
    return true;
}

void checkEnvironmentOptions(const EnvironmentSpec& env) {
    if (env.value.empty() && (env.rotateDegrees != 0.0f || env.scale != 1.0f))
        throw Error("--env-rotate and --env-scale need --env");
}

const char* const kEnvironmentHelp =
    "  --env R,G,B|FILE     environment light: a constant radiance, or an equirectangular HDR\n"
    "                       image (.exr, .pfm, .hdr; +y up, centre column towards -z),\n"
    "                       importance-sampled (pt, direct, pmc-ip, pmc-ip-direct, pmc-pt)\n"
    "  --env-rotate DEG     rotate the environment about +y (default 0)\n"
    "  --env-scale S        scale its radiance (default 1)\n";

}  // namespace pmcr::cli
