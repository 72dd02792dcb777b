// The Vulkan core: device selection, a dispatch round trip, buffer transfers, validation.
#include <gtest/gtest.h>

#include <memory>
#include <numeric>

#include "gpu_test.h"
#include "core/error.h"
#include "vk/gpu_timer.h"

namespace pmcr::test {
namespace {

class ContextTest : public GpuTest {
protected:
    // tests/smoke over kSmokeItems items of 1, for batches to dispatch: its kernel and work set.
    static constexpr uint32_t kSmokeItems = 4096;
    void makeSmoke() {
        m_kernel = std::make_unique<vk::Kernel>(layout(), "tests/smoke");
        m_in = storage(std::vector<uint32_t>(kSmokeItems, 1u));
        m_out = zeros(kSmokeItems * 4);
        m_work = std::make_unique<vk::DescriptorSet>(layout(), vk::DescriptorSet::Kind::Work, "smoke work");
        m_work->bind(0, m_in);
        m_work->bind(1, m_out);
    }
    // `dispatches` dispatches of the smoke kernel recorded into `batch`.
    void recordSmoke(vk::CommandBatch& batch, int dispatches) {
        batch.bind(*m_work);
        uint32_t count = kSmokeItems;
        for (int i = 0; i < dispatches; ++i) batch.dispatch(*m_kernel, count, count);
    }

private:
    std::unique_ptr<vk::Kernel> m_kernel;
    vk::Buffer m_in, m_out;
    std::unique_ptr<vk::DescriptorSet> m_work;
};

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
    makeSmoke();
    vk::GpuTimer timer(context());
    vk::CommandBatch batch(layout(), &timer);
    recordSmoke(batch, 3);
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
    makeSmoke();
    vk::GpuTimer timer(context());
    auto other = zeros(64);
    vk::CommandBatch first(layout(), &timer), second(layout(), &timer);
    for (vk::CommandBatch* b : {&first, &second}) {
        recordSmoke(*b, 2);
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
