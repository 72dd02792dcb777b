// Embree 3 (Debian libembree-dev) as the speed anchor of bench/throughput: the same triangles,
// the same rays, traced by a native CPU ray tracer on as many threads as lavapipe uses. Only the
// benchmark includes this file (PMCR_HAVE_EMBREE, set by bench/CMakeLists.txt when Embree is
// found); pmcr itself never needs Embree.
//
// Each ray set is traced with Embree's single-ray API (rtcIntersect1 / rtcOccluded1), its 8-wide
// packets (rtcIntersect8 / rtcOccluded8, eight consecutive rays of the set) and its ray streams
// (rtcIntersect1M / rtcOccluded1M, coherent flag on primary rays), each best of `repeats` runs;
// the benchmark reports the fastest. The BVH is built with RTC_BUILD_QUALITY_HIGH.
#pragma once

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "core/error.h"
#include "scene/scene.h"

namespace pmcr::bench {

class EmbreeTracer {
public:
    enum class Api { Single, Packet8, Stream };
    static const char* apiName(Api api) {
        return api == Api::Single ? "rtcIntersect1" : api == Api::Packet8 ? "rtcIntersect8" : "rtcIntersect1M";
    }

    EmbreeTracer(const Scene& scene, unsigned threads) : m_threads(std::max(1u, threads)) {
        const std::string config = "threads=" + std::to_string(m_threads);
        m_device = rtcNewDevice(config.c_str());
        if (!m_device) throw Error("embree: rtcNewDevice failed");
        m_scene = rtcNewScene(m_device);
        rtcSetSceneBuildQuality(m_scene, RTC_BUILD_QUALITY_HIGH);
        RTCGeometry geometry = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
        auto* positions = static_cast<float*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), scene.vertices.size()));
        for (size_t i = 0; i < scene.vertices.size(); ++i)
            std::memcpy(positions + 3 * i, &scene.vertices[i].position, 3 * sizeof(float));
        auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), scene.triangles.size()));
        for (size_t i = 0; i < scene.triangles.size(); ++i) {
            indices[3 * i] = scene.triangles[i].i0;
            indices[3 * i + 1] = scene.triangles[i].i1;
            indices[3 * i + 2] = scene.triangles[i].i2;
        }
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(m_scene, geometry);
        rtcReleaseGeometry(geometry);
        rtcCommitScene(m_scene);
    }
    ~EmbreeTracer() {
        rtcReleaseScene(m_scene);
        rtcReleaseDevice(m_device);
    }
    EmbreeTracer(const EmbreeTracer&) = delete;
    EmbreeTracer& operator=(const EmbreeTracer&) = delete;

    struct Result {
        double seconds = 0.0;  // best of the repeats
        std::vector<gpu::Hit> hits;  // closest: triangle (BVH_NO_HIT on a miss) and t; any: t = 0 on a hit
    };

    // Traces `rays` (closest hit, or occlusion with anyHit) with `api`; best of `repeats` runs.
    Result trace(const std::vector<gpu::BvhQuery>& rays, bool anyHit, bool coherent, Api api,
                 int repeats) const {
        Result r;
        r.hits.resize(rays.size());
        r.seconds = 1e30;
        for (int rep = 0; rep < repeats; ++rep) {
            const auto start = std::chrono::steady_clock::now();
            parallelChunks(rays.size(), [&](size_t begin, size_t end) {
                traceRange(rays, begin, end, anyHit, coherent, api, r.hits);
            });
            r.seconds = std::min(
                r.seconds, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        }
        return r;
    }

private:
    // Splits [0, n) into chunks of 256 rays (a multiple of 8) taken by m_threads threads.
    template <typename F>
    void parallelChunks(size_t n, F&& f) const {
        constexpr size_t kChunk = 256;
        std::atomic<size_t> next{0};
        auto worker = [&] {
            for (size_t begin; (begin = next.fetch_add(kChunk)) < n;) f(begin, std::min(n, begin + kChunk));
        };
        std::vector<std::thread> pool;
        for (unsigned t = 1; t < m_threads; ++t) pool.emplace_back(worker);
        worker();
        for (auto& t : pool) t.join();
    }

    static void setRay(RTCRay& ray, const gpu::BvhQuery& q) {
        ray.org_x = q.origin.x;
        ray.org_y = q.origin.y;
        ray.org_z = q.origin.z;
        ray.tnear = 0.0f;
        ray.dir_x = q.direction.x;
        ray.dir_y = q.direction.y;
        ray.dir_z = q.direction.z;
        ray.time = 0.0f;
        ray.tfar = q.tMax;
        ray.mask = ~0u;
        ray.id = 0;
        ray.flags = 0;
    }

    void traceRange(const std::vector<gpu::BvhQuery>& rays, size_t begin, size_t end, bool anyHit,
                    bool coherent, Api api, std::vector<gpu::Hit>& hits) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        if (coherent) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        auto store = [&](size_t i, float tfar, unsigned geomID, unsigned primID, float u, float v) {
            if (anyHit) hits[i] = {tfar < 0.0f ? 0.0f : rays[i].tMax, 0u, 0.0f, 0.0f};
            else if (geomID == RTC_INVALID_GEOMETRY_ID) hits[i] = {rays[i].tMax, gpu::BVH_NO_HIT, 0.0f, 0.0f};
            else hits[i] = {tfar, primID, u, v};
        };
        if (api == Api::Single) {
            for (size_t i = begin; i < end; ++i) {
                RTCRayHit rh;
                setRay(rh.ray, rays[i]);
                if (anyHit) {
                    rtcOccluded1(m_scene, &context, &rh.ray);
                    store(i, rh.ray.tfar, 0, 0, 0, 0);
                } else {
                    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                    rtcIntersect1(m_scene, &context, &rh);
                    store(i, rh.ray.tfar, rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v);
                }
            }
        } else if (api == Api::Stream) {
            const size_t n = end - begin;
            std::vector<RTCRayHit> batch(n);
            for (size_t k = 0; k < n; ++k) {
                setRay(batch[k].ray, rays[begin + k]);
                batch[k].hit.geomID = RTC_INVALID_GEOMETRY_ID;
            }
            if (anyHit) {
                rtcOccluded1M(m_scene, &context, &batch[0].ray, unsigned(n), sizeof(RTCRayHit));
                for (size_t k = 0; k < n; ++k) store(begin + k, batch[k].ray.tfar, 0, 0, 0, 0);
            } else {
                rtcIntersect1M(m_scene, &context, batch.data(), unsigned(n), sizeof(RTCRayHit));
                for (size_t k = 0; k < n; ++k)
                    store(begin + k, batch[k].ray.tfar, batch[k].hit.geomID, batch[k].hit.primID,
                          batch[k].hit.u, batch[k].hit.v);
            }
        } else {
            for (size_t base = begin; base < end; base += 8) {
                alignas(32) int valid[8];
                alignas(32) RTCRayHit8 rh;
                for (int k = 0; k < 8; ++k) {
                    const size_t i = std::min(base + k, end - 1);
                    valid[k] = base + k < end ? -1 : 0;
                    const gpu::BvhQuery& q = rays[i];
                    rh.ray.org_x[k] = q.origin.x;
                    rh.ray.org_y[k] = q.origin.y;
                    rh.ray.org_z[k] = q.origin.z;
                    rh.ray.tnear[k] = 0.0f;
                    rh.ray.dir_x[k] = q.direction.x;
                    rh.ray.dir_y[k] = q.direction.y;
                    rh.ray.dir_z[k] = q.direction.z;
                    rh.ray.time[k] = 0.0f;
                    rh.ray.tfar[k] = q.tMax;
                    rh.ray.mask[k] = ~0u;
                    rh.ray.id[k] = 0;
                    rh.ray.flags[k] = 0;
                    rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                }
                if (anyHit) rtcOccluded8(valid, m_scene, &context, &rh.ray);
                else rtcIntersect8(valid, m_scene, &context, &rh);
                for (int k = 0; k < 8 && base + k < end; ++k)
                    store(base + k, rh.ray.tfar[k], rh.hit.geomID[k], rh.hit.primID[k], rh.hit.u[k], rh.hit.v[k]);
            }
        }
    }

    unsigned m_threads;
    RTCDevice m_device = nullptr;
    RTCScene m_scene = nullptr;
};

}  // namespace pmcr::bench
