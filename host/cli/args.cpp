#include "cli/args.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

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

uint32_t parseUint(const std::string& option, const std::string& text, uint32_t min, uint32_t max) {
    char* end = nullptr;
    errno = 0;
    unsigned long long v = std::strtoull(text.c_str(), &end, 10);
    if (text.empty() || text[0] == '-' || *end != '\0' || errno == ERANGE || v < min || v > max)
        throw Error(option + ": expected an integer in [" + std::to_string(min) + ", " +
                    std::to_string(max) + "], got '" + text + "'");
    return uint32_t(v);
}

int parseInt(const std::string& option, const std::string& text, int min, int max) {
    char* end = nullptr;
    errno = 0;
    long long v = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno == ERANGE || v < min || v > max)
        throw Error(option + ": expected an integer in [" + std::to_string(min) + ", " +
                    std::to_string(max) + "], got '" + text + "'");
    return int(v);
}

double parseDouble(const std::string& option, const std::string& text, double min, double max) {
    char* end = nullptr;
    errno = 0;
    double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v) || v < min || v > max)
        throw Error(option + ": expected a number in [" + std::to_string(min) + ", " +
                    std::to_string(max) + "], got '" + text + "'");
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
