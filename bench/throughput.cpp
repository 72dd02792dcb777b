// Ray-traversal throughput: the GPU kernel (shaders/common/bvh.glsl) against Embree (the speed
// anchor, when found at configure time) and the host's scalar C++ traversal of the same BVH on one
// thread, for coherent primary rays, incoherent bounce rays and shadow (any-hit) rays, plus
// path-tracing samples per second. Prints one table, or with --json one object per scene; ratios
// are measured in the same run on the same machine.
//
//   pmcr-bench-throughput [--width W] [--height H] [--device ID] [--repeats N] [--threads T]
//                         [--cpu-time] [--steps] [--fetch-ceiling] [--step-ceiling SMALL]
//                         [--rays-per-invocation P]
//                         [--json] [SCENE...]
#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <numeric>
#include <random>
#include <thread>

#include <nlohmann/json.hpp>
#include <sys/resource.h>

#include "cli/args.h"
#include "core/error.h"
#include "core/log.h"
#include "render/gpu_scene.h"
#include "render/renderer.h"
#include "scene/bvh.h"
#include "scene/gltf_loader.h"
#include "scene/scene.h"
#include "vk/command_batch.h"
#include "vk/context.h"
#ifdef PMCR_HAVE_EMBREE
#include "embree_tracer.h"
#endif

using namespace pmcr;

namespace {

using Clock = std::chrono::steady_clock;

const char* const kUsage =
    "usage: pmcr-bench-throughput [--width W] [--height H] [--device ID] [--repeats N]\n"
    "                             [--threads T] [--cpu-time] [--steps] [--fetch-ceiling]\n"
    "                             [--step-ceiling SMALL] [--rays-per-invocation P] [--json] SCENE...\n"
    "       (bench/throughput runs it on the default scene and the dragon)\n"
    "\n"
    "Traces three ray sets: primary rays (one per pixel of a W x H image, default 256 x 256,\n"
    "through the scene's camera), cosine-distributed bounce rays from their hits, and shadow\n"
    "(any-hit) rays from the bounce rays' hits to random emitter points (chosen by power,\n"
    "uniform on the triangle). Each set is traced by the GPU kernel (shaders/common/bvh.glsl, one\n"
    "dispatch, shader compiled beforehand), by Embree 3 with a high-quality BVH on T threads (the\n"
    "fastest of rtcIntersect1, rtcIntersect8 and rtcIntersect1M; only when the benchmark was\n"
    "built with Embree) and by the host's scalar C++ traversal of pmcr's BVH on one thread; each\n"
    "timing is the best of N runs. Prints Mrays/s and the GPU/Embree ratios, and path-tracing\n"
    "samples/s (pt, 4 spp at W x H, over its sampling time, best of N renders). Warns when the\n"
    "tracers' hits disagree.\n"
    "Ratios are measured in one run on one machine; compare ratios, not absolute rates.\n"
    "  --width W --height H  ray set size (16..4096, default 256)\n"
    "  --device ID           Vulkan device index or name substring (see pmcr --list-devices)\n"
    "  --repeats N           runs of each timing, the best kept (1..20, default 3)\n"
    "  --threads T           Embree's threads (default: $LP_NUM_THREADS, else the CPU count,\n"
    "                        the threads lavapipe uses)\n"
    "  --json                print a JSON array on stdout, one object per scene, nothing else:\n"
    "                        scene, triangles, {gpu,embree}_{primary,bounce,shadow}_mrays,\n"
    "                        cpu_{primary,bounce}_mrays, pt_msamples (Embree keys null\n"
    "                        without Embree)\n"
    "  --steps               also print the kernel's traversal steps per ray (wide nodes, leaf\n"
    "                        steps of two triangles) and the share of an 8-lane vector's steps\n"
    "                        that do work\n"
    "                        (the loop runs until its slowest lane is done), and the GPU's\n"
    "                        Mrays/s on the same rays sorted by their steps (lanes kept busy)\n"
    "  --fetch-ceiling       --steps, and the Mrays/s of the traversal's texel fetches\n"
    "                        alone (shaders/bench/fetch_steps.comp: each ray's steps, 7 or 4\n"
    "                        texels a step, no arithmetic or stack), an upper bound on any\n"
    "                        traversal that fetches that much per step with lanes as idle\n"
    "  --step-ceiling SMALL  --steps, and the Mrays/s each ray set would reach with free memory\n"
    "                        reads: the kernel's cost per step and per ray, fitted on scene SMALL\n"
    "                        (e.g. scenes/cornell-classic.glb, 36 triangles: its BVH stays\n"
    "                        in the L1 cache), times each ray's steps; with the measured idle\n"
    "                        lanes and with none\n"
    "  --rays-per-invocation P  trace P rays in turn per invocation, a lane starting its next\n"
    "                        ray when its last ends (1..64, default 1)\n"
    "  --cpu-time            also print Mrays/s per CPU second: the process's CPU time during\n"
    "                        the dispatch (on lavapipe, its worker threads) and the tracing\n"
    "                        thread's CPU time; steadier than wall time on a loaded machine\n";

// CPU seconds used so far by the whole process (every thread, lavapipe's workers included).
double processCpu() {
    rusage u;
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}
// CPU seconds used so far by the calling thread.
double threadCpu() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}
double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

// The fastest of `repeats` timings of one dispatch that `record` records into a batch (with the
// scene's descriptor set and `work` bound), in seconds per dispatch, and the
// process's CPU seconds per dispatch in that timing. On a GPU a timing runs as many dispatches
// in one batch as take about kBatchSeconds: one there takes about a millisecond, and a lone
// submission (its latency, the clocks of an idle GPU) would be most of what is timed; its rates
// moved 2-3x between runs (docs/benchmarks.md). On a CPU device (lavapipe) a dispatch takes tens
// of milliseconds and is timed alone: two in a batch measured slower per dispatch there (the
// dragon's primary rays at 5 rather than 8 Mrays/s in two of three runs).
struct DispatchTiming {
    double seconds = 1e30;
    double cpuSeconds = 0.0;
};
DispatchTiming timeDispatches(const vk::Context& context, const vk::PipelineLayout& layout,
                              const GpuScene& scene, const vk::DescriptorSet& work,
                              const std::function<void(vk::CommandBatch&)>& record, int repeats) {
    constexpr double kBatchSeconds = 0.05;
    constexpr int kMaxDispatches = 4096;
    auto run = [&](int dispatches, DispatchTiming& best) {
        const auto start = Clock::now();
        const double cpuStart = processCpu();
        vk::CommandBatch batch(layout);
        batch.bind(scene.descriptorSet());
        batch.bind(work);
        for (int d = 0; d < dispatches; ++d) record(batch);
        batch.submitAndWait();
        const double seconds = secondsSince(start) / dispatches;
        if (seconds < best.seconds) best = {seconds, (processCpu() - cpuStart) / dispatches};
    };
    DispatchTiming one;
    run(1, one);  // also the warm-up: the first dispatch compiles the shader on lavapipe
    run(1, one);
    const int dispatches =
        context.isCpuDevice()
            ? 1
            : int(std::clamp(std::ceil(kBatchSeconds / std::max(one.seconds, 1e-9)), 1.0, double(kMaxDispatches)));
    DispatchTiming best;
    for (int rep = 0; rep < repeats; ++rep) run(dispatches, best);
    return best;
}

// Primary rays through jittered pixel positions of the scene's camera.
std::vector<gpu::BvhQuery> primaryRays(const gpu::SceneInfo& info, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<gpu::BvhQuery> rays;
    rays.reserve(size_t(info.width) * info.height);
    for (uint32_t y = 0; y < info.height; ++y)
        for (uint32_t x = 0; x < info.width; ++x) {
            const float px = float(x) + u(rng), py = float(y) + u(rng);
            const float sx = (2.0f * px / float(info.width) - 1.0f) * info.tanHalfFovY * info.aspect;
            const float sy = (1.0f - 2.0f * py / float(info.height)) * info.tanHalfFovY;
            glm::vec3 d = glm::normalize(info.cameraForward + sx * info.cameraRight + sy * info.cameraUp);
            rays.push_back({info.cameraPosition, 1e30f, d, 0});
        }
    return rays;
}

// Where `ray` hits: the point, the triangle's geometric normal turned to face the ray's origin,
// and an origin for rays leaving it (offset along that normal, relative to the point's size).
struct SurfaceHit {
    glm::vec3 point, normal, spawn;
};
SurfaceHit surfaceHit(const Scene& scene, const gpu::BvhQuery& ray, const gpu::Hit& hit) {
    const gpu::Triangle& t = scene.triangles[hit.triangle];
    const glm::vec3 p0 = scene.vertices[t.i0].position, p1 = scene.vertices[t.i1].position,
                    p2 = scene.vertices[t.i2].position;
    glm::vec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    if (glm::dot(n, ray.direction) > 0.0f) n = -n;
    const glm::vec3 p = ray.origin + hit.t * ray.direction;
    return {p, n, p + n * 1e-4f * std::max(1.0f, glm::length(p))};
}

// Bounce rays: from each primary hit, a cosine-distributed direction about the surface normal
// (Malley's method: a uniform point of the unit disk, r = sqrt(u1), lifted to the hemisphere;
// pbrt-v4 section A.5.3).
std::vector<gpu::BvhQuery> bounceRays(const Scene& scene, const std::vector<gpu::BvhQuery>& primary,
                                      const std::vector<gpu::Hit>& hits, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<gpu::BvhQuery> rays;
    for (size_t i = 0; i < primary.size(); ++i) {
        if (hits[i].triangle == gpu::BVH_NO_HIT) continue;
        const SurfaceHit s = surfaceHit(scene, primary[i], hits[i]);
        const glm::vec3& n = s.normal;
        const float r = std::sqrt(u(rng)), phi = 6.2831853f * u(rng);
        const glm::vec3 a = std::abs(n.x) > 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
        const glm::vec3 tx = glm::normalize(glm::cross(a, n)), ty = glm::cross(n, tx);
        const glm::vec3 d = glm::normalize(r * std::cos(phi) * tx + r * std::sin(phi) * ty +
                                           std::sqrt(std::max(0.0f, 1.0f - r * r)) * n);
        rays.push_back({s.spawn, 1e30f, d, 0});
    }
    return rays;
}

// Shadow rays: from each bounce ray's hit towards a random emitter point (an emitter chosen by
// power as the renderer's light sampling does, a uniform point on its triangle by the
// square-root mapping b0 = 1 - sqrt(u1), b1 = u2 sqrt(u1); Osada et al. 2002, eq. 1), ending
// just short of it. Traced as any-hit queries.
std::vector<gpu::BvhQuery> shadowRays(const Scene& scene, const std::vector<gpu::BvhQuery>& bounce,
                                      const std::vector<gpu::Hit>& hits, std::mt19937& rng) {
    const EmitterTable table = buildEmitters(scene);
    std::vector<double> weights;
    for (const gpu::Emitter& e : table.emitters) weights.push_back(e.pmf);
    std::discrete_distribution<size_t> pick(weights.begin(), weights.end());
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<gpu::BvhQuery> rays;
    for (size_t i = 0; i < bounce.size(); ++i) {
        if (hits[i].triangle == gpu::BVH_NO_HIT) continue;
        const glm::vec3 o = surfaceHit(scene, bounce[i], hits[i]).spawn;
        const gpu::Triangle& l = scene.triangles[table.emitters[pick(rng)].triangle];
        const float su = std::sqrt(u(rng)), b1 = 1.0f - su, b2 = u(rng) * su;
        const glm::vec3 q = (1.0f - b1 - b2) * scene.vertices[l.i0].position +
                            b1 * scene.vertices[l.i1].position + b2 * scene.vertices[l.i2].position;
        const float dist = glm::length(q - o);
        if (!(dist > 0.0f)) continue;
        rays.push_back({o, dist * (1.0f - 1e-4f), (q - o) / dist, 0});
    }
    return rays;
}

struct Timing {
    double seconds = 0.0;
    double cpuSeconds = 0.0;  // threadCpu (host traversal) or processCpu (GPU dispatch)
    std::vector<gpu::Hit> hits;
};

Timing traceCpu(const Bvh& bvh, const std::vector<gpu::BvhQuery>& rays, bool anyHit, int repeats) {
    Timing t;
    t.hits.resize(rays.size());
    t.seconds = 1e30;
    for (int rep = 0; rep < repeats; ++rep) {
        auto start = Clock::now();
        const double cpuStart = threadCpu();
        for (size_t i = 0; i < rays.size(); ++i) {
            if (anyHit) {
                const bool hit = bvh.traceAny(rays[i].origin, rays[i].direction, rays[i].tMax);
                t.hits[i] = {hit ? 0.0f : rays[i].tMax, 0u, 0.0f, 0.0f};
            } else if (!bvh.traceClosest(rays[i].origin, rays[i].direction, rays[i].tMax, t.hits[i])) {
                t.hits[i].triangle = gpu::BVH_NO_HIT;
            }
        }
        const double seconds = secondsSince(start);
        if (seconds < t.seconds) {
            t.seconds = seconds;
            t.cpuSeconds = threadCpu() - cpuStart;
        }
    }
    return t;
}

Timing traceGpu(vk::Context& context, const vk::PipelineLayout& layout, const GpuScene& scene,
                const std::vector<gpu::BvhQuery>& rays, bool anyHit, int repeats,
                uint32_t raysPerInvocation, const char* kernelName = "bench/trace_rays") {
    vk::Kernel kernel(layout, kernelName);
    auto queries = vk::Buffer::storage(context, rays, "bench rays");
    vk::Buffer hits(context, std::max<size_t>(16, rays.size() * sizeof(gpu::Hit)),
                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "bench hits");
    vk::DescriptorSet work(layout, vk::DescriptorSet::Kind::Work, "bench work");
    work.bind(0, queries);
    work.bind(1, hits);
    struct Push {
        uint32_t count;
        uint32_t anyHit;
        uint32_t raysPerInvocation;
    };
    const uint32_t flag = anyHit ? 1u : 0u;
    const uint32_t count = uint32_t(rays.size());
    const DispatchTiming d = timeDispatches(
        context, layout, scene, work,
        [&](vk::CommandBatch& batch) {
            batch.dispatch(kernel, Push{count, flag, raysPerInvocation},
                           (count + raysPerInvocation - 1) / raysPerInvocation);
        },
        repeats);
    Timing t;
    t.seconds = d.seconds;
    t.cpuSeconds = d.cpuSeconds;
    t.hits = hits.download<gpu::Hit>(rays.size());
    return t;
}

// Share of rays on which two tracers agree: the same triangle, or hits at the same distance
// (a ray through a shared edge may report either triangle); for any-hit sets, the same answer.
double agreement(const std::vector<gpu::Hit>& a, const std::vector<gpu::Hit>& b, bool anyHit) {
    size_t same = 0;
    if (anyHit) {  // every tracer stores t = 0 for occluded, tMax for clear
        for (size_t i = 0; i < a.size(); ++i) same += (a[i].t == 0.0f) == (b[i].t == 0.0f);
        return a.empty() ? 1.0 : double(same) / double(a.size());
    }
    for (size_t i = 0; i < a.size(); ++i)
        same += a[i].triangle == b[i].triangle ||
                (a[i].triangle != gpu::BVH_NO_HIT && b[i].triangle != gpu::BVH_NO_HIT &&
                 std::abs(a[i].t - b[i].t) <= 1e-5f * std::max(1.0f, a[i].t));
    return a.empty() ? 1.0 : double(same) / double(a.size());
}

// The steps the kernel's loop runs when the rays `order` lists run 8 at a time as the lanes of
// one vector (lavapipe's 8 consecutive invocations): each vector's loop runs until its slowest
// lane is done, so the sum over vectors of their longest ray's steps.
double vectorSteps(const std::vector<uint32_t>& steps, const std::vector<size_t>& order) {
    double sum = 0.0;
    for (size_t first = 0; first < order.size(); first += 8) {
        uint32_t longest = 0;
        for (size_t i = first; i < std::min(first + 8, order.size()); ++i)
            longest = std::max(longest, steps[order[i]]);
        sum += longest;
    }
    return sum;
}

// The share of those lane-steps that do work: 1 when no lane idles.
double laneEfficiency(const std::vector<uint32_t>& steps, const std::vector<size_t>& order) {
    double lane = 0.0;
    for (size_t i : order) lane += steps[i];
    const double vector = 8.0 * vectorSteps(steps, order);
    return vector > 0.0 ? lane / vector : 1.0;
}

// 0, 1, ..., n - 1: the rays in their own order.
std::vector<size_t> inOrder(size_t n) {
    std::vector<size_t> order(n);
    std::iota(order.begin(), order.end(), size_t{0});
    return order;
}

// What the kernel's traversal loop does per ray (trace_rays_steps.comp): wide-node and leaf
// steps, on average, and per ray in all.
struct StepCounts {
    double node = 0.0, leaf = 0.0;
    std::vector<uint32_t> steps;
};
StepCounts countSteps(vk::Context& context, const vk::PipelineLayout& layout, const GpuScene& scene,
                      const std::vector<gpu::BvhQuery>& rays, bool anyHit) {
    const Timing t = traceGpu(context, layout, scene, rays, anyHit, 1, 1, "bench/trace_rays_steps");
    StepCounts c;
    for (size_t i = 0; i < rays.size(); ++i) {
        const uint32_t node = std::bit_cast<uint32_t>(t.hits[i].b1);
        const uint32_t leaf = std::bit_cast<uint32_t>(t.hits[i].b2);
        c.node += node;
        c.leaf += leaf;
        c.steps.push_back(node + leaf);
    }
    c.node /= double(std::max<size_t>(1, rays.size()));
    c.leaf /= double(std::max<size_t>(1, rays.size()));
    return c;
}

// Mrays/s of fetch_steps.comp over rays that take `steps` steps each, fetchesPerStep texels a
// step: the traversal's fetches alone, best of `repeats`.
double fetchCeiling(vk::Context& context, const vk::PipelineLayout& layout, const GpuScene& scene,
                    const std::vector<uint32_t>& steps, uint32_t fetchesPerStep, int repeats) {
    vk::Kernel kernel(layout, "bench/fetch_steps", 0, fetchesPerStep);  // constant 1: kFetchesPerStep
    auto stepBuffer = vk::Buffer::storage(context, steps, "bench steps");
    vk::Buffer out(context, std::max<size_t>(16, steps.size() * 16), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                   "bench fetch results");
    vk::DescriptorSet work(layout, vk::DescriptorSet::Kind::Work, "bench fetch work");
    work.bind(0, stepBuffer);
    work.bind(1, out);
    struct Push {
        uint32_t count;
    };
    const uint32_t count = uint32_t(steps.size());
    const double best =
        timeDispatches(context, layout, scene, work,
                       [&](vk::CommandBatch& batch) { batch.dispatch(kernel, Push{count}, count); }, repeats)
            .seconds;
    return best > 0.0 ? double(count) / best * 1e-6 : 0.0;
}

// The traversal's cost with its memory reads nearly free: the kernel's time per 8-lane vector
// step and per vector of rays (loading the ray, storing the hit), for closest-hit and any-hit
// rays, fitted on a scene small enough for its whole BVH to stay in the L1 cache. A set of rays
// takes about vectors * perVector + steps * perStep there, where steps is vectorSteps(); two
// sets per kind give the two costs: the scene's own rays, and as many rays from outside the
// scene pointing away from it, which end after one step.
struct StepCost {
    double perStep[2] = {0.0, 0.0};    // seconds, [closest hit, any hit]
    double perVector[2] = {0.0, 0.0};
};

StepCost measureStepCost(vk::Context& context, const vk::PipelineLayout& layout, const std::string& path,
                         int width, int height, int repeats) {
    Scene scene = loadScene(path);
    GpuScene gpuScene(context, layout, scene, 0, width, height);
    std::mt19937 rng(7);
    auto primary = primaryRays(gpuScene.info(), rng);
    auto bounce = bounceRays(scene, primary, traceCpu(gpuScene.bvh(), primary, false, 1).hits, rng);
    auto shadow = shadowRays(scene, bounce, traceCpu(gpuScene.bvh(), bounce, false, 1).hits, rng);
    const glm::vec3 away = glm::normalize(glm::vec3(1.0f, 1.0f, 1.0f));
    const glm::vec3 start = scene.boundsMax + (scene.boundsMax - scene.boundsMin + 1.0f);
    // Each set repeated 8 times, so that a dispatch lasts long enough (about 0.2 s on two
    // lavapipe threads) for the fit not to follow the scheduling noise of short ones.
    const int copies = 8;
    auto repeated = [&](const std::vector<gpu::BvhQuery>& rays) {
        std::vector<gpu::BvhQuery> r;
        for (int i = 0; i < copies; ++i) r.insert(r.end(), rays.begin(), rays.end());
        return r;
    };
    bounce = repeated(bounce);
    shadow = repeated(shadow);
    StepCost cost;
    for (int kind = 0; kind < 2; ++kind) {
        const bool anyHit = kind == 1;
        const std::vector<gpu::BvhQuery>& rays = anyHit ? shadow : bounce;
        const std::vector<gpu::BvhQuery> one(rays.size(), gpu::BvhQuery{start, 1e30f, away, 0u});
        const double vectors = double((rays.size() + 7) / 8);
        const double steps = vectorSteps(countSteps(context, layout, gpuScene, rays, anyHit).steps,
                                         inOrder(rays.size()));
        const double all = traceGpu(context, layout, gpuScene, rays, anyHit, repeats, 1).seconds;
        const double oneTime = traceGpu(context, layout, gpuScene, one, anyHit, repeats, 1).seconds;
        if (steps < 2.0 * vectors)
            throw Error(path + ": its rays take about one traversal step each, too few to fit a step's "
                        "cost (--step-ceiling wants a scene of a few dozen triangles)");
        // all = vectors perVector + steps perStep, oneTime = vectors (perVector + perStep).
        cost.perStep[kind] = std::max(0.0, (all - oneTime) / (steps - vectors));
        cost.perVector[kind] = std::max(0.0, oneTime / vectors - cost.perStep[kind]);
    }
    return cost;
}

// Mrays/s of one ray set by each tracer.
struct RaySetResult {
    double gpu = 0.0, embree = 0.0, cpu = 0.0;
    double gpuPerCpuSecond = 0.0, cpuPerCpuSecond = 0.0;
    const char* embreeApi = "";
    double agreeCpu = 1.0, agreeEmbree = 1.0;
};

RaySetResult measure(vk::Context& context, const vk::PipelineLayout& layout, const GpuScene& gpuScene,
                     [[maybe_unused]] const void* embree, const std::vector<gpu::BvhQuery>& rays,
                     bool anyHit, [[maybe_unused]] bool coherent, int repeats,
                     uint32_t raysPerInvocation, Timing& cpu) {
    auto mrays = [&](double s) { return s > 0.0 ? double(rays.size()) / s * 1e-6 : 0.0; };
    RaySetResult r;
    cpu = traceCpu(gpuScene.bvh(), rays, anyHit, repeats);
    Timing gpu = traceGpu(context, layout, gpuScene, rays, anyHit, repeats, raysPerInvocation);
    r.gpu = mrays(gpu.seconds);
    r.cpu = mrays(cpu.seconds);
    r.gpuPerCpuSecond = mrays(gpu.cpuSeconds);
    r.cpuPerCpuSecond = mrays(cpu.cpuSeconds);
    r.agreeCpu = agreement(cpu.hits, gpu.hits, anyHit);
#ifdef PMCR_HAVE_EMBREE
    const auto* tracer = static_cast<const bench::EmbreeTracer*>(embree);
    if (tracer) {
        double best = 1e30;
        for (auto api : {bench::EmbreeTracer::Api::Single, bench::EmbreeTracer::Api::Packet8,
                         bench::EmbreeTracer::Api::Stream}) {
            auto e = tracer->trace(rays, anyHit, coherent, api, repeats);
            if (e.seconds < best) {
                best = e.seconds;
                r.embreeApi = bench::EmbreeTracer::apiName(api);
                r.agreeEmbree = agreement(cpu.hits, e.hits, anyHit);
            }
        }
        r.embree = mrays(best);
    }
#endif
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        cli::Args args(argc, argv, 1);
        int width = 256, height = 256, repeats = 3;
        bool cpuTime = false, json = false, steps = false, ceiling = false;
        uint32_t raysPerInvocation = 1;
        unsigned threads = std::max(1u, std::thread::hardware_concurrency());
        if (const char* lp = std::getenv("LP_NUM_THREADS"); lp && std::atoi(lp) > 0) threads = unsigned(std::atoi(lp));
        std::string device, stepScene;
        std::vector<std::string> scenes;
        while (!args.done()) {
            std::string a = args.next();
            if (a == "--width") width = cli::parseInt(a, args.value(a), 16, 4096);
            else if (a == "--height") height = cli::parseInt(a, args.value(a), 16, 4096);
            else if (a == "--device") device = args.value(a);
            else if (a == "--repeats") repeats = cli::parseInt(a, args.value(a), 1, 20);
            else if (a == "--threads") threads = unsigned(cli::parseInt(a, args.value(a), 1, 256));
            else if (a == "--cpu-time") cpuTime = true;
            else if (a == "--json") json = true;
            else if (a == "--steps") steps = true;
            else if (a == "--fetch-ceiling") ceiling = steps = true;
            else if (a == "--step-ceiling") {
                stepScene = args.value(a);
                steps = true;
            }
            else if (a == "--rays-per-invocation")
                raysPerInvocation = uint32_t(cli::parseInt(a, args.value(a), 1, 64));
            else if (a == "--help" || a == "-h") {
                std::printf("%s", kUsage);
                return 0;
            } else if (a.rfind("-", 0) == 0) throw Error(a + ": unknown option (see --help)");
            else scenes.push_back(a);
        }
        if (scenes.empty()) throw Error("no scene given (see --help)");
        log::setQuiet(true);
        vk::ContextOptions options;
        options.device = device;
        vk::Context context(options);
        vk::PipelineLayout layout(context);
#ifdef PMCR_HAVE_EMBREE
        const bool haveEmbree = true;
#else
        const bool haveEmbree = false;
#endif
        if (!json) {
            std::printf("device: %s (%s); %dx%d camera rays; best of %d runs; Embree: %s; CPU = scalar C++ "
                        "traversal of pmcr's BVH, 1 thread\n\n",
                        context.deviceName().c_str(), context.deviceTypeName().c_str(), width, height, repeats,
                        haveEmbree ? (std::to_string(threads) + " threads, high-quality BVH").c_str()
                                   : "not built (libembree-dev missing at configure time)");
            std::printf("%-20s %9s | %-8s %8s %8s %8s %8s | %10s\n", "scene", "triangles", "rays", "GPU",
                        "Embree", "GPU/Emb", "CPU", "pt Msamp/s");
        }
        StepCost stepCost;
        if (!stepScene.empty() && !json)  // printed beside the table only
            stepCost = measureStepCost(context, layout, stepScene, width, height, repeats);
        nlohmann::json out = nlohmann::json::array();
        for (const auto& path : scenes) {
            Scene scene = loadScene(path);
            GpuScene gpuScene(context, layout, scene, 0, width, height);
            const void* embree = nullptr;
#ifdef PMCR_HAVE_EMBREE
            bench::EmbreeTracer embreeTracer(scene, threads);
            embree = &embreeTracer;
#endif
            std::mt19937 rng(7);
            auto primary = primaryRays(gpuScene.info(), rng);
            Timing cpuPrimary, cpuBounce, cpuShadow;
            RaySetResult p = measure(context, layout, gpuScene, embree, primary, false, true, repeats,
                                     raysPerInvocation, cpuPrimary);
            auto bounce = bounceRays(scene, primary, cpuPrimary.hits, rng);
            RaySetResult b = measure(context, layout, gpuScene, embree, bounce, false, false, repeats,
                                     raysPerInvocation, cpuBounce);
            auto shadow = shadowRays(scene, bounce, cpuBounce.hits, rng);
            RaySetResult sh = measure(context, layout, gpuScene, embree, shadow, true, false, repeats,
                                      raysPerInvocation, cpuShadow);

            RenderSettings s;
            s.method = "pt";
            s.width = width;
            s.height = height;
            s.spp = 4;
            s.quiet = true;
            double ptRate = 0.0;  // best of the repeats, Msamples/s
            for (int rep = 0; rep < repeats; ++rep) {
                RenderResult r = renderScene(context, scene, s);
                // Samples over the time spent sampling: the fixed set-up (kernel compilation,
                // scene upload) is not the path tracer's speed.
                ptRate = std::max(ptRate, double(r.output.cameraSamples) / r.samplingSeconds * 1e-6);
            }
            const std::string name = std::filesystem::path(path).filename().string();

            auto orNull = [&](double v) { return haveEmbree ? nlohmann::json(v) : nlohmann::json(nullptr); };
            out.push_back({{"scene", name},
                           {"triangles", scene.triangles.size()},
                           {"gpu_primary_mrays", p.gpu},
                           {"gpu_bounce_mrays", b.gpu},
                           {"gpu_shadow_mrays", sh.gpu},
                           {"embree_primary_mrays", orNull(p.embree)},
                           {"embree_bounce_mrays", orNull(b.embree)},
                           {"embree_shadow_mrays", orNull(sh.embree)},
                           {"cpu_primary_mrays", p.cpu},
                           {"cpu_bounce_mrays", b.cpu},
                           {"pt_msamples", ptRate}});
            if (json) continue;
            const struct {
                const char* name;
                const RaySetResult& r;
            } rows[] = {{"primary", p}, {"bounce", b}, {"shadow", sh}};
            for (const auto& row : rows) {
                const bool first = &row.r == &p;
                char ratio[16] = "-";
                if (haveEmbree) std::snprintf(ratio, sizeof ratio, "%.2fx", row.r.gpu / row.r.embree);
                std::printf("%-20s %9s | %-8s %8.2f %8.2f %8s %8.2f | %10s\n", first ? name.c_str() : "",
                            first ? std::to_string(scene.triangles.size()).c_str() : "", row.name, row.r.gpu,
                            row.r.embree, ratio, row.r.cpu, first ? std::to_string(ptRate).substr(0, 5).c_str() : "");
                if (cpuTime)
                    std::printf("%-20s %9s | %-8s %8.2f %8s %8s %8.2f |\n", "", "", "  /CPU s", row.r.gpuPerCpuSecond,
                                "", "", row.r.cpuPerCpuSecond);
                if (row.r.agreeCpu < 0.999 || (haveEmbree && row.r.agreeEmbree < 0.99))
                    std::printf("  warning: %s rays: GPU agrees with the CPU traversal on %.4f, Embree (%s) on %.4f\n",
                                row.name, row.r.agreeCpu, row.r.embreeApi, row.r.agreeEmbree);
            }
            if (haveEmbree)
                std::printf("%-20s %9s | Embree's fastest API: %s (primary), %s (bounce), %s (shadow)\n", "", "",
                            p.embreeApi, b.embreeApi, sh.embreeApi);
            if (steps) {
                const std::vector<gpu::BvhQuery>* sets[] = {&primary, &bounce, &shadow};
                for (int k = 0; k < 3; ++k) {
                    const StepCounts c = countSteps(context, layout, gpuScene, *sets[k], k == 2);
                    // The same rays ordered by their step counts, so that the 8 lanes of a vector
                    // take (nearly) as many steps each: what refilling idle lanes could gain at
                    // most (it also gives up primary rays' coherence).
                    std::vector<size_t> order = inOrder(sets[k]->size());
                    const double efficiency = laneEfficiency(c.steps, order);
                    // Sorted within windows of 256 rays, which keeps most of the rays' locality.
                    for (size_t w = 0; w < order.size(); w += 256)
                        std::stable_sort(order.begin() + w, order.begin() + std::min(w + 256, order.size()),
                                         [&](size_t a, size_t b) { return c.steps[a] < c.steps[b]; });
                    std::vector<gpu::BvhQuery> sorted;
                    for (size_t i : order) sorted.push_back((*sets[k])[i]);
                    const Timing t = traceGpu(context, layout, gpuScene, sorted, k == 2, repeats, 1);
                    const double full = t.seconds > 0.0 ? double(sorted.size()) / t.seconds * 1e-6 : 0.0;
                    char ratio[16] = "-";
                    if (haveEmbree) std::snprintf(ratio, sizeof ratio, "%.2fx", full / rows[k].r.embree);
                    std::printf("%-20s %9s | %-8s steps/ray %.1f node + %.1f leaf; 8-lane "
                                "efficiency %.2f; sorted by steps: %.2f, %.2f Mrays/s (%s Embree)\n", "", "",
                                rows[k].name, c.node, c.leaf, efficiency,
                                laneEfficiency(c.steps, order), full, ratio);
                    if (!stepScene.empty()) {
                        // This set's rays at the small scene's costs: memory free, and either
                        // the measured idle lanes or none.
                        const int kind = k == 2 ? 1 : 0;
                        const double m = c.node + c.leaf;
                        const double idle = 8.0 / (stepCost.perVector[kind] + stepCost.perStep[kind] * m / efficiency);
                        const double busy = 8.0 / (stepCost.perVector[kind] + stepCost.perStep[kind] * m);
                        std::printf("%-20s %9s | %-8s memory free (%.0f ns a vector step, %.0f a vector of rays): "
                                    "%.2f Mrays/s (%.2fx Embree), lanes never idle %.2f (%.2fx)\n", "", "",
                                    rows[k].name, stepCost.perStep[kind] * 1e9, stepCost.perVector[kind] * 1e9,
                                    idle * 1e-6, haveEmbree ? idle * 1e-6 / rows[k].r.embree : 0.0, busy * 1e-6,
                                    haveEmbree ? busy * 1e-6 / rows[k].r.embree : 0.0);
                    }
                    if (!ceiling) continue;
                    double rate[2];
                    const uint32_t fetches[2] = {gpu::BVH_NODE_TEXELS, 4};
                    for (int f = 0; f < 2; ++f)
                        rate[f] = fetchCeiling(context, layout, gpuScene, c.steps, fetches[f], repeats);
                    std::printf("%-20s %9s | %-8s fetches alone, 7 / 4 texels a step: %.2f / %.2f Mrays/s "
                                "(%.2fx / %.2fx Embree)\n", "", "", rows[k].name, rate[0], rate[1],
                                haveEmbree ? rate[0] / rows[k].r.embree : 0.0,
                                haveEmbree ? rate[1] / rows[k].r.embree : 0.0);
                }
            }
        }
        if (json) std::printf("%s\n", out.dump(2).c_str());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pmcr-bench-throughput: error: %s\n", e.what());
        return 1;
    }
}
