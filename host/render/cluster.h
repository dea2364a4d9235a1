// The processes one render is split across: MPI ranks under mpirun (app/mpi_cluster.h, in the
// clpt executable only), or this process alone (Cluster itself, whose calls do nothing).
// The renderer plans each pass over every rank's devices with these few collective calls, so
// every rank must make the same calls in the same order; rank 0 keeps the clock and the stop
// flag and alone writes files. Nothing here knows MPI: the library, the tests and the Python
// module use the single-process Cluster.
#pragma once

#include <cstddef>
#include <exception>
#include <functional>
#include <string>
#include <vector>

namespace clpt {

class Cluster {
 public:
  virtual ~Cluster() = default;

  virtual int rank() const { return 0; }
  virtual int size() const { return 1; }
  bool root() const { return rank() == 0; }

  // Every rank's values, concatenated in rank order (ranks may give different counts).
  virtual std::vector<double> all_gather(const std::vector<double>& mine) const { return mine; }
  // `root`'s values on every rank (all ranks pass vectors of the same size).
  virtual void broadcast(std::vector<double>& values, int root) const { (void)values, (void)root; }
  virtual void broadcast(std::string& text, int root) const { (void)text, (void)root; }
  // An array to send (the other ranks), or the size of one to receive (rank 0).
  struct Piece {
    const void* data;
    size_t bytes;
  };
  // add(piece, offset, chunk, bytes): adds `bytes` bytes of another rank's piece `piece`, from
  // byte `offset` on, into this rank's piece (the memory `pieces` points at). Chunks are at
  // most kChunkBytes and start at multiples of it.
  using AddChunk = std::function<void(size_t, size_t, const void*, size_t)>;
  static constexpr size_t kChunkBytes = size_t(16) << 20;  // a multiple of every element size
  // Sums every rank's pieces into rank 0's (every rank's pieces have the same sizes) through a
  // binomial tree: a rank receives the sums of its subtree's ranks, chunk by chunk into one
  // scratch buffer, handing each chunk to add(), and then sends its pieces, its own and what
  // it added, on towards rank 0. A lower rank's values always come first, and the tree is
  // fixed by the number of ranks, so sums add up alike every run; log2 of the ranks in
  // transfers of a film, and a 16 MiB buffer beside the result, whatever the film.
  virtual void gather_to_root(const std::vector<Piece>& pieces, const AddChunk& add) const {
    (void)pieces, (void)add;
  }
  // The same for text of any length (small: statistics): rank 0's add() gets each other
  // rank's, in rank order.
  virtual void gather_text_to_root(const std::string& mine,
                                   const std::function<void(const std::string&)>& add) const {
    (void)mine, (void)add;
  }

  // Every rank's bytes, concatenated in rank order, on every rank (gathered to rank 0, then
  // broadcast from it). Alone: `mine`.
  std::string all_gather_bytes(std::string mine) const;
  // Every rank says whether it failed (`mine`: its exception, or null). If any did, every rank
  // throws the same Error: the failing rank's code and message, from the lowest such rank.
  // Alone: rethrows `mine`.
  void agree(std::exception_ptr mine) const;
};

// Runs `f` and returns what it threw (null if nothing), for Cluster::agree.
std::exception_ptr capture(const std::function<void()>& f);

}  // namespace clpt
