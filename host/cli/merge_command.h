// `pmcr merge IMAGE... -o OUT`: independent render pieces averaged by sample count
// (metrics/merge.h).
#pragma once

#include "cli/args.h"

namespace pmcr::cli {

int runMerge(Args& args);
void printMergeHelp();

}  // namespace pmcr::cli
