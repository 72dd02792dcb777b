// pmcr command-line entry point.
#include <cstdio>

int main() {
    std::printf("pmcr %s\n", PMCR_VERSION);
    return 0;
}
