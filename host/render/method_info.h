// What the registry (render/methods.h) holds for one method: its name, summary, options and how
// to create it. Each method defines its entries beside its integrator, in its folder under
// host/methods/.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "render/integrator.h"
#include "render/settings.h"

namespace pmcr {

struct MethodOption {
    std::string name;          // "chain-length" for --chain-length
    std::string defaultValue;
    std::string help;
    bool biased = false;       // a biased option (ERPT's noise filters): labelled in --help
    // A paper's own baseline (render/baseline_options.h): which value reproduces which paper's
    // conditions, labelled in --help. Empty for other options.
    std::string paperBaseline;
};

struct MethodInfo {
    std::string name;
    std::string summary;
    bool unbiased = true;
    std::vector<MethodOption> options;
    // Empty when the method is not implemented yet; `plannedIn` then says where it is tracked.
    // Creating an integrator only parses its options (throwing pmcr::Error for a bad value) and
    // touches no device: `pmcr bench` creates each method once to check its options up front.
    std::function<std::unique_ptr<Integrator>(const RenderSettings&)> create;
    std::string plannedIn;
};

}  // namespace pmcr
