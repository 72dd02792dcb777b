// pmcr command-line entry point.
#include "cli/cli.h"

int main(int argc, char** argv) { return pmcr::cli::run(argc, argv); }
