#include "methods/energy_redistribution/redistribution.h"

#include <limits>
#include <string>

#include "core/error.h"

#include "shared/host_device.h"
#include "vk/context.h"

namespace pmcr {

RedistributionBatch::RedistributionBatch(RenderSession& session, bool ownCounters)
    : m_session(session),
      m_batch(session.layout(), &session.timer()),
      m_energy(session.context(), gpu::ENERGY_SLOTS * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "redistribution energy",
               vk::MemoryUsage::Readback) {
    if (ownCounters) m_counters = Film::makeCounters(session.context(), "redistribution counters");
}

const vk::Buffer& RedistributionBatch::counters() const {
    return m_counters.valid() ? m_counters : m_session.film().counters();
}

void RedistributionBatch::begin() {
    m_batch.fill(counters(), 0);
    m_batch.fill(m_energy, 0);
    m_batch.bind(m_session.scene().descriptorSet());
}

void RedistributionBatch::submit() {
    launch();
    complete();
}

void RedistributionBatch::launch() { m_batch.submit(); }

void RedistributionBatch::complete() {
    m_batch.wait();
    Film::addCounters(counters(), m_session.counters());
    float e[gpu::ENERGY_SLOTS];
    m_energy.download(e, sizeof(e));
    m_seedEnergy += e[gpu::ENERGY_SEED];
    m_depositedEnergy += e[gpu::ENERGY_DEPOSITED];
    m_directEnergy += e[gpu::ENERGY_DIRECT];
}

void completeRedistributionPass(RenderSession& session, SplatFilm& splat, float depositEnergy,
                                uint64_t pathsPerPass, uint32_t pass, uint32_t passes,
                                uint32_t count) {
    splat.completePass(count);
    reportRedistributionPass(session, splat, depositEnergy, pathsPerPass, pass, passes);
}

void reportRedistributionPass(RenderSession& session, const SplatFilm& splat, float depositEnergy,
                              uint64_t pathsPerPass, uint32_t pass, uint32_t passes) {
    session.snapshotIfDue(uint64_t(splat.completedPasses()) * pathsPerPass,
                          [&] { return splat.resolve(depositEnergy); });
    const double fraction = passes != std::numeric_limits<uint32_t>::max()
                                ? double(pass + 1) / double(passes)
                                : session.elapsedSeconds() / session.settings().timeLimit;
    session.progress().update(fraction, double(pass + 1), "passes");
}

namespace {

uint32_t parseMutationMode(const std::string& name) {
    if (name == "erpt") return gpu::MUTATION_ERPT;
    if (name == "mix") return gpu::MUTATION_MIX;
    if (name == "lens") return gpu::MUTATION_LENS;
    if (name == "caustic") return gpu::MUTATION_CAUSTIC;
    throw Error("--mutation: expected erpt, mix, lens or caustic, got '" + name + "'");
}

}  // namespace

PerturbationOptions PerturbationOptions::fromSettings(const RenderSettings& s) {
    PerturbationOptions o;
    o.mutationMode = parseMutationMode(s.optionString("mutation", "erpt"));
    o.lensRadius = float(s.optionDouble("lens-radius", o.lensRadius));
    if (!(o.lensRadius > 0.0f)) throw Error("--lens-radius: expected a positive number of pixels");
    o.causticThetaMin = float(s.optionDouble("caustic-theta-min", o.causticThetaMin));
    o.causticThetaMax = float(s.optionDouble("caustic-theta-max", o.causticThetaMax));
    if (!(o.causticThetaMin > 0.0f) || !(o.causticThetaMax > o.causticThetaMin) || o.causticThetaMax > 1.5f)
        throw Error("--caustic-theta-min/max: expected 0 < min < max <= 1.5 radians");
    o.causticProbability = float(s.optionDouble("caustic-probability", o.causticProbability));
    if (!(o.causticProbability >= 0.0f && o.causticProbability <= 1.0f))
        throw Error("--caustic-probability: expected a probability");
    return o;
}

std::vector<MethodOption> PerturbationOptions::help() {
    return {{"mutation", "erpt", "erpt (caustic for L..SDE, lens otherwise), mix, lens or caustic"},
            {"lens-radius", "3", "lens perturbation disk radius in pixels (the ERPT paper: a 9x9 square)"},
            {"caustic-theta-min", "0.0001", "caustic perturbation angle, log-uniform from (radians)"},
            {"caustic-theta-max", "0.1", "... to (radians)"},
            {"caustic-probability", "0.5", "--mutation mix: chance of a caustic perturbation"}};
}

nlohmann::json mutationStatistics(const Counters& c) {
    auto ratio = [](uint64_t a, uint64_t b) { return b > 0 ? double(a) / double(b) : 0.0; };
    return {
        {"lens_proposed", c.values[gpu::COUNTER_LENS_PROPOSED]},
        {"lens_acceptance", ratio(c.values[gpu::COUNTER_LENS_ACCEPTED], c.values[gpu::COUNTER_LENS_PROPOSED])},
        {"caustic_proposed", c.values[gpu::COUNTER_CAUSTIC_PROPOSED]},
        {"caustic_acceptance", ratio(c.values[gpu::COUNTER_CAUSTIC_ACCEPTED], c.values[gpu::COUNTER_CAUSTIC_PROPOSED])},
        {"large_step_proposed", c.values[gpu::COUNTER_LARGE_PROPOSED]},
        {"large_step_acceptance", ratio(c.values[gpu::COUNTER_LARGE_ACCEPTED], c.values[gpu::COUNTER_LARGE_PROPOSED])},
        {"small_step_proposed", c.values[gpu::COUNTER_SMALL_PROPOSED]},
        {"small_step_acceptance", ratio(c.values[gpu::COUNTER_SMALL_ACCEPTED], c.values[gpu::COUNTER_SMALL_PROPOSED])},
        {"invalid_proposals", c.values[gpu::COUNTER_INVALID_PROPOSALS]},
        {"deposits", c.values[gpu::COUNTER_DEPOSITS]},
        {"deposits_dropped", c.values[gpu::COUNTER_DEPOSITS_DROPPED]},
    };
}

}  // namespace pmcr
