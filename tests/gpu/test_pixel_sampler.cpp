// The camera samples' positions in their pixels as the path tracer draws them
// (shaders/methods/pt/camera_sample_kernel.glsl), read back from the pt_record kernel's path
// records: with KERNEL_OPTION_INDEPENDENT_PIXELS (--pixel-sampler independent) they are uniform in
// the pixel and independent from sample to sample (chi-square tests), where the default
// positions are stratified (a (0,2)-sequence: samples 2j and 2j + 1 of a pixel fall in opposite
// halves); request lists (PMC-IP, PMC-PT) draw the same positions as tiles.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "distribution_test.h"
#include "gpu_test.h"
#include "methods/energy_redistribution/path_records.h"
#include "render/session.h"
#include "render_test.h"
#include "vk/command_batch.h"

namespace pmcr::test {
namespace {

constexpr int kSide = 16;                          // image kSide x kSide
constexpr uint32_t kPixels = kSide * kSide;
constexpr uint32_t kSamplesPerDispatch = 16;       // per pixel
constexpr uint32_t kRecords = kPixels * kSamplesPerDispatch;

// pt_record on cornell-spheres, one bounce, specialized for `kernelOptions`.
class PixelPositions {
public:
    PixelPositions(vk::Context& context, uint32_t kernelOptions)
        : m_session(context, testScene("scenes/cornell-spheres.glb"), settings(), kSide, kSide),
          m_kernel(m_session.layout(), "methods/pt/pt_record", m_session.scene().features(),
                   kernelOptions),
          m_records(context, kRecords, "pixel sampler test"),
          m_work(m_session.layout(), vk::DescriptorSet::Kind::Work, "pixel sampler work") {}

    // Position in its pixel of sample s (0 .. spp - 1) of every pixel, at [pixel * spp + s]:
    // tiles of kSamplesPerDispatch samples, or with `requests` the same samples as one request
    // list per tile.
    std::vector<glm::vec2> draw(uint32_t spp, bool requests) {
        std::vector<glm::vec2> positions(size_t(kPixels) * spp);
        for (uint32_t base = 0; base < spp; base += kSamplesPerDispatch) {
            gpu::PtPush push{};
            push.seed = 5;
            push.maxDepth = 1;
            push.rrDepth = 3;
            push.lightSamples = 1;
            push.sampleBase = base;
            std::vector<gpu::SampleRequest> list;
            if (requests) {
                for (uint32_t p = 0; p < kPixels; ++p)
                    for (uint32_t k = 0; k < kSamplesPerDispatch; ++k)
                        list.push_back({p, base + k, glm::vec2(0.0f)});
                push.source = gpu::PT_SOURCE_LIST;
                push.invocationCount = kRecords;
            } else {
                push.source = gpu::PT_SOURCE_TILE;
                push.invocationCount = kPixels;
                push.samplesPerPixel = kSamplesPerDispatch;
            }
            vk::Buffer requestBuffer =
                requests ? vk::Buffer::storage(m_session.context(), list, "pixel sampler requests")
                         : vk::Buffer();
            m_records.bindTracer(m_work, m_session,
                                 requests ? requestBuffer : m_session.placeholder());
            vk::CommandBatch batch(m_session.layout());
            batch.bind(m_session.scene().descriptorSet());
            batch.bind(m_work);
            batch.dispatch(m_kernel, push, push.invocationCount);
            batch.submitAndWait();
            // Record i of either source is sample base + i % kSamplesPerDispatch of pixel
            // i / kSamplesPerDispatch.
            const auto records = m_records.records().download<gpu::PathRecord>(kRecords);
            for (uint32_t i = 0; i < kRecords; ++i) {
                const uint32_t pixel = i / kSamplesPerDispatch, s = base + i % kSamplesPerDispatch;
                const glm::vec2 corner(float(pixel % kSide), float(pixel / kSide));
                positions[size_t(pixel) * spp + s] = records[i].raster - corner;
            }
        }
        return positions;
    }

private:
    static RenderSettings settings() {
        RenderSettings s;
        s.width = kSide;
        s.height = kSide;
        return s;
    }
    RenderSession m_session;
    vk::Kernel m_kernel;
    PathRecords m_records;
    vk::DescriptorSet m_work;
};

int cell(float u, int bins) { return std::clamp(int(u * float(bins)), 0, bins - 1); }

TEST_F(GpuTest, IndependentPixelSamplesAreUniformAndIndependent) {
    PixelPositions independent(context(), gpu::KERNEL_OPTION_INDEPENDENT_PIXELS);
    const uint32_t spp = 256;
    const auto positions = independent.draw(spp, false);
    for (const glm::vec2& u : positions) {
        ASSERT_GE(u.x, 0.0f);
        ASSERT_LE(u.x, 1.0f);
        ASSERT_GE(u.y, 0.0f);
        ASSERT_LE(u.y, 1.0f);
    }
    // Uniform in the pixel: 65536 positions over 16 x 16 cells of the pixel.
    const int bins = 16;
    auto uniform = [&](size_t n) {
        return std::vector<double>(bins * bins, double(n) / (bins * bins));
    };
    std::vector<double> inPixel(bins * bins, 0.0);
    for (const glm::vec2& u : positions)
        inPixel[size_t(cell(u.x, bins) * bins + cell(u.y, bins))] += 1.0;
    EXPECT_TRUE(chi2Passes(inPixel, uniform(positions.size()),
                           "independent positions in the pixel"));
    // Independent from sample to sample: the x of samples 2j and 2j + 1 of a pixel, jointly
    // uniform; stratified positions put them in opposite halves of the pixel, every time.
    auto pairs = [&](const std::vector<glm::vec2>& p, int& same) {
        std::vector<double> joint(bins * bins, 0.0);
        same = 0;
        for (size_t i = 0; i + 1 < p.size(); i += 2) {
            joint[size_t(cell(p[i].x, bins) * bins + cell(p[i + 1].x, bins))] += 1.0;
            same += (p[i].x < 0.5f) == (p[i + 1].x < 0.5f);
        }
        return joint;
    };
    int sameHalf = 0;
    const auto joint = pairs(positions, sameHalf);
    EXPECT_TRUE(chi2Passes(joint, uniform(positions.size() / 2),
                           "x of consecutive independent samples of a pixel"));
    EXPECT_GT(sameHalf, 0);
    PixelPositions stratified(context(), 0);
    pairs(stratified.draw(32, false), sameHalf);
    EXPECT_EQ(sameHalf, 0) << "the default positions are stratified";
}

// pmc-ip and pmc-pt ask for samples by (pixel, sample index) in request lists: the same
// positions as tiles, with either sampler.
TEST_F(GpuTest, RequestListsDrawTheTilesPixelPositions) {
    for (uint32_t options : {0u, gpu::KERNEL_OPTION_INDEPENDENT_PIXELS}) {
        PixelPositions rig(context(), options);
        const auto tiles = rig.draw(kSamplesPerDispatch, false);
        const auto lists = rig.draw(kSamplesPerDispatch, true);
        for (size_t i = 0; i < tiles.size(); ++i)
            ASSERT_EQ(tiles[i], lists[i]) << "sample " << i << ", kernel options " << options;
    }
}

}  // namespace
}  // namespace pmcr::test
