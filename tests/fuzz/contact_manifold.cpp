// tests/fuzz/contact_manifold.cpp - fuzzes contact_manifold (collision/manifold.hpp) for every
// pair kind it offers: spheres, capsules, cuboids, convex hulls and triangles against each
// other (face clipping, capsule segments, the box separating-axis test), each of them and the
// single-point kinds (cylinder, segment, polytope view) against a half-space in either order,
// and the single-point pairs; mostly touching or overlapping (B near A), with the default or
// a larger prediction distance, sometimes hostile. Properties:
//  - count in [0, 4]; failed for non-finite input (pose, radius, shape parameter), with
//    count 0; reasonable input never fails;
//  - reasonable input, each point: finite; separation finite and <= prediction; point_a in A,
//    point_b in B (on the plane for a half-space); point_b - point_a = separation * normal;
//    ids unique; a unit normal whenever there are points;
//  - consistent with the pair's signed distance s (penetration(), or the plane distance for a
//    half-space): no points only when s > prediction (within the tolerance); with points,
//    the deepest separation is s (single-point pairs and half-spaces, where the deepest point
//    is kept), or within the reference face's tilt of it (clipped pairs);
//  - two cuboids: box_pair_manifold's lanes equal its scalar calls (check_lanes), and its
//    nearest-edges point has the pair's distance as its separation.
#include "fuzz_input.hpp"
#include "fuzz_shapes.hpp"

#include <plume/collision/epa.hpp>
#include <plume/collision/manifold.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <set>
#include <type_traits>

namespace {

using namespace plume;
using namespace plume::fuzz;

bool pose_finite(Iso3 const& p) {
  return finite(p.translation) && std::isfinite(p.rotation.x) && std::isfinite(p.rotation.y) &&
         std::isfinite(p.rotation.z) && std::isfinite(p.rotation.w);
}

/// A manifold operand: a shape of any GJK kind, or a half-space.
struct Operand {
  bool half_space = false;
  HalfSpace plane{};
  AnyShape shape;

  template <class F>
  decltype(auto) visit(F&& f) const {
    if (half_space) return f(plane);
    return shape.visit(f);
  }
};

template <class S>
constexpr bool is_half_space = std::is_same_v<S, HalfSpace>;
template <class S>
constexpr bool clipped_kind = std::is_same_v<S, Cuboid> || std::is_same_v<S, ConvexHull> ||
                              std::is_same_v<S, Triangle> || std::is_same_v<S, Capsule>;

/// Extent along a world unit u of a shape at a pose (a half-space: +inf unless u is its
/// normal, where it is the plane's offset).
template <class S>
double extent(S const& s, Iso3 const& pose, Vec3 const& u) {
  if constexpr (is_half_space<S>) {
    D3 const n(pose.transform_vector(s.normal));
    if ((D3(u) - n).length() <= 1e-6) return D3(pose.translation).dot(n);
    return INFINITY;
  } else {
    return extent_along(s, pose, u);
  }
}

/// p lies in the shape (within tol): below its extent along every probe direction, below
/// the plane for a half-space.
template <class S>
bool contains(S const& s, Iso3 const& pose, D3 p, double tol) {
  if constexpr (is_half_space<S>) {
    D3 const n(pose.transform_vector(s.normal));
    return (p - D3(pose.translation)).dot(n) <= tol;
  } else {
    for (auto const& u : probe_directions())
      if (p.dot(D3(u)) > extent_along(s, pose, u) + tol) return false;
    return true;
  }
}

/// The signed distance of the pair: the plane distance of the other shape for a half-space
/// pair (min over it of n . (x - o)), else from penetration() (NaN when it failed).
template <class SA, class SB>
double signed_distance(SA const& sa, Iso3 const& pa, SB const& sb, Iso3 const& pb) {
  if constexpr (is_half_space<SA> && is_half_space<SB>) {
    return -INFINITY;
  } else if constexpr (is_half_space<SA>) {
    Vec3 const n = pa.transform_vector(sa.normal);
    return -extent_along(sb, pb, -n) - D3(pa.translation).dot(D3(n));
  } else if constexpr (is_half_space<SB>) {
    Vec3 const n = pb.transform_vector(sb.normal);
    return -extent_along(sa, pa, -n) - D3(pb.translation).dot(D3(n));
  } else {
    PenetrationResult const p = penetration(sa, pa, sb, pb);
    return p.status == PenetrationStatus::failed ? NAN : -double(p.depth);
  }
}

/// Two cuboids: box_pair_manifold at the build's widest width, the pair in the even lanes and
/// the pair swapped in the odd ones, each lane bitwise equal to the scalar call on its inputs.
void check_lanes(Cuboid const& sa, Iso3 const& pa, Cuboid const& sb, Iso3 const& pb,
                 ManifoldConfig const& cfg) {
  using W = f32xN;
  GVec3<W> ea, eb;
  GIso3<W> wa, wb;
  for (std::size_t l = 0; l < lanes_v<W>; ++l) {
    bool const swap = l % 2 == 1;
    ea = with_lane(ea, l, swap ? sb.half_extents : sa.half_extents);
    eb = with_lane(eb, l, swap ? sa.half_extents : sb.half_extents);
    wa = with_lane(wa, l, swap ? pb : pa);
    wb = with_lane(wb, l, swap ? pa : pb);
  }
  GBoxPairManifold<W> const w = box_pair_manifold(ea, wa, eb, wb, cfg.prediction);
  auto const same = [](float x, float y) {
    return std::bit_cast<std::uint32_t>(x) == std::bit_cast<std::uint32_t>(y);
  };
  auto const same3 = [&](Vec3 x, Vec3 y) {
    return same(x.x, y.x) && same(x.y, y.y) && same(x.z, y.z);
  };
  for (std::size_t l = 0; l < lanes_v<W>; ++l) {
    bool const swap = l % 2 == 1;
    GBoxPairManifold<float> const s =
        swap ? box_pair_manifold(sb.half_extents, pb, sa.half_extents, pa, cfg.prediction)
             : box_pair_manifold(sa.half_extents, pa, sb.half_extents, pb, cfg.prediction);
    PLUME_FUZZ_CHECK((((bitmask(w.general) >> l) & 1u) != 0) == s.general);
    PLUME_FUZZ_CHECK((((bitmask(w.ref_is_b) >> l) & 1u) != 0) == s.ref_is_b);
    PLUME_FUZZ_CHECK(same(lane(w.count, l), s.count) && same3(lane(w.normal, l), s.normal));
    for (std::size_t k = 0; k < std::size_t(s.count); ++k)
      PLUME_FUZZ_CHECK(same3(lane(w.point_a[k], l), s.point_a[k]) &&
                       same3(lane(w.point_b[k], l), s.point_b[k]) &&
                       same(lane(w.separation[k], l), s.separation[k]) &&
                       same(lane(w.key[k], l), s.key[k]));
  }
}

template <class SA, class SB>
void check(SA const& sa, Operand const& a, Iso3 const& pa, SB const& sb, Operand const& b,
           Iso3 const& pb, ManifoldConfig const& cfg, bool hostile) {
  if constexpr (std::is_same_v<SA, Cuboid> && std::is_same_v<SB, Cuboid>)
    check_lanes(sa, pa, sb, pb, cfg);
  Manifold const m = contact_manifold(sa, pa, sb, pb, cfg);
  PLUME_FUZZ_CHECK(m.count >= 0 && m.count <= 4);
  bool const finite_input = pose_finite(pa) && pose_finite(pb) &&
                            (a.half_space ? finite(a.plane.normal) : a.shape.finite) &&
                            (b.half_space ? finite(b.plane.normal) : b.shape.finite);
  if (!finite_input) PLUME_FUZZ_CHECK(m.failed);
  if (!hostile) PLUME_FUZZ_CHECK(!m.failed);
  if (m.failed) {
    PLUME_FUZZ_CHECK(m.count == 0);
    return;
  }
  if (hostile) return; // huge finite values: survival and the bad-input contract only

  double const size_a = a.half_space ? 0.0 : double(a.shape.size);
  double const size_b = b.half_space ? 0.0 : double(b.shape.size);
  double const scale =
      double(norm(pa.translation)) + double(norm(pb.translation)) + size_a + size_b;
  double const tol = 1e-4 * (1.0 + scale);
  double const prediction = cfg.prediction;

  std::set<std::uint64_t> ids;
  if (m.count > 0) PLUME_FUZZ_CHECK(std::abs(norm(m.normal) - 1.0f) <= 1e-4f);
  for (auto const& c : m) {
    PLUME_FUZZ_CHECK(finite(c.point_a) && finite(c.point_b) && std::isfinite(c.separation));
    PLUME_FUZZ_CHECK(c.separation <= prediction + 1e-6 * (1.0 + scale));
    PLUME_FUZZ_CHECK(ids.insert(c.id).second);
    D3 const qa(c.point_a), qb(c.point_b);
    PLUME_FUZZ_CHECK(contains(sa, pa, qa, tol));
    PLUME_FUZZ_CHECK(contains(sb, pb, qb, tol));
    PLUME_FUZZ_CHECK(((qb - qa) - D3(m.normal) * double(c.separation)).length() <= tol);
  }

  if constexpr (is_half_space<SA> && is_half_space<SB>) {
    PLUME_FUZZ_CHECK(m.count == 0); // two half-spaces: no manifold
  } else {
    double const s = signed_distance(sa, pa, sb, pb);
    PLUME_FUZZ_CHECK(!std::isnan(s));
    if (m.count == 0) {
      PLUME_FUZZ_CHECK(s > prediction - tol);
    } else {
      // The deepest point: the pair's signed distance where the deepest point is kept, within
      // the tilt a reference face may have (face_alignment: about 0.02 rad) where clipped.
      double const deepest = m.min_separation();
      bool const clipped = clipped_kind<SA> && clipped_kind<SB>;
      double const slack = clipped ? tol + 0.05 * (size_a + size_b) : tol;
      PLUME_FUZZ_CHECK(deepest <= s + slack);
      if (!clipped) PLUME_FUZZ_CHECK(deepest >= s - slack);
      if constexpr (std::is_same_v<SA, Cuboid> && std::is_same_v<SB, Cuboid>) {
        // The cuboid kernel's nearest edges (key 25) claim the boxes' distance itself.
        auto const w = box_pair_manifold(sa.half_extents, pa, sb.half_extents, pb, cfg.prediction);
        if (!w.general && w.count == 1.0f && w.key[0] == 25.0f)
          PLUME_FUZZ_CHECK(std::abs(deepest - s) <= tol);
      }
    }
  }
}

Operand make_operand(Input& in, bool hostile) {
  Operand o;
  int const k = in.integer(0, kind_count); // kind_count: a half-space
  if (k == kind_count) {
    o.half_space = true;
    o.plane.normal = hostile ? in.maybe_bad_vec3(-1, 1) : unit_vector(in);
    if (!hostile || finite(o.plane.normal)) {
      float const l = norm(o.plane.normal);
      o.plane.normal = l > 1e-3f ? o.plane.normal * (1.0f / l) : Vec3{0, 1, 0};
    }
  } else {
    o.shape = make_shape(in, Kind(k), hostile);
  }
  return o;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  Input in(data, size);
  bool const hostile = (in.byte() & 7) == 0;
  Operand const a = make_operand(in, hostile);
  Operand const b = make_operand(in, hostile);
  Iso3 const pa = make_pose(in, 4, hostile);
  Iso3 pb = make_pose(in, 4, hostile);
  if (!hostile && (in.byte() & 3) != 0) pb.translation = pa.translation + in.vec3(-1.5f, 1.5f);
  ManifoldConfig cfg;
  if (in.flag()) cfg.prediction = in.real(0, 0.5f);
  a.visit([&](auto const& sa) {
    b.visit([&](auto const& sb) { check(sa, a, pa, sb, b, pb, cfg, hostile); });
  });
  return 0;
}
