// The processes that render one image together: one, or the ranks of an MPI job
// (`mpirun -n N pmcr render ...`, docs/mpi.md). Methods call the collectives at the points where
// they adapt as one population (PMC-IP's pilot statistics, PMC-HI's feedback image, the energy
// pre-pass of ERPT and PMC-ER); `pmcr render` reduces the ranks' images at the end
// (render/distributed.h). With one process every collective returns its input unchanged, so a
// render without MPI and one with a single rank run the same arithmetic and give the same image.
//
// Every rank must make the same collective calls in the same order: a method whose ranks adapt
// together decides to stop together (anyTrue), never on one rank's clock alone.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pmcr {

class Communicator {
public:
    virtual ~Communicator() = default;

    virtual int rank() const { return 0; }
    virtual int size() const { return 1; }
    // The rank among those on this machine, and how many share it (to give each its own GPU
    // and a fair share of the CPU cores).
    virtual int localRank() const { return 0; }
    virtual int localSize() const { return 1; }
    bool distributed() const { return size() > 1; }

    // Element-wise sums over the ranks, the result on every rank.
    virtual void allReduceSum(std::vector<double>& values) { (void)values; }
    virtual void allReduceSum(std::vector<float>& values) { (void)values; }
    virtual void allReduceSum(std::vector<uint64_t>& values) { (void)values; }
    double allReduceSum(double value);
    // True on every rank when `value` is true on any.
    virtual bool anyTrue(bool value) { return value; }
    // Every rank's text, in rank order, on rank 0 (an empty list elsewhere).
    virtual std::vector<std::string> gatherToRoot(const std::string& text) { return {text}; }
    // Ends every rank of the job at once with `status` (a rank that failed mid-render, when the
    // others may be waiting in a collective). Returns only without MPI.
    virtual void abortJob(int status) { (void)status; }
};

// The processes of this run: an MPI job's ranks when pmcr was built with MPI and started by an
// MPI launcher (mpirun sets OMPI_COMM_WORLD_SIZE / PMIX_RANK), else this process alone. MPI is
// initialised on the first call and finalised at exit.
Communicator& worldCommunicator();

// This process alone (tests, `pmcr bench`).
Communicator& localCommunicator();

}  // namespace pmcr
