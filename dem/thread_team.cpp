#include "dem/thread_team.hpp"

#include <stdexcept>

namespace demcal::dem {
namespace {

inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

}  // namespace

ThreadTeam::ThreadTeam(int size) : size_(size) {
  if (size < 1) throw std::invalid_argument("a thread team needs at least one member");
  workers_.reserve(static_cast<std::size_t>(size - 1));
  for (int m = 1; m < size; ++m) workers_.emplace_back([this, m] { worker(m); });
}

ThreadTeam::~ThreadTeam() {
  if (workers_.empty()) return;
  stop_ = true;
  start_generation_.fetch_add(1, std::memory_order_release);
  start_generation_.notify_all();
  for (auto& w : workers_) w.join();
}

void ThreadTeam::wait_while_equal(const std::atomic<std::uint32_t>& word, std::uint32_t old) {
  const std::uint32_t budget = spin_budget_.load(std::memory_order_relaxed);
  for (std::uint32_t s = 0; s < budget; ++s) {
    if (word.load(std::memory_order_acquire) != old) {
      if (budget < kMaxSpin)
        spin_budget_.store(std::min(kMaxSpin, budget + budget / 4 + 1), std::memory_order_relaxed);
      return;
    }
    cpu_relax();
  }
  // Spinning did not pay: the member we wait for is not running. Spin less
  // next time and give the core away now.
  spin_budget_.store(std::max(kMinSpin, budget / 2), std::memory_order_relaxed);
  while (word.load(std::memory_order_acquire) == old) word.wait(old, std::memory_order_acquire);
}

void ThreadTeam::run_erased(Call call, void* context) {
  call_ = call;
  context_ = context;
  const std::uint32_t done = done_generation_.load(std::memory_order_acquire);
  start_generation_.fetch_add(1, std::memory_order_release);
  start_generation_.notify_all();
  call(context, 0);
  wait_while_equal(done_generation_, done);
}

void ThreadTeam::worker(int member) {
  std::uint32_t seen = 0;
  for (;;) {
    wait_while_equal(start_generation_, seen);
    seen = start_generation_.load(std::memory_order_acquire);
    if (stop_) return;
    call_(context_, member);
    if (finished_.fetch_add(1, std::memory_order_acq_rel) + 1 == static_cast<std::uint32_t>(size_ - 1)) {
      finished_.store(0, std::memory_order_relaxed);
      done_generation_.fetch_add(1, std::memory_order_release);
      done_generation_.notify_all();
    }
  }
}

void ThreadTeam::barrier() {
  if (size_ == 1) return;
  const std::uint32_t generation = barrier_generation_.load(std::memory_order_acquire);
  if (barrier_arrived_.fetch_add(1, std::memory_order_acq_rel) + 1 == static_cast<std::uint32_t>(size_)) {
    barrier_arrived_.store(0, std::memory_order_relaxed);
    barrier_generation_.fetch_add(1, std::memory_order_release);
    barrier_generation_.notify_all();
    return;
  }
  wait_while_equal(barrier_generation_, generation);
}

}  // namespace demcal::dem
