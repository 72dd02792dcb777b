// vk::DeviceActivity, behind the stats' device_idle_seconds: submissions in flight together
// count once, and one whose fence had signalled before the host looked ends where its
// timestamps say (after the one before it), not when the host came to wait, even while a
// later submission is still in flight.
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

// The host works 4 s with the second batch done and not looked at, then submits a third: the
// device waited for it (counted as busy while only the host's view was kept: 6 s).
TEST(DeviceActivity, AFinishedBatchNotYetSeenLeavesTheDeviceIdle) {
    vk::DeviceActivity activity;
    const Clock::time_point t0 = secondsAfter(Clock::now(), -10.0);
    activity.submitted(t0);
    activity.submitted(secondsAfter(t0, 0.5));
    activity.completed(t0, true, 1.0);                   // [0, 1]
    activity.submitted(secondsAfter(t0, 5.0));
    activity.completed(secondsAfter(t0, 0.5), true, 1.0);  // [1, 2]
    activity.completed(secondsAfter(t0, 5.0), true, 1.0);  // [5, 6]
    EXPECT_NEAR(activity.busySeconds(), 3.0, 1e-6);
}

TEST(DeviceActivity, ASubmissionNotYetSeenCountsUntilNow) {
    vk::DeviceActivity activity;
    const Clock::time_point t0 = secondsAfter(Clock::now(), -3.0);
    activity.submitted(t0);
    activity.submitted(secondsAfter(t0, 1.0));
    activity.completed(secondsAfter(t0, 1.0), true, 0.5);  // seen first, queued behind the first
    EXPECT_GE(activity.busySeconds(), 3.0);              // the first is still in flight
    activity.completed(t0, true, 2.0);                   // [0, 2], then the second [2, 2.5]
    EXPECT_NEAR(activity.busySeconds(), 2.5, 1e-6);
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
