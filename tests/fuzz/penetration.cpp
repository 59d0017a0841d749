// tests/fuzz/penetration.cpp - fuzzes penetration (collision/epa.hpp): signed distance and
// penetration depth between two shapes of every kind GJK takes (sphere, capsule, cuboid,
// cylinder, triangle, segment, polytope view, convex hull), mostly overlapping (B placed near
// A), sometimes apart, sometimes hostile. Properties:
//  - the status is one of the four documented values; failed exactly for non-finite input
//    (pose, radius, shape parameter), with a NaN depth and points and a zero normal;
//    reasonable input never fails;
//  - sizes >= 0: separated, depth <= 0; penetrating / approximate, depth >= 0;
//  - reasonable input: a finite depth and points, a unit normal;
//  - reasonable input: the depth is the smallest overlap of the shapes' extents over
//    directions (h(u) = extent of A along u + extent of B along -u >= depth for every probe
//    direction, approximate included: its depth is a lower bound) and the normal attains it
//    (h(normal) = depth, within EPA's tolerance, or GJK's normal rounding when GJK decided);
//    point_a and point_b lie in their shapes; apart, point_b - point_a = -depth * normal;
//    penetrating, moving B by depth (plus a little) along the normal separates the shapes
//    (closest_points distance >= 0 within the tolerance).
#include "fuzz_input.hpp"
#include "fuzz_shapes.hpp"

#include <plume/collision/epa.hpp>
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

template <class SA, class SB>
void check(SA const& sa, AnyShape const& a, Iso3 const& pa, SB const& sb, AnyShape const& b,
           Iso3 const& pb, bool hostile) {
  PenetrationResult const r = penetration(sa, pa, sb, pb);
  using St = PenetrationStatus;
  PLUME_FUZZ_CHECK(r.status == St::separated || r.status == St::penetrating ||
                   r.status == St::approximate || r.status == St::failed);
  float const ra = sa.core_radius(), rb = sb.core_radius();
  bool const finite_input = pose_finite(pa) && pose_finite(pb) && a.finite && b.finite &&
                            std::isfinite(ra) && std::isfinite(rb);
  if (!finite_input) PLUME_FUZZ_CHECK(r.status == St::failed);
  if (!hostile) PLUME_FUZZ_CHECK(r.status != St::failed);
  if (r.status == St::failed) {
    PLUME_FUZZ_CHECK(std::isnan(r.depth) && std::isnan(r.point_a.x) && std::isnan(r.point_b.x));
    PLUME_FUZZ_CHECK(r.normal.x == 0 && r.normal.y == 0 && r.normal.z == 0);
    return;
  }
  // (Negative sizes, from hostile bytes, are unspecified shapes: no sign.)
  if (a.sized && b.sized) {
    if (r.status == St::separated) PLUME_FUZZ_CHECK(r.depth <= 0);
    if (r.status != St::separated) PLUME_FUZZ_CHECK(r.depth >= 0);
  }
  PLUME_FUZZ_CHECK(r.iterations >= 0);
  if (hostile) return; // huge finite values: survival and the bad-input contract only

  PLUME_FUZZ_CHECK(std::isfinite(r.depth) && finite(r.point_a) && finite(r.point_b));
  PLUME_FUZZ_CHECK(std::abs(norm(r.normal) - 1.0f) <= 1e-4f);
  double const scale =
      double(norm(pa.translation)) + double(norm(pb.translation)) + double(a.size) + double(b.size);
  double const tol = 1e-4 * (1.0 + scale);
  double const depth = r.depth;
  auto const h = [&](Vec3 const& u) { return extent_along(sa, pa, u) + extent_along(sb, pb, -u); };

  // The depth is the smallest overlap over directions, and the normal attains it.
  for (auto const& u : probe_directions())
    PLUME_FUZZ_CHECK(h(u) >= depth - tol);
  Vec3 const centre = pb.translation - pa.translation;
  if (norm(centre) > 1e-3f) PLUME_FUZZ_CHECK(h(centre * (1.0f / norm(centre))) >= depth - tol);
  PLUME_FUZZ_CHECK(h(r.normal) >= depth - tol);
  if (r.status != St::approximate) {
    // EPA's answer is within its tolerance; GJK's (iterations 0) carries its normal's
    // rounding (see gjk_distance.cpp): about eps * scale / d radians, d the distance of the
    // points its normal is the direction between, the cores'. Rounded shapes that overlap
    // with their cores apart are ra + rb - depth apart there, which can be far less than the
    // depth (findings/penetration/normal-beyond-extent, now corpus
    // regress-rounded-cores-nearly-touching: a capsule of radius 0.25 whose core is 3.3e-5
    // from a polytope's vertex, 7 units from the origin; the normal is 0.0146 rad off).
    double const core_gap = double(ra) + double(rb) - depth;
    double const d = std::max(std::min(std::abs(depth), std::abs(core_gap)), 1e-30);
    double const slack = r.iterations > 0 ? tol : tol + scale * (3e-4 + 1e-5 * scale / d);
    PLUME_FUZZ_CHECK(h(r.normal) <= depth + slack);
  }

  // The points lie in their shapes.
  D3 const qa(r.point_a), qb(r.point_b);
  for (auto const& u : probe_directions()) {
    PLUME_FUZZ_CHECK(qa.dot(D3(u)) <= extent_along(sa, pa, u) + tol);
    PLUME_FUZZ_CHECK(qb.dot(D3(u)) <= extent_along(sb, pb, u) + tol);
  }
  if (r.status == St::separated)
    PLUME_FUZZ_CHECK(((qb - qa) + D3(r.normal) * depth).length() <= tol);

  if (r.status == St::penetrating) {
    // Moving B by the depth (plus a little) along the normal separates them.
    float const extra = float(10 * tol);
    Iso3 const out{pb.rotation, pb.translation + r.normal * (r.depth + extra)};
    ClosestPoints const c = closest_points(sa, pa, sb, out);
    PLUME_FUZZ_CHECK(!c.failed);
    PLUME_FUZZ_CHECK(!c.overlap && c.distance >= -tol);
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  Input in(data, size);
  bool const hostile = (in.byte() & 7) == 0;
  Kind const ka = read_kind(in), kb = read_kind(in);
  AnyShape const a = make_shape(in, ka, hostile);
  AnyShape const b = make_shape(in, kb, hostile);
  Iso3 const pa = make_pose(in, 4, hostile);
  Iso3 pb = make_pose(in, 4, hostile);
  // Mostly overlapping: B within about a shape's size of A.
  if (!hostile && (in.byte() & 3) != 0) pb.translation = pa.translation + in.vec3(-1.5f, 1.5f);
  a.visit([&](auto const& sa) {
    b.visit([&](auto const& sb) { check(sa, a, pa, sb, b, pb, hostile); });
  });
  return 0;
}
