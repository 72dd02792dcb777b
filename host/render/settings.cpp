#include "render/settings.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "core/decimal.h"
#include "core/error.h"

namespace pmcr {

int RenderSettings::optionInt(const std::string& name, int defaultValue) const {
    auto it = options.find(name);
    if (it == options.end()) return defaultValue;
    // Decimal only, as every number on the command line (core/decimal.h).
    errno = 0;
    const bool decimal = isDecimalInteger(it->second);
    const long long v = decimal ? std::strtoll(it->second.c_str(), nullptr, 10) : 0;
    if (!decimal || errno == ERANGE || v < INT32_MIN || v > INT32_MAX)
        throw Error("--" + name + ": expected an integer, got '" + it->second + "'");
    return int(v);
}

double RenderSettings::optionDouble(const std::string& name, double defaultValue) const {
    auto it = options.find(name);
    if (it == options.end()) return defaultValue;
    errno = 0;
    const bool decimal = isDecimalNumber(it->second);
    const double v = decimal ? std::strtod(it->second.c_str(), nullptr) : 0.0;
    if (!decimal || errno == ERANGE || !std::isfinite(v))
        throw Error("--" + name + ": expected a number, got '" + it->second + "'");
    return v;
}

bool RenderSettings::optionBool(const std::string& name, bool defaultValue) const {
    auto it = options.find(name);
    if (it == options.end()) return defaultValue;
    if (it->second == "1" || it->second == "true" || it->second == "on") return true;
    if (it->second == "0" || it->second == "false" || it->second == "off") return false;
    throw Error("--" + name + ": expected on/off, got '" + it->second + "'");
}

std::string RenderSettings::optionString(const std::string& name,
                                         const std::string& defaultValue) const {
    auto it = options.find(name);
    return it == options.end() ? defaultValue : it->second;
}

std::vector<double> RenderSettings::optionNumbers(const std::string& name,
                                                  const std::string& defaultValue) const {
    return parseNumberList(name, optionString(name, defaultValue));
}

std::vector<double> parseNumberList(const std::string& option, const std::string& text) {
    std::string list = text;
    for (char& c : list)
        if (c == '/') c = ',';
    std::vector<double> numbers;
    std::stringstream in(list);
    std::string field;
    bool ok = !list.empty() && list.back() != ',';
    while (ok && std::getline(in, field, ',')) {
        errno = 0;
        const double v = isDecimalNumber(field) ? std::strtod(field.c_str(), nullptr) : 0.0;
        ok = isDecimalNumber(field) && errno != ERANGE && std::isfinite(v);
        numbers.push_back(v);
    }
    if (!ok) throw Error("--" + option + ": expected numbers separated by , or /, got '" + text + "'");
    return numbers;
}

}  // namespace pmcr
