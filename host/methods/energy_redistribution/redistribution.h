// What the energy-redistribution methods (ERPT, PMC-ER) share on the host: a command batch that
// clears and reads back the kernels' counters and their seed, deposited and directly deposited
// energy sums (shared/chain_types.h ERPT_BINDING_ENERGY), and the mutation statistics they report.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "methods/energy_redistribution/splat_film.h"
#include "render/method_info.h"
#include "render/session.h"
#include "vk/buffer.h"
#include "vk/command_batch.h"

namespace pmcr {

class RedistributionBatch {
public:
    // `ownCounters`: the kernels count in a counters buffer of this batch's (counters()), not
    // in the film's, so that several batches can be in flight (PMC-ER's lanes).
    explicit RedistributionBatch(RenderSession& session, bool ownCounters = false);

    vk::CommandBatch& batch() { return m_batch; }
    // float[3] the kernels add seed, deposited and directly deposited energy to (units of e_d).
    const vk::Buffer& energy() const { return m_energy; }
    // The COUNTER_* buffer the batch's kernels are bound to count in.
    const vk::Buffer& counters() const;
    // Starts recording: clears the counters and the energy sums, binds the scene.
    void begin();
    // Submits, waits, and adds the batch's counters and energies to the totals.
    void submit();
    // The same in two steps: the host works while the device runs the batch.
    void launch();
    void complete();

    double seedEnergy() const { return m_seedEnergy; }
    double depositedEnergy() const { return m_depositedEnergy; }
    double directEnergy() const { return m_directEnergy; }

private:
    RenderSession& m_session;
    vk::CommandBatch m_batch;
    vk::Buffer m_energy;
    vk::Buffer m_counters;  // with ownCounters
    double m_seedEnergy = 0.0;
    double m_depositedEnergy = 0.0;
    double m_directEnergy = 0.0;
};

// Ends seed pass `pass` (0-based) of `passes` (UINT32_MAX: as many as --time allows), and the
// `count` - 1 before it run together with it: the device film's deposits join the completed
// passes, a snapshot is written if one is due (`pathsPerPass` path-traced paths per pass), and
// the progress bar moves by passes, or by time.
void completeRedistributionPass(RenderSession& session, SplatFilm& splat, float depositEnergy,
                                uint64_t pathsPerPass, uint32_t pass, uint32_t passes,
                                uint32_t count = 1);
// Its second half, for passes already added to `splat`: the snapshot and the progress bar.
void reportRedistributionPass(RenderSession& session, const SplatFilm& splat, float depositEnergy,
                              uint64_t pathsPerPass, uint32_t pass, uint32_t passes);

// ERPT's perturbations as options, shared by erpt and mlt (which runs ERPT's own mutations):
// which perturbation (--mutation: erpt, mix, lens, caustic), the lens disk and the caustic angles.
struct PerturbationOptions {
    uint32_t mutationMode = 0;        // gpu::MUTATION_*
    float lensRadius = 3.0f;          // pixels (ERPT: a 9x9 square, area ~ a disk of radius 5)
    float causticThetaMin = 1e-4f;    // radians (ERPT footnote 4)
    float causticThetaMax = 0.1f;
    float causticProbability = 0.5f;  // MUTATION_MIX

    static PerturbationOptions fromSettings(const RenderSettings& settings);
    // Their --help entries, in the method registry's form.
    static std::vector<MethodOption> help();
};

// Proposals and acceptance per perturbation type, invalid proposals, deposits and drops.
nlohmann::json mutationStatistics(const Counters& counters);

}  // namespace pmcr
