// The MPI job's ranks (Open MPI from Debian: libopenmpi-dev). Compiled only when CMake finds MPI
// (PMCR_WITH_MPI); see core/communicator.h.
// The C API only: the deprecated C++ bindings would need libmpi_cxx.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <algorithm>
#include <cstdlib>

#include "core/communicator.h"

namespace pmcr {

namespace {

// Whether an MPI launcher started this process. A plain `pmcr render` never initialises MPI, so
// it runs exactly as a build without MPI does (no singleton start-up, no launcher needed).
bool startedByMpiLauncher() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
        if (std::getenv(name)) return true;
    return false;
}

class MpiCommunicator final : public Communicator {
public:
    MpiCommunicator() {
        MPI_Init(nullptr, nullptr);
        MPI_Comm_rank(MPI_COMM_WORLD, &m_rank);
        MPI_Comm_size(MPI_COMM_WORLD, &m_size);
        MPI_Comm local;
        MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, m_rank, MPI_INFO_NULL, &local);
        MPI_Comm_rank(local, &m_localRank);
        MPI_Comm_size(local, &m_localSize);
        MPI_Comm_free(&local);
    }
    ~MpiCommunicator() override {
        int finalized = 0;
        MPI_Finalized(&finalized);
        if (!finalized) MPI_Finalize();
    }

    int rank() const override { return m_rank; }
    int size() const override { return m_size; }
    int localRank() const override { return m_localRank; }
    int localSize() const override { return m_localSize; }

    void allReduceSum(std::vector<double>& values) override { reduce(values, MPI_DOUBLE); }
    void allReduceSum(std::vector<float>& values) override { reduce(values, MPI_FLOAT); }
    void allReduceSum(std::vector<uint64_t>& values) override { reduce(values, MPI_UINT64_T); }

    bool anyTrue(bool value) override {
        int mine = value ? 1 : 0, any = 0;
        MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
        return any != 0;
    }

    std::vector<std::string> gatherToRoot(const std::string& text) override {
        int length = int(text.size());
        std::vector<int> lengths(m_rank == 0 ? size_t(m_size) : 0);
        MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
        std::vector<int> offsets(lengths.size(), 0);
        int total = 0;
        for (size_t r = 0; r < lengths.size(); ++r) {
            offsets[r] = total;
            total += lengths[r];
        }
        std::string all(size_t(total), '\0');
        MPI_Gatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(),
                    MPI_CHAR, 0, MPI_COMM_WORLD);
        std::vector<std::string> texts;
        for (size_t r = 0; r < lengths.size(); ++r)
            texts.push_back(all.substr(size_t(offsets[r]), size_t(lengths[r])));
        return texts;
    }

    void abortJob(int status) override { MPI_Abort(MPI_COMM_WORLD, status); }

private:
    template <typename T>
    static void reduce(std::vector<T>& values, MPI_Datatype type) {
        // MPI counts are ints: reduce in chunks of 2^28 elements.
        const size_t chunk = size_t(1) << 28;
        for (size_t first = 0; first < values.size(); first += chunk) {
            const int n = int(std::min(chunk, values.size() - first));
            MPI_Allreduce(MPI_IN_PLACE, values.data() + first, n, type, MPI_SUM, MPI_COMM_WORLD);
        }
    }

    int m_rank = 0;
    int m_size = 1;
    int m_localRank = 0;
    int m_localSize = 1;
};

}  // namespace

std::unique_ptr<Communicator> createMpiCommunicator() {
    if (!startedByMpiLauncher()) return nullptr;
    return std::make_unique<MpiCommunicator>();
}

}  // namespace pmcr
