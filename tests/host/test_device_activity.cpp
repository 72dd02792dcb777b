// vk::DeviceActivity, behind the stats' device_idle_seconds: submissions in flight together
// count once, and one whose fence had signalled before the host looked ends where its
// timestamps say (after the one before it), not when the host came to wait.
#include <gtest/gtest.h>

#include "vk/device_activity.h"

namespace pmcr::test {
namespace {

using Clock = vk::DeviceActivity::Clock;

Clock::time_point secondsAfter(Clock::time_point t, double s) {
    return t + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

TEST(DeviceActivity, OverlappingSubmissionsCountOnceAndEndAtTheirDeviceSpan) {
    vk::DeviceActivity activity;
    const Clock::time_point t0 = secondsAfter(Clock::now(), -10.0);
    activity.submitted(t0);
    activity.submitted(secondsAfter(t0, 1.0));
    // The first ran 2 s from t0; the second, queued behind it, 3 s from t0 + 2 s.
    activity.completed(t0, true, 2.0);
    activity.completed(secondsAfter(t0, 1.0), true, 3.0);
    EXPECT_NEAR(activity.busySeconds(), 5.0, 1e-6);
}

TEST(DeviceActivity, GapsBetweenSubmissionsAreIdle) {
    vk::DeviceActivity activity;
    const Clock::time_point t0 = secondsAfter(Clock::now(), -10.0);
    activity.submitted(t0);
    activity.completed(t0, true, 1.0);
    activity.submitted(secondsAfter(t0, 4.0));  // 3 s with nothing in flight
    activity.completed(secondsAfter(t0, 4.0), true, 2.0);
    EXPECT_NEAR(activity.busySeconds(), 3.0, 1e-6);
}

TEST(DeviceActivity, WithoutTimestampsASubmissionLastsUntilTheHostSawItEnd) {
    vk::DeviceActivity activity;
    const Clock::time_point t0 = secondsAfter(Clock::now(), -2.0);
    activity.submitted(t0);
    activity.completed(t0, false, -1.0);
    EXPECT_GE(activity.busySeconds(), 2.0);
}

}  // namespace
}  // namespace pmcr::test
