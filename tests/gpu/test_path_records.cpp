// Path records (shared/path_types.h), written by the pt_record kernel for ERPT and PMC-ER:
// recording must not change the estimate (the same film as pt up to float rounding: bit for bit
// on lavapipe, while a GPU's compiler may fuse multiply-adds differently in the two kernels, 1
// ulp apart on an NVIDIA H200; sameEstimate), and each record must
// describe its sample: vertices on their triangles, contributions summing to the radiance,
// light connections on emitters, specular flags only on delta materials.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "gpu_test.h"
#include "methods/energy_redistribution/path_records.h"
#include "render/session.h"
#include "render_test.h"
#include "scene/environment.h"
#include "vk/command_batch.h"

namespace pmcr::test {
namespace {

class PathRecords : public GpuTest {};

// pt's and pt_record's estimates of one sample agree up to float rounding (a few ulps); a lost
// or doubled contribution is orders of magnitude more.
::testing::AssertionResult sameEstimate(const glm::vec3& plain, const glm::vec3& recorded) {
    for (int c = 0; c < 3; ++c) {
        const float scale = std::max(std::abs(plain[c]), std::abs(recorded[c]));
        if (std::abs(plain[c] - recorded[c]) > 1e-6f * scale)
            return ::testing::AssertionFailure()
                   << "pt " << plain[c] << ", pt_record " << recorded[c] << " (component " << c << ")";
    }
    return ::testing::AssertionSuccess();
}

// Distance from p to the plane of triangle t, and whether p is inside it (with slack).
bool onTriangle(const Scene& scene, uint32_t tri, const glm::vec3& p) {
    const gpu::Triangle& t = scene.triangles[tri];
    const glm::vec3 a = scene.vertices[t.i0].position, b = scene.vertices[t.i1].position,
                    c = scene.vertices[t.i2].position;
    const glm::vec3 n = glm::cross(b - a, c - a);
    const float area2 = glm::length(n);
    const float planeDistance = std::abs(glm::dot(p - a, n)) / area2;
    // Barycentrics by sub-areas.
    const float wa = glm::dot(glm::cross(b - p, c - p), n) / (area2 * area2);
    const float wb = glm::dot(glm::cross(c - p, a - p), n) / (area2 * area2);
    const float wc = 1.0f - wa - wb;
    const float scale = 1e-3f;
    return planeDistance < 1e-4f && wa > -scale && wb > -scale && wc > -scale;
}

TEST_F(PathRecords, RecordingKeepsTheEstimateAndDescribesEachSample) {
    const Scene& scene = testScene("scenes/cornell-spheres.glb");
    RenderSettings settings;
    settings.width = 32;
    settings.height = 32;
    RenderSession session(context(), scene, settings, 32, 32);
    const uint32_t pixels = 32 * 32;

    vk::Kernel pt(session.layout(), "methods/pt/pt");
    vk::Kernel ptRecord(session.layout(), "methods/pt/pt_record");
    Film& film = session.film();
    pmcr::PathRecords paths(context(), pixels, "test path");
    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "record work");
    paths.bindTracer(work, session, session.placeholder());

    gpu::PtPush push{};
    push.source = gpu::PT_SOURCE_TILE;
    push.flags = gpu::PT_FLAG_DEPOSIT;
    push.invocationCount = pixels;
    push.samplesPerPixel = 1;
    push.sampleBase = 3;
    push.seed = 11;
    push.maxDepth = 8;
    push.rrDepth = 3;
    auto renderWith = [&](const vk::Kernel& kernel, uint32_t perInvocation = 1) {
        film.clear();
        vk::CommandBatch batch(session.layout());
        batch.bind(session.scene().descriptorSet());
        batch.bind(work);
        push.itemsPerInvocation = perInvocation;
        batch.dispatch(kernel, push, (pixels + perInvocation - 1) / perInvocation);
        batch.submitAndWait();
        return film.download();
    };
    auto plain = renderWith(pt);
    auto recorded = renderWith(ptRecord);
    for (uint32_t i = 0; i < pixels; ++i) {
        ASSERT_TRUE(sameEstimate(plain[i].sum, recorded[i].sum)) << "pixel " << i;
        ASSERT_EQ(plain[i].sampleCount, recorded[i].sampleCount);
    }

    auto recs = paths.records().download<gpu::PathRecord>(pixels);
    auto verts = paths.vertices().download<gpu::PathVertex>(pixels * gpu::PATH_MAX_VERTICES);
    int withLight = 0, withEmitterHit = 0, specular = 0;
    for (uint32_t i = 0; i < pixels; ++i) {
        const gpu::PathRecord& r = recs[i];
        ASSERT_EQ(r.pixel, i);
        ASSERT_GE(r.raster.x, float(i % 32));
        ASSERT_LT(r.raster.x, float(i % 32 + 1));
        ASSERT_LE(r.vertexCount, push.maxDepth + 1);
        ASSERT_EQ(r.firstVertex, i * gpu::PATH_MAX_VERTICES);
        glm::vec3 sum(0.0f);
        for (uint32_t k = 0; k < r.vertexCount; ++k) {
            const gpu::PathVertex& v = verts[r.firstVertex + k];
            ASSERT_TRUE(onTriangle(scene, v.triangle, v.position)) << "record " << i << " vertex " << k;
            ASSERT_EQ(v.material, scene.triangles[v.triangle].material);
            const gpu::Material& m = scene.materials[v.material];
            if (v.flags & gpu::VERTEX_SPECULAR) {
                ++specular;
                // Only the smooth mirror and glass have delta lobes in this scene.
                ASSERT_TRUE(m.metallic > 0.0f || m.transmission > 0.0f) << scene.materialNames[v.material];
                ASSERT_LT(m.roughness, 0.05f);
            }
            if (v.flags & gpu::VERTEX_HAS_LIGHT_SAMPLE) {
                ++withLight;
                const gpu::Material& lm = scene.materials[scene.triangles[v.lightTriangle].material];
                ASSERT_GT(lm.emission.x + lm.emission.y + lm.emission.z, 0.0f);
                ASSERT_TRUE(onTriangle(scene, v.lightTriangle, v.lightPosition));
            }
            if (v.flags & gpu::VERTEX_EMITTER) ++withEmitterHit;
            sum += v.explicitContribution + v.implicitContribution;
        }
        const float tolerance = 1e-5f * std::max(1.0f, glm::length(r.radiance));
        ASSERT_NEAR(sum.x, r.radiance.x, tolerance) << "record " << i;
        ASSERT_NEAR(sum.y, r.radiance.y, tolerance);
        ASSERT_NEAR(sum.z, r.radiance.z, tolerance);
    }
    // The test image must exercise every kind of record.
    EXPECT_GT(withLight, int(pixels) / 2);
    EXPECT_GT(withEmitterHit, 0);
    EXPECT_GT(specular, 0);

    // Paths in turn (PtPush::itemsPerInvocation): the same film, records and vertices, bit for
    // bit, with 7 pixels per invocation.
    auto inTurn = renderWith(ptRecord, 7);
    auto recs7 = paths.records().download<gpu::PathRecord>(pixels);
    auto verts7 = paths.vertices().download<gpu::PathVertex>(pixels * gpu::PATH_MAX_VERTICES);
    for (uint32_t i = 0; i < pixels; ++i) {
        ASSERT_EQ(recorded[i].sum, inTurn[i].sum) << "pixel " << i;
        ASSERT_EQ(recorded[i].sampleCount, inTurn[i].sampleCount) << "pixel " << i;
        ASSERT_EQ(std::memcmp(&recs[i], &recs7[i], sizeof(gpu::PathRecord)), 0) << "record " << i;
        ASSERT_EQ(std::memcmp(&verts[recs[i].firstVertex], &verts7[recs[i].firstVertex],
                              recs[i].vertexCount * sizeof(gpu::PathVertex)), 0) << "record " << i;
    }
}

// With punctual lights and an environment (the _all_lights kernels): recording still keeps the
// estimate (sameEstimate), light samples of every kind are recorded (a punctual light's index, the
// environment's direction), rays that escape to the environment end the record with one vertex
// that is not a surface (shared/path_types.h), and the contributions still sum to the radiance.
TEST_F(PathRecords, OtherLightsAreRecordedAsSeedPaths) {
    Scene scene = testScene("scenes/cornell-glass.glb");
    const glm::vec3 size = scene.boundsMax - scene.boundsMin;
    gpu::PunctualLight point{};
    point.type = gpu::PUNCTUAL_POINT;
    point.position = scene.boundsMin + size * glm::vec3(0.3f, 0.85f, 0.55f);
    point.direction = glm::vec3(0, -1, 0);
    point.intensity = glm::vec3(glm::dot(size, size));
    scene.punctualLights = {point};
    scene.environment = loadEnvironment({"0.5,0.7,0.9"});
    scene.path = "cornell-glass-other-lights.glb";
    finalizeScene(scene);
    RenderSettings settings;
    settings.width = 32;
    settings.height = 32;
    RenderSession session(context(), scene, settings, 32, 32);
    const uint32_t pixels = 32 * 32;
    vk::Kernel pt(session.layout(), "methods/pt/pt_all_lights");
    vk::Kernel ptRecord(session.layout(), "methods/pt/pt_record_all_lights");
    Film& film = session.film();
    pmcr::PathRecords paths(context(), pixels, "test path");
    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "record work");
    paths.bindTracer(work, session, session.placeholder());
    gpu::PtPush push{};
    push.source = gpu::PT_SOURCE_TILE;
    push.flags = gpu::PT_FLAG_DEPOSIT;
    push.invocationCount = pixels;
    push.samplesPerPixel = 1;
    push.sampleBase = 5;
    push.seed = 13;
    push.maxDepth = 8;
    push.rrDepth = 3;
    push.itemsPerInvocation = 1;
    auto renderWith = [&](const vk::Kernel& kernel) {
        film.clear();
        vk::CommandBatch batch(session.layout());
        batch.bind(session.scene().descriptorSet());
        batch.bind(work);
        batch.dispatch(kernel, push, pixels);
        batch.submitAndWait();
        return film.download();
    };
    auto plain = renderWith(pt);
    auto recorded = renderWith(ptRecord);
    for (uint32_t i = 0; i < pixels; ++i)
        ASSERT_TRUE(sameEstimate(plain[i].sum, recorded[i].sum)) << "pixel " << i;

    auto recs = paths.records().download<gpu::PathRecord>(pixels);
    auto verts = paths.vertices().download<gpu::PathVertex>(pixels * gpu::PATH_MAX_VERTICES);
    int sampledPunctual = 0, sampledEnvironment = 0, escaped = 0;
    for (uint32_t i = 0; i < pixels; ++i) {
        const gpu::PathRecord& r = recs[i];
        glm::vec3 sum(0.0f);
        for (uint32_t k = 0; k < r.vertexCount; ++k) {
            const gpu::PathVertex& v = verts[r.firstVertex + k];
            if (v.flags & gpu::VERTEX_ENVIRONMENT) {
                ++escaped;
                ASSERT_EQ(k + 1, r.vertexCount) << "the environment ends a record";
                ASSERT_TRUE(v.flags & gpu::VERTEX_EMITTER);
            } else {
                ASSERT_TRUE(onTriangle(scene, v.triangle, v.position)) << "record " << i << " vertex " << k;
            }
            if (v.flags & gpu::VERTEX_SAMPLED_PUNCTUAL) {
                ++sampledPunctual;
                ASSERT_TRUE(v.flags & gpu::VERTEX_HAS_LIGHT_SAMPLE);
                ASSERT_EQ(v.lightTriangle, 0u);
            }
            if (v.flags & gpu::VERTEX_SAMPLED_ENVIRONMENT) {
                ++sampledEnvironment;
                ASSERT_TRUE(v.flags & gpu::VERTEX_HAS_LIGHT_SAMPLE);
                ASSERT_LE(std::abs(v.lightB1) + std::abs(v.lightB2), 1.0f + 1e-6f);  // octahedral
            }
            sum += v.explicitContribution + v.implicitContribution;
        }
        const float tolerance = 1e-5f * std::max(1.0f, glm::length(r.radiance));
        ASSERT_NEAR(sum.x, r.radiance.x, tolerance) << "record " << i;
        ASSERT_NEAR(sum.y, r.radiance.y, tolerance);
        ASSERT_NEAR(sum.z, r.radiance.z, tolerance);
    }
    std::printf("  %d punctual and %d environment light samples, %d escaped rays recorded\n",
                sampledPunctual, sampledEnvironment, escaped);
    EXPECT_GT(sampledPunctual, int(pixels) / 8);
    EXPECT_GT(sampledEnvironment, 0);
    EXPECT_GT(escaped, 0);
}

}  // namespace
}  // namespace pmcr::test
