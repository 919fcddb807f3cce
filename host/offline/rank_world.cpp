#include "offline/rank_world.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include "offline/parallel_for.h"

#if SWUM_WITH_MPI
#include <mpi.h>
#endif

namespace swum::host {
namespace {

// Set by mpirun (OpenMPI's own and the PMIx/PMI variables other launchers use).
int launcher_world_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_SIZE", "PMI_SIZE"}) {
    if (const char* v = std::getenv(name)) return std::max(1, std::atoi(v));
  }
  if (std::getenv("PMIX_RANK") != nullptr) return 2;  // a PMIx launch that does not say its size
  return 1;
}

// The items of rank `rank` of `size`.
std::vector<std::size_t> items_of(std::size_t count, int rank, int size) {
  std::vector<std::size_t> mine;
  for (std::size_t i = static_cast<std::size_t>(rank); i < count; i += static_cast<std::size_t>(size)) {
    mine.push_back(i);
  }
  return mine;
}

}  // namespace

RankWorld::RankWorld() {
  const int launched_size = launcher_world_size();
#if SWUM_WITH_MPI
  if (launched_size > 1 || std::getenv("OMPI_COMM_WORLD_RANK") != nullptr) {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    joined_ = true;
    if (provided < MPI_THREAD_FUNNELED) {
      MPI_Finalize();
      joined_ = false;
      throw std::runtime_error("MPI: this MPI library cannot run threads next to MPI calls (MPI_THREAD_FUNNELED)");
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    MPI_Comm local;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &local);
    MPI_Comm_size(local, &local_size_);
    MPI_Comm_free(&local);
    if (launched_size > 1 && size_ == 1) {
      // Another MPI's launcher (or a broken setup): every process would be a world of one and
      // run the whole study into the same files.
      MPI_Finalize();
      joined_ = false;
      throw std::invalid_argument("started by a launcher with " + std::to_string(launched_size) +
                                  " ranks, but MPI formed a world of 1 (another MPI's mpirun?): every rank would "
                                  "run the whole study; use this MPI's mpirun (OpenMPI)");
    }
  }
#else
  if (launched_size > 1) {
    throw std::invalid_argument(
        "started by mpirun with " + std::to_string(launched_size) +
        " ranks, but this swum was built without MPI (SWUM_WITH_MPI=OFF): every rank would run the whole "
        "study; install libopenmpi-dev (tools/setup) and build again");
  }
#endif
}

RankWorld::~RankWorld() {
#if SWUM_WITH_MPI
  if (joined_) MPI_Finalize();
#endif
}

unsigned RankWorld::threads(unsigned requested) const {
  if (requested > 0) return requested;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  return std::max(1u, cores / static_cast<unsigned>(std::max(1, local_size_)));
}

int RankWorld::max_over_ranks(int value) const {
#if SWUM_WITH_MPI
  if (joined_) {
    int result = value;
    MPI_Allreduce(&value, &result, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return result;
  }
#endif
  return value;
}

int RankWorld::from_root(int value) const {
#if SWUM_WITH_MPI
  if (joined_) MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD);
#endif
  return value;
}

void RankWorld::abort(int code) const {
#if SWUM_WITH_MPI
  if (joined_) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

void RankWorld::for_each(std::size_t count, unsigned threads, const Compute& compute, const Deliver& deliver) const {
  const std::vector<std::size_t> mine = items_of(count, rank_, size_);
  const ParallelFor parallel = make_parallel_for(threads);
  std::mutex deliver_mutex;
  const auto deliver_one = [&](std::size_t i, std::string bytes) {
    const std::lock_guard lock(deliver_mutex);
    deliver(i, std::move(bytes));
  };
  if (size_ == 1) {
    parallel(mine.size(), [&](std::size_t k) { deliver_one(mine[k], compute(mine[k])); });
    return;
  }
#if SWUM_WITH_MPI
  // Only this (the main) thread calls MPI (MPI_THREAD_FUNNELED): the items are computed on a
  // worker thread running the parallel-for; rank 0 delivers its own as they complete and
  // receives the others', every other rank sends its results to rank 0 as they complete.
  constexpr int kTag = 16;
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<std::pair<std::size_t, std::string>> outbox;
  bool local_done = false;
  bool stop = false;
  std::exception_ptr worker_failure;
  std::thread worker([&] {
    try {
      parallel(mine.size(), [&](std::size_t k) {
        {
          const std::lock_guard lock(mutex);
          if (stop) throw std::runtime_error("stopped");
        }
        std::string bytes = compute(mine[k]);
        if (root()) {
          deliver_one(mine[k], std::move(bytes));
          return;
        }
        const std::lock_guard lock(mutex);
        outbox.emplace_back(mine[k], std::move(bytes));
        changed.notify_all();
      });
    } catch (...) {
      worker_failure = std::current_exception();
    }
    const std::lock_guard lock(mutex);
    local_done = true;
    changed.notify_all();
  });
  std::exception_ptr failure;
  try {
    if (root()) {
      std::size_t remote = count - mine.size();
      while (true) {
        bool done = false;
        {
          const std::lock_guard lock(mutex);
          done = local_done;
        }
        if (done && (remote == 0 || worker_failure)) break;
        if (remote == 0) {
          std::unique_lock lock(mutex);
          changed.wait(lock, [&] { return local_done; });
          continue;
        }
        // Polled every 2 ms rather than MPI_Probe: OpenMPI's blocking calls spin on a core that
        // the ranks still computing may need (a result every ~0.1-1 s needs no faster answer).
        MPI_Status status;
        int arrived = 0;
        MPI_Iprobe(MPI_ANY_SOURCE, kTag, MPI_COMM_WORLD, &arrived, &status);
        if (!arrived) {
          std::unique_lock lock(mutex);
          if (local_done) {
            lock.unlock();
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
          } else {
            changed.wait_for(lock, std::chrono::milliseconds(2), [&] { return local_done; });
          }
          continue;
        }
        int size = 0;
        MPI_Get_count(&status, MPI_BYTE, &size);
        std::string message(static_cast<std::size_t>(size), '\0');
        MPI_Recv(message.data(), size, MPI_BYTE, status.MPI_SOURCE, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        std::uint64_t i = 0;
        if (message.size() < sizeof i) throw std::runtime_error("MPI: a result message without its item number");
        std::memcpy(&i, message.data(), sizeof i);
        deliver_one(static_cast<std::size_t>(i), message.substr(sizeof i));
        --remote;
      }
    } else {
      while (true) {
        std::unique_lock lock(mutex);
        changed.wait(lock, [&] { return !outbox.empty() || local_done; });
        if (outbox.empty()) break;
        auto [i, bytes] = std::move(outbox.front());
        outbox.pop_front();
        lock.unlock();
        const auto item = static_cast<std::uint64_t>(i);
        std::string message(sizeof item, '\0');
        std::memcpy(message.data(), &item, sizeof item);
        message += bytes;
        MPI_Send(message.data(), static_cast<int>(message.size()), MPI_BYTE, 0, kTag, MPI_COMM_WORLD);
      }
    }
  } catch (...) {
    failure = std::current_exception();
    const std::lock_guard lock(mutex);
    stop = true;
  }
  worker.join();
  if (failure) std::rethrow_exception(failure);
  if (worker_failure) std::rethrow_exception(worker_failure);
#else
  (void)count;
  (void)compute;
#endif
}

}  // namespace swum::host
