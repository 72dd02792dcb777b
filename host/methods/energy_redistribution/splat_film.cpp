#include "methods/energy_redistribution/splat_film.h"

#include "vk/context.h"

namespace pmcr {

SplatFilm::SplatFilm(vk::Context& context, int width, int height)
    : m_width(width),
      m_height(height),
      m_pixels(context, VkDeviceSize(width) * VkDeviceSize(height) * sizeof(gpu::SplatPixel),
               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "splat film"),
      m_accumulated(size_t(width) * size_t(height) * 3, 0) {
    m_pixels.fill(0);
}

void SplatFilm::completePass(uint32_t count) {
    auto pass = m_pixels.download<uint64_t>(m_accumulated.size());
    for (size_t i = 0; i < pass.size(); ++i) m_accumulated[i] += pass[i];
    m_pixels.fill(0);
    m_passes += int(count);
}

void SplatFilm::addPasses(const std::vector<uint64_t>& deposits, uint32_t count) {
    for (size_t i = 0; i < m_accumulated.size() && i < deposits.size(); ++i) m_accumulated[i] += deposits[i];
    m_passes += int(count);
}

Image SplatFilm::resolve(float depositEnergy) const {
    Image image(m_width, m_height);
    if (m_passes == 0) return image;
    const double scale = double(depositEnergy) / double(gpu::SPLAT_QUANTA_PER_DEPOSIT) / m_passes;
    for (size_t i = 0; i < m_accumulated.size(); ++i) image.rgb[i] = float(double(m_accumulated[i]) * scale);
    return image;
}

Image SplatFilm::resolveTotal(double scale) {
    completePass(0);
    Image image(m_width, m_height);
    const double perQuantum = scale / double(gpu::SPLAT_QUANTA_PER_DEPOSIT);
    for (size_t i = 0; i < m_accumulated.size(); ++i) image.rgb[i] = float(double(m_accumulated[i]) * perQuantum);
    return image;
}

}  // namespace pmcr
