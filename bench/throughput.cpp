// Ray-traversal throughput: the GPU kernel (shaders/common/bvh.glsl) against the host's scalar
// C++ traversal of the same BVH on one thread, for coherent primary rays and incoherent bounce
// rays, plus path-tracing samples per second. Prints one table; ratios are measured in the same
// run on the same machine.
//
//   pmcr-bench-throughput [--width W] [--height H] [--device ID] [--cpu-time] [SCENE...]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <random>

#include <sys/resource.h>

#include "cli/args.h"
#include "core/error.h"
#include "core/log.h"
#include "render/gpu_scene.h"
#include "render/renderer.h"
#include "scene/bvh.h"
#include "scene/gltf_loader.h"
#include "vk/command_batch.h"
#include "vk/context.h"

using namespace pmcr;

namespace {

using Clock = std::chrono::steady_clock;

const char* const kUsage =
    "usage: pmcr-bench-throughput [--width W] [--height H] [--device ID] [--cpu-time] SCENE...\n"
    "       (bench/throughput runs it on the default scene and the dragon)\n"
    "\n"
    "Traces one set of primary rays (one per pixel of a W x H image, default 256 x 256, through\n"
    "the scene's camera) and one set of cosine-distributed bounce rays from their hits, with the\n"
    "GPU kernel (shaders/common/bvh.glsl, one dispatch, shader compiled beforehand) and with the\n"
    "host's scalar C++ traversal of the same BVH on one thread; prints Mrays/s of both and their\n"
    "ratio, and path-tracing samples/s (pt, 4 spp at W x H). Warns if GPU and CPU hits differ.\n"
    "Ratios are measured in one run on one machine; compare ratios, not absolute rates.\n"
    "  --width W --height H  ray set size (16..4096, default 256)\n"
    "  --device ID           Vulkan device index or name substring (see pmcr --list-devices)\n"
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

// Bounce rays: from each primary hit, a cosine-distributed direction about the surface normal.
std::vector<gpu::BvhQuery> bounceRays(const Scene& scene, const std::vector<gpu::BvhQuery>& primary,
                                      const std::vector<gpu::Hit>& hits, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<gpu::BvhQuery> rays;
    for (size_t i = 0; i < primary.size(); ++i) {
        if (hits[i].triangle == gpu::BVH_NO_HIT) continue;
        const gpu::Triangle& t = scene.triangles[hits[i].triangle];
        const glm::vec3 p0 = scene.vertices[t.i0].position, p1 = scene.vertices[t.i1].position,
                        p2 = scene.vertices[t.i2].position;
        glm::vec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
        if (glm::dot(n, primary[i].direction) > 0.0f) n = -n;
        const glm::vec3 p = primary[i].origin + hits[i].t * primary[i].direction;
        // Cosine hemisphere about n.
        const float r = std::sqrt(u(rng)), phi = 6.2831853f * u(rng);
        const glm::vec3 a = std::abs(n.x) > 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
        const glm::vec3 tx = glm::normalize(glm::cross(a, n)), ty = glm::cross(n, tx);
        const glm::vec3 d = glm::normalize(r * std::cos(phi) * tx + r * std::sin(phi) * ty +
                                           std::sqrt(std::max(0.0f, 1.0f - r * r)) * n);
        rays.push_back({p + n * 1e-4f * std::max(1.0f, glm::length(p)), 1e30f, d, 0});
    }
    return rays;
}

struct Timing {
    double seconds = 0.0;
    double cpuSeconds = 0.0;  // threadCpu (host traversal) or processCpu (GPU dispatch)
    std::vector<gpu::Hit> hits;
};

Timing traceCpu(const Bvh& bvh, const std::vector<gpu::BvhQuery>& rays) {
    Timing t;
    t.hits.resize(rays.size());
    auto start = Clock::now();
    const double cpuStart = threadCpu();
    for (size_t i = 0; i < rays.size(); ++i)
        if (!bvh.traceClosest(rays[i].origin, rays[i].direction, rays[i].tMax, t.hits[i]))
            t.hits[i].triangle = gpu::BVH_NO_HIT;
    t.seconds = secondsSince(start);
    t.cpuSeconds = threadCpu() - cpuStart;
    return t;
}

Timing traceGpu(vk::Context& context, const vk::PipelineLayout& layout, const GpuScene& scene,
                const std::vector<gpu::BvhQuery>& rays) {
    vk::Kernel kernel(layout, "bench/trace_rays");
    auto queries = vk::Buffer::storage(context, rays, "bench rays");
    vk::Buffer hits(context, std::max<size_t>(16, rays.size() * sizeof(gpu::Hit)),
                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "bench hits");
    vk::DescriptorSet work(layout, vk::DescriptorSet::Kind::Work, "bench work");
    work.bind(0, queries);
    work.bind(1, hits);
    struct Push {
        uint32_t count;
        uint32_t anyHit;
    };
    // Warm-up: the first dispatch compiles the shader on lavapipe.
    {
        vk::CommandBatch batch(layout);
        batch.bind(scene.descriptorSet());
        batch.bind(work);
        batch.dispatch(kernel, Push{std::min<uint32_t>(uint32_t(rays.size()), 64), 0}, 64);
        batch.submitAndWait();
    }
    Timing t;
    auto start = Clock::now();
    const double cpuStart = processCpu();
    vk::CommandBatch batch(layout);
    batch.bind(scene.descriptorSet());
    batch.bind(work);
    batch.dispatch(kernel, Push{uint32_t(rays.size()), 0}, uint32_t(rays.size()));
    batch.submitAndWait();
    t.seconds = secondsSince(start);
    t.cpuSeconds = processCpu() - cpuStart;
    t.hits = hits.download<gpu::Hit>(rays.size());
    return t;
}

double agreement(const std::vector<gpu::Hit>& a, const std::vector<gpu::Hit>& b) {
    size_t same = 0;
    for (size_t i = 0; i < a.size(); ++i)
        same += a[i].triangle == b[i].triangle ||
                (a[i].triangle != gpu::BVH_NO_HIT && b[i].triangle != gpu::BVH_NO_HIT &&
                 std::abs(a[i].t - b[i].t) <= 1e-5f * std::max(1.0f, a[i].t));
    return a.empty() ? 1.0 : double(same) / double(a.size());
}

}  // namespace

int main(int argc, char** argv) {
    try {
        cli::Args args(argc, argv, 1);
        int width = 256, height = 256;
        bool cpuTime = false;
        std::string device;
        std::vector<std::string> scenes;
        while (!args.done()) {
            std::string a = args.next();
            if (a == "--width") width = cli::parseInt(a, args.value(a), 16, 4096);
            else if (a == "--height") height = cli::parseInt(a, args.value(a), 16, 4096);
            else if (a == "--device") device = args.value(a);
            else if (a == "--cpu-time") cpuTime = true;
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
        std::printf("device: %s (%s); %dx%d rays per set; CPU = scalar C++ BVH traversal, 1 thread\n\n",
                    context.deviceName().c_str(), context.deviceTypeName().c_str(), width, height);
        std::printf("%-22s %9s | %-31s | %-31s | %10s\n", "scene", "triangles",
                    "primary Mrays/s: GPU  CPU  ratio", "bounce Mrays/s: GPU  CPU  ratio", "pt Msamp/s");
        for (const auto& path : scenes) {
            Scene scene = loadScene(path);
            GpuScene gpuScene(context, layout, scene, 0, width, height);
            std::mt19937 rng(7);
            auto primary = primaryRays(gpuScene.info(), rng);
            Timing cpuPrimary = traceCpu(gpuScene.bvh(), primary);
            Timing gpuPrimary = traceGpu(context, layout, gpuScene, primary);
            auto bounce = bounceRays(scene, primary, cpuPrimary.hits, rng);
            Timing cpuBounce = traceCpu(gpuScene.bvh(), bounce);
            Timing gpuBounce = traceGpu(context, layout, gpuScene, bounce);
            const double agreePrimary = agreement(cpuPrimary.hits, gpuPrimary.hits);
            const double agreeBounce = agreement(cpuBounce.hits, gpuBounce.hits);

            RenderSettings s;
            s.method = "pt";
            s.width = width;
            s.height = height;
            s.spp = 4;
            s.quiet = true;
            RenderResult r = renderScene(context, scene, s);
            const double ptRate = double(r.output.cameraSamples) / r.seconds;

            auto mrays = [](size_t n, double s) { return double(n) / s * 1e-6; };
            const double gp = mrays(primary.size(), gpuPrimary.seconds), cp = mrays(primary.size(), cpuPrimary.seconds);
            const double gb = mrays(bounce.size(), gpuBounce.seconds), cb = mrays(bounce.size(), cpuBounce.seconds);
            std::printf("%-22s %9zu | %8.2f %6.2f %7.2fx       | %8.2f %6.2f %7.2fx       | %10.3f\n",
                        std::filesystem::path(path).filename().string().c_str(), scene.triangles.size(),
                        gp, cp, gp / cp, gb, cb, gb / cb, ptRate * 1e-6);
            if (cpuTime) {
                const double gpc = mrays(primary.size(), gpuPrimary.cpuSeconds);
                const double cpc = mrays(primary.size(), cpuPrimary.cpuSeconds);
                const double gbc = mrays(bounce.size(), gpuBounce.cpuSeconds);
                const double cbc = mrays(bounce.size(), cpuBounce.cpuSeconds);
                std::printf("%-22s %9s | %8.2f %6.2f %7.2fx       | %8.2f %6.2f %7.2fx       |\n",
                            "  per CPU second", "", gpc, cpc, gpc / cpc, gbc, cbc, gbc / cbc);
            }
            if (agreePrimary < 0.999 || agreeBounce < 0.999)
                std::printf("  warning: GPU and CPU hits agree on %.4f (primary), %.4f (bounce) of rays\n",
                            agreePrimary, agreeBounce);
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pmcr-bench-throughput: error: %s\n", e.what());
        return 1;
    }
}
