// The Vulkan core: device selection, a dispatch round trip, buffer transfers, validation.
#include <gtest/gtest.h>

#include <numeric>

#include "gpu_test.h"
#include "core/error.h"
#include "vk/gpu_timer.h"

namespace pmcr::test {
namespace {

class ContextTest : public GpuTest {};

TEST_F(ContextTest, ChoosesAUsableDevice) {
    EXPECT_FALSE(context().deviceName().empty());
    auto devices = vk::Context::listDevices();
    ASSERT_FALSE(devices.empty());
    bool chosenListed = false;
    for (const auto& d : devices)
        if (d.name == context().deviceName()) chosenListed = d.missing.empty();
    EXPECT_TRUE(chosenListed) << "the chosen device must be listed as usable";
}

TEST_F(ContextTest, UnknownDeviceNameFailsWithClearMessage) {
    vk::ContextOptions options;
    options.device = "no-such-device-xyz";
    try {
        vk::Context c(options);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no-such-device-xyz"), std::string::npos);
    }
}

TEST_F(ContextTest, SmokeKernelRoundTrip) {
    const uint32_t n = 1000;  // not a multiple of the workgroup size
    std::vector<uint32_t> in(n);
    std::iota(in.begin(), in.end(), 7u);
    auto inBuf = storage(in, "smoke in");
    auto outBuf = zeros(n * 4, "smoke out");
    run("tests/smoke", n, n, {&inBuf, &outBuf});
    auto out = outBuf.download<uint32_t>(n);
    for (uint32_t i = 0; i < n; ++i) ASSERT_EQ(out[i], in[i] * 2 + i) << i;
}

TEST_F(ContextTest, StorageLimitIsEnforcedWithNamedBuffer) {
    const VkDeviceSize tooBig = VkDeviceSize(context().limits().maxStorageBufferRange) + 16;
    try {
        vk::Buffer b(context(), tooBig, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "huge triangle buffer");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("huge triangle buffer"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("maxStorageBufferRange"), std::string::npos);
    }
}

TEST_F(ContextTest, TimestampsMeasureDispatches) {
    if (!context().timestampsSupported()) GTEST_SKIP() << "device has no compute timestamps";
    vk::GpuTimer timer(context());
    vk::Kernel kernel(layout(), "tests/smoke");
    std::vector<uint32_t> in(4096, 1u);
    auto inBuf = storage(in);
    auto outBuf = zeros(in.size() * 4);
    vk::DescriptorSet work(layout(), vk::DescriptorSet::Kind::Work, "timer work");
    work.bind(0, inBuf);
    work.bind(1, outBuf);
    vk::CommandBatch batch(layout(), &timer);
    batch.bind(work);
    uint32_t count = 4096;
    for (int i = 0; i < 3; ++i) batch.dispatch(kernel, count, count);
    batch.submitAndWait();
    ASSERT_EQ(timer.totals().count("tests/smoke"), 1u);
    EXPECT_EQ(timer.totals().at("tests/smoke").dispatches, 3u);
    EXPECT_GT(timer.totals().at("tests/smoke").milliseconds, 0.0);
}

// Two batches in flight: each gets its own dispatch times (copied to mapped memory by the batch:
// lavapipe's vkGetQueryPoolResults waits for the whole device), and a submission of the host's
// own made meanwhile, which waits for them too, is counted as a queue drain.
TEST_F(ContextTest, BatchesInFlightKeepTheirTimesAndAWaitBehindThemIsADrain) {
    if (!context().timestampsSupported()) GTEST_SKIP() << "device has no compute timestamps";
    vk::GpuTimer timer(context());
    vk::Kernel kernel(layout(), "tests/smoke");
    std::vector<uint32_t> in(4096, 1u);
    auto inBuf = storage(in);
    auto outBuf = zeros(in.size() * 4);
    auto other = zeros(64);
    vk::DescriptorSet work(layout(), vk::DescriptorSet::Kind::Work, "in-flight work");
    work.bind(0, inBuf);
    work.bind(1, outBuf);
    vk::CommandBatch first(layout(), &timer), second(layout(), &timer);
    uint32_t count = 4096;
    for (vk::CommandBatch* b : {&first, &second}) {
        b->bind(work);
        for (int i = 0; i < 2; ++i) b->dispatch(kernel, count, count);
        b->submit();
    }
    const uint64_t drains = context().queueDrains();
    other.fill(0);  // a submitAndWait behind the two
    EXPECT_EQ(context().queueDrains(), drains + 1);
    first.wait();
    second.wait();
    EXPECT_GT(first.lastDeviceSeconds(), 0.0);
    EXPECT_GT(second.lastDeviceSeconds(), 0.0);
    EXPECT_EQ(timer.totals().at("tests/smoke").dispatches, 4u);
    other.fill(0);  // nothing in flight: no drain
    EXPECT_EQ(context().queueDrains(), drains + 1);
}

}  // namespace
}  // namespace pmcr::test

namespace pmcr::test {
namespace {

// The fixture's promise ("a validation message fails the test") is only worth something if the
// layer is really on: record a harmless misuse (a fill whose size is not a multiple of 4, which
// drivers tolerate) and expect a message.
TEST(ValidationLayer, ReportsMisuse) {
    if (!gpuContext().validationEnabled()) GTEST_SKIP() << "PMCR_VALIDATE=0";
    gpuContext().clearValidationMessages();
    vk::Buffer buffer(gpuContext(), 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "misuse target");
    gpuContext().submitAndWait(
        [&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, buffer.handle(), 0, 6, 0); });
    auto messages = gpuContext().validationMessages();
    ASSERT_FALSE(messages.empty());
    EXPECT_NE(messages.front().find("vkCmdFillBuffer"), std::string::npos) << messages.front();
    gpuContext().clearValidationMessages();
}

}  // namespace
}  // namespace pmcr::test
