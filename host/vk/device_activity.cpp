#include "vk/device_activity.h"

#include <algorithm>

namespace pmcr::vk {

namespace {
double seconds(DeviceActivity::Clock::duration d) { return std::chrono::duration<double>(d).count(); }
}  // namespace

DeviceActivity::Clock::time_point DeviceActivity::endOf(const Submission& s, Clock::time_point start) {
    if (!s.done) return std::max(start, Clock::now());
    Clock::time_point end = s.seen;
    if (s.alreadySignalled && s.deviceSeconds >= 0.0)
        end = std::min(end, start + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(s.deviceSeconds)));
    return std::max(end, start);
}

void DeviceActivity::submitted(Clock::time_point t) {
    Submission s;
    s.submitted = t;
    m_open.push_back(s);
}

void DeviceActivity::completed(Clock::time_point submittedAt, bool alreadySignalled, double deviceSeconds) {
    auto it = std::find_if(m_open.begin(), m_open.end(),
                           [&](const Submission& s) { return !s.done && s.submitted == submittedAt; });
    if (it == m_open.end()) return;
    it->done = true;
    it->seen = Clock::now();
    it->alreadySignalled = alreadySignalled;
    it->deviceSeconds = deviceSeconds;
    // The submissions done from the oldest on are final: into m_busy.
    while (!m_open.empty() && m_open.front().done) {
        const Clock::time_point start = std::max(m_open.front().submitted, m_lastEnd);
        const Clock::time_point end = endOf(m_open.front(), start);
        m_busy += seconds(end - start);
        m_lastEnd = end;
        m_open.pop_front();
    }
}

size_t DeviceActivity::inFlight() const {
    return size_t(std::count_if(m_open.begin(), m_open.end(), [](const Submission& s) { return !s.done; }));
}

double DeviceActivity::busySeconds() const {
    double busy = m_busy;
    Clock::time_point last = m_lastEnd;
    for (const Submission& s : m_open) {
        const Clock::time_point start = std::max(s.submitted, last);
        const Clock::time_point end = endOf(s, start);
        busy += seconds(end - start);
        last = end;
    }
    return busy;
}

}  // namespace pmcr::vk
