#pragma once
// A persistent team of threads for the engine's step, with a wait policy the
// engine sets itself.
//
// Why not OpenMP's parallel regions: libgomp's threads busy-wait at every
// fork, join and barrier (its default spin count), and its wait policy can
// only be changed through OMP_WAIT_POLICY before the library loads, not by the
// program. A step forked five times; on a machine where another process holds
// a core, each fork or barrier then waited for a thread the kernel had
// descheduled while its partner spun on the other core, and a 2-thread run
// slowed down 10-25x (BENCHMARKS.md). This team spins only briefly (a few
// microseconds, long enough for a partner that is merely behind) and then
// sleeps on a futex (std::atomic::wait), so a member that waits gives its core
// back to the member it is waiting for.
//
// Work is split statically by member index, so a run is bit-identical for a
// given thread count. A team of one runs the work on the caller, with no
// thread and no synchronisation at all.

#include <atomic>
#include <cstdint>
#include <thread>
#include <type_traits>
#include <vector>

namespace demcal::dem {

class ThreadTeam {
 public:
  // Starts size - 1 worker threads (the caller is member 0).
  explicit ThreadTeam(int size = 1);
  ~ThreadTeam();
  ThreadTeam(const ThreadTeam&) = delete;
  ThreadTeam& operator=(const ThreadTeam&) = delete;

  int size() const { return size_; }

  // Calls fn(member) on every member, member 0 on the calling thread, and
  // returns when all have finished: one fork and one join. fn must not throw
  // (the engine's loops report errors through their results instead).
  template <class Fn>
  void run(Fn&& fn) {
    if (size_ == 1) {
      fn(0);
      return;
    }
    run_erased([](void* f, int member) { (*static_cast<std::remove_reference_t<Fn>*>(f))(member); },
               static_cast<void*>(&fn));
  }

  // Inside run(): waits until every member has arrived.
  void barrier();

  // The half-open range [begin, end) of n items that member m of the team works on.
  static std::size_t split(std::size_t n, int members, int m) {
    return n * static_cast<std::size_t>(m) / static_cast<std::size_t>(members);
  }

 private:
  using Call = void (*)(void*, int);
  void run_erased(Call call, void* context);
  void worker(int member);
  // Spins briefly on `word` while it equals `old`, then sleeps until it changes.
  void wait_while_equal(const std::atomic<std::uint32_t>& word, std::uint32_t old);

  int size_ = 1;
  std::vector<std::thread> workers_;
  Call call_ = nullptr;
  void* context_ = nullptr;
  bool stop_ = false;
  // Each on its own cache line: they are the only words members write to.
  alignas(64) std::atomic<std::uint32_t> start_generation_{0};
  alignas(64) std::atomic<std::uint32_t> finished_{0};
  alignas(64) std::atomic<std::uint32_t> done_generation_{0};
  alignas(64) std::atomic<std::uint32_t> barrier_arrived_{0};
  alignas(64) std::atomic<std::uint32_t> barrier_generation_{0};
  // How many pause instructions a waiter spins before it sleeps. Adapts: it
  // shrinks when spinning did not pay (the partner was descheduled, as on a
  // shared machine) and grows back while waits end during the spin.
  alignas(64) std::atomic<std::uint32_t> spin_budget_{kMaxSpin};
  static constexpr std::uint32_t kMinSpin = 64;
  static constexpr std::uint32_t kMaxSpin = 1u << 14;
};

}  // namespace demcal::dem
