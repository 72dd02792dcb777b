#include "core/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace pmcr {

Progress::Progress(const std::string& label, bool enabled)
    : m_label(label),
      m_enabled(enabled && isatty(fileno(stderr))),
      m_start(std::chrono::steady_clock::now()),
      m_lastDraw(m_start) {}

Progress::~Progress() { finish(); }

void Progress::update(double fraction, double done, const std::string& unit) {
    if (!m_enabled) return;
    auto now = std::chrono::steady_clock::now();
    if (m_drawn && now - m_lastDraw < std::chrono::milliseconds(100) && fraction < 1.0) return;
    m_lastDraw = now;
    fraction = std::clamp(fraction, 0.0, 1.0);
    const double elapsed = std::chrono::duration<double>(now - m_start).count();
    const double rate = elapsed > 0.0 ? done / elapsed : 0.0;
    const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    const int width = 30;
    const int filled = int(fraction * width);
    std::string bar(size_t(filled), '=');
    if (filled < width) bar += '>' + std::string(size_t(width - filled - 1), ' ');
    std::fprintf(stderr, "\r%s [%s] %3d%% %.0f %s  %.3g %s/s  ETA %.0fs  ", m_label.c_str(),
                 bar.c_str(), int(fraction * 100.0), done, unit.c_str(), rate, unit.c_str(), eta);
    std::fflush(stderr);
    m_drawn = true;
}

void Progress::finish() {
    if (m_enabled && m_drawn) {
        std::fprintf(stderr, "\n");
        m_drawn = false;
    }
}

}  // namespace pmcr
