// The host's per-pixel work spread over the cores (a GPU machine has many, and the device
// waits while the host adapts between iterations; issue 38). Work is split into fixed
// blocks whatever the number of threads, so results that are combined block by block in
// order (parallelSum) are the same bit for bit on any machine.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

namespace pmcr {

// Calls body(begin, end) over [0, count) in blocks of `block` items, on up to as many threads
// as the machine has cores, or `maxThreads` when not 0 (one when count is a single block).
// Returns after all blocks.
void parallelFor(size_t count, size_t block, const std::function<void(size_t begin, size_t end)>& body,
                 size_t maxThreads = 0);

// The sum of term(i) over [0, count): each block summed in order, then the blocks' sums in
// order, so it does not depend on the number of threads.
double parallelSum(size_t count, size_t block, const std::function<double(size_t i)>& term);

// Concatenates, in item order, what each item of [0, count) contributes: sizeOf(i) elements,
// written by emit(i, out) from `out` on. Counted block by block over the cores, then each block
// writes at its place, so the result is the same as one thread's.
template <class T, class SizeOf, class Emit>
void parallelConcat(size_t count, size_t block, std::vector<T>& to, const SizeOf& sizeOf, const Emit& emit) {
    std::vector<size_t> first((count + block - 1) / block + 1, 0);
    parallelFor(count, block, [&](size_t begin, size_t end) {
        size_t n = 0;
        for (size_t i = begin; i < end; ++i) n += sizeOf(i);
        first[begin / block + 1] = n;
    });
    for (size_t b = 1; b < first.size(); ++b) first[b] += first[b - 1];
    to.resize(first.back());
    parallelFor(count, block, [&](size_t begin, size_t end) {
        T* out = to.data() + first[begin / block];
        for (size_t i = begin; i < end; ++i) out = emit(i, out);
    });
}

}  // namespace pmcr
