#include "render/film.h"

#include "vk/context.h"

namespace pmcr {

Film::Film(vk::Context& context, int width, int height)
    : m_width(width),
      m_height(height),
      m_pixels(context, VkDeviceSize(width) * VkDeviceSize(height) * sizeof(gpu::FilmPixel),
               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "film"),
      m_counters(makeCounters(context, "counters")) {
    clear();
}

void Film::clear() {
    m_pixels.fill(0);
    m_counters.fill(0);
}

std::vector<gpu::FilmPixel> Film::download() const {
    return m_pixels.download<gpu::FilmPixel>(pixelCount());
}

vk::Buffer Film::makeCounters(vk::Context& context, const std::string& name) {
    vk::Buffer counters(context, gpu::COUNTER_COUNT * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                        name, vk::MemoryUsage::Readback);
    counters.fill(0);
    return counters;
}

void Film::addCounters(const vk::Buffer& counters, Counters& totals) {
    auto values = counters.download<uint32_t>(gpu::COUNTER_COUNT);
    for (uint32_t i = 0; i < gpu::COUNTER_COUNT; ++i) totals.values[i] += values[i];
}

Image resolveAverage(const std::vector<gpu::FilmPixel>& pixels, int width, int height) {
    Image image(width, height);
    for (size_t i = 0; i < pixels.size(); ++i) {
        const auto& p = pixels[i];
        if (p.sampleCount == 0) continue;
        glm::vec3 v = p.sum / float(p.sampleCount);
        image.rgb[3 * i + 0] = v.x;
        image.rgb[3 * i + 1] = v.y;
        image.rgb[3 * i + 2] = v.z;
    }
    return image;
}

Image resolveScaled(const std::vector<gpu::FilmPixel>& pixels, int width, int height, float scale) {
    Image image(width, height);
    for (size_t i = 0; i < pixels.size(); ++i) {
        glm::vec3 v = pixels[i].sum * scale;
        image.rgb[3 * i + 0] = v.x;
        image.rgb[3 * i + 1] = v.y;
        image.rgb[3 * i + 2] = v.z;
    }
    return image;
}

Image sampleCountImage(const std::vector<gpu::FilmPixel>& pixels, int width, int height) {
    Image image(width, height);
    for (size_t i = 0; i < pixels.size(); ++i) {
        const float n = float(pixels[i].sampleCount);
        image.rgb[3 * i + 0] = image.rgb[3 * i + 1] = image.rgb[3 * i + 2] = n;
    }
    return image;
}

}  // namespace pmcr
