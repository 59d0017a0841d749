// Closed-form ray casts: against long-double oracles on random rays, the header's bad-input
// cases, the robust sphere discriminant on far spheres, and lane-exactness of every shape.
#include "../math/math_support.hpp"

#include <plume/collision/ray_cast.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

using namespace plume;
using namespace plume::test;

namespace {

using LD = long double;
struct ld3 {
  LD x, y, z;
};
ld3 ld(Vec3 v) { return {v.x, v.y, v.z}; }
LD dot(ld3 a, ld3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

/// First t >= 0 with |o + t d - c|^2 = r^2 (entry; or exit when the origin is inside and
/// exit is asked), naive quadratic in long double.
std::optional<LD> sphere_oracle(ld3 o, ld3 d, ld3 c, LD r, bool exit = false) {
  ld3 const f{o.x - c.x, o.y - c.y, o.z - c.z};
  LD const a = dot(d, d), b = dot(f, d), cc = dot(f, f) - r * r;
  LD const disc = b * b - a * cc;
  if (disc < 0 || a == 0) return std::nullopt;
  LD const s = std::sqrt(disc);
  LD const t0 = (-b - s) / a, t1 = (-b + s) / a;
  if (exit) return t1 >= 0 ? std::optional<LD>(t1) : std::nullopt;
  if (t1 < 0) return std::nullopt;
  return t0 >= 0 ? t0 : 0;
}

/// Slab test in long double; origin-in-slab decides parallel axes.
std::optional<LD> box_oracle(ld3 o, ld3 d, ld3 e) {
  LD tin = -INFINITY, tout = INFINITY;
  LD const oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z}, ee[3] = {e.x, e.y, e.z};
  for (int i = 0; i < 3; ++i) {
    if (dd[i] == 0) {
      if (std::abs(oo[i]) > ee[i]) return std::nullopt;
      continue;
    }
    LD t1 = (-ee[i] - oo[i]) / dd[i], t2 = (ee[i] - oo[i]) / dd[i];
    if (t1 > t2) std::swap(t1, t2);
    tin = std::max(tin, t1);
    tout = std::min(tout, t2);
  }
  if (tin > tout || tout < 0) return std::nullopt;
  return std::max<LD>(tin, 0);
}

/// Capsule entry: the earliest of the side (clipped to |y| <= h) and the two end spheres.
std::optional<LD> capsule_oracle(ld3 o, ld3 d, LD h, LD r) {
  std::optional<LD> best;
  auto take = [&](std::optional<LD> t) {
    if (t && (!best || *t < *best)) best = t;
  };
  take(sphere_oracle(o, d, {0, h, 0}, r));
  take(sphere_oracle(o, d, {0, -h, 0}, r));
  LD const a = d.x * d.x + d.z * d.z, b = o.x * d.x + o.z * d.z, c = o.x * o.x + o.z * o.z - r * r;
  LD const disc = b * b - a * c;
  if (a > 0 && disc >= 0) {
    LD const t0 = (-b - std::sqrt(disc)) / a, t1 = (-b + std::sqrt(disc)) / a;
    if (t1 >= 0) {
      LD const t = std::max<LD>(t0, 0);
      if (std::abs(o.y + d.y * t) <= h) take(t);
    }
  }
  return best;
}

/// Cylinder entry by clipping the ray's interval against the side and the caps.
std::optional<LD> cylinder_oracle(ld3 o, ld3 d, LD h, LD r) {
  LD tin = -INFINITY, tout = INFINITY;
  LD const a = d.x * d.x + d.z * d.z, b = o.x * d.x + o.z * d.z, c = o.x * o.x + o.z * o.z - r * r;
  if (a == 0) {
    if (c > 0) return std::nullopt;
  } else {
    LD const disc = b * b - a * c;
    if (disc < 0) return std::nullopt;
    tin = (-b - std::sqrt(disc)) / a;
    tout = (-b + std::sqrt(disc)) / a;
  }
  if (d.y == 0) {
    if (std::abs(o.y) > h) return std::nullopt;
  } else {
    LD t1 = (-h - o.y) / d.y, t2 = (h - o.y) / d.y;
    if (t1 > t2) std::swap(t1, t2);
    tin = std::max(tin, t1);
    tout = std::min(tout, t2);
  }
  if (tin > tout || tout < 0) return std::nullopt;
  return std::max<LD>(tin, 0);
}

/// Compares plume (float, solid casts in the local frame) with an oracle on random rays:
/// hit agreement away from grazing, toi within tol, and the normal against the surface.
template <class Shape, class Oracle, class Grazing>
void check_against_oracle(char const* name, Shape const& shape, Oracle oracle, Grazing grazing,
                          double tol) {
  rng r(17);
  int compared = 0, hits = 0, mismatches = 0;
  for (int t = 0; t < 20000; ++t) {
    Vec3 const o = r.vec3<float>(-4, 4);
    // Half the rays aim at a point near the shape, half go anywhere.
    Vec3 const target = r.vec3<float>(-1.5, 1.5);
    Vec3 const d = t % 2 ? (target - o) * float(r.uniform(0.2, 3)) : r.vec3<float>(-1, 1);
    auto const h = ray_cast_local(shape, Ray3{o, d}, std::numeric_limits<float>::infinity());
    auto const want = oracle(ld(o), ld(d));
    if (grazing(ld(o), ld(d))) continue; // tangency: either answer is right
    ++compared;
    if (bool(h.hit) != want.has_value()) {
      if (mismatches++ < 3)
        FAIL_CHECK(name << ": hit " << h.hit << " vs oracle " << want.has_value() << " for o " << o
                        << " d " << d);
      continue;
    }
    if (!want) continue;
    ++hits;
    LD const scale = 1 + *want * std::sqrt(dot(ld(d), ld(d)));
    if (std::abs(LD(h.toi) - *want) * std::sqrt(dot(ld(d), ld(d))) > tol * scale &&
        mismatches++ < 3)
      FAIL_CHECK(name << ": toi " << h.toi << " vs " << double(*want) << " for o " << o << " d "
                      << d);
    if (*want > 0) CHECK(std::abs(h.normal.length() - 1) < 1e-5f);
  }
  INFO(name << ": " << compared << " rays compared, " << hits << " hits");
  CHECK(mismatches == 0);
  CHECK(hits > 2000);
}

} // namespace

TEST_CASE("ray casts agree with long-double oracles", "[collision][ray]") {
  // Grazing: the oracle's discriminant is within a relative 1e-4 of zero, or the hit is on a
  // seam the float and long-double answers may see on either side. Tolerances on the hit
  // distance relative to 1 + distance, about three times the worst error seen on these
  // 20,000 rays (measured: sphere 2.7, cuboid 0.65, capsule 7.6, cylinder 7.2 FLT_EPSILON;
  // the capsule and cylinder solve a quadric in xz, then test heights).
  double const eps = std::numeric_limits<float>::epsilon();
  check_against_oracle(
      "sphere", Sphere{1.25f},
      [](ld3 o, ld3 d) {
        return sphere_oracle(o, d, {0, 0, 0}, 1.25L);
      },
      [](ld3 o, ld3 d) {
        LD const a = dot(d, d), b = dot(o, d), c = dot(o, o) - 1.25L * 1.25L;
        return std::abs(b * b - a * c) <= 1e-4L * (b * b + std::abs(a * c)) || std::abs(c) < 1e-5L;
      },
      8 * eps);
  Vec3 const e{1.5f, 0.5f, 1};
  check_against_oracle(
      "cuboid", Cuboid{e}, [&](ld3 o, ld3 d) { return box_oracle(o, d, ld(e)); },
      [&](ld3 o, ld3 d) {
        // Rays through an edge or corner region within a relative 1e-5.
        auto const t = box_oracle(o, d, {e.x * (1 + 1e-5L), e.y * (1 + 1e-5L), e.z * (1 + 1e-5L)});
        auto const u = box_oracle(o, d, {e.x * (1 - 1e-5L), e.y * (1 - 1e-5L), e.z * (1 - 1e-5L)});
        return t.has_value() != u.has_value() ||
               (std::abs(o.x) - e.x) * (std::abs(o.x) - e.x) < 1e-10L;
      },
      2 * eps);
  check_against_oracle(
      "capsule", Capsule{0.75f, 0.5f},
      [](ld3 o, ld3 d) { return capsule_oracle(o, d, 0.75L, 0.5L); },
      [](ld3 o, ld3 d) {
        auto const t = capsule_oracle(o, d, 0.75L, 0.5L * (1 + 1e-5L));
        auto const u = capsule_oracle(o, d, 0.75L, 0.5L * (1 - 1e-5L));
        return t.has_value() != u.has_value();
      },
      24 * eps);
  check_against_oracle(
      "cylinder", Cylinder{0.75f, 0.5f},
      [](ld3 o, ld3 d) { return cylinder_oracle(o, d, 0.75L, 0.5L); },
      [](ld3 o, ld3 d) {
        auto const t = cylinder_oracle(o, d, 0.75L * (1 + 1e-5L), 0.5L * (1 + 1e-5L));
        auto const u = cylinder_oracle(o, d, 0.75L * (1 - 1e-5L), 0.5L * (1 - 1e-5L));
        return t.has_value() != u.has_value();
      },
      24 * eps);
}

TEST_CASE("ray casts: inside, surface, parallel, zero and non-finite input", "[collision][ray]") {
  float const inf = std::numeric_limits<float>::infinity();
  float const nan = std::numeric_limits<float>::quiet_NaN();
  Sphere const s{1};
  Cuboid const box{{1, 2, 3}};
  SECTION("origin inside: solid hits at 0 with no normal, hollow at the exit") {
    auto const a = ray_cast_local(s, Ray3{{0.5f, 0, 0}, {1, 0, 0}}, inf);
    CHECK(a.hit);
    CHECK(a.toi == 0);
    CHECK(a.normal.length() == 0);
    auto const b = ray_cast_local(s, Ray3{{0.5f, 0, 0}, {1, 0, 0}}, inf, false);
    CHECK(b.hit);
    CHECK(b.toi == 0.5f);
    CHECK(b.normal.x == 1);
    auto const bs = ray_cast_local(box, Ray3{{0.5f, 1, -2}, {1, 0, 0}}, inf);
    CHECK(bs.hit);
    CHECK(std::bit_cast<std::uint32_t>(bs.toi) == 0u); // +0
    CHECK(bs.normal.length() == 0);
    CHECK(bs.feature == -1);
    auto const c = ray_cast_local(box, Ray3{{0, 0, 0}, {0, -2, 0}}, inf, false);
    CHECK(c.toi == 1);
    CHECK(c.normal.y == -1);
    auto const cap = ray_cast_local(Capsule{1, 0.5f}, Ray3{{0, 0, 0}, {0, 1, 0}}, inf, false);
    CHECK(cap.toi == 1.5f);
    CHECK(cap.normal.y == 1);
  }
  SECTION("origin on the surface") {
    CHECK(ray_cast_local(s, Ray3{{1, 0, 0}, {1, 0, 0}}, inf).toi == 0); // solid: inside
    auto const in = ray_cast_local(s, Ray3{{1, 0, 0}, {-1, 0, 0}}, inf, false);
    CHECK(in.toi == 2); // hollow: across to the far side
    // Hollow, along the tangent plane: both roots are 0 (q = 0 in the robust form, where
    // c / q would be 0 / 0), so the ray leaves at once, through the surface it starts on.
    for (Vec3 const o : {Vec3{1, 0, 0}, Vec3{0, -1, 0}}) {
      Vec3 const along = o.any_orthonormal_vector();
      auto const t = ray_cast_local(s, Ray3{o, along}, inf, false);
      CHECK(t.hit);
      CHECK(t.toi == 0);
      CHECK((t.normal.x == o.x && t.normal.y == o.y && t.normal.z == o.z));
      auto const side = ray_cast_local(Cylinder{1, 1}, Ray3{o.x != 0 ? o : Vec3{0, 0, 1}, Vec3::Y},
                                       inf, false); // on the side, along it: the top cap
      CHECK(side.toi == 1);
    }
    CHECK(ray_cast_local(box, Ray3{{1, 0, 0}, {1, 0, 0}}, inf).hit);
  }
  SECTION("box: a solid cast whose entry time rounds to 0 starts in contact") {
    // 1e-30 outside the face x = 0. With |d| <= 1 the entry time stays nonzero and the face
    // is hit from outside; with d.x = 1e20 it underflows to +0 (1e-30 / 1e20): the solid cast
    // counts that as starting inside (toi +0, no normal, feature -1), the hollow cast, which
    // tests the signs of lo - o exactly, as an outside hit at +0 through the -x face.
    GAabb3<float> const unit{{0, 0, 0}, {1, 1, 1}};
    Vec3 const o{-1e-30f, 0.5f, 0.5f};
    auto const near = ray_cast(unit, Ray3{o, {1, 0, 0}}, inf);
    CHECK(near.hit);
    CHECK(near.toi == 1e-30f);
    CHECK(near.normal.x == -1);
    CHECK(near.feature == 0);
    auto const solid = ray_cast(unit, Ray3{o, {1e20f, 0, 0}}, inf);
    CHECK(solid.hit);
    CHECK(std::bit_cast<std::uint32_t>(solid.toi) == 0u);
    CHECK(solid.normal.length() == 0);
    CHECK(solid.feature == -1);
    auto const hollow = ray_cast(unit, Ray3{o, {1e20f, 0, 0}}, inf, false);
    CHECK(hollow.hit);
    CHECK(hollow.toi == 0);
    CHECK(hollow.normal.x == -1);
    CHECK(hollow.feature == 0);
  }
  SECTION("origin on a slab plane with a +0 or -0 direction component") {
    for (float zero : {0.0f, -0.0f}) {
      // Along the face y = 2 (grazing the box): hits, the origin being on the closed box.
      auto const g = ray_cast_local(box, Ray3{{-5, 2, 0}, {1, zero, 0}}, inf);
      CHECK(g.hit);
      CHECK(g.toi == 4);
      CHECK(g.normal.x == -1);
      auto const m = ray_cast_local(box, Ray3{{-5, 2.001f, 0}, {1, zero, 0}}, inf);
      CHECK_FALSE(m.hit);
      CHECK(ray_cast(GAabb3<float>{{0, 0, 0}, {1, 1, 1}}, Ray3{{-1, 0, 1}, {1, zero, zero}}, inf)
                .toi == 1);
    }
  }
  SECTION("box: a direction component so small that 1/d overflows acts as parallel") {
    // 1e-40 is subnormal: 1/d = inf, and (plane - origin) * inf is 0 * inf = NaN on the
    // plane. The origin is on the closed slab there, so the slab must not reject the ray.
    float const tiny = 1e-40f;
    for (float t : {tiny, -tiny}) {
      auto const g = ray_cast_local(box, Ray3{{-5, 2, 0}, {1, t, 0}}, inf);
      CHECK(g.hit);
      CHECK(g.toi == 4);
      CHECK(g.normal.x == -1);
      auto const h = ray_cast_local(box, Ray3{{-1, -2, 0}, {0, 1, t}}, inf, false);
      CHECK(h.hit); // hollow from inside, leaving through +y
      CHECK(h.toi == 4);
      CHECK(h.normal.y == 1);
    }
    // The cylinder's cap slab likewise: along the top cap plane, as the d.y = 0 rim case.
    for (float t : {tiny, -tiny}) {
      auto const rim = ray_cast_local(Cylinder{1, 0.5f}, Ray3{{-3, 1, 0}, {1, t, 0}}, inf);
      CHECK(rim.hit);
      CHECK(rim.toi == 2.5f);
    }
    CHECK_FALSE(ray_cast_local(Cylinder{1, 0.5f}, Ray3{{0, -12, 0}, {0, 2e-38f, 0}}, inf).hit);
    CHECK_FALSE(ray_cast_local(Cylinder{1, 0.5f}, Ray3{{0, 2, 0}, {1, 0, 0}}, inf).hit);
    // An entry so far that (plane - origin) / d overflows: t = +infinity, a miss (not a hit
    // at infinity), even with max_toi = +infinity. (10 * 5e37 > FLT_MAX.)
    auto const far = ray_cast_local(box, Ray3{{0, -12, 0}, {0, 2e-38f, 0}}, inf);
    CHECK_FALSE(far.hit);
    CHECK(far.toi == inf);
    // The same for the solid sphere's and capsule's entry root c / q: from 2e19 away with
    // |d| = 5e-20, c = 4e38 overflows (the entry, 4e38, is past FLT_MAX): a miss. From 1e19
    // with |d| = 1e-19 the entry 1e38 is finite and hits.
    for (Vec3 axis : {Vec3{1, 0, 0}, Vec3{0, 1, 0}}) {
      CHECK_FALSE(ray_cast_local(s, Ray3{axis * 2e19f, axis * -5e-20f}, inf).hit);
      CHECK_FALSE(ray_cast_local(Capsule{0.5f, 1}, Ray3{axis * 2e19f, axis * -5e-20f}, inf).hit);
      CHECK(ray_cast_local(Sphere{1}, Ray3{axis * 1e19f, axis * -1e-19f}, inf).hit);
      CHECK(ray_cast_local(Capsule{0.5f, 1}, Ray3{axis * 1e19f, axis * -1e-19f}, inf).hit);
    }
  }
  SECTION("zero direction: only a solid shape around the origin") {
    CHECK(ray_cast_local(s, Ray3{{0, 0, 0}, {0, 0, 0}}, inf).hit);
    CHECK_FALSE(ray_cast_local(s, Ray3{{0, 0, 0}, {0, 0, 0}}, inf, false).hit);
    CHECK_FALSE(ray_cast_local(s, Ray3{{3, 0, 0}, {0, 0, 0}}, inf).hit);
    CHECK_FALSE(ray_cast_local(box, Ray3{{3, 0, 0}, {0, 0, 0}}, inf).hit);
    CHECK_FALSE(ray_cast_local(Capsule{1, 1}, Ray3{{3, 0, 0}, {0, 0, 0}}, inf).hit);
    CHECK_FALSE(ray_cast_local(Cylinder{1, 1}, Ray3{{0, 0, 0}, {0, 0, 0}}, inf, false).hit);
    CHECK(ray_cast_local(Cylinder{1, 1}, Ray3{{0, 0, 0}, {0, 0, 0}}, inf).hit);
  }
  SECTION("NaN and infinity: a miss, never a NaN toi") {
    for (Vec3 o : {Vec3{nan, 0, 0}, Vec3{-inf, 0, 0}})
      for (auto const& h : {ray_cast_local(s, Ray3{o, {1, 0, 0}}, inf),
                            ray_cast_local(box, Ray3{o, {1, 0, 0}}, inf),
                            ray_cast_local(Capsule{1, 1}, Ray3{o, {1, 0, 0}}, inf),
                            ray_cast_local(Cylinder{1, 1}, Ray3{o, {1, 0, 0}}, inf),
                            ray_cast_local(HalfSpace{{0, 1, 0}}, Ray3{o, {1, 0, 0}}, inf)}) {
        CHECK_FALSE(h.hit);
        CHECK(h.toi == inf);
      }
    CHECK_FALSE(ray_cast_local(s, Ray3{{-3, 0, 0}, {nan, 0, 0}}, inf).hit);
    // A NaN max_toi: a miss for every shape, solid or hollow, from outside or inside (no
    // validity test of its own: toi <= max_toi is false for NaN).
    for (bool solid : {true, false})
      for (Vec3 o : {Vec3{-3, 0.1f, 0.2f}, Vec3{0.1f, 0.2f, 0.1f}}) {
        Ray3 const ray{o, Vec3{1, 0.05f, 0.02f}};
        for (auto const& h :
             {ray_cast_local(s, ray, nan, solid), ray_cast_local(box, ray, nan, solid),
              ray_cast(GAabb3<float>{{-1, -1, -1}, {1, 1, 1}}, ray, nan, solid),
              ray_cast_local(Capsule{1, 1}, ray, nan, solid),
              ray_cast_local(Cylinder{1, 1}, ray, nan, solid),
              ray_cast_local(HalfSpace{{1, 0, 0}}, ray, nan, solid)}) {
          CHECK_FALSE(h.hit);
          CHECK(h.toi == inf);
        }
      }
    CHECK_FALSE(ray_cast_local(Triangle{{0, -1, -1}, {0, 1, -1}, {0, 0, 1}},
                               Ray3{{-3, 0, 0}, {1, 0, 0}}, nan)
                    .hit);
  }
  SECTION("max distance: inclusive, infinite allowed") {
    CHECK(ray_cast_local(s, Ray3{{-3, 0, 0}, {1, 0, 0}}, 2.0f).hit);
    CHECK_FALSE(ray_cast_local(s, Ray3{{-3, 0, 0}, {1, 0, 0}}, 1.999f).hit);
    CHECK(ray_cast_local(s, Ray3{{-3, 0, 0}, {0.5f, 0, 0}}, 4.0f).toi == 4); // non-unit dir
  }
  SECTION("grazing rays touch") {
    auto const g = ray_cast_local(s, Ray3{{-3, 1, 0}, {1, 0, 0}}, inf);
    CHECK(g.hit);
    CHECK(g.toi == 3);
    CHECK(g.normal.y == 1);
  }
  SECTION("radius 0 and zero extents") {
    CHECK(ray_cast_local(Sphere{0}, Ray3{{-3, 0, 0}, {1, 0, 0}}, inf).toi == 3);
    CHECK_FALSE(ray_cast_local(Sphere{0}, Ray3{{-3, 0.001f, 0}, {1, 0, 0}}, inf).hit);
    CHECK(ray_cast_local(Cuboid{{1, 0, 1}}, Ray3{{0, 5, 0}, {0, -1, 0}}, inf).toi == 5);
    CHECK(ray_cast_local(Capsule{1, 0}, Ray3{{0, 5, 0}, {0, -1, 0}}, inf).toi == 4);
    // A zero radius has no normal: zero, not p / 0.
    for (auto const& h : {ray_cast_local(Sphere{0}, Ray3{{-3, 0, 0}, {1, 0, 0}}, inf),
                          ray_cast_local(Capsule{1, 0}, Ray3{{0, 5, 0}, {0, -1, 0}}, inf)}) {
      CHECK(h.hit);
      CHECK(h.normal.x == 0);
      CHECK(h.normal.y == 0);
      CHECK(h.normal.z == 0);
    }
  }
  SECTION("capsule and cylinder: along the axis, at the cap seam") {
    Capsule const cap{1, 0.5f};
    CHECK(ray_cast_local(cap, Ray3{{0, 5, 0}, {0, -1, 0}}, inf).toi == 3.5f);
    CHECK(ray_cast_local(cap, Ray3{{0.4f, 5, 0}, {0, -1, 0}}, inf).hit);
    CHECK_FALSE(ray_cast_local(cap, Ray3{{0.6f, 5, 0}, {0, -1, 0}}, inf).hit);
    auto const seam = ray_cast_local(cap, Ray3{{-3, 1, 0}, {1, 0, 0}}, inf); // at y = h
    CHECK(seam.toi == 2.5f);
    CHECK(seam.normal.x == -1);
    Cylinder const cyl{1, 0.5f};
    auto const top = ray_cast_local(cyl, Ray3{{0.3f, 5, 0}, {0, -1, 0}}, inf);
    CHECK(top.toi == 4);
    CHECK(top.normal.y == 1);
    CHECK_FALSE(ray_cast_local(cyl, Ray3{{0.6f, 5, 0}, {0, -1, 0}}, inf).hit);
    auto const rim = ray_cast_local(cyl, Ray3{{-3, 1, 0}, {1, 0, 0}}, inf); // along the top cap
    CHECK(rim.toi == 2.5f);
  }
  SECTION("half-space") {
    HalfSpace const ground{{0, 1, 0}};
    auto const h = ray_cast_local(ground, Ray3{{0, 2, 0}, {0, -0.5f, 0}}, inf);
    CHECK(h.toi == 4);
    CHECK(h.normal.y == 1);
    CHECK_FALSE(ray_cast_local(ground, Ray3{{0, 2, 0}, {1, 0, 0}}, inf).hit);
    CHECK(ray_cast_local(ground, Ray3{{0, -1, 0}, {1, 0, 0}}, inf).toi == 0);
    CHECK(ray_cast_local(ground, Ray3{{0, -1, 0}, {0, 1, 0}}, inf, false).toi == 1);
  }
  SECTION("at a pose") {
    Iso3 const pose = Iso3::from_rotation_translation(Quat::from_rotation_z(0.5f), {10, 0, 0});
    auto const h = ray_cast(box, pose, Ray3{{10, 10, 0}, {0, -1, 0}}, inf);
    CHECK(h.hit);
    // The vertical line through the centre of the tilted box meets its local +X face (the top
    // face spans x in [-1.84, -0.08]): normal (cos 0.5, sin 0.5, 0), at local x = 1, i.e.
    // y = 1 / sin 0.5 above the centre.
    CHECK((h.normal - Vec3{std::cos(0.5f), std::sin(0.5f), 0}).length() < 1e-6f);
    CHECK(std::abs(h.toi - (10 - 1 / std::sin(0.5f))) < 1e-5f);
    CHECK(std::abs(h.normal.length() - 1) < 1e-6f);
  }
}

TEMPLATE_TEST_CASE("a ray with any non-finite component misses, from inside too",
                   "[collision][ray]", float, double) {
  // Every arrangement of +-inf and NaN among the six components, next to zero, small and
  // large finite ones, with the origin also inside or on each shape: a miss with toi
  // +infinity, solid or hollow. The solid sphere and capsule casts do not test the ray's
  // validity as a whole; they rely on the entry roots failing for non-finite input and test
  // only the direction of an origin inside, so a gap in that argument shows here.
  using S = TestType;
  using V = GVec3<S>;
  S const inf = std::numeric_limits<S>::infinity(), nan = std::numeric_limits<S>::quiet_NaN();
  S const o_vals[] = {S(0), S(0.25), S(-0.5), S(3), S(-1e30), inf, -inf, nan};
  S const d_vals[] = {S(0), S(1), S(-0.5), S(1e-30), inf, -inf, nan};
  auto const finite = [](V const& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  int checked = 0, failures = 0;
  auto const expect_miss = [&](char const* name, GRayHit<S> const& h, V const& o, V const& d,
                               bool solid) {
    ++checked;
    if ((h.hit || !(h.toi == inf)) && failures++ < 8)
      FAIL_CHECK(name << (solid ? " solid" : " hollow") << " o " << o << " d " << d << " hit "
                      << h.hit << " toi " << h.toi);
  };
  for (S ox : o_vals)
    for (S oy : o_vals)
      for (S oz : o_vals)
        for (S dx : d_vals)
          for (S dy : d_vals)
            for (S dz : d_vals) {
              V const o{ox, oy, oz}, d{dx, dy, dz};
              if (finite(o) && finite(d)) continue;
              GRay3<S> const ray{o, d};
              for (bool solid : {true, false}) {
                expect_miss("sphere", ray_cast_local(GSphere<S>{S(1)}, ray, inf, solid), o, d,
                            solid);
                expect_miss("capsule", ray_cast_local(GCapsule<S>{S(0.5), S(1)}, ray, inf, solid),
                            o, d, solid);
                expect_miss("cylinder", ray_cast_local(GCylinder<S>{S(0.5), S(1)}, ray, inf, solid),
                            o, d, solid);
                expect_miss("cuboid", ray_cast_local(GCuboid<S>{V{1, 2, 3}}, ray, inf, solid), o, d,
                            solid);
                expect_miss("half-space",
                            ray_cast_local(GHalfSpace<S>{V{0, 1, 0}}, ray, inf, solid), o, d,
                            solid);
                expect_miss("aabb", ray_cast(GAabb3<S>{V{-1, -1, -1}, V{1, 1, 1}}, ray, inf, solid),
                            o, d, solid);
              }
            }
  CHECK(failures == 0);
  CHECK(checked > 100000);
  // The same rays with a finite origin inside and on each shape, so that only the direction
  // is not finite (the solid casts' inside path).
  for (V const o : {V{0, 0, 0}, V{0.25, -0.5, 0.25}, V{1, 0, 0}, V{0, 1.5, 0}})
    for (S dx : d_vals)
      for (S dy : d_vals)
        for (S dz : d_vals) {
          V const d{dx, dy, dz};
          if (finite(d)) continue;
          GRay3<S> const ray{o, d};
          for (bool solid : {true, false}) {
            expect_miss("sphere (inside)", ray_cast_local(GSphere<S>{S(1)}, ray, inf, solid), o, d,
                        solid);
            expect_miss("capsule (inside)",
                        ray_cast_local(GCapsule<S>{S(0.5), S(1)}, ray, inf, solid), o, d, solid);
            expect_miss("cylinder (inside)",
                        ray_cast_local(GCylinder<S>{S(0.5), S(1)}, ray, inf, solid), o, d, solid);
            expect_miss("cuboid (inside)", ray_cast_local(GCuboid<S>{V{1, 2, 3}}, ray, inf, solid),
                        o, d, solid);
          }
        }
  CHECK(failures == 0);
  // And the finite direction from inside still hits at 0 (the toi that carries the test).
  for (V const o : {V{0, 0, 0}, V{0.25, -0.5, 0.25}, V{1, 0, 0}}) {
    CHECK(ray_cast_local(GSphere<S>{S(1)}, GRay3<S>{o, V{1, S(-1e-30), 3}}, inf).toi == S(0));
    CHECK(ray_cast_local(GCapsule<S>{S(0.5), S(1)}, GRay3<S>{o, V{0, 0, 0}}, inf).toi == S(0));
  }
}

TEST_CASE("a long finite direction from inside: toi 0 up to the documented overflow",
          "[collision][ray]") {
  // The solid sphere and capsule test an inside origin's direction through b - b with
  // b = f . d (see ray_cast.hpp's conventions): any direction whose dot product with the
  // origin stays finite hits at 0, one where it overflows is a miss, not a NaN hit.
  float const inf = std::numeric_limits<float>::infinity();
  Vec3 const o{0.5f, 0.5f, 0.5f}; // inside Sphere{1} and Capsule{0.5, 1}
  for (Vec3 const d : {Vec3{1e30f, -1e30f, 2e30f}, Vec3{1e38f, 1e38f, -1e38f}}) {
    for (bool sphere : {true, false}) {
      RayHit const h = sphere ? ray_cast_local(Sphere{1}, Ray3{o, d}, inf)
                              : ray_cast_local(Capsule{0.5f, 1}, Ray3{o, d}, inf);
      INFO((sphere ? "sphere" : "capsule") << " d " << d);
      CHECK(h.hit);
      CHECK(h.toi == 0.0f);
      CHECK(h.normal.length() == 0.0f);
      CHECK(h.feature == -1.0f);
    }
  }
  // 0.5 * 3e38 * 3 = 4.5e38 > FLT_MAX: a miss. The capsule's test sees the origin relative
  // to its top end, (0.5, 0, 0.5) here: 0.5 * 3e38 * 2 is finite and it still hits; from
  // (0.5, 0.9, 0.5), 1.4 * 3e38 overflows.
  Vec3 const huge{3e38f, 3e38f, 3e38f};
  RayHit const sphere = ray_cast_local(Sphere{1}, Ray3{o, huge}, inf);
  CHECK_FALSE(sphere.hit);
  CHECK(sphere.toi == inf);
  CHECK(ray_cast_local(Capsule{0.5f, 1}, Ray3{o, huge}, inf).toi == 0.0f);
  RayHit const capsule = ray_cast_local(Capsule{0.5f, 1}, Ray3{{0.5f, 0.9f, 0.5f}, huge}, inf);
  CHECK_FALSE(capsule.hit);
  CHECK(capsule.toi == inf);
}

TEST_CASE("far spheres: the robust discriminant classifies rays like long double",
          "[collision][ray]") {
  // r / |f| = 1e-3: rays aimed within a few radii of a sphere 1000 radii away.
  rng r(3);
  int wrong = 0, naive_wrong = 0, n = 0;
  for (int t = 0; t < 20000; ++t) {
    Vec3 const c = r.unit3<float>() * 1000.0f;
    Vec3 const aim = c + r.vec3<float>(-2, 2);
    Vec3 const d = aim.normalize();
    auto const want = sphere_oracle({0, 0, 0}, ld(d), ld(c), 1.0L);
    auto const got = ray_cast_local(Sphere{1}, Ray3{-c, d}, std::numeric_limits<float>::infinity());
    // Naive float: b^2 - a c.
    float const b = (-c).dot(d), a = d.dot(d), cc = c.dot(c) - 1;
    bool const naive = b * b - a * cc >= 0 && b < 0;
    ++n;
    wrong += bool(got.hit) != want.has_value();
    naive_wrong += naive != want.has_value();
  }
  INFO("misclassified: robust " << wrong << ", naive " << naive_wrong << " of " << n);
  CHECK(wrong <= n / 1000);
  CHECK(naive_wrong > 10 * (wrong + 1));
}

TEST_CASE("far coordinates: a sphere 1e5 away", "[collision][ray]") {
  for (float dist : {1e4f, 1e5f, 1e6f}) {
    Vec3 const c{dist, dist * 0.5f, -dist};
    Vec3 const o{0, 0, 0};
    Vec3 const d = (c - o).normalize();
    auto const h = ray_cast(Sphere{2}, Iso3::from_translation(c), Ray3{o, d},
                            std::numeric_limits<float>::infinity());
    INFO("distance " << dist);
    REQUIRE(h.hit);
    CHECK(std::abs(h.toi - (c.length() - 2)) <= 1e-6f * c.length() * 4);
  }
}

TEST_CASE("small spheres and capsules far from the origin: unit normals", "[collision][ray]") {
  // The hit point's rounding is about ulp(10) = 1e-6 here, 1% of the radius: p / r was 1.4e-3
  // off unit for r = 1e-4 (found by the ray_cast fuzz target). The normal is normalised.
  float const inf = std::numeric_limits<float>::infinity();
  int hits = 0;
  for (int i = 0; i < 200; ++i) {
    float const a = 0.031f * float(i);
    Vec3 const o{10.3f + std::sin(a), -9.7f, 10.1f + std::cos(3 * a)};
    for (float r : {1e-4f, 3e-5f}) {
      Vec3 const d = (Vec3{0, 0.5f * r * std::sin(5 * a), 0.5f * r} - o).normalize();
      for (bool solid : {true, false}) {
        auto const s = ray_cast(Sphere{r}, Iso3{}, Ray3{o, d}, inf, solid);
        auto const c = ray_cast(Capsule{2 * r, r}, Iso3{}, Ray3{o, d}, inf, solid);
        for (RayHit const& h : {s, c}) {
          if (!h.hit) continue;
          ++hits;
          CHECK(std::abs(h.normal.length() - 1.0f) <= 4e-7f);
          CHECK(h.normal.dot(d) < 0.0f); // entering from outside
        }
      }
    }
  }
  CHECK(hits > 600);
}

TEST_CASE("a half-space entered so far that toi overflows: a miss", "[collision][ray]") {
  // toi = -s / (n . dir) overflows for a tiny direction (found by the ray_cast fuzz target: a
  // hit at toi = +infinity).
  float const inf = std::numeric_limits<float>::infinity();
  HalfSpace const ground{{0, 1, 0}};
  Ray3 const ray{{0, 5, 0}, {0, -1e-38f, 0}};
  for (bool solid : {true, false}) {
    auto const h = ray_cast(ground, Iso3{}, ray, inf, solid);
    CHECK(!h.hit);
    CHECK(h.toi == inf);
    CHECK(h.normal.length_squared() == 0.0f);
  }
  // Just in range: a hit at a huge but finite toi.
  auto const far = ray_cast(ground, Iso3{}, Ray3{{0, 5, 0}, {0, -1e-37f, 0}}, inf);
  CHECK(far.hit);
  CHECK(far.toi == Approx(5e37f));
}

TEST_CASE("a tiny direction whose toi overflows misses every closed form", "[collision][ray]") {
  // ray_cast regress-capsule-toi-overflow: a hollow cast at a capsule 12 m away along a
  // direction of length 1.1e-19: |dir|^2 is subnormal, the root's division overflowed, and the
  // cast reported a hit at toi +infinity. Every shape, solid and hollow, from 1 to 100 m, with
  // directions from 1e-17 to 1e-40 long: a hit has a finite toi (a miss otherwise).
  float const inf = std::numeric_limits<float>::infinity();
  Iso3 const pose{Quat::from_xyzw(-0.453825444f, -0.749281704f, 0.295525491f, 0.3811616f),
                  {-3.95629811f, -3.99987793f, 1.20625639f}};
  Ray3 const found{{-4.41254282f, 7.99707031f, 0.000122070312f},
                   {5.3809861e-43f, -1.08261392e-19f, -9.165613e-41f}};
  int hits = 0, misses = 0;
  auto const check = [&](RayHit const& h) {
    CHECK((!h.hit || std::isfinite(h.toi)));
    CHECK((h.hit || h.toi == inf));
    hits += int(h.hit);
    misses += int(!h.hit);
  };
  for (bool solid : {true, false}) {
    check(ray_cast(Capsule{1.0f, 0.8f}, pose, found, inf, solid));
    for (float distance : {1.0f, 10.0f, 100.0f})
      for (float len : {1e-17f, 1e-19f, 1e-20f, 1e-22f, 1e-30f, 1e-40f}) {
        Ray3 const r{pose.translation + Vec3{0.1f, distance + 2.0f, -0.2f},
                     {0.1f * len, -len, 0.05f * len}};
        check(ray_cast(Sphere{1.0f}, pose, r, inf, solid));
        check(ray_cast(Capsule{1.0f, 0.8f}, pose, r, inf, solid));
        check(ray_cast(Cylinder{1.0f, 0.8f}, pose, r, inf, solid));
        check(ray_cast(Cuboid{Vec3{1.0f, 0.8f, 0.6f}}, pose, r, inf, solid));
      }
  }
  CHECK(hits > 10);   // the longer directions still hit, at huge finite tois
  CHECK(misses > 10); // the shortest overflow
}

TEST_CASE("triangles: watertight on a fan, oracle hits, degenerate cases", "[collision][ray]") {
  float const inf = std::numeric_limits<float>::infinity();
  SECTION("a dense ray grid through a 16-triangle fan: every ray inside hits exactly once") {
    // A fan around a centre off the grid's symmetry (so rays cross edges and the shared
    // vertex exactly), tilted out of the z = 0 plane, wound consistently.
    constexpr int K = 16;
    Vec3 const centre{0.125f, -0.0625f, 0.25f};
    std::vector<Vec3> ring;
    for (int k = 0; k < K; ++k) {
      float const a = 6.2831853f * float(k) / K;
      ring.push_back({std::cos(a), std::sin(a), 0.25f + 0.125f * std::sin(2 * a)});
    }
    std::vector<Triangle> fan;
    for (int k = 0; k < K; ++k)
      fan.push_back({centre, ring[std::size_t(k)], ring[std::size_t((k + 1) % K)]});
    int leaks = 0, doubles = 0, rays = 0;
    for (int i = -300; i <= 300; ++i)
      for (int j = -300; j <= 300; ++j) {
        // Grid points at multiples of 1/256 hit the centre vertex (0.125, -0.0625) exactly.
        Vec3 const o{float(i) / 256, float(j) / 256, 2};
        if (Vec3{o.x, o.y, 0}.length() > 0.9f) continue; // inside the ring's polygon
        ++rays;
        int hits = 0;
        for (auto const& t : fan)
          hits += bool(ray_cast_local(t, Ray3{o, {0, 0, -1}}, inf).hit);
        leaks += hits == 0;
        doubles += hits > 1;
      }
    // Rays through the shared vertex and along the spokes, from several directions.
    for (Vec3 d : {Vec3{0, 0, -1}, Vec3{0.3f, 0.1f, -1}, Vec3{-0.2f, 0.4f, -1}}) {
      int hits = 0;
      for (auto const& t : fan)
        hits += bool(ray_cast_local(t, Ray3{centre - d * 2.0f, d}, inf).hit);
      CHECK(hits == 1);
    }
    INFO(rays << " rays");
    CHECK(leaks == 0);
    CHECK(doubles == 0);
  }
  SECTION("hits agree with a long-double plane intersection") {
    rng r(12);
    int compared = 0;
    for (int t = 0; t < 5000; ++t) {
      Triangle const tri{r.vec3<float>(-1, 1), r.vec3<float>(-1, 1), r.vec3<float>(-1, 1)};
      Vec3 const o = r.vec3<float>(-3, 3);
      Vec3 const d = (r.vec3<float>(-0.8, 0.8) - o) * float(r.uniform(0.5, 2));
      auto const h = ray_cast_local(tri, Ray3{o, d}, inf);
      // Long double: barycentric coordinates of the line's plane crossing.
      ld3 const a = ld(tri.a), b = ld(tri.b), c = ld(tri.c), oo = ld(o), dd = ld(d);
      ld3 const e1{b.x - a.x, b.y - a.y, b.z - a.z}, e2{c.x - a.x, c.y - a.y, c.z - a.z};
      ld3 const p{dd.y * e2.z - dd.z * e2.y, dd.z * e2.x - dd.x * e2.z, dd.x * e2.y - dd.y * e2.x};
      LD const det = dot(e1, p);
      if (std::abs(det) < 1e-6L) continue;
      ld3 const s{oo.x - a.x, oo.y - a.y, oo.z - a.z};
      LD const u = dot(s, p) / det;
      ld3 const q{s.y * e1.z - s.z * e1.y, s.z * e1.x - s.x * e1.z, s.x * e1.y - s.y * e1.x};
      LD const v = dot(dd, q) / det, tt = dot(e2, q) / det;
      LD const margin = std::min({u, v, 1 - u - v});
      if (std::abs(margin) < 1e-4L || std::abs(tt) < 1e-4L) continue; // on an edge: either way
      bool const want = margin > 0 && tt > 0;
      ++compared;
      REQUIRE(bool(h.hit) == want);
      if (want) {
        CHECK(std::abs(LD(h.toi) - tt) <= 1e-5L * (1 + tt));
        CHECK(h.normal.dot(d) <= 0);
        CHECK(std::abs(h.normal.length() - 1) < 1e-5f);
      }
    }
    CHECK(compared > 4000);
  }
  SECTION("degenerate triangles and rays in the plane miss; the back side hits") {
    Triangle const tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    CHECK_FALSE(ray_cast_local(tri, Ray3{{-1, 0.2f, 0}, {1, 0, 0}}, inf).hit); // in the plane
    CHECK_FALSE(
        ray_cast_local(Triangle{{0, 0, 0}, {1, 1, 0}, {2, 2, 0}}, Ray3{{1, 1, 1}, {0, 0, -1}}, inf)
            .hit);
    CHECK_FALSE(
        ray_cast_local(Triangle{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, Ray3{{0, 0, 1}, {0, 0, -1}}, inf)
            .hit);
    auto const back = ray_cast_local(tri, Ray3{{0.2f, 0.2f, -1}, {0, 0, 1}}, inf);
    CHECK(back.hit);
    CHECK(back.toi == 1);
    CHECK(back.normal.z == -1); // faces the ray
    CHECK_FALSE(ray_cast_local(tri, Ray3{{0.2f, 0.2f, -1}, {0, 0, 0}}, inf).hit);
    CHECK_FALSE(ray_cast_local(tri, Ray3{{0.2f, 0.2f, 1}, {0, 0, 1}}, inf).hit); // pointing away
  }
}

TEST_CASE("ray hits name the feature they hit", "[collision][ray]") {
  float const inf = std::numeric_limits<float>::infinity();
  // Boxes: faces 0..5 = -x, +x, -y, +y, -z, +z, entering and (hollow) leaving.
  Cuboid const box{{1, 2, 3}};
  Vec3 const axes[3] = {Vec3::X, Vec3::Y, Vec3::Z};
  for (int a = 0; a < 3; ++a)
    for (float sgn : {-1.0f, 1.0f}) {
      Vec3 const out = axes[a] * (10 * sgn);
      float const want = float(2 * a + (sgn > 0 ? 1 : 0));
      CHECK(ray_cast_local(box, Ray3{out, -out}, inf).feature == want);      // entering
      CHECK(ray_cast_local(box, Ray3{{}, out}, inf, false).feature == want); // leaving
      CHECK(ray_cast(Aabb3{{-1, -2, -3}, {1, 2, 3}}, Ray3{out, -out}, inf).feature == want);
    }
  // Exactly on an edge or a corner (the crossings tie): the first axis's face and normal,
  // entering and leaving (the box is a cube here, so the ties are exact).
  Cuboid const cube{{1, 1, 1}};
  struct tie {
    Vec3 dir;
    int axis;
  };
  for (tie const t : {tie{{1, 1, 0}, 0}, tie{{0, 1, 1}, 1}, tie{{1, 0, 1}, 0}, tie{{1, 1, 1}, 0},
                      tie{{-1, 1, -1}, 0}, tie{{0, -1, -1}, 1}}) {
    INFO("direction " << t.dir);
    float const c[3] = {t.dir.x, t.dir.y, t.dir.z};
    float const sgn = c[t.axis] > 0 ? 1.0f : -1.0f;
    auto const equal = [](Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; };
    auto const in = ray_cast_local(cube, Ray3{t.dir * -3.0f, t.dir}, inf);
    CHECK(in.toi == 2);
    CHECK(in.feature == float(2 * t.axis + (sgn > 0 ? 0 : 1)));
    CHECK(equal(in.normal, axes[t.axis] * -sgn));
    auto const out = ray_cast_local(cube, Ray3{{}, t.dir}, inf, false);
    CHECK(out.toi == 1);
    CHECK(out.feature == float(2 * t.axis + (sgn > 0 ? 1 : 0)));
    CHECK(equal(out.normal, axes[t.axis] * sgn));
  }
  CHECK(ray_cast_local(box, Ray3{{}, {1, 0, 0}}, inf).feature == -1);        // solid, inside
  CHECK(ray_cast_local(box, Ray3{{5, 5, 5}, {1, 0, 0}}, inf).feature == -1); // miss
  // Capsules: side, upper end, lower end.
  Capsule const cap{1, 0.5f};
  CHECK(ray_cast_local(cap, Ray3{{5, 0.5f, 0}, {-1, 0, 0}}, inf).feature == 0);
  CHECK(ray_cast_local(cap, Ray3{{0, 5, 0}, {0, -1, 0}}, inf).feature == 1);
  CHECK(ray_cast_local(cap, Ray3{{0.1f, -5, 0}, {0, 1, 0}}, inf).feature == 2);
  CHECK(ray_cast_local(cap, Ray3{{5, 1.2f, 0}, {-1, 0, 0}}, inf).feature == 1);
  // Cylinders: side, top cap, bottom cap.
  Cylinder const cyl{1, 0.5f};
  CHECK(ray_cast_local(cyl, Ray3{{5, 0.5f, 0}, {-1, 0, 0}}, inf).feature == 0);
  CHECK(ray_cast_local(cyl, Ray3{{0.2f, 5, 0}, {0, -1, 0}}, inf).feature == 1);
  CHECK(ray_cast_local(cyl, Ray3{{0.2f, -5, 0}, {0, 1, 0}}, inf).feature == 2);
  CHECK(ray_cast_local(cyl, Ray3{{0, 0, 0}, {0, 1, 0}}, inf, false).feature == 1);
  // Triangles: front and back.
  Triangle const tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}; // front: +z
  CHECK(ray_cast_local(tri, Ray3{{0.2f, 0.2f, 1}, {0, 0, -1}}, inf).feature == 0);
  CHECK(ray_cast_local(tri, Ray3{{0.2f, 0.2f, -1}, {0, 0, 1}}, inf).feature == 1);
  CHECK(ray_cast_local(tri, Ray3{{2, 2, -1}, {0, 0, 1}}, inf).feature == -1);
  // Spheres and half-spaces have one part.
  CHECK(ray_cast_local(Sphere{1}, Ray3{{5, 0, 0}, {-1, 0, 0}}, inf).feature == 0);
  CHECK(ray_cast_local(HalfSpace{{0, 1, 0}}, Ray3{{0, 5, 0}, {0, -1, 0}}, inf).feature == 0);
}

/// Two hits equal bit for bit (NaN equal to NaN, +0 unequal to -0).
template <class H>
bool same_hit(H const& a, H const& b) {
  return same(a.toi, b.toi) && same(a.normal, b.normal) && a.hit == b.hit &&
         same(a.feature, b.feature);
}

PLUME_WIDE_TEST_CASE("triangle casts are lane-exact, on shared edges and vertices too",
                     "[collision][ray][lanes]", wide_real_types) {
  // The triangle cast takes a branch for a whole batch when any lane has an edge function
  // exactly zero (a ray through an edge or a vertex): that lane is recomputed in double and
  // decided by edge ownership, and the others must come out as if cast alone. Lanes here mix
  // rays of a grid through a fan's shared edges and vertex with random rays, in coordinates
  // permuted per lane (so the dominant axis and its sign differ between lanes), with
  // degenerate triangles and non-finite rays in some lanes.
  using T = TestType;
  using S = scalar_t<T>;
  constexpr std::size_t L = lanes_v<T>;
  constexpr int K = 8;
  GVec3<S> const centre{S(0.125), S(-0.0625), S(0.25)};
  std::vector<GTriangle<S>> fan;
  for (int k = 0; k < K; ++k) {
    double const a0 = 6.283185307179586 * k / K, a1 = 6.283185307179586 * (k + 1) / K;
    fan.push_back({centre, GVec3<S>{S(std::cos(a0)), S(std::sin(a0)), S(0.25)},
                   GVec3<S>{S(std::cos(a1)), S(std::sin(a1)), S(0.25)}});
  }
  // Lane coordinates: a cyclic permutation and a sign per lane, applied to triangle and ray
  // alike (both exact, so a ray through an edge still passes through it exactly).
  auto const move = [](GVec3<S> v, std::size_t m) {
    GVec3<S> const p = m % 3 == 0   ? v
                       : m % 3 == 1 ? GVec3<S>{v.y, v.z, v.x}
                                    : GVec3<S>{v.z, v.x, v.y};
    return (m / 3) % 2 ? -p : p;
  };
  rng r(17);
  S const inf = infinity<S>();
  // Watertight in every lane frame: a ray through the shared vertex hits exactly one triangle
  // of the fan, whatever the permutation and sign.
  for (std::size_t m = 0; m < 6; ++m) {
    int hits = 0;
    for (auto const& t : fan)
      hits +=
          bool(ray_cast_local(
                   GTriangle<S>{move(t.a, m), move(t.b, m), move(t.c, m)},
                   GRay3<S>{move(centre + GVec3<S>{0, 0, 1}, m), move(GVec3<S>{0, 0, -1}, m)}, inf)
                   .hit);
    CHECK(hits == 1);
  }
  int failures = 0, batches = 0;
  // Steps of 4/64 and 2/64 pass through the vertex (0.125, -0.0625) = (8, -4) / 64.
  for (int i = -48; i <= 48; i += 4)
    for (int j = -48; j <= 48; j += 2) {
      for (int tri_k = 0; tri_k < K; tri_k += 3) {
        std::array<GTriangle<S>, L> tris;
        std::array<GRay3<S>, L> rays;
        std::array<S, L> limits;
        for (std::size_t l = 0; l < L; ++l) {
          std::size_t const m = std::size_t(i + j) * 7 + l * 5;
          GTriangle<S> t = fan[std::size_t(tri_k + int(l)) % K];
          // A grid ray (multiples of 1/64 pass exactly through the centre vertex and along
          // the spokes) on most lanes, a random one on every third batch's lane 1.
          GVec3<S> o{S(i) / 64, S(j) / 64, 2}, d{0, 0, -1};
          if (batches % 3 == 0 && l == 1) o = r.vec3<S>(-1, 1), d = r.unit3<S>();
          if (l == 2 && batches % 5 == 0) t = {t.a, t.b, t.a + (t.b - t.a) * S(2)}; // collinear
          if (l == 3 && batches % 7 == 0) d.x = nan<S>();
          if (l + 1 == L && batches % 4 == 0) o = centre + GVec3<S>{0, 0, 1}; // the shared vertex
          tris[l] = {move(t.a, m), move(t.b, m), move(t.c, m)};
          rays[l] = {move(o, m), move(d, m)};
          limits[l] = l % 2 ? inf : S(3);
        }
        ++batches;
        GVec3<T> a, b, c, o, d;
        T limit{};
        for (std::size_t l = 0; l < L; ++l) {
          a = with_lane(a, l, tris[l].a), b = with_lane(b, l, tris[l].b);
          c = with_lane(c, l, tris[l].c);
          o = with_lane(o, l, rays[l].origin), d = with_lane(d, l, rays[l].dir);
          limit = with_lane(limit, l, limits[l]);
        }
        auto const w = ray_cast_local(GTriangle<T>{a, b, c}, GRay3<T>{o, d}, limit);
        for (std::size_t l = 0; l < L; ++l) {
          auto const s = ray_cast_local(tris[l], rays[l], limits[l]);
          GRayHit<S> const wl{lane(w.hit, l), lane(w.toi, l), lane(w.normal, l),
                              lane(w.feature, l)};
          if (!same_hit(wl, s) && failures++ < 5)
            FAIL_CHECK("lane " << l << ": wide " << wl.hit << " " << wl.toi << " " << wl.normal
                               << " scalar " << s.hit << " " << s.toi << " " << s.normal);
        }
      }
    }
  INFO(batches << " batches");
  CHECK(failures == 0);
}

PLUME_WIDE_TEST_CASE("every ray cast is lane-exact", "[collision][ray][lanes]", wide_real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  lane_pool<T> const pool(11);
  rng r(5);
  auto const make_ray = [&](std::size_t k) {
    GVec3<T> o = r.vec3<T>(-4, 4), d = r.vec3<T>(-1, 1);
    // Some lanes: adversarial components, zero directions, axis-parallel directions.
    if (k % 3 == 0) o.x = pool.pick(k);
    if (k % 5 == 0) d.y = pool.pick(k + 1);
    if (k % 7 == 0) d = GVec3<T>{};
    if (k % 4 == 1) d.x = zero<T>();
    return GRay3<T>{o, d};
  };
  int failures = 0;
  auto const check = [&](char const* name, auto const& wide_shape, auto lane_shape, auto cast) {
    for (std::size_t k = 0; k < 200; ++k) {
      GRay3<T> const ray = make_ray(k);
      // max_toi: finite or +inf, and on every third ray a special value per lane (NaN, +-0,
      // negative, tiny, huge): the wide solid box folds its bounds into one compare, scalar
      // code does not, and the two must agree.
      T max_toi = plume::select(r.elem<T>(0, 1) < splat<T>(0.2), r.elem<T>(0, 6), infinity<T>());
      if (k % 3 == 2) {
        S const special[] = {nan<S>(), S(-0.0),       S(0), S(-1),
                             S(1e-30), infinity<S>(), S(3), std::numeric_limits<S>::max()};
        for (std::size_t i = 0; i < lanes_v<T>; ++i)
          max_toi = plume::with_lane(max_toi, i, special[(k / 3 + i) % 8]);
      }
      bool const solid = k % 2 == 0;
      auto const w = cast(wide_shape, ray, max_toi, solid);
      for (std::size_t i = 0; i < lanes_v<T>; ++i) {
        GRay3<S> const rl{lane(ray.origin, i), lane(ray.dir, i)};
        auto const s = cast(lane_shape(i), rl, lane(max_toi, i), solid);
        GRayHit<S> const wl{lane(w.hit, i), lane(w.toi, i), lane(w.normal, i), lane(w.feature, i)};
        if (!same_hit(wl, s) && failures++ < 5)
          FAIL_CHECK(name << " lane " << i << ": wide " << wl.toi << " " << wl.normal << " scalar "
                          << s.toi << " " << s.normal);
      }
    }
  };
  T const radius = r.elem<T>(0, 2), hh = r.elem<T>(0, 1.5);
  GVec3<T> const ext = r.vec3<T>(0, 2);
  GIso3<T> const pose{r.quat<T>(), r.vec3<T>(-1, 1)};
  auto const cast_local = [](auto const& shape, auto const& ray, auto max_toi, bool solid) {
    return ray_cast_local(shape, ray, max_toi, solid);
  };
  check(
      "sphere", GSphere<T>{radius}, [&](std::size_t i) { return GSphere<S>{lane(radius, i)}; },
      cast_local);
  check(
      "cuboid", GCuboid<T>{ext}, [&](std::size_t i) { return GCuboid<S>{lane(ext, i)}; },
      cast_local);
  check(
      "capsule", GCapsule<T>{hh, radius},
      [&](std::size_t i) {
        return GCapsule<S>{lane(hh, i), lane(radius, i)};
      },
      cast_local);
  check(
      "cylinder", GCylinder<T>{hh, radius},
      [&](std::size_t i) {
        return GCylinder<S>{lane(hh, i), lane(radius, i)};
      },
      cast_local);
  GVec3<T> const hn = r.unit3<T>();
  check(
      "half-space", GHalfSpace<T>{hn}, [&](std::size_t i) { return GHalfSpace<S>{lane(hn, i)}; },
      cast_local);
  GVec3<T> const lo = r.vec3<T>(-2, 0);
  check(
      "aabb", GAabb3<T>{lo, lo + ext},
      [&](std::size_t i) {
        return GAabb3<S>{lane(lo, i), lane(lo + ext, i)};
      },
      [](auto const& box, auto const& ray, auto max_toi, bool solid) {
        return ray_cast(box, ray, max_toi, solid);
      });
  check(
      "posed cuboid", std::pair{GCuboid<T>{ext}, pose},
      [&](std::size_t i) {
        return std::pair{GCuboid<S>{lane(ext, i)}, lane(pose, i)};
      },
      [](auto const& sp, auto const& ray, auto max_toi, bool solid) {
        return ray_cast(sp.first, sp.second, ray, max_toi, solid);
      });
  CHECK(failures == 0);
}
