#include "methods/energy_redistribution/path_records.h"

#include "render/film.h"
#include "shared/host_device.h"

namespace pmcr {

PathRecords::PathRecords(vk::Context& context, uint32_t capacity, const std::string& name)
    : m_records(context, VkDeviceSize(capacity) * sizeof(gpu::PathRecord), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                name + " records"),
      m_vertices(context, VkDeviceSize(capacity) * gpu::PATH_MAX_VERTICES * sizeof(gpu::PathVertex),
                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, name + " record vertices") {}

void PathRecords::bindTracer(vk::DescriptorSet& work, RenderSession& session, const vk::Buffer& requests,
                             const vk::Buffer* counters) const {
    work.bind(gpu::PT_BINDING_FILM, session.film().pixels());
    work.bind(gpu::PT_BINDING_COUNTERS, counters ? *counters : session.film().counters());
    work.bind(gpu::PT_BINDING_REQUESTS, requests);
    work.bind(gpu::PT_BINDING_RESULTS, session.placeholder());
    work.bind(gpu::PT_BINDING_PATH_RECORDS, m_records);
    work.bind(gpu::PT_BINDING_PATH_VERTICES, m_vertices);
}

void PathRecords::bindSeeds(vk::DescriptorSet& work) const {
    work.bind(gpu::ERPT_BINDING_RECORDS, m_records);
    work.bind(gpu::ERPT_BINDING_RECORD_VERTICES, m_vertices);
}

}  // namespace pmcr
