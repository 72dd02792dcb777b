// The film on the device (one FilmPixel per pixel, see shared/render_types.h) and the counters
// buffer every kernel adds statistics to.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "image/image.h"
#include "shared/host_device.h"
#include "vk/buffer.h"

namespace pmcr {

// Host totals of the GPU counters (COUNTER_*), 64-bit.
struct Counters {
    std::array<uint64_t, gpu::COUNTER_COUNT> values{};
    uint64_t rays() const { return values[gpu::COUNTER_RAYS]; }
    uint64_t nanDropped() const { return values[gpu::COUNTER_NAN_DROPPED]; }
    uint64_t paths() const { return values[gpu::COUNTER_PATHS]; }
};

class Film {
public:
    Film(vk::Context& context, int width, int height);

    int width() const { return m_width; }
    int height() const { return m_height; }
    uint32_t pixelCount() const { return uint32_t(m_width) * uint32_t(m_height); }
    const vk::Buffer& pixels() const { return m_pixels; }
    const vk::Buffer& counters() const { return m_counters; }

    void clear();
    std::vector<gpu::FilmPixel> download() const;
    // Adds the GPU counters to `totals`; the caller zeroes them at the start of each batch.
    void addCounters(Counters& totals) const { addCounters(m_counters, totals); }
    // The same for any buffer of COUNTER_COUNT counters (a batch in flight has its own).
    static void addCounters(const vk::Buffer& counters, Counters& totals);
    static vk::Buffer makeCounters(vk::Context& context, const std::string& name);

private:
    int m_width;
    int m_height;
    vk::Buffer m_pixels;
    vk::Buffer m_counters;
};

// Per-pixel estimators: sum / sampleCount (0 where a pixel has no sample).
Image resolveAverage(const std::vector<gpu::FilmPixel>& pixels, int width, int height);
// Splatting estimators: sum * scale.
Image resolveScaled(const std::vector<gpu::FilmPixel>& pixels, int width, int height, float scale);
// Samples per pixel as a one-channel-in-three image (for diagnostics).
Image sampleCountImage(const std::vector<gpu::FilmPixel>& pixels, int width, int height);

}  // namespace pmcr
