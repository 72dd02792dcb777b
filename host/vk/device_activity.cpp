#include "vk/device_activity.h"

#include <algorithm>

namespace pmcr::vk {

void DeviceActivity::submitted(Clock::time_point t) {
    if (m_inFlight++ == 0) m_since = t;
}

void DeviceActivity::completed(Clock::time_point submittedAt, bool alreadySignalled,
                               double deviceSeconds) {
    if (m_inFlight == 0) return;
    Clock::time_point end = Clock::now();
    if (alreadySignalled && deviceSeconds >= 0.0) {
        // It ran from when it was submitted (or the one before it ended) for its device span.
        const Clock::time_point start = std::max(submittedAt, m_lastEnd);
        end = std::min(end, start + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(deviceSeconds)));
    }
    end = std::max(end, m_since);
    m_lastEnd = end;
    if (--m_inFlight == 0) m_busy += std::chrono::duration<double>(end - m_since).count();
}

double DeviceActivity::busySeconds() const {
    return m_busy + (m_inFlight > 0 ? std::chrono::duration<double>(Clock::now() - m_since).count() : 0.0);
}

}  // namespace pmcr::vk
