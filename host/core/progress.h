// A progress bar on stderr: fraction done, work done, rate and ETA. Silent with --quiet or
// when stderr is not a terminal.
#pragma once

#include <chrono>
#include <string>

namespace pmcr {

class Progress {
public:
    Progress(const std::string& label, bool enabled);
    ~Progress();
    // fraction in [0, 1]; `done` and `unit` describe the work, e.g. 12 "spp".
    void update(double fraction, double done, const std::string& unit);
    void finish();

private:
    std::string m_label;
    bool m_enabled;
    bool m_drawn = false;
    std::chrono::steady_clock::time_point m_start;
    std::chrono::steady_clock::time_point m_lastDraw;
};

}  // namespace pmcr
