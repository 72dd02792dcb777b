#include "core/interrupt.h"

#include <atomic>
#include <csignal>

namespace pmcr {

namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void onSignal(int signal) {
    if (g_interrupted.exchange(true)) {
        // Second signal: give up immediately with the conventional status.
        std::signal(signal, SIG_DFL);
        std::raise(signal);
    }
}

}  // namespace

void installInterruptHandler() {
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
}

bool interruptRequested() { return g_interrupted.load(); }
void requestInterrupt() { g_interrupted = true; }
void clearInterrupt() { g_interrupted = false; }

}  // namespace pmcr
