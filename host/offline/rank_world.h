// The processes of one `swum population` run: the ranks of an MPI job when launched by
// `mpirun` (and built with SWUM_WITH_MPI), else this process alone. Items are split over the
// ranks (item i on rank i mod size) and over each rank's threads (the host's parallel-for);
// rank 0 receives every result (docs/population.md).
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace swum::host {

class RankWorld {
 public:
  /// Joins the MPI job when mpirun started this process (OpenMPI / PMIx environment) and MPI is
  /// built in; alone otherwise. Throws std::invalid_argument when started by mpirun with more
  /// than one rank in a build without MPI (each rank would run the whole study).
  RankWorld();
  ~RankWorld();  // MPI_Finalize when joined
  RankWorld(const RankWorld&) = delete;
  RankWorld& operator=(const RankWorld&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }
  /// Threads for `requested` (0 = this machine's cores shared by the ranks running on it).
  unsigned threads(unsigned requested) const;

  /// The largest `value` over all ranks (every rank calls it; alone: `value`).
  int max_over_ranks(int value) const;
  /// Rank 0's `value`, on every rank (every rank calls it; alone: `value`).
  int from_root(int value) const;
  /// Ends every rank of the job with `code` (MPI_Abort); alone: std::exit(code).
  [[noreturn]] void abort(int code) const;

  /// Bytes computed for item i, on this rank's threads (called concurrently).
  using Compute = std::function<std::string(std::size_t i)>;
  /// Rank 0 only, one call at a time, for every item of every rank, in completion order.
  using Deliver = std::function<void(std::size_t i, std::string bytes)>;
  /// Computes this rank's items (i mod size == rank) on `threads` threads and hands every item's
  /// bytes to `deliver` on rank 0. What compute or deliver throws stops this rank's work and is
  /// rethrown here once the items under way are done; with several ranks the caller must then
  /// abort() (the other ranks would wait for it).
  void for_each(std::size_t count, unsigned threads, const Compute& compute, const Deliver& deliver) const;

 private:
  int rank_ = 0;
  int size_ = 1;
  int local_size_ = 1;  // ranks on this machine
  bool joined_ = false;
};

}  // namespace swum::host
