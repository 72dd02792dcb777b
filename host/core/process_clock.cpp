#include "core/process_clock.h"

#include <chrono>

namespace pmcr {

double processSeconds() {
    static const auto start = std::chrono::steady_clock::now();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace pmcr
