// ThreadPool (include/plume/solver/world/tasks.hpp): open tasks in a fixed array of slots,
// ranges claimed with an atomic counter per task and finished ranges counted with another, no
// lock on the way; idle workers spin for a short time (the world enqueues its solver's colours
// back to back, hundreds per step) and then block on a condition variable.
#include <plume/solver/world/tasks.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace plume {

namespace {

void pause() noexcept {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#else
  std::this_thread::yield();
#endif
}

/// Spins (then yields) until done() is true.
template <class Done>
void spin_until(Done&& done) noexcept {
  for (std::uint32_t spins = 0; !done(); ++spins)
    spins < 256 ? pause() : std::this_thread::yield();
}

/// How long an idle worker spins before it blocks.
constexpr auto idle_spin = std::chrono::microseconds(50);

enum : std::uint32_t { slot_free, slot_filling, slot_open, slot_closing };

} // namespace

/// One enqueued task. A slot is reused, never freed, so a worker that read a slot's state a
/// moment ago may still touch its counters: it registers in `users` first and then checks
/// the state again, and wait() returns only once no worker is registered.
struct alignas(64) TaskSlot {
  std::atomic<std::uint32_t> state{slot_free};
  TaskFn fn = nullptr;
  void* context = nullptr;
  std::uint32_t count = 0, range = 1, ranges = 0;
  alignas(64) std::atomic<std::uint32_t> next{0};  ///< the next range to claim
  std::atomic<std::uint32_t> done{0};              ///< ranges that have run
  alignas(64) std::atomic<std::uint32_t> users{0}; ///< workers inside run()

  /// Claims and runs ranges until none is left.
  void run(std::uint32_t worker) {
    for (;;) {
      std::uint32_t const r = next.fetch_add(1, std::memory_order_relaxed);
      if (r >= ranges) return;
      std::uint32_t const begin = r * range;
      fn(begin, std::min(count, begin + range), worker, context);
      done.fetch_add(1, std::memory_order_release);
    }
  }
};

struct ThreadPool::Shared {
  /// Tasks open at once (several threads may enqueue); enqueue() runs a task inline when every
  /// slot is taken.
  static constexpr std::size_t slot_count = 16;
  std::array<TaskSlot, slot_count> slots;
  alignas(64) std::atomic<std::uint64_t> posted{0}; ///< enqueue() count
  std::atomic<std::uint32_t> sleepers{0};           ///< workers blocked (or about to)
  std::mutex mutex;                                 ///< for the condition variable only
  std::condition_variable_any posted_cv;
};

ThreadPool::ThreadPool(std::uint32_t threads)
    : threads_(std::max<std::uint32_t>(threads, 1)), shared_(std::make_unique<Shared>()) {
  workers_.reserve(threads_ - 1);
  for (std::uint32_t w = 1; w < threads_; ++w)
    workers_.emplace_back([this, w](std::stop_token stop) { work(stop, w); });
}

ThreadPool::ThreadPool() : ThreadPool(std::max(1u, std::thread::hardware_concurrency())) {}

ThreadPool::~ThreadPool() {
  for (auto& w : workers_)
    w.request_stop(); // wakes the blocked ones (condition_variable_any with a stop token)
  workers_.clear();   // joins
}

void* ThreadPool::enqueue(TaskFn fn, std::uint32_t count, std::uint32_t min_range, void* context) {
  if (count == 0) return nullptr;
  min_range = std::max<std::uint32_t>(min_range, 1);
  Shared& s = *shared_;
  TaskSlot* t = nullptr;
  if (threads_ > 1 && count > min_range)
    for (TaskSlot& slot : s.slots) {
      std::uint32_t expected = slot_free;
      if (slot.state.compare_exchange_strong(expected, slot_filling, std::memory_order_acquire)) {
        t = &slot;
        break;
      }
    }
  if (t == nullptr) { // one thread, little work, or every slot taken
    fn(0, count, 0, context);
    return nullptr;
  }
  t->fn = fn;
  t->context = context;
  t->count = count;
  // About four ranges per thread (balance when items cost unevenly), none below min_range.
  std::uint32_t const target = 4 * threads_;
  t->range = std::max(min_range, (count + target - 1) / target);
  t->ranges = (count + t->range - 1) / t->range;
  t->next.store(0, std::memory_order_relaxed);
  t->done.store(0, std::memory_order_relaxed);
  t->state.store(slot_open, std::memory_order_release);
  s.posted.fetch_add(1, std::memory_order_seq_cst);
  // A worker counts itself in sleepers before it checks posted for the last time (both
  // seq_cst), so either it sees this post or this sees it and wakes it.
  if (s.sleepers.load(std::memory_order_seq_cst) != 0) {
    { std::lock_guard lock(s.mutex); }
    s.posted_cv.notify_all();
  }
  return t;
}

void ThreadPool::wait(void* handle) {
  auto* t = static_cast<TaskSlot*>(handle);
  t->run(0); // help
  spin_until([t] { return t->done.load(std::memory_order_acquire) >= t->ranges; });
  // Closed to new workers; one registered before the store may still make a failed claim
  // (reading the fields), so the slot is free for another enqueue() only after it left.
  t->state.store(slot_closing, std::memory_order_seq_cst);
  spin_until([t] { return t->users.load(std::memory_order_seq_cst) == 0; });
  t->state.store(slot_free, std::memory_order_release);
}

void ThreadPool::work(std::stop_token stop, std::uint32_t worker) {
  Shared& s = *shared_;
  while (!stop.stop_requested()) {
    std::uint64_t const seen = s.posted.load(std::memory_order_seq_cst);
    bool ran = false;
    for (TaskSlot& t : s.slots) {
      if (t.state.load(std::memory_order_acquire) != slot_open) continue;
      t.users.fetch_add(1, std::memory_order_seq_cst);
      if (t.state.load(std::memory_order_seq_cst) == slot_open &&
          t.next.load(std::memory_order_relaxed) < t.ranges) {
        t.run(worker);
        ran = true;
      }
      t.users.fetch_sub(1, std::memory_order_release);
    }
    if (ran) continue;
    // Idle: spin a little for the next task, then block until one is posted.
    auto const until = std::chrono::steady_clock::now() + idle_spin;
    bool posted = false;
    for (std::uint32_t spins = 0; !stop.stop_requested(); ++spins) {
      if (s.posted.load(std::memory_order_acquire) != seen) {
        posted = true;
        break;
      }
      if (spins % 64 == 63) {
        if (std::chrono::steady_clock::now() > until) break;
        std::this_thread::yield(); // a thread with work may be waiting for this core
      } else {
        pause();
      }
    }
    if (posted) continue;
    std::unique_lock lock(s.mutex);
    s.sleepers.fetch_add(1, std::memory_order_seq_cst);
    s.posted_cv.wait(lock, stop, [&] { return s.posted.load(std::memory_order_seq_cst) != seen; });
    s.sleepers.fetch_sub(1, std::memory_order_relaxed);
  }
}

} // namespace plume
