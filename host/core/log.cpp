#include "core/log.h"

#include <atomic>
#include <cstdio>

namespace pmcr::log {

namespace {
std::atomic<bool> g_quiet{false};
}

void setQuiet(bool quiet) { g_quiet = quiet; }
bool quiet() { return g_quiet; }

void info(const std::string& message) {
    if (!g_quiet) std::fprintf(stderr, "%s\n", message.c_str());
}

void warning(const std::string& message) {
    std::fprintf(stderr, "warning: %s\n", message.c_str());
}

}  // namespace pmcr::log
