// The path tracer's records of its samples' light paths (shared/path_types.h): the buffers
// pt_record writes and the energy-redistribution kernels (ERPT, PMC-ER) read as seeds, and
// their places in both kernels' work sets.
#pragma once

#include <string>

#include "render/session.h"
#include "vk/buffer.h"
#include "vk/pipeline.h"

namespace pmcr {

class PathRecords {
public:
    // Room for `capacity` records (one per path-traced sample) of up to PATH_MAX_VERTICES.
    PathRecords(vk::Context& context, uint32_t capacity, const std::string& name);

    const vk::Buffer& records() const { return m_records; }
    const vk::Buffer& vertices() const { return m_vertices; }

    // pt_record's work set: the session's film and counters (or `counters`), `requests`
    // (PT_SOURCE_LIST / PT_SOURCE_POINTS; the session's placeholder for tiles) and these records.
    void bindTracer(vk::DescriptorSet& work, RenderSession& session, const vk::Buffer& requests,
                    const vk::Buffer* counters = nullptr) const;
    // These records as the seeds of an ERPT or PMC-ER work set (ERPT_BINDING_RECORDS, ..._VERTICES).
    void bindSeeds(vk::DescriptorSet& work) const;

private:
    vk::Buffer m_records;
    vk::Buffer m_vertices;
};

}  // namespace pmcr
