#include "core/parallel.h"

#include <algorithm>
#include <atomic>
#include <thread>

namespace pmcr {

void parallelFor(size_t count, size_t block, const std::function<void(size_t, size_t)>& body, size_t maxThreads) {
    if (count == 0) return;
    block = std::max<size_t>(block, 1);
    const size_t blocks = (count + block - 1) / block;
    const size_t cores = std::max(1u, std::thread::hardware_concurrency());
    const size_t threads = std::min<size_t>(blocks, maxThreads > 0 ? std::min(maxThreads, cores) : cores);
    std::atomic<size_t> next{0};
    auto worker = [&]() {
        for (size_t b; (b = next.fetch_add(1)) < blocks;) body(b * block, std::min(count, (b + 1) * block));
    };
    std::vector<std::thread> pool;
    for (size_t t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
}

double parallelSum(size_t count, size_t block, const std::function<double(size_t)>& term) {
    block = std::max<size_t>(block, 1);
    std::vector<double> sums((count + block - 1) / block, 0.0);
    parallelFor(count, block, [&](size_t begin, size_t end) {
        double s = 0.0;
        for (size_t i = begin; i < end; ++i) s += term(i);
        sums[begin / block] = s;
    });
    double total = 0.0;
    for (double s : sums) total += s;
    return total;
}

}  // namespace pmcr
