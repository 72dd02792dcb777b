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
// as the machine has cores (one when count is a single block). Returns after all blocks.
void parallelFor(size_t count, size_t block, const std::function<void(size_t begin, size_t end)>& body);

// The sum of term(i) over [0, count): each block summed in order, then the blocks' sums in
// order, so it does not depend on the number of threads.
double parallelSum(size_t count, size_t block, const std::function<double(size_t i)>& term);

}  // namespace pmcr
