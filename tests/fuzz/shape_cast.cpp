// tests/fuzz/shape_cast.cpp - fuzzes shape_cast (collision/gjk.hpp): shape A of any kind GJK
// takes (sphere, capsule, cuboid, cylinder, triangle, segment, polytope view, convex hull)
// moving by t * motion against a still shape B of any kind, at random poses and motions,
// motions aimed at B, with and without a target distance (skin), stop_at_penetration on and
// off, max_toi 1 or another, and hostile input. Properties:
//  - bad input: a non-finite pose, motion, radius or shape parameter gives failed and no hit;
//    reasonable input never fails; exactly one of converged / penetrating /
//    out_of_iterations / failed holds;
//  - a hit: toi in [0, max_toi], finite, 0 when penetrating; a unit normal, or a zero one
//    only when penetrating; a miss: toi +inf, zero normal;
//  - reasonable input: at the time of impact of a converged hit the shapes are within the
//    target distance (point_a on A moved there and point_b on B, target * normal apart) and
//    not closer than it; before it (t = 0 and toi / 2) never closer than the target (never
//    late); a penetrating start is within the target at t = 0; a converged miss is farther
//    than the target at t = 0 (unless stop_at_penetration is off and the start is within it)
//    and at samples up to max_toi.
#include "fuzz_input.hpp"
#include "fuzz_shapes.hpp"

#include <plume/collision/gjk.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace {

using namespace plume;
using namespace plume::fuzz;

bool pose_finite(Iso3 const& p) {
  return finite(p.translation) && std::isfinite(p.rotation.x) && std::isfinite(p.rotation.y) &&
         std::isfinite(p.rotation.z) && std::isfinite(p.rotation.w);
}

bool is_zero(Vec3 const& v) { return v.x == 0 && v.y == 0 && v.z == 0; }

Iso3 moved(Iso3 const& p, Vec3 const& motion, float t) {
  return Iso3{p.rotation, p.translation + motion * t};
}

template <class SA, class SB>
void check(SA const& sa, AnyShape const& a, Iso3 const& pa, Vec3 const& motion, SB const& sb,
           AnyShape const& b, Iso3 const& pb, ShapeCastConfig const& cfg, bool hostile) {
  ShapeCastHit const r = shape_cast(sa, pa, motion, sb, pb, cfg);
  float const ra = sa.core_radius(), rb = sb.core_radius();
  bool const finite_input = pose_finite(pa) && pose_finite(pb) && finite(motion) && a.finite &&
                            b.finite && std::isfinite(ra + rb + cfg.target_distance);
  if (!finite_input) PLUME_FUZZ_CHECK(r.failed);
  if (!hostile) PLUME_FUZZ_CHECK(!r.failed);
  PLUME_FUZZ_CHECK(int(bool(r.converged)) + int(bool(r.penetrating)) +
                       int(bool(r.out_of_iterations)) + int(bool(r.failed)) ==
                   1);
  if (r.failed) {
    PLUME_FUZZ_CHECK(!r.hit && r.toi == INFINITY && is_zero(r.normal));
    return;
  }
  if (!r.hit) {
    PLUME_FUZZ_CHECK(r.toi == INFINITY && is_zero(r.normal));
  } else {
    PLUME_FUZZ_CHECK(!std::isnan(r.toi) && r.toi >= 0 && r.toi <= cfg.max_toi);
    PLUME_FUZZ_CHECK(std::isfinite(r.toi));
    if (r.penetrating) PLUME_FUZZ_CHECK(r.toi == 0);
    if (!hostile) {
      if (!r.penetrating) PLUME_FUZZ_CHECK(std::abs(norm(r.normal) - 1.0f) <= 1e-4f);
      if (r.penetrating)
        PLUME_FUZZ_CHECK(is_zero(r.normal) || std::abs(norm(r.normal) - 1.0f) <= 1e-4f);
    }
  }
  if (hostile) return; // huge finite values: survival and the bad-input contract only

  double const scale = double(norm(pa.translation)) + double(norm(pb.translation)) +
                       double(norm(motion)) * std::max(1.0, double(cfg.max_toi)) + double(a.size) +
                       double(b.size);
  double const tol = 1e-4 * (1.0 + scale);
  double const target = cfg.target_distance;
  // The distance between the shapes with A moved by t * motion (0 when the cores overlap; GJK
  // can only err above the true distance, which never makes the checks below fail falsely).
  auto const distance_at = [&](float t) {
    ClosestPoints const c = closest_points(sa, moved(pa, motion, t), sb, pb);
    return c.converged ? double(c.distance) : INFINITY;
  };

  if (r.hit) {
    // Never late: not closer than the target before the time of impact.
    if (r.toi > 0) {
      PLUME_FUZZ_CHECK(distance_at(0) >= target - tol);
      PLUME_FUZZ_CHECK(distance_at(r.toi * 0.5f) >= target - tol);
    }
    if (r.penetrating) {
      // Started within the target distance.
      ClosestPoints const c = closest_points(sa, pa, sb, pb);
      if (c.converged) PLUME_FUZZ_CHECK(c.overlap || c.distance <= target + tol);
    }
    if (r.converged) {
      // At the time of impact: within the target, shown by the reported points (on A moved
      // there and on B, target * normal apart), and not closer than the target.
      Iso3 const at = moved(pa, motion, r.toi);
      D3 const qa(r.point_a), qb(r.point_b);
      for (auto const& u : probe_directions()) {
        PLUME_FUZZ_CHECK(qa.dot(D3(u)) <= extent_along(sa, at, u) + tol);
        PLUME_FUZZ_CHECK(qb.dot(D3(u)) <= extent_along(sb, pb, u) + tol);
      }
      PLUME_FUZZ_CHECK(((qb - qa) - D3(r.normal) * target).length() <= tol);
      PLUME_FUZZ_CHECK(distance_at(r.toi) >= target - tol);
    }
  } else if (r.converged) {
    // A miss: farther than the target all along (at the start too, unless a separating
    // start was ignored).
    bool const ignored_start = !cfg.stop_at_penetration && distance_at(0) <= target + tol;
    if (!ignored_start) {
      for (float s : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f})
        PLUME_FUZZ_CHECK(distance_at(s * cfg.max_toi) >= target - tol);
    }
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  Input in(data, size);
  bool const hostile = (in.byte() & 7) == 0;
  Kind const ka = read_kind(in), kb = read_kind(in);
  AnyShape const a = make_shape(in, ka, hostile);
  AnyShape const b = make_shape(in, kb, hostile);
  Iso3 const pa = make_pose(in, 4, hostile), pb = make_pose(in, 4, hostile);
  Vec3 motion = hostile ? in.maybe_bad_vec3(-8, 8) : in.vec3(-8, 8);
  if (!hostile && in.flag()) {
    // Aimed at B: past its centre by a random fraction, with a random offset.
    float const past = in.real(0.5f, 2);
    Vec3 const offset = in.vec3(-0.5f, 0.5f);
    motion = (pb.translation - pa.translation) * past + offset;
  }
  ShapeCastConfig cfg;
  std::uint8_t const opts = in.byte();
  if (opts & 1) cfg.target_distance = in.real(0, 0.5f);
  if (opts & 2) cfg.stop_at_penetration = false;
  if (opts & 4) cfg.max_toi = in.real(0, 2);
  a.visit([&](auto const& sa) {
    b.visit([&](auto const& sb) { check(sa, a, pa, motion, sb, b, pb, cfg, hostile); });
  });
  return 0;
}
