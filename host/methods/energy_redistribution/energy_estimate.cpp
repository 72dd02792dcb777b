#include "methods/energy_redistribution/energy_estimate.h"

#include "methods/pt/pt_integrator.h"
#include "scene/scene.h"
#include "vk/command_batch.h"
#include "vk/context.h"

namespace pmcr {

double estimateMeanLuminance(RenderSession& session, uint32_t spp) {
    const double start = session.elapsedSeconds();
    const RenderSettings& s = session.settings();
    Film film(session.context(), session.width(), session.height());
    const vk::Kernel& kernel = session.kernel(pathTracingKernel(session.scene(), "pt"));
    vk::DescriptorSet work(session.layout(), vk::DescriptorSet::Kind::Work, "energy pre-pass");
    bindTileWork(work, film, session);
    gpu::PtPush push{};
    push.source = gpu::PT_SOURCE_TILE;
    push.flags = gpu::PT_FLAG_DEPOSIT;
    push.samplesPerPixel = 1;
    push.seed = s.seed ^ 0x9e3779b9u;  // independent of the samples the method itself draws
    push.maxDepth = s.maxDepth;
    push.rrDepth = s.rrDepth;
    const uint32_t pixels = film.pixelCount();
    const uint32_t chunk = session.context().isCpuDevice() ? 16384u : pixels;
    // Under --time alone (issue 38: the pre-pass inside the budget), whole samples per pixel
    // until the clock passes a tenth of the budget, at least one: e_d sets only how finely
    // energy is dealt out, never what the chains deposit in expectation.
    const bool timed = s.timeLimit > 0.0 && s.spp == 0;
    for (uint32_t pass = 0; pass < spp; ++pass) {
        if (timed && pass > 0 && session.elapsedSeconds() >= kPrepassShareOfTime * s.timeLimit) break;
        for (uint32_t offset = 0; offset < pixels; offset += chunk) {
            vk::CommandBatch batch(session.layout(), &session.timer());
            batch.bind(session.scene().descriptorSet());
            batch.bind(work);
            push.pixelOffset = offset;
            push.invocationCount = std::min(chunk, pixels - offset);
            push.sampleBase = pass;
            batch.dispatch(kernel, push, push.invocationCount);
            batch.submitAndWait();
        }
    }
    film.addCounters(session.counters());
    double sum = 0.0;
    for (const auto& p : film.download())
        if (p.sampleCount > 0) sum += double(luminance(p.sum / float(p.sampleCount)));
    // With several ranks, the mean of their pre-passes (each its own seed): every rank then
    // deposits the same e_d (core/communicator.h).
    Communicator& comm = session.comm();
    const double mean = comm.allReduceSum(sum / double(pixels)) / double(comm.size());
    session.addPrepassSeconds(session.elapsedSeconds() - start);
    return mean;
}

}  // namespace pmcr
