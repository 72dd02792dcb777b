// `pmcr bench SCENE ...`: methods side by side against a reference (bench/bench.h, report.h).
#pragma once

#include "cli/args.h"

namespace pmcr::cli {

int runBench(Args& args);
void printBenchHelp();

}  // namespace pmcr::cli
