// tests/fuzz/gjk_distance.cpp - fuzzes closest_points (collision/gjk.hpp) between two shapes
// of every kind GJK takes (sphere, capsule, cuboid, cylinder, triangle, segment, polytope view,
// convex hull) at random poses, with and without a warm-start axis. Properties:
//  - bad input: a non-finite pose, radius, shape parameter or axis gives failed, with a NaN
//    distance and points and a zero normal; reasonable input never fails; a result that did
//    not fail has a distance that is not NaN, at least -(radius A + radius B) for radii >= 0;
//  - overlap: distance 0 and a zero normal; else a unit normal;
//  - converged, reasonable input: the distance is at most the distance between any two
//    points of the shapes (vertex pairs of polytopes, support points of every kind) and not
//    below the gap between the shapes' extents along the normal, a certified lower bound,
//    which it nearly equals (up to the normal's rounding: the contract is on distances);
//    point_a and point_b lie in their shapes, (nearly) extreme along the normal, and
//    point_b - point_a = distance * normal; overlapping cores have overlapping extents along
//    every probe direction; the swapped query and a warm-started one agree (the same distance,
//    or nearly touching cores where only one of them reports core overlap).
#include "fuzz_input.hpp"
#include "fuzz_shapes.hpp"

#include <plume/collision/gjk.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace {

using namespace plume;
using namespace plume::fuzz;

bool pose_finite(Iso3 const& p) {
  return finite(p.translation) && std::isfinite(p.rotation.x) && std::isfinite(p.rotation.y) &&
         std::isfinite(p.rotation.z) && std::isfinite(p.rotation.w);
}

template <class SA, class SB>
void check(SA const& sa, AnyShape const& a, Iso3 const& pa, SB const& sb, AnyShape const& b,
           Iso3 const& pb, Vec3 const& axis, bool hostile) {
  ClosestPoints const r = closest_points(sa, pa, sb, pb, GjkConfig{}, axis);
  float const ra = sa.core_radius(), rb = sb.core_radius();
  bool const finite_input = pose_finite(pa) && pose_finite(pb) && a.finite && b.finite &&
                            finite(axis) && std::isfinite(ra) && std::isfinite(rb);
  if (!finite_input) PLUME_FUZZ_CHECK(r.failed);
  if (!hostile) PLUME_FUZZ_CHECK(!r.failed);
  if (r.failed) {
    PLUME_FUZZ_CHECK(std::isnan(r.distance));
    PLUME_FUZZ_CHECK(!r.converged);
    PLUME_FUZZ_CHECK(r.normal.x == 0 && r.normal.y == 0 && r.normal.z == 0);
    PLUME_FUZZ_CHECK(std::isnan(r.point_a.x) && std::isnan(r.point_b.x));
    return;
  }
  PLUME_FUZZ_CHECK(!std::isnan(r.distance));
  // (Negative radii, from hostile bytes, are unspecified shapes: no bound.)
  if (ra >= 0 && rb >= 0) PLUME_FUZZ_CHECK(r.distance >= -ra - rb);
  if (r.overlap) {
    PLUME_FUZZ_CHECK(r.distance == 0);
    PLUME_FUZZ_CHECK(r.normal.x == 0 && r.normal.y == 0 && r.normal.z == 0);
  }
  if (hostile) return; // huge finite values: survival and the bad-input contract only
  PLUME_FUZZ_CHECK(finite(r.point_a) && finite(r.point_b) && std::isfinite(r.distance));
  if (!r.overlap) PLUME_FUZZ_CHECK(std::abs(norm(r.normal) - 1.0f) <= 1e-5f);
  if (!r.converged) return;

  // Tolerance: GJK's 1e-5 plus float rounding of the coordinates in play.
  double const scale =
      double(norm(pa.translation)) + double(norm(pb.translation)) + double(a.size) + double(b.size);
  double const tol = 2e-5 * (1.0 + scale);
  double const d = r.distance; // 0 when the cores overlap

  // No two points of the shapes are closer than the distance.
  std::vector<Vec3> const pts_a = sample_points(a, pa), pts_b = sample_points(b, pb);
  for (auto const& p : pts_a)
    for (auto const& q : pts_b)
      PLUME_FUZZ_CHECK(d <= (D3(q) - D3(p)).length() + tol);

  if (r.overlap) {
    // Overlapping shapes: no probe direction separates them.
    for (auto const& u : probe_directions())
      PLUME_FUZZ_CHECK(extent_along(sa, pa, u) + extent_along(sb, pb, -u) >= -tol);
  } else {
    // The normal certifies the distance: the gap between the extents along it is a lower
    // bound of the true distance, so the distance is not below it; and it is nearly the
    // distance. Nearly: the contract promises the distance's accuracy, not the normal's. Where
    // float cannot see d^2 improve any more (a relative change below eps), GJK stops with the
    // distance right but the normal off by up to about sqrt(eps) radians, and a normal taken
    // from a difference of coordinates carries their rounding (about eps * scale / d radians,
    // any direction for a distance at the rounding floor); the extents move by that angle
    // times the size of the shapes.
    Vec3 const n = r.normal;
    double const ha = extent_along(sa, pa, n), hb = extent_along(sb, pb, -n);
    double const gap = -(ha + hb);
    double const loose = tol + scale * (3e-4 + 1e-5 * scale / std::max(d, 1e-30));
    PLUME_FUZZ_CHECK(d >= gap - tol);
    PLUME_FUZZ_CHECK(gap >= d - loose);
    // The points: inside their shapes, (nearly) extreme along the normal, distance * normal
    // apart.
    D3 const qa(r.point_a), qb(r.point_b);
    PLUME_FUZZ_CHECK(std::abs(qa.dot(D3(n)) - ha) <= loose);
    PLUME_FUZZ_CHECK(std::abs(qb.dot(D3(n)) + hb) <= loose);
    for (auto const& u : probe_directions()) {
      PLUME_FUZZ_CHECK(qa.dot(D3(u)) <= extent_along(sa, pa, u) + tol);
      PLUME_FUZZ_CHECK(qb.dot(D3(u)) <= extent_along(sb, pb, u) + tol);
    }
    D3 const diff = (qb - qa) - D3(n) * d;
    PLUME_FUZZ_CHECK(diff.length() <= tol);
  }

  // The same pair the other way round, and warm-started from the result's axis, agree: the
  // same distance, or, where one says the cores overlap (distance 0) and the other does not,
  // cores that nearly touch (distance -(radius A + radius B) within the tolerance).
  auto const agree = [&](ClosestPoints const& o) {
    if (o.failed) return false;
    if (!o.converged) return true;
    if (o.overlap == r.overlap) return o.overlap || std::abs(double(o.distance) - d) <= tol;
    ClosestPoints const& apart = o.overlap ? r : o;
    return double(apart.distance) <= -double(ra) - double(rb) + tol;
  };
  PLUME_FUZZ_CHECK(agree(closest_points(sb, pb, sa, pa)));
  if (finite(r.axis)) PLUME_FUZZ_CHECK(agree(closest_points(sa, pa, sb, pb, GjkConfig{}, r.axis)));
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  Input in(data, size);
  bool const hostile = (in.byte() & 7) == 0;
  Kind const ka = read_kind(in), kb = read_kind(in);
  AnyShape const a = make_shape(in, ka, hostile);
  AnyShape const b = make_shape(in, kb, hostile);
  Iso3 const pa = make_pose(in, 4, hostile), pb = make_pose(in, 4, hostile);
  Vec3 axis{};
  if ((in.byte() & 3) == 0) axis = hostile ? in.maybe_bad_vec3(-1, 1) : in.vec3(-1, 1);
  a.visit([&](auto const& sa) {
    b.visit([&](auto const& sb) { check(sa, a, pa, sb, b, pb, axis, hostile); });
  });
  return 0;
}
