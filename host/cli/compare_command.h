// `pmcr compare IMAGE REFERENCE`: the papers' error and efficiency metrics (metrics/metrics.h).
#pragma once

#include "cli/args.h"

namespace pmcr::cli {

int runCompare(Args& args);
void printCompareHelp();

}  // namespace pmcr::cli
