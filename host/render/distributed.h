// One image from the ranks of an MPI job (`mpirun -n N pmcr render ...`, docs/mpi.md):
// what each rank renders, on which device, and how rank 0 turns the ranks' results into one.
//
// Each rank renders an independent, unbiased share of the image with its own random streams;
// the methods that adapt do so as one population through the communicator's collectives
// (core/communicator.h). Rank 0 then averages the ranks' images weighted by their camera
// samples, w_r = n_r / sum n, exactly as `pmcr merge` weighs independent renders
// (metrics/merge.h): for the per-pixel estimators that is the mean of all the samples, and any
// fixed weights summing to one keep an unbiased share unbiased.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "core/communicator.h"
#include "render/renderer.h"

namespace pmcr {

// Rank r's seed: the user's for rank 0 (so one rank renders exactly what a run without MPI
// renders), else seed ^ fmix32(r), distinct for every rank (fmix32 is a bijection with
// fmix32(0) = 0), so no two ranks share a random stream.
uint32_t rankSeed(uint32_t seed, int rank);

// Rank r's share of `settings`: its seed, and its part of the total --spp (the method's
// `defaultSpp` when neither --spp nor --time is given), spp / N plus one for the first
// spp mod N ranks. Throws pmcr::Error when there are fewer samples per pixel than ranks.
// --time applies to every rank: they render side by side for that long.
RenderSettings rankSettings(const RenderSettings& settings, uint32_t defaultSpp, const Communicator& comm);

// Before the device opens: the device a rank uses when --device is not given (the local
// rank's GPU, round robin, when the machine has usable GPUs; else "" for the automatic choice,
// lavapipe on a machine without one), and, when several ranks share this machine and the user
// set no LP_NUM_THREADS, lavapipe threads so the ranks share the cores fairly. Returns a line
// describing the choice for the log.
std::string chooseRankDevice(RenderSettings& settings, const Communicator& comm);

// Runs one stage of a render (reading the scene, opening the device) on every rank; when it
// fails on any rank, every rank stops there with a pmcr::Error, and rank 0's carries the one
// line to print: its own error (bad input fails alike on every rank, so it is reported once),
// else the first failing rank's, as "rank R: ...". Without MPI it just runs the stage.
void onEveryRank(Communicator& comm, const std::function<void()>& stage);

// Collective: every rank's result becomes one on rank 0 (the image and diagnostics weighted by
// camera samples, counts summed, the stats JSON with "ranks" and "rank_stats" and the totals);
// `requested` holds the user's settings (total --spp and seed). Other ranks get theirs back.
RenderResult reduceRenderResults(RenderResult mine, const RenderSettings& requested, Communicator& comm);

}  // namespace pmcr
