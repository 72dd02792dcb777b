// The device's activity over a render, from the host's side (vk::Context keeps one, every
// submission reports to it): what the stats' device_idle_seconds are made of.
#pragma once

#include <chrono>
#include <deque>

namespace pmcr::vk {

// Whether the device has work: the time with a submission executing, summed, for the stats'
// device_idle_seconds (a render's time minus this). The queue runs its submissions in order,
// so a submission executes from when it is submitted or the one before it ends, whichever is
// later, until the host sees its fence signalled, or, when the fence had signalled before the
// host looked, for the span its kernels' timestamps give. A submission the host has not looked
// at yet counts as executing until now. (Counting only the time with some submission not yet
// looked at missed the device's waits while the host worked with a finished batch unseen.)
class DeviceActivity {
public:
    using Clock = std::chrono::steady_clock;
    void submitted(Clock::time_point t);
    // The submission made at `submittedAt` is done; `deviceSeconds`: its span on the device from
    // timestamps (< 0: unknown).
    void completed(Clock::time_point submittedAt, bool alreadySignalled, double deviceSeconds);
    // Seconds with a submission executing up to now.
    double busySeconds() const;
    // Submissions not yet seen done.
    size_t inFlight() const;

private:
    struct Submission {
        Clock::time_point submitted{};
        Clock::time_point seen{};  // when the host saw it done
        double deviceSeconds = -1.0;
        bool done = false, alreadySignalled = false;
    };
    // When `s` ended, had it started at `start`.
    static Clock::time_point endOf(const Submission& s, Clock::time_point start);
    std::deque<Submission> m_open;  // in submission order, from the oldest not yet done
    Clock::time_point m_lastEnd{};  // the end of the last submission folded into m_busy
    double m_busy = 0.0;            // the submissions done before m_open's
};

}  // namespace pmcr::vk
