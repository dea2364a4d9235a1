#include "mpi/mpi_cluster.h"

#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

namespace clpt {
namespace {

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
    for (size_t at = 0; at < n; at += kChunkBytes)
      MPI_Bcast(text.data() + at, static_cast<int>(std::min(kChunkBytes, n - at)), MPI_CHAR, root,
                MPI_COMM_WORLD);
  }

  // A binomial tree, the same for every run with the same number of ranks: in round k (step
  // 2^k), a rank whose number is a multiple of 2^(k+1) receives the sums of rank + 2^k and adds
  // them into its own pieces; that rank sends and is done. Rank 0 has every rank's sums after
  // ceil(log2(size)) rounds, each a film's transfer, where receiving from every rank in turn
  // took size - 1 (docs/scaling.md's cost model).
  void gather_to_root(const std::vector<Piece>& pieces, const AddChunk& add) const override {
    // The pieces' sizes first, so that a rank whose film differs is an error, not a hang.
    std::vector<uint64_t> sizes;
    for (const Piece& p : pieces) sizes.push_back(p.bytes);
    std::vector<uint64_t> theirs(sizes.size());
    std::vector<char> chunk;
    for (int step = 1; step < size_; step *= 2) {
      if (rank_ % (2 * step) == step) {  // pass this subtree's sums on, and leave
        const int to = rank_ - step;
        MPI_Send(sizes.data(), static_cast<int>(sizes.size()), MPI_UINT64_T, to, kTag, MPI_COMM_WORLD);
        for (const Piece& p : pieces) send(p.data, p.bytes, to);
        return;
      }
      const int from = rank_ + step;
      if (from >= size_) continue;
      MPI_Recv(theirs.data(), static_cast<int>(theirs.size()), MPI_UINT64_T, from, kTag, MPI_COMM_WORLD,
               MPI_STATUS_IGNORE);
      if (theirs != sizes)
        throw std::logic_error("rank " + std::to_string(from) + " sent a film of another size");
      for (size_t i = 0; i < pieces.size(); ++i)
        for (size_t at = 0; at < sizes[i]; at += kChunkBytes) {
          const size_t n = std::min<size_t>(kChunkBytes, sizes[i] - at);
          chunk.resize(n);
          MPI_Recv(chunk.data(), static_cast<int>(n), MPI_BYTE, from, kTag, MPI_COMM_WORLD,
                   MPI_STATUS_IGNORE);
          add(i, at, chunk.data(), n);
        }
    }
  }

  void gather_text_to_root(const std::string& mine,
                           const std::function<void(const std::string&)>& add) const override {
    if (rank_ != 0) {
      const uint64_t n = mine.size();
      MPI_Send(&n, 1, MPI_UINT64_T, 0, kTag, MPI_COMM_WORLD);
      send(mine.data(), n, 0);
      return;
    }
    std::string text;
    for (int r = 1; r < size_; ++r) {
      uint64_t n = 0;
      MPI_Recv(&n, 1, MPI_UINT64_T, r, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      text.resize(n);
      receive(text.data(), n, r);
      add(text);
    }
  }

 private:
  static constexpr int kTag = 7;
  // In the chunks gather_to_root receives, which also fit a count of int.
  static void send(const void* data, size_t bytes, int to) {
    const char* at = static_cast<const char*>(data);
    for (size_t done = 0; done < bytes; done += kChunkBytes)
      MPI_Send(at + done, static_cast<int>(std::min(kChunkBytes, bytes - done)), MPI_BYTE, to, kTag,
               MPI_COMM_WORLD);
  }
  static void receive(void* data, size_t bytes, int from) {
    char* at = static_cast<char*>(data);
    for (size_t done = 0; done < bytes; done += kChunkBytes)
      MPI_Recv(at + done, static_cast<int>(std::min(kChunkBytes, bytes - done)), MPI_BYTE, from, kTag,
               MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  }
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
