// plume/solver/world/tasks.hpp - how the world's step runs on several threads: a task interface
// the host application implements (its own job system) and two implementations, inline and
// a small pool of std::jthread workers.
//
//   plume::ThreadPool pool(4);              // 4 threads: the caller and 3 workers
//   world.set_task_system(&pool);           // or WorldConfig::tasks; nullptr: one thread
//   world.step(1.0f / 60.0f);               // same bits as with one thread
//
// The interface is Box2D v3's: a task is a function over a range of item indices [0, count),
// which the task system may split into sub-ranges of at least min_range items (the last may
// be shorter) and run in any order, on any of its workers, at once or one after another;
// enqueue() starts it (or runs it before returning) and wait() returns once every item has
// run. The world enqueues from the thread that calls step(), one task at a time, and waits
// for it before the next; it never enqueues from inside a task. A task's function does not
// throw and touches only what the world gives it.
//
// Determinism: every stage the world runs through tasks writes each item's result to a place
// of its own (a body's state, a block's lanes, a fixed chunk of pairs' manifolds) and merges
// lists in item order afterwards, so the world is bitwise the same for any task system, any
// split and any thread count (tests/world/test_threads.cpp runs the ranges in random order,
// one item at a time or min_range items at a time, and with 1, 2 and 8 threads). Each range
// runs with the floating-point environment (MXCSR on x86: flush-to-zero, rounding) of the
// thread that called parallel_for, whatever thread runs it, so a host that changes its own
// thread's settings does not make workers compute differently.
//
// ThreadPool: threads - 1 workers (std::jthread) plus the thread that waits, which helps with
// the ranges of the task it waits for (as worker 0). Idle workers spin for 50 us, then block
// on a condition variable. 0 or 1 threads: no workers, tasks run inline. Several threads may
// enqueue and wait at once, each on its own tasks (up to 16 open at once; enqueue() runs a
// task inline while all 16 are open); each waiting thread is worker 0. Destroying the pool
// while a task is unfinished is undefined; it joins its workers. Why a pool of our own and
// not oneTBB: docs/performance.md, "Threads".
#pragma once

#include <cstdint>
#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h> // _mm_getcsr, _mm_setcsr
#endif
#include <memory>
#include <thread>
#include <type_traits>
#include <vector>

namespace plume {

/// A range task: runs items [begin, end) of the task; worker < worker_count() tells apart the
/// threads that run ranges of one task at once (for scratch memory of their own; the world
/// does not use it).
using TaskFn = void (*)(std::uint32_t begin, std::uint32_t end, std::uint32_t worker,
                        void* context);

/// The task interface a host application implements to run the world's step on its own
/// threads (the header's top says what the world expects of it).
class TaskSystem {
public:
  virtual ~TaskSystem() = default;
  /// Threads that may run ranges of one task at once, the waiting thread included; 1 or less:
  /// the world runs every stage inline and never enqueues.
  virtual std::uint32_t worker_count() const noexcept = 0;
  /// Starts fn over [0, count) (count >= 1), split into ranges of at least min_range items
  /// (>= 1). Returns a handle for wait(), or nullptr when every range has already run.
  virtual void* enqueue(TaskFn fn, std::uint32_t count, std::uint32_t min_range, void* context) = 0;
  /// Returns once every range of the task `task` (an enqueue() handle, not null) has run.
  virtual void wait(void* task) = 0;
};

/// Runs every task inline, as one range, in enqueue() (what the world does without a task
/// system; for tests and for hosts that want the interface without threads).
class InlineTasks final : public TaskSystem {
public:
  std::uint32_t worker_count() const noexcept override { return 1; }
  void* enqueue(TaskFn fn, std::uint32_t count, std::uint32_t, void* context) override {
    fn(0, count, 0, context);
    return nullptr;
  }
  void wait(void*) override {}
};

/// A pool of threads - 1 std::jthread workers; the waiting thread is worker 0.
class ThreadPool final : public TaskSystem {
public:
  /// threads: the caller and threads - 1 workers; 0 and 1 run every task inline.
  explicit ThreadPool(std::uint32_t threads);
  /// As many threads as the machine has (std::thread::hardware_concurrency, at least 1).
  ThreadPool();
  ~ThreadPool() override;
  ThreadPool(ThreadPool const&) = delete;
  ThreadPool& operator=(ThreadPool const&) = delete;

  std::uint32_t worker_count() const noexcept override { return threads_; }
  void* enqueue(TaskFn fn, std::uint32_t count, std::uint32_t min_range, void* context) override;
  void wait(void* task) override;

private:
  struct Shared;
  void work(std::stop_token stop, std::uint32_t worker);
  std::uint32_t threads_;
  std::unique_ptr<Shared> shared_;
  std::vector<std::jthread> workers_;
};

} // namespace plume

namespace plume {

/// Runs f(begin, end) over sub-ranges of [0, count) that cover every index once, through
/// `tasks` (ranges of at least min_range indices, in any order, on any of its threads), and
/// returns when all have run. Inline, as f(0, count), when tasks is null, has one worker, or
/// count <= min_range. f must not throw (a throw from a range run as a task terminates).
template <class F>
void parallel_for(TaskSystem* tasks, std::uint32_t count, std::uint32_t min_range, F&& f) {
  if (count == 0) return;
  if (tasks == nullptr || count <= min_range || tasks->worker_count() <= 1) {
    f(std::uint32_t(0), count);
    return;
  }
  struct Context {
    std::remove_reference_t<F>* f;
    unsigned fp_env; ///< the caller's MXCSR (x86), applied around each range
  };
  Context context{&f, 0u};
#if defined(__SSE__) || defined(__x86_64__)
  context.fp_env = _mm_getcsr();
#endif
  // noexcept: a throwing range ends the program (a task system cannot carry it back).
  TaskFn const fn = [](std::uint32_t begin, std::uint32_t end, std::uint32_t, void* c) noexcept {
    Context const& ctx = *static_cast<Context const*>(c);
#if defined(__SSE__) || defined(__x86_64__)
    unsigned const own = _mm_getcsr();
    if (own != ctx.fp_env) _mm_setcsr(ctx.fp_env);
    (*ctx.f)(begin, end);
    if (own != ctx.fp_env) _mm_setcsr(own);
#else
    (*ctx.f)(begin, end);
#endif
  };
  if (void* const task = tasks->enqueue(fn, count, min_range, &context)) tasks->wait(task);
}

} // namespace plume
