#include "vk/gpu_timer.h"

#include "vk/context.h"

namespace pmcr::vk {

GpuTimer::GpuTimer(Context& context) : m_enabled(context.timestampsSupported()) {}

void GpuTimer::add(const std::string& name, double milliseconds) {
    Total& t = m_totals[name];
    t.milliseconds += milliseconds;
    t.dispatches += 1;
}

double GpuTimer::totalMilliseconds() const {
    double sum = 0.0;
    for (const auto& [name, total] : m_totals) sum += total.milliseconds;
    return sum;
}

}  // namespace pmcr::vk
