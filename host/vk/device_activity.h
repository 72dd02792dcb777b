// The device's activity over a render, from the host's side (vk::Context keeps one, every
// submission reports to it): what the stats' device_idle_seconds are made of.
#pragma once

#include <chrono>

namespace pmcr::vk {

// Whether the device has work: the time with at least one submission in flight, summed, for the
// stats' device_idle_seconds (a render's time minus this). A submission counts from
// vkQueueSubmit until the host sees its fence signalled, or, when the fence had signalled
// before the host looked, until the end its kernels' timestamps give (execution starts when
// both it is submitted and the one before it is done).
class DeviceActivity {
public:
    using Clock = std::chrono::steady_clock;
    void submitted(Clock::time_point t);
    // `deviceSeconds`: the submission's span on the device from timestamps (< 0: unknown).
    void completed(Clock::time_point submittedAt, bool alreadySignalled, double deviceSeconds);
    // Seconds with work in flight up to now.
    double busySeconds() const;

private:
    int m_inFlight = 0;
    Clock::time_point m_since{};
    Clock::time_point m_lastEnd{};
    double m_busy = 0.0;
};

}  // namespace pmcr::vk
