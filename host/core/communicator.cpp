#include "core/communicator.h"


namespace pmcr {

#ifdef PMCR_WITH_MPI
// mpi_communicator.cpp: the MPI job's ranks, or null when no MPI launcher started us.
std::unique_ptr<Communicator> createMpiCommunicator();
#endif

double Communicator::allReduceSum(double value) {
    std::vector<double> v{value};
    allReduceSum(v);
    return v[0];
}

Communicator& localCommunicator() {
    static Communicator local;
    return local;
}

Communicator& worldCommunicator() {
#ifdef PMCR_WITH_MPI
    static std::unique_ptr<Communicator> world = createMpiCommunicator();
    if (world) return *world;
#endif
    return localCommunicator();
}

}  // namespace pmcr
