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

ThreadTeam::ThreadTeam(int size, WorkerParking parking, WorkerParkingOptions parking_options)
    : size_(size), parking_(parking, parking_options) {
  if (size < 1) throw std::invalid_argument("a thread team needs at least one member");
  // No chunk is open until the first run.
  next_chunk_.store(static_cast<std::uint32_t>(size), std::memory_order_relaxed);
  workers_.reserve(static_cast<std::size_t>(size - 1));
  for (int m = 1; m < size; ++m) workers_.emplace_back([this] { worker(); });
}

ThreadTeam::~ThreadTeam() {
  if (workers_.empty()) return;
  stop_ = true;
  start_generation_.fetch_add(1, std::memory_order_release);
  start_generation_.notify_all();
  for (auto& w : workers_) w.join();
}

void ThreadTeam::wait_while_equal(const std::atomic<std::uint32_t>& word, std::uint32_t old) {
  // Spin for a fixed time, then sleep. The clock is read every 32 pauses
  // (a pause lasts 10 to 140 cycles depending on the processor, so a count
  // of pauses is no measure of time).
  const auto give_up = std::chrono::steady_clock::now() + kSpinTime;
  for (;;) {
    for (int s = 0; s < 32; ++s) {
      if (word.load(std::memory_order_acquire) != old) return;
      cpu_relax();
    }
    if (std::chrono::steady_clock::now() >= give_up) break;
  }
  while (word.load(std::memory_order_acquire) == old) word.wait(old, std::memory_order_acquire);
}

void ThreadTeam::work_on_chunks() {
  const auto chunks = static_cast<std::uint32_t>(size_);
  for (;;) {
    const std::uint32_t chunk = next_chunk_.fetch_add(1, std::memory_order_acq_rel);
    if (chunk >= chunks) return;
    call_(context_, static_cast<int>(chunk));
    if (completed_.fetch_add(1, std::memory_order_acq_rel) + 1 == chunks) {
      done_generation_.fetch_add(1, std::memory_order_release);
      done_generation_.notify_all();
    }
  }
}

void ThreadTeam::run_erased(Call call, void* context) {
  // Every chunk of the previous run is done (run waited for it), so no thread
  // is inside call_; a late worker may still try to claim, and claims succeed
  // only once next_chunk_ is reset below, when call_ is already this run's.
  call_ = call;
  context_ = context;
  completed_.store(0, std::memory_order_relaxed);
  const std::uint32_t done = done_generation_.load(std::memory_order_acquire);
  next_chunk_.store(0, std::memory_order_release);
  start_generation_.fetch_add(1, std::memory_order_release);
  start_generation_.notify_all();
  work_on_chunks();
  wait_while_equal(done_generation_, done);
}

void ThreadTeam::worker() {
  std::uint32_t seen = 0;
  for (;;) {
    wait_while_equal(start_generation_, seen);
    seen = start_generation_.load(std::memory_order_acquire);
    if (stop_) return;
    work_on_chunks();
  }
}

}  // namespace demcal::dem
