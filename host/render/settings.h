// What the user asked a render to do: method, budget, image size, seed and method options.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace pmcr {

struct RenderSettings {
    std::string method = "pt";
    int width = 0;            // 0: the scene's default size, else 640 wide at the camera's aspect
    int height = 0;
    bool paperSize = false;   // --paper-size: the size the scene's paper used (scene extras)
    uint32_t spp = 0;         // samples per pixel (0: the method's default unless --time is given)
    double timeLimit = 0.0;   // seconds of rendering; 0 = no limit
    uint32_t seed = 1;
    uint32_t maxDepth = 16;   // bounces (pbrt-v4 semantics: 1 = direct lighting only)
    uint32_t rrDepth = 3;     // Russian roulette from this bounce on
    int camera = 0;
    bool quiet = false;
    std::string device;       // --device
    bool validate = false;
    // Method-specific options (--chain-length 100 -> {"chain-length", "100"}), checked against
    // the method's declared options (render/methods.h).
    std::map<std::string, std::string> options;
    // Convergence snapshots (`pmcr bench`): the image so far is recorded at these times on the
    // render clock (seconds) and sample counts (samples per pixel), ascending; see
    // RenderSession::snapshotIfDue.
    std::vector<double> snapshotSeconds;
    std::vector<double> snapshotSpp;

    // Typed access to an option with a default; throws pmcr::Error on a malformed value.
    int optionInt(const std::string& name, int defaultValue) const;
    double optionDouble(const std::string& name, double defaultValue) const;
    bool optionBool(const std::string& name, bool defaultValue) const;
    std::string optionString(const std::string& name, const std::string& defaultValue) const;
    // A list of numbers separated by ',' or '/' (`pmcr bench --methods` splits methods at
    // commas): parseNumberList of the option's value, or of `defaultValue`.
    std::vector<double> optionNumbers(const std::string& name, const std::string& defaultValue) const;
};

// "5,10,50" or "5/10/50" -> {5, 10, 50}; throws pmcr::Error naming --`option` on an empty list,
// an empty field or one that is not a finite number.
std::vector<double> parseNumberList(const std::string& option, const std::string& text);

}  // namespace pmcr
