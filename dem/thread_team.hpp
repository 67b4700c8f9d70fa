#pragma once
// A persistent team of threads for the engine's step, with a wait policy the
// engine sets itself.
//
// Why not OpenMP's parallel regions: libgomp's threads busy-wait at every
// fork, join and barrier (its default spin count), its wait policy can only be
// changed through OMP_WAIT_POLICY before the library loads, and a region's
// work is tied to its threads. A step forked five times; on a machine where
// another process holds a core, each fork or barrier waited for a thread the
// kernel had descheduled, and a 2-thread run slowed down 10-25x
// (BENCHMARKS.md).
//
// Here the work of a run is a fixed set of chunks, one per member of the
// team, that any thread may take: the caller and the workers claim chunks
// until none is left, each its own chunk first (so a thread keeps working on
// the same particles, in its own core's cache, from run to run). When a worker is descheduled, or
// still asleep when the run starts, the caller takes its chunk instead of waiting for it, so a
// 2-thread run on a busy machine degrades to about the speed of one thread,
// not below it. Chunk c is always the same work and writes the same buffers,
// whichever thread runs it, so a run is bit-identical for a given thread
// count. A thread that finds nothing to do spins briefly, then sleeps on a
// futex (std::atomic::wait) and gives its core back. A team of one runs the
// work on the caller, with no thread and no synchronisation at all.
//
// On a shared machine even that is slower than one thread (a chunk half done
// by a descheduled worker cannot be taken over), so the team can also park its
// workers and run every chunk on the caller: same chunks, same buffers, same
// results bit for bit. Whether it does is decided during the run from its own
// measured wall time (dem/worker_parking.hpp).

#include "dem/worker_parking.hpp"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <thread>
#include <type_traits>
#include <vector>

namespace demcal::dem {

class ThreadTeam {
 public:
  // Starts size - 1 worker threads (the caller is member 0). `parking` says
  // whether they may be parked (dem/worker_parking.hpp); it never changes results.
  explicit ThreadTeam(int size = 1, WorkerParking parking = WorkerParking::kAdaptive,
                      WorkerParkingOptions parking_options = {});
  ~ThreadTeam();
  ThreadTeam(const ThreadTeam&) = delete;
  ThreadTeam& operator=(const ThreadTeam&) = delete;

  int size() const { return size_; }

  // Calls fn(chunk) for every chunk 0 .. size()-1, each once, on whichever
  // thread claims it (the caller works too), and returns when all are done.
  // fn must not throw (the engine's loops report errors through their results).
  template <class Fn>
  void run(Fn&& fn) {
    if (size_ == 1) {
      fn(0);
      return;
    }
    const auto start = std::chrono::steady_clock::now();
    if (parking_.park()) {
      // The chunks in their own order on the caller: the workers sleep.
      for (int chunk = 0; chunk < size_; ++chunk) fn(chunk);
    } else {
      run_erased([](void* f, int chunk) { (*static_cast<std::remove_reference_t<Fn>*>(f))(chunk); },
                 static_cast<void*>(&fn));
    }
    parking_.record(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }

  // The parking rule's state (how often it probed and switched, and where it settled).
  const WorkerParkingPolicy& parking() const { return parking_; }

  // The half-open range [begin, end) of n items that chunk m of `members` works on.
  static std::size_t split(std::size_t n, int members, int m) {
    return n * static_cast<std::size_t>(m) / static_cast<std::size_t>(members);
  }

 private:
  using Call = void (*)(void*, int);
  void run_erased(Call call, void* context);
  void worker(int member);
  // Claims and runs chunks of the current run until none is left, its own
  // chunk (= member) first.
  void work_on_chunks(int member);
  // Spins briefly on `word` while it equals `old`, then sleeps until it changes.
  void wait_while_equal(const std::atomic<std::uint32_t>& word, std::uint32_t old);

  int size_ = 1;
  // Read and written by the caller of run() only.
  WorkerParkingPolicy parking_;
  std::vector<std::thread> workers_;
  Call call_ = nullptr;
  void* context_ = nullptr;
  bool stop_ = false;
  // Each on its own cache line: they are the only words members write to.
  alignas(64) std::atomic<std::uint32_t> start_generation_{0};
  // One claim flag per chunk, each on its own cache line; 0 = open.
  struct alignas(64) ChunkClaim {
    std::atomic<std::uint32_t> taken{1};
  };
  std::unique_ptr<ChunkClaim[]> chunk_claims_;
  alignas(64) std::atomic<std::uint32_t> completed_{0};
  alignas(64) std::atomic<std::uint32_t> done_generation_{0};
  // How long a waiter spins before it sleeps on the futex. Long enough to
  // cover the gap between two runs of a step (tens to hundreds of
  // microseconds), which a sleep and a wake-up would cost again: a budget that
  // halved at every sleep, as up to 2026-12-05, settled at its floor and put a
  // 2-thread pour to sleep at 40 % of its waits, 25 % slower (BENCHMARKS.md).
  // On a shared machine the spin is not the cure (a descheduled partner
  // cannot be waited out): worker parking is.
  static constexpr std::chrono::microseconds kSpinTime{300};
};

}  // namespace demcal::dem
