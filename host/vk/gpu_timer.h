// Per-kernel GPU time from timestamp queries, accumulated over a whole render and reported by
// `--stats` and the stats JSON. Each vk::CommandBatch given a timer writes timestamps around
// its dispatches into a query pool of its own (so that two batches can be in flight at once)
// and adds them here once it has completed. Devices without compute timestamps report nothing.
#pragma once

#include <volk.h>

#include <map>
#include <string>

namespace pmcr::vk {

class Context;

class GpuTimer {
public:
    struct Total {
        double milliseconds = 0.0;
        uint64_t dispatches = 0;
    };

    explicit GpuTimer(Context& context);

    bool enabled() const { return m_enabled; }
    // One dispatch of kernel `name` took `milliseconds`.
    void add(const std::string& name, double milliseconds);

    const std::map<std::string, Total>& totals() const { return m_totals; }
    double totalMilliseconds() const;

private:
    bool m_enabled = false;
    std::map<std::string, Total> m_totals;
};

}  // namespace pmcr::vk
