#include "mpi/mpi_cluster.h"

#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace clpt {
namespace {

// Messages go in pieces a count of int can name.
constexpr size_t kPiece = size_t(1) << 30;

class MpiCluster final : public Cluster {
 public:
  MpiCluster() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~MpiCluster() override { MPI_Finalize(); }

  int rank() const override { return rank_; }
  int size() const override { return size_; }

  std::vector<double> all_gather(const std::vector<double>& mine) const override {
    int n = static_cast<int>(mine.size());
    std::vector<int> counts(size_), offsets(size_);
    MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    int total = 0;
    for (int r = 0; r < size_; ++r) {
      offsets[r] = total;
      total += counts[r];
    }
    std::vector<double> all(total);
    MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), offsets.data(),
                   MPI_DOUBLE, MPI_COMM_WORLD);
    return all;
  }

  void broadcast(std::vector<double>& values, int root) const override {
    MPI_Bcast(values.data(), static_cast<int>(values.size()), MPI_DOUBLE, root, MPI_COMM_WORLD);
  }

  void broadcast(std::string& text, int root) const override {
    uint64_t n = text.size();
    MPI_Bcast(&n, 1, MPI_UINT64_T, root, MPI_COMM_WORLD);
    text.resize(n);
    for (size_t at = 0; at < n; at += kPiece)
      MPI_Bcast(text.data() + at, static_cast<int>(std::min(kPiece, n - at)), MPI_CHAR, root,
                MPI_COMM_WORLD);
  }

  void gather_to_root(const std::string& mine,
                      const std::function<void(const std::string&)>& add) const override {
    if (rank_ != 0) {
      const uint64_t n = mine.size();
      MPI_Send(&n, 1, MPI_UINT64_T, 0, kTag, MPI_COMM_WORLD);
      for (size_t at = 0; at < n; at += kPiece)
        MPI_Send(mine.data() + at, static_cast<int>(std::min(kPiece, n - at)), MPI_CHAR, 0, kTag,
                 MPI_COMM_WORLD);
      return;
    }
    std::string bytes;
    for (int r = 1; r < size_; ++r) {
      uint64_t n = 0;
      MPI_Recv(&n, 1, MPI_UINT64_T, r, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      bytes.resize(n);
      for (size_t at = 0; at < n; at += kPiece)
        MPI_Recv(bytes.data() + at, static_cast<int>(std::min(kPiece, n - at)), MPI_CHAR, r, kTag,
                 MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      add(bytes);
    }
  }

 private:
  static constexpr int kTag = 7;
  int rank_ = 0, size_ = 1;
};

bool launched_by_mpi() {
  // Open MPI's mpirun, PMIx launchers (Open MPI 5, Slurm with PMIx) and PMI-1/2 (srun, MPICH).
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
    if (std::getenv(v)) return true;
  return false;
}

}  // namespace

std::unique_ptr<Cluster> start_mpi_if_launched(int* argc, char*** argv) {
  if (!launched_by_mpi()) return nullptr;
  // Funneled: the renderer's per-device threads never call MPI, only the main thread does.
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  return std::make_unique<MpiCluster>();
}

}  // namespace clpt
