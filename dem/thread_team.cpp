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
  chunk_claims_.reset(new ChunkClaim[static_cast<std::size_t>(size)]);
  for (int c = 0; c < size; ++c) chunk_claims_[c].taken.store(1, std::memory_order_relaxed);
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

void ThreadTeam::work_on_chunks(int member) {
  // Member m tries chunk m first, then the others: each thread then works on
  // the same particles at every run of a step (the kicks and the force loop
  // give chunk m the same particles), which stay in its core's cache. Any
  // member may still take any chunk, so a late or descheduled thread's
  // chunk is done by another and nobody waits for it.
  const auto chunks = static_cast<std::uint32_t>(size_);
  for (std::uint32_t k = 0; k < chunks; ++k) {
    const std::uint32_t chunk = (static_cast<std::uint32_t>(member) + k) % chunks;
    std::atomic<std::uint32_t>& taken = chunk_claims_[chunk].taken;
    if (taken.load(std::memory_order_relaxed) != 0) continue;
    if (taken.exchange(1, std::memory_order_acq_rel) != 0) continue;
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
  // only once the chunks are opened below, when call_ is already this run's.
  call_ = call;
  context_ = context;
  completed_.store(0, std::memory_order_relaxed);
  const std::uint32_t done = done_generation_.load(std::memory_order_acquire);
  for (int c = 0; c < size_; ++c) chunk_claims_[c].taken.store(0, std::memory_order_release);
  start_generation_.fetch_add(1, std::memory_order_release);
  start_generation_.notify_all();
  work_on_chunks(0);
  wait_while_equal(done_generation_, done);
}

void ThreadTeam::worker(int member) {
  std::uint32_t seen = 0;
  for (;;) {
    wait_while_equal(start_generation_, seen);
    seen = start_generation_.load(std::memory_order_acquire);
    if (stop_) return;
    work_on_chunks(member);
  }
}

}  // namespace demcal::dem
