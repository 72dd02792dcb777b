#include "core/log.h"

#include <atomic>
#include <cstdio>
#include <mutex>
#include <vector>

namespace pmcr::log {

namespace {
std::atomic<bool> g_quiet{false};
std::mutex g_mutex;
bool g_holding = false;
std::vector<std::string> g_held;  // whole lines, as they would have been printed

void print(const std::string& line) {
    std::lock_guard<std::mutex> lock(g_mutex);
    if (g_holding) {
        g_held.push_back(line);
        return;
    }
    std::fprintf(stderr, "%s\n", line.c_str());
}
}  // namespace

void setQuiet(bool quiet) { g_quiet = quiet; }
bool quiet() { return g_quiet; }

void info(const std::string& message) {
    if (!g_quiet) print(message);
}

void warning(const std::string& message) { print("warning: " + message); }

void hold() {
    std::lock_guard<std::mutex> lock(g_mutex);
    g_holding = true;
}

void release() {
    std::lock_guard<std::mutex> lock(g_mutex);
    for (const std::string& line : g_held) std::fprintf(stderr, "%s\n", line.c_str());
    std::fflush(stderr);
    g_held.clear();
    g_holding = false;
}

void discard() {
    std::lock_guard<std::mutex> lock(g_mutex);
    g_held.clear();
    g_holding = false;
}

}  // namespace pmcr::log
