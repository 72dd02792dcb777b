// `pmcr compare IMAGE REFERENCE`, `pmcr merge IMAGE... -o OUT` and `pmcr bench SCENE ...`.
#pragma once

#include "cli/args.h"

namespace pmcr::cli {

int runCompare(Args& args);
void printCompareHelp();

int runMerge(Args& args);
void printMergeHelp();

int runBench(Args& args);
void printBenchHelp();

}  // namespace pmcr::cli
