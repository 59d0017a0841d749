// Depenetration (Gauss–Seidel push-out) and the plane-set builder: exact answers for
// orthogonal planes, convergence for a general corner, bounded non-convergence for opposing
// planes, the rejection and bad-input rules, and lane-exactness of the wide forms.
#include "character_support.hpp"

#include <plume/solver/character/depenetration.hpp>
#include <plume/solver/character/plane_set.hpp>

#include <array>
#include <limits>

using namespace plume;
using namespace plume::test;

namespace {
using P3 = Penetration3;
} // namespace

TEST_CASE("depenetration: exact answers", "[solver][depenetration]") {
  SECTION("single plane") {
    std::array<P3, 1> const p = {P3{{0, 0, 1}, 0.3f}};
    auto const r = depenetrate(p);
    CHECK(r.correction.x == 0);
    CHECK(r.correction.y == 0);
    CHECK(r.correction.z == 0.3f);
    CHECK(r.converged);
    CHECK(r.passes == 2); // one pass pushes, the second confirms
  }
  SECTION("two orthogonal planes") {
    std::array<P3, 2> const p = {P3{{0, 0, 1}, 0.25f}, P3{{-1, 0, 0}, 0.125f}};
    auto const r = depenetrate(p);
    CHECK(r.correction.x == -0.125f);
    CHECK(r.correction.y == 0);
    CHECK(r.correction.z == 0.25f);
    CHECK(r.converged);
  }
  SECTION("a corner of three orthogonal planes") {
    std::array<P3, 3> const p = {P3{{0, 0, 1}, 0.25f}, P3{{-1, 0, 0}, 0.125f},
                                 P3{{0, 1, 0}, 0.0625f}};
    auto const r = depenetrate(p);
    CHECK(r.correction.x == -0.125f);
    CHECK(r.correction.y == 0.0625f);
    CHECK(r.correction.z == 0.25f);
    CHECK(r.converged);
  }
  SECTION("a general corner converges to every plane within max_error") {
    std::array<P3, 3> const p = {P3{Vec3{0.2f, 0.1f, 1}.normalize(), 0.2f},
                                 P3{Vec3{-1, 0.3f, 0.2f}.normalize(), 0.1f},
                                 P3{Vec3{0.1f, 1, 0.4f}.normalize(), 0.15f}};
    auto const r = depenetrate(p);
    CHECK(r.converged);
    CHECK(r.passes < 16);
    for (auto const& q : p)
      CHECK(r.correction.dot(q.normal) >= q.depth - 1e-4f);
    // Each pass only adds push along the normals, so the fix is a non-negative combination
    // of them: no component against any normal beyond what the others force.
    CHECK(r.correction.length() <= 0.2f + 0.1f + 0.15f);
  }
  SECTION("opposing planes: bounded, finite, not converged") {
    std::array<P3, 2> const p = {P3{{0, 0, 1}, 0.1f}, P3{{0, 0, -1}, 0.1f}};
    auto const r = depenetrate(p);
    CHECK_FALSE(r.converged);
    CHECK(r.passes == 16);
    CHECK(r.correction.is_finite());
    CHECK(r.correction.length() <= 0.2f + 1e-6f);
  }
  SECTION("nothing to do: zero, converged after one pass") {
    auto const r = depenetrate(std::span<P3 const>{});
    CHECK(r.correction.length() == 0);
    CHECK(r.converged);
    CHECK(r.passes == 1);
    std::array<P3, 1> const separated = {P3{{0, 0, 1}, -0.2f}};
    CHECK(depenetrate(separated).correction.length() == 0);
  }
}

TEST_CASE("depenetration: rejection, bad input, scaling", "[solver][depenetration]") {
  float const nan = std::numeric_limits<float>::quiet_NaN();
  float const inf = std::numeric_limits<float>::infinity();
  std::array<P3, 5> const p = {P3{{0, 0, 1}, 0.2f}, P3{{1, 0, 0}, 0.6f} /* deeper than 0.5 */,
                               P3{{nan, 0, 0}, 0.1f}, P3{{0, 1, 0}, nan}, P3{{0, inf, 0}, 0.1f}};
  auto const r = depenetrate(p);
  CHECK(r.correction.x == 0);
  CHECK(r.correction.y == 0);
  CHECK(r.correction.z == 0.2f);
  CHECK(r.converged);
  // In centimetres the 0.6 deep pair is shallow (threshold 50).
  auto const cm = depenetrate(p, DepenetrationConfig{}.scaled(100));
  CHECK(cm.correction.x == 0.6f);
  CHECK(DepenetrationConfig{}.scaled(100).max_error == 1e-4f * 100);
}

PLUME_WIDE_TEST_CASE("wide depenetration equals scalar per lane", "[solver][depenetration][lanes]",
                     wide_real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  rng r(31);
  int failures = 0;
  for (int t = 0; t < 200; ++t) {
    std::vector<GPenetration<GVec3<T>>> wide(std::size_t(1 + t % 7));
    for (auto& p : wide) {
      p.normal = r.unit3<T>();
      p.depth = r.elem<T>(-0.1, 0.7);
    }
    if (t % 5 == 0) // an opposing pair in some lanes
      wide.push_back({-wide[0].normal, wide[0].depth});
    auto const res = depenetrate(wide);
    for (std::size_t l = 0; l < lanes_v<T>; ++l) {
      std::vector<GPenetration<GVec3<S>>> one;
      for (auto const& p : wide)
        one.push_back({lane(p.normal, l), lane(p.depth, l)});
      auto const s = depenetrate(one);
      bool const ok = same(lane(res.correction, l), s.correction) &&
                      lane(res.converged, l) == s.converged && same(lane(res.passes, l), s.passes);
      if (!ok && failures++ < 3) FAIL_CHECK("case " << t << " lane " << l);
    }
  }
  CHECK(failures == 0);
}

TEST_CASE("2D depenetration", "[solver][depenetration][2d]") {
  std::array<Penetration2, 2> const p = {Penetration2{{0, 1}, 0.5f - 0.25f},
                                         Penetration2{{1, 0}, 0.125f}};
  auto const r = depenetrate(p);
  CHECK(r.correction.x == 0.125f);
  CHECK(r.correction.y == 0.25f);
}

// ------------------------------------------------------------------------------------ plane sets

TEST_CASE("plane set: merging, rejection, capacity", "[solver][planes]") {
  Vec3 const v{1, 0, -1};
  SECTION("normals within 5 degrees merge, keeping the one most against v") {
    PlaneSet3 set(v);
    Vec3 const a = Vec3{-1, 0, 0.02f}.normalize(); // 1.1 degrees from -x
    Vec3 const b = Vec3{-1, 0, 0.06f}.normalize(); // 2.3 degrees; more against v (smaller n . v)
    CHECK(set.add(a * 3.0f));                      // any length: normalised
    CHECK(set.add(b));
    REQUIRE(set.count() == 1);
    CHECK((set.normals()[0] - b).length() <= 1e-6f);
    CHECK(set.add({-1, 0, 0.5f})); // 26.6 degrees away: a second plane
    CHECK(set.count() == 2);
  }
  SECTION("just outside 5 degrees: two planes") {
    PlaneSet3 set(v);
    set.add({0, 0, 1});
    set.add({std::sin(0.0885f), 0, std::cos(0.0885f)}); // 5.07 degrees
    CHECK(set.count() == 2);
  }
  SECTION("zero and non-finite normals are rejected") {
    PlaneSet3 set(v);
    CHECK_FALSE(set.add({0, 0, 0}));
    CHECK_FALSE(set.add({std::numeric_limits<float>::quiet_NaN(), 0, 1}));
    CHECK_FALSE(set.add({std::numeric_limits<float>::infinity(), 0, 1}));
    CHECK(set.count() == 0);
    CHECK(set.normals().empty());
  }
  SECTION("any finite nonzero normal is a direction: huge and subnormal ones too") {
    PlaneSet3 set(v);
    CHECK(set.add({0, -1.7e38f, 3e38f})); // its square overflows
    REQUIRE(set.count() == 1);
    Vec3 const want = Vec3{0, -1.7f, 3.0f}.normalize();
    CHECK((set.normals()[0] - want).length() <= 1e-6f);
    CHECK(set.add({1e-44f, 0, 0})); // subnormal: its square underflows
    REQUIRE(set.count() == 2);
    CHECK(set.normals()[1].x == 1.0f);
    for (auto const& n : set.normals())
      CHECK(std::abs(n.length() - 1.0f) <= 1e-6f);
  }
  SECTION("more planes than max_planes: the least relevant is replaced, overflow reported") {
    PlaneSetConfig cfg;
    cfg.max_planes = 3;
    PlaneSet3 set(v, cfg);
    set.add({0, 1, 0});                 // n . v = 0
    set.add({0, -1, 0});                // 0
    set.add(Vec3{1, 0, 1}.normalize()); // 0 (perpendicular), kept
    CHECK_FALSE(set.overflowed());
    CHECK(set.add({-1, 0, 0})); // n . v = -1: replaces the first largest (slot 0)
    CHECK(set.overflowed());
    CHECK(set.count() == 3);
    CHECK(set.normals()[0].x == -1);
    CHECK_FALSE(set.add(Vec3{0.3f, 0.9f, 0.3f}.normalize())); // n . v = 0: not more relevant
  }
  SECTION("dense nearly parallel planes collapse and projection works on the result") {
    PlaneSet3 set(v);
    for (int i = 0; i < 200; ++i) {
      float const a = 0.0004f * float(i); // 200 normals within 4.6 degrees
      set.add({-std::cos(a), std::sin(a), 0});
    }
    CHECK(set.count() == 1); // all within 5 degrees of the first, the one most against v
    auto const r = project_velocity(v, set.normals());
    CHECK(r.converged);
    for (auto const& n : set.normals())
      CHECK(n.dot(r.velocity) >= -0.005f);
  }
}

PLUME_WIDE_TEST_CASE("wide plane sets equal scalar ones per lane", "[solver][planes][lanes]",
                     wide_real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  rng r(8);
  GPlaneSetConfig<S> cfg;
  cfg.max_planes = 6;
  GVec3<T> const v = r.vec3<T>(-3, 3);
  GPlaneSet3<T> wide(v, cfg);
  std::vector<GVec3<T>> added;
  for (int i = 0; i < 40; ++i) {
    GVec3<T> n = r.unit3<T>();
    if (i % 3 == 1) n = added.back() + r.vec3<T>(-0.03, 0.03); // near an earlier one
    if (i == 7) n = with_lane(n, 0, GVec3<S>{});               // a zero normal in lane 0
    added.push_back(n);
    wide.add(n);
  }
  for (std::size_t l = 0; l < lanes_v<T>; ++l) {
    GPlaneSet3<S> one(lane(v, l), cfg);
    for (auto const& n : added)
      one.add(lane(n, l));
    CHECK(lane(wide.count(), l) == one.count());
    CHECK(lane(wide.overflowed(), l) == one.overflowed());
    for (std::size_t i = 0; i < one.normals().size(); ++i)
      CHECK(same(lane(wide.normals()[i], l), one.normals()[i]));
    for (std::size_t i = one.normals().size(); i < wide.normals().size(); ++i)
      CHECK(same(lane(wide.normals()[i], l), GVec3<S>{}));
  }
}

TEST_CASE("2D plane set and configurations scaled by a length unit", "[solver][planes][2d]") {
  Vec2 const v{1, -1};
  PlaneSet2 set(v);
  CHECK(set.add({0, 2}));                             // floor, normalised
  CHECK(set.add({std::sin(0.05f), std::cos(0.05f)})); // 2.9 degrees: merged
  CHECK(set.add({-1, 0}));                            // wall
  REQUIRE(set.count() == 2);
  CHECK(set.normals()[0].y == 1);
  auto const r = project_velocity(v, set.normals());
  CHECK(r.velocity.x == 0);
  CHECK(r.velocity.y == 0);

  // scaled() is the configuration it is called on with its lengths multiplied: the
  // dimensionless fields, defaults or not, stay.
  CHECK(DepenetrationConfig{}.scaled(100).rejection_threshold == 0.5f * 100);
  DepenetrationConfig few;
  few.iterations = 3;
  few.max_error = 2e-4f;
  CHECK(few.scaled(100).iterations == 3);
  CHECK(few.scaled(100).max_error == 2e-4f * 100);
  CHECK(few.scaled(100).rejection_threshold == 0.5f * 100);
  VelocityProjectionConfig tight;
  tight.max_steps = 4;
  tight.epsilon = 1e-3f;
  CHECK(tight.scaled(100).max_steps == 4);
  CHECK(tight.scaled(100).epsilon == 1e-3f * 100);
  auto const cm = VelocityProjectionConfig{}.scaled(100);
  CHECK(cm.epsilon == 0.005f * 100);
  CHECK(cm.parallel_epsilon == VelocityProjectionConfig{}.parallel_epsilon);
  // A 0.3 cm/s component into a wall is below the default tolerance in centimetres only.
  std::vector<Vec3> const wall = {{-1, 0, 0}};
  CHECK(project_velocity(Vec3{0.3f, 1, 0}, wall, cm).velocity.x == 0.3f);
  CHECK(project_velocity(Vec3{0.3f, 1, 0}, wall).velocity.x == 0);
}
