// The world's step on several threads (solver/world/tasks.hpp): ThreadPool and parallel_for
// cover every index once, and the world is bitwise the same for any task system (none,
// inline, ranges run in random order one at a time, 1, 2 and 8 threads, and a change of
// system between steps) at every f32 width of the build. Built as its own executable so
// that the ThreadSanitizer job (tests/run_all.sh) compiles only this.
#include <catch2/catch.hpp>

#include "../common/types.hpp"
#include "../spatial/mesh_support.hpp"
#include <fixtures/scenes.hpp>
#include <plume/solver/world/tasks.hpp>
#include <plume/solver/world/world.hpp>
#include <plume/spatial/triangle_mesh.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <numeric>
#include <random>
#include <set>
#include <thread>
#include <vector>

using namespace plume;
using namespace plume::scenes;
using plume::test::grid;
using plume::test::make;

namespace {

constexpr float dt = 1.0f / 60.0f;

// Steps per run of the determinism test: fewer under the sanitizers (ten times slower or more),
// whose job is races and memory errors, which a few steps of every stage already exercise.
#if defined(__SANITIZE_THREAD__) || defined(__SANITIZE_ADDRESS__)
constexpr int determinism_steps = 6;
#else
constexpr int determinism_steps = 40;
#endif

/// A task system for tests: every task split into ranges of exactly min_range items (the
/// last shorter; with `single`, of one item, below what the world asks for, which must not
/// change its result either), run inline in a random order (seeded), and every
/// (count, min_range) seen recorded, so a test can tell which of the world's stages went
/// through it.
class ShuffledTasks final : public TaskSystem {
public:
  explicit ShuffledTasks(std::uint32_t seed, bool single = false) : rng_(seed), single_(single) {}
  std::uint32_t worker_count() const noexcept override { return 4; }
  void* enqueue(TaskFn fn, std::uint32_t count, std::uint32_t min_range, void* context) override {
    min_ranges.insert(min_range);
    ++tasks;
    std::uint32_t const range = single_ ? 1 : min_range;
    std::vector<std::uint32_t> starts;
    for (std::uint32_t b = 0; b < count; b += range)
      starts.push_back(b);
    std::shuffle(starts.begin(), starts.end(), rng_);
    for (std::uint32_t b : starts)
      fn(b, std::min(count, b + range), std::uint32_t(rng_() % 4), context);
    return nullptr;
  }
  void wait(void*) override { FAIL("wait() on a task enqueue() finished"); }

  std::set<std::uint32_t> min_ranges;
  std::size_t tasks = 0;

private:
  std::mt19937 rng_;
  bool single_;
};

/// Enough work that every parallel stage exceeds its minimum range at the widest width: a
/// 10-layer box pyramid (385 boxes), two chains of 150 capsules on spherical joints, spheres
/// and capsules falling on a triangle-mesh floor beside it, a chain of five links driven by an
/// absurd motor (its bodies turn non-finite and freeze in finalize), and one fast body
/// (continuous collision).
World make_scene() {
  World w;
  add_ground(w);
  add_box_pyramid(w, 10);
  add_chain(w, {-20.0f, 40.0f, 0.0f}, 150);
  add_chain(w, {-20.0f, 40.0f, 3.0f}, 150, 0.5f, 4.0f);
  // A bumpy mesh floor at x in [20, 36], z in [-8, 8], 0.5-0.9 m above the ground.
  auto const bumps = [](float x, float z) {
    return 0.5f + 0.1f * float((int(x) * 7 + int(z) * 3) % 5);
  };
  w.create_body(
      {.type = BodyType::static_body,
       .pose = Iso3::from_translation({20.0f, 0.0f, -8.0f}),
       .shape = MeshShape{std::make_shared<TriangleMesh const>(make(grid(16, 1.0f, bumps)))}});
  for (int i = 0; i < 12; ++i)
    for (int k = 0; k < 12; ++k) {
      BodyDef def;
      def.pose = Iso3{Quat::from_rotation_x(0.3f * float(i + k)),
                      {21.0f + 1.2f * float(i), 2.0f + 0.1f * float(k), -7.0f + 1.2f * float(k)}};
      if ((i + k) % 3 == 0)
        def.shape = Sphere{0.4f};
      else if ((i + k) % 3 == 1)
        def.shape = Capsule{0.3f, 0.2f};
      else
        def.shape = Cuboid{{0.3f, 0.2f, 0.4f}};
      w.create_body(def);
    }
  BodyDef fast;
  fast.shape = Sphere{0.1f};
  fast.pose = Iso3::from_translation({0.0f, 30.0f, 20.0f});
  fast.linear_velocity = {0.0f, -300.0f, 0.0f};
  w.create_body(fast);
  BodyId prev = w.create_body({.type = BodyType::static_body,
                               .pose = Iso3::from_translation({0.0f, 5.0f, -20.0f}),
                               .shape = Sphere{0.1f}})
                    .id;
  for (int i = 0; i < 5; ++i) {
    BodyId const link =
        w.create_body({.pose = Iso3::from_translation({0.5f + float(i), 5.0f, -20.0f}),
                       .shape = Cuboid{{0.45f, 0.1f, 0.1f}}})
            .id;
    Vec3 const at{float(i), 5.0f, -20.0f};
    REQUIRE(w.create_joint({.body_a = prev,
                            .body_b = link,
                            .frame_a = w.joint_frame(prev, at, Vec3::Z, Vec3::X),
                            .frame_b = w.joint_frame(link, at, Vec3::Z, Vec3::X),
                            .type = RevoluteJoint{.motor = Motor::velocity_control(3e38f, 1e38f)}})
                .error == JointError::none);
    prev = link;
  }
  return w;
}

/// The world after `steps` steps with `tasks` (changed per step by `pick` when given).
template <class T, class Pick>
std::uint64_t run(int steps, Pick&& pick) {
  World w = make_scene();
  for (int s = 0; s < steps; ++s) {
    w.set_task_system(pick(s));
    w.template step_with<T>(dt);
  }
  REQUIRE(!w.frozen_bodies().empty()); // the motor's chain went through the freezing path
  // The frozen list's order is part of the result.
  std::uint64_t h = w.state_hash();
  for (BodyId b : w.frozen_bodies())
    h = h * 1099511628211u ^ b.index;
  return h;
}

} // namespace

TEST_CASE("ThreadPool and parallel_for run every index once", "[threads]") {
  for (std::uint32_t threads : {0u, 1u, 2u, 3u, 8u}) {
    ThreadPool pool(threads);
    CHECK(pool.worker_count() == std::max(threads, 1u));
    for (std::uint32_t count : {1u, 2u, 7u, 64u, 1000u, 4097u})
      for (std::uint32_t min_range : {0u, 1u, 3u, 16u, 5000u}) { // 0: taken as 1
        // (Catch2's assertions are not thread-safe: the ranges record, the test checks.)
        std::vector<std::atomic<int>> hits(count);
        std::atomic<int> calls{0}, bad_ranges{0};
        parallel_for(&pool, count, min_range, [&](std::uint32_t begin, std::uint32_t end) {
          // Not empty, inside [0, count), at least min_range long but the last.
          if (!(begin < end && end <= count && (end - begin >= min_range || end == count)))
            bad_ranges.fetch_add(1);
          for (std::uint32_t i = begin; i < end && i < count; ++i)
            hits[i].fetch_add(1);
          calls.fetch_add(1);
        });
        INFO("threads " << threads << ", count " << count << ", min_range " << min_range);
        CHECK(bad_ranges.load() == 0);
        for (std::uint32_t i = 0; i < count; ++i)
          REQUIRE(hits[i].load() == 1);
        if (threads <= 1 || count <= min_range) CHECK(calls.load() == 1);
      }
  }
  // Nothing to do: f is not called.
  ThreadPool pool(2);
  bool called = false;
  parallel_for(&pool, 0, 1, [&](std::uint32_t, std::uint32_t) { called = true; });
  parallel_for(nullptr, 0, 1, [&](std::uint32_t, std::uint32_t) { called = true; });
  CHECK_FALSE(called);
}

TEST_CASE("ThreadPool: workers take part, and worker indices stay below worker_count",
          "[threads]") {
  ThreadPool pool(4);
  std::mutex m;
  std::set<std::thread::id> ids;
  std::atomic<bool> bad_worker{false};
  struct Ctx {
    std::mutex* m;
    std::set<std::thread::id>* ids;
    std::atomic<bool>* bad;
  } ctx{&m, &ids, &bad_worker};
  TaskFn const fn = [](std::uint32_t, std::uint32_t, std::uint32_t worker, void* c) {
    auto& x = *static_cast<Ctx*>(c);
    if (worker >= 4) x.bad->store(true);
    {
      std::lock_guard lock(*x.m);
      x.ids->insert(std::this_thread::get_id());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2)); // long enough to be shared
  };
  for (int round = 0; round < 5 && ids.size() < 2; ++round)
    if (void* t = pool.enqueue(fn, 64, 1, &ctx)) pool.wait(t);
  CHECK_FALSE(bad_worker.load());
  CHECK(ids.size() >= 2); // some range ran off the waiting thread
}

TEST_CASE("ThreadPool: several threads enqueue and wait at once", "[threads]") {
  ThreadPool pool(3);
  std::vector<std::uint64_t> sums(4, 0);
  {
    std::vector<std::jthread> callers;
    for (std::size_t c = 0; c < sums.size(); ++c)
      callers.emplace_back([&pool, &sums, c] {
        for (int rep = 0; rep < 200; ++rep) {
          std::vector<std::uint64_t> out(512, 0);
          parallel_for(&pool, 512, 8, [&](std::uint32_t begin, std::uint32_t end) {
            for (std::uint32_t i = begin; i < end; ++i)
              out[i] = i * (c + 1);
          });
          sums[c] += std::accumulate(out.begin(), out.end(), std::uint64_t(0));
        }
      });
  }
  for (std::size_t c = 0; c < sums.size(); ++c)
    CHECK(sums[c] == 200u * (c + 1) * (511u * 512u / 2));
}

#if defined(__SSE__) || defined(__x86_64__)
TEST_CASE("Ranges run with the calling thread's floating-point environment", "[threads]") {
  ThreadPool pool(3); // its workers start with this thread's MXCSR as it is now
  unsigned const before = _mm_getcsr();
  unsigned const ftz_daz = before | 0x8040u; // flush to zero, denormals are zero
  _mm_setcsr(ftz_daz);
  std::vector<unsigned> seen(64, 0);
  std::atomic<int> off_thread{0};
  std::thread::id const me = std::this_thread::get_id();
  for (int round = 0; round < 20 && off_thread.load() == 0; ++round)
    parallel_for(&pool, 64, 1, [&](std::uint32_t begin, std::uint32_t end) {
      if (std::this_thread::get_id() != me) off_thread.fetch_add(1);
      for (std::uint32_t i = begin; i < end; ++i)
        seen[i] = _mm_getcsr();
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    });
  unsigned const after = _mm_getcsr();
  _mm_setcsr(before);
  CHECK(after == ftz_daz); // the caller's own setting is left as it was
  CHECK(off_thread.load() > 0);
  for (unsigned m : seen)
    CHECK(m == ftz_daz);

  // And a host's thread that ran a range gets its own setting back afterwards.
  struct OtherThread final : TaskSystem {
    unsigned own = 0, during = 0, after = 0;
    std::uint32_t worker_count() const noexcept override { return 2; }
    void* enqueue(TaskFn fn, std::uint32_t count, std::uint32_t, void* context) override {
      std::thread([&] {
        _mm_setcsr(own); // the host thread's own setting (a new thread inherits its creator's)
        fn(0, count, 1, context);
        after = _mm_getcsr();
      }).join();
      return nullptr;
    }
    void wait(void*) override {}
  } host;
  host.own = before;
  _mm_setcsr(ftz_daz);
  parallel_for(&host, 8, 1, [&](std::uint32_t, std::uint32_t) { host.during = _mm_getcsr(); });
  _mm_setcsr(before);
  CHECK(host.during == ftz_daz);
  CHECK(host.after == host.own);
  CHECK(host.own != ftz_daz);
}
#endif

TEST_CASE("The world's stages go through the task system", "[threads]") {
  ShuffledTasks tasks(7);
  run<f32xN>(3, [&](int) { return &tasks; });
  // Pair chunks (2 chunks), bodies (256) and constraint blocks (at least 4, one range per
  // worker: 4 workers here): every kind of stage was handed over, so the determinism test
  // below compares parallel runs, not inline ones.
  CHECK(tasks.min_ranges.count(2) == 1);
  CHECK(tasks.min_ranges.count(256) == 1);
  CHECK(std::count_if(tasks.min_ranges.begin(), tasks.min_ranges.end(),
                      [](std::uint32_t r) { return r >= 4 && r != 256; }) >= 1);
  CHECK(tasks.tasks > 100);
}

TEMPLATE_LIST_TEST_CASE("The world is bitwise the same for every task system and thread count",
                        "[threads]", test::f32_types) {
  using T = TestType;
  int const steps = determinism_steps;
  std::uint64_t const reference =
      run<T>(steps, [](int) { return static_cast<TaskSystem*>(nullptr); });
  InlineTasks inline_tasks;
  CHECK(run<T>(steps, [&](int) { return &inline_tasks; }) == reference);
  ShuffledTasks shuffled(1234);
  CHECK(run<T>(steps, [&](int) { return &shuffled; }) == reference);
  ShuffledTasks single(99, true);
  CHECK(run<T>(steps, [&](int) { return &single; }) == reference);
  for (std::uint32_t threads : {0u, 1u, 2u, 8u}) {
    ThreadPool pool(threads);
    INFO("threads: " << threads);
    CHECK(run<T>(steps, [&](int) { return &pool; }) == reference);
  }
  // The system (and its thread count) changed between steps.
  ThreadPool two(2), eight(8);
  TaskSystem* const order[] = {&two, nullptr, &shuffled, &eight, &inline_tasks};
  CHECK(run<T>(steps, [&](int s) { return order[s % 5]; }) == reference);
  // And every width gives the scalar world (the widths' own test, here with threads).
  if constexpr (!std::is_same_v<T, float>) {
    ThreadPool pool(2);
    CHECK(run<float>(steps, [&](int) { return &pool; }) == reference);
  }
}

TEST_CASE("A world with a task system keeps it through copies and changes", "[threads]") {
  ThreadPool pool(2);
  WorldConfig cfg;
  cfg.tasks = &pool;
  World w(cfg);
  CHECK(w.task_system() == &pool);
  World copy = w;
  CHECK(copy.task_system() == &pool);
  w.set_task_system(nullptr);
  CHECK(w.task_system() == nullptr);
  add_ground(w);
  add_box_pyramid(w, 3);
  w.step(dt); // runs inline
  CHECK(w.body_count() == 1 + 14);
}
