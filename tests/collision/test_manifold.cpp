// Contact manifolds: boxes resting on boxes (4 points at the right depth), tilted boxes (edge
// contacts), speculative points, capsules and spheres, half-spaces, triangles, edge-edge
// contacts, the 4-point reduction, feature ids that persist, and consistent normals when the
// shapes swap places; the configs' scaled().
#include "collision_support.hpp"

#include <plume/collision/manifold.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <set>
#include <utility>
#include <vector>

using namespace plume;
using namespace plume::test;

namespace {

/// The feature ids of a manifold's points.
std::set<std::uint64_t> ids_of(Manifold const& m) {
  std::set<std::uint64_t> ids;
  for (auto const& c : m)
    ids.insert(c.id);
  return ids;
}

/// Invariants of every manifold: unit normal, at most 4 points, unique ids, points joined by
/// separation * normal, separations within the prediction distance.
void check_manifold(Manifold const& m, ManifoldConfig const& cfg = {}) {
  REQUIRE(m.count <= 4);
  if (m.count == 0) return;
  CHECK(std::abs(m.normal.length() - 1) < 1e-5f);
  for (auto const& c : m) {
    CHECK(c.separation <= cfg.prediction + 1e-6f);
    Vec3 const gap = c.point_b - c.point_a;
    CHECK((gap - m.normal * c.separation).length() <= 1e-4f);
  }
  CHECK(ids_of(m).size() == std::size_t(m.count)); // unique
}

Iso3 at(Vec3 t, Quat q = Quat::IDENTITY) { return {q, t}; }

/// A disc of radius 1 and thickness 0.1 (a regular prism of `sides` sides) as a hull.
ConvexHull disc_hull(int sides) {
  std::vector<Vec3> pts;
  for (int k = 0; k < sides; ++k) {
    float const a = float(2 * std::numbers::pi * k / sides);
    pts.push_back({std::cos(a), -0.05f, std::sin(a)});
    pts.push_back({std::cos(a), 0.05f, std::sin(a)});
  }
  return hull_of(pts);
}

/// The lowest world y of a hull's vertices at a pose.
float lowest_y(ConvexHull const& h, Iso3 const& pose) {
  float y = std::numeric_limits<float>::infinity();
  for (auto const& v : h.vertices())
    y = std::min(y, pose.transform_point(v).y);
  return y;
}

} // namespace

TEST_CASE("manifold: a box resting on a box has 4 points at the depth", "[collision][manifold]") {
  Cuboid const ground{{5, 1, 5}};
  Iso3 const ground_pose = at({0, -1, 0}); // top face at y = 0
  Cuboid const box{{0.5f, 0.5f, 0.5f}};
  for (float depth : {0.01f, 0.1f}) {
    auto const m = contact_manifold(box, at({0.3f, 0.5f - depth, -0.2f}), ground, ground_pose);
    check_manifold(m);
    REQUIRE(m.count == 4);
    CHECK(m.normal.y == Approx(-1).margin(1e-6)); // from the box (A) toward the ground (B)
    for (auto const& c : m) {
      CHECK(c.separation == Approx(-depth).margin(1e-5));
      CHECK(std::abs(std::abs(c.point_a.x - 0.3f) - 0.5f) < 1e-5f); // at the corners
      CHECK(std::abs(std::abs(c.point_a.z + 0.2f) - 0.5f) < 1e-5f);
      CHECK(c.point_b.y == Approx(0).margin(1e-5)); // on the ground's top face
    }
    // The same with both shapes as hulls, and with the roles swapped (normal flips).
    ConvexHull const hb = box_hull(box.half_extents), hg = box_hull(ground.half_extents);
    auto const mh = contact_manifold(hb, at({0.3f, 0.5f - depth, -0.2f}), hg, ground_pose);
    check_manifold(mh);
    CHECK(mh.count == 4);
    CHECK(mh.min_separation() == Approx(-depth).margin(1e-5));
    auto const sw = contact_manifold(ground, ground_pose, box, at({0.3f, 0.5f - depth, -0.2f}));
    check_manifold(sw);
    CHECK(sw.count == 4);
    CHECK(sw.normal.y == Approx(1).margin(1e-6));
  }
  // Turned about the vertical: still 4 points, at the turned corners.
  Quat const turn = Quat::from_rotation_y(0.6f);
  auto const m = contact_manifold(box, at({0, 0.48f, 0}, turn), ground, ground_pose);
  check_manifold(m);
  REQUIRE(m.count == 4);
  for (auto const& c : m)
    CHECK(std::hypot(c.point_a.x, c.point_a.z) == Approx(std::sqrt(0.5f)).margin(1e-5));
  // A small box on a large one's face, the large one as reference: still 4 points.
  auto const small =
      contact_manifold(Cuboid{{0.1f, 0.1f, 0.1f}}, at({2, 0.09f, 2}), ground, ground_pose);
  check_manifold(small);
  CHECK(small.count == 4);
}

TEST_CASE("manifold: tilted boxes touch along an edge, edge-edge touches at a point",
          "[collision][manifold]") {
  Cuboid const ground{{5, 1, 5}};
  Iso3 const ground_pose = at({0, -1, 0});
  Cuboid const box{{0.5f, 0.5f, 0.5f}};
  // Tilted 30 degrees about z: the lowest edge runs along z, at x = centre - ... and height
  // (half diagonal in the xy plane) * cos(45 - 30 degrees) above the centre's base.
  float const tilt = float(std::numbers::pi / 6);
  float const low = 0.5f * (std::cos(tilt) + std::sin(tilt)); // centre height of the edge
  float const depth = 0.02f;
  auto const m = contact_manifold(box, at({0, low - depth, 0}, Quat::from_rotation_z(tilt)), ground,
                                  ground_pose);
  check_manifold(m);
  REQUIRE(m.count == 2);
  CHECK(m.normal.y == Approx(-1).margin(1e-5));
  float zs[2];
  int i = 0;
  for (auto const& c : m) {
    CHECK(c.separation == Approx(-depth).margin(1e-5));
    zs[i++] = c.point_a.z;
  }
  CHECK(std::abs(zs[0] - zs[1]) == Approx(1).margin(1e-5)); // both ends of the edge
  // Tilted about two axes: a single corner touches.
  Quat const corner = Quat::from_rotation_z(0.5f) * Quat::from_rotation_x(0.4f);
  Cuboid const b2 = box;
  // Find the corner height by the support point.
  Vec3 const lowest = corner * b2.support(corner.inverse() * Vec3{0, -1, 0});
  auto const mc = contact_manifold(b2, at({0, -lowest.y - 0.01f, 0}, corner), ground, ground_pose);
  check_manifold(mc);
  CHECK(mc.count == 1);
  CHECK(mc.points[0].separation == Approx(-0.01f).margin(1e-5));
  // Two boxes whose edges cross (one turned 45 degrees about x, the other about y... and
  // lifted so only the edges meet): one point, normal along the edges' common perpendicular.
  Quat const qa = Quat::from_rotation_x(float(std::numbers::pi / 4));
  Quat const qb = Quat::from_rotation_z(float(std::numbers::pi / 4));
  float const r = 0.5f * std::sqrt(2.0f);
  auto const ee = contact_manifold(box, at({0, 2 * r - 0.01f, 0}, qa), box, at({0, 0, 0}, qb));
  check_manifold(ee);
  REQUIRE(ee.count == 1);
  CHECK(ee.normal.y == Approx(-1).margin(1e-4));
  CHECK(ee.points[0].separation == Approx(-0.01f).margin(1e-4));
}

TEST_CASE("manifold: speculative points, apart, ids that persist", "[collision][manifold]") {
  Cuboid const ground{{5, 1, 5}};
  Iso3 const ground_pose = at({0, -1, 0});
  Cuboid const box{{0.5f, 0.5f, 0.5f}};
  ManifoldConfig cfg;
  cfg.prediction = 0.02f;
  auto const above = contact_manifold(box, at({0, 0.51f, 0}), ground, ground_pose, cfg);
  check_manifold(above, cfg);
  CHECK(above.count == 4);
  CHECK(above.min_separation() == Approx(0.01f).margin(1e-5));
  auto const far = contact_manifold(box, at({0, 0.53f, 0}), ground, ground_pose, cfg);
  CHECK(far.count == 0);
  CHECK(far.normal.y == Approx(-1).margin(1e-5)); // the normal is still reported
  // Ids: the same features give the same ids after a small move, in any order.
  auto const m1 = contact_manifold(box, at({0.1f, 0.49f, 0}), ground, ground_pose);
  auto const m2 = contact_manifold(box, at({0.12f, 0.485f, 0.01f}), ground, ground_pose);
  std::set<std::uint64_t> const ids1 = ids_of(m1), ids2 = ids_of(m2);
  CHECK(ids1 == ids2);
  CHECK(ids1.size() == 4);
  // A box overhanging a small ledge: clipped points, with ids that persist too.
  Cuboid const ledge{{0.3f, 0.5f, 0.3f}};
  Iso3 const ledge_pose = at({0, -0.5f, 0});
  auto const c1 = contact_manifold(box, at({0.1f, 0.49f, 0.05f}, Quat::from_rotation_y(0.3f)),
                                   ledge, ledge_pose);
  auto const c2 = contact_manifold(box, at({0.11f, 0.488f, 0.05f}, Quat::from_rotation_y(0.31f)),
                                   ledge, ledge_pose);
  check_manifold(c1);
  check_manifold(c2);
  std::set<std::uint64_t> const k1 = ids_of(c1), k2 = ids_of(c2);
  CHECK(c1.count == 4);
  CHECK(k1 == k2);
  // A box wobbling on a slab by 1e-4 rad: the slab's face then separates the pair by 1.5 x
  // the tilt more than the box's own face (up to 3e-4 here), less than the reference face's
  // hysteresis (0.1 x prediction = 2e-3), so the box's face stays the reference and the ids
  // persist (a reference flipping from frame to frame would lose the solver's warm start).
  Cuboid const slab{{2, 0.5f, 2}};
  Iso3 const slab_pose = at({0, -0.5f, 0});
  std::set<std::uint64_t> const flat_ids =
      ids_of(contact_manifold(box, at({0.2f, 0.49f, 0}), slab, slab_pose));
  CHECK(flat_ids.size() == 4);
  for (float wobble : {1e-4f, -1e-4f, 2e-4f}) {
    for (Quat const q : {Quat::from_rotation_x(wobble), Quat::from_rotation_z(wobble)}) {
      auto const w = contact_manifold(box, at({0.2f, 0.49f, 0}, q), slab, slab_pose);
      check_manifold(w);
      std::set<std::uint64_t> const ids = ids_of(w);
      CHECK(ids == flat_ids);
      CHECK((w.normal - q * Vec3{0, -1, 0}).length() < 1e-6f); // the box's face, not the slab's
    }
  }
  // The same as hulls (the GJK/EPA path, whose face choice has its own hysteresis).
  ConvexHull const box_h = box_hull(box.half_extents), slab_h = box_hull(slab.half_extents);
  std::set<std::uint64_t> const flat_hull_ids =
      ids_of(contact_manifold(box_h, at({0.2f, 0.49f, 0}), slab_h, slab_pose));
  CHECK(flat_hull_ids.size() == 4);
  for (float wobble : {1e-3f, -1e-3f}) { // EPA's normal is the slab's; the faces' alignments
    Quat const q = Quat::from_rotation_x(wobble); // with it differ by 5e-7 (in float, 1e-4 by 0)
    auto const w = contact_manifold(box_h, at({0.2f, 0.49f, 0}, q), slab_h, slab_pose);
    check_manifold(w);
    std::set<std::uint64_t> const ids = ids_of(w);
    CHECK(ids == flat_hull_ids);
    CHECK((w.normal - q * Vec3{0, -1, 0}).length() < 1e-6f);
  }
  // NaN pose: failed, no points.
  float const nan = std::numeric_limits<float>::quiet_NaN();
  auto const bad = contact_manifold(box, at({nan, 0, 0}), ground, ground_pose);
  CHECK(bad.failed);
  CHECK(bad.count == 0);
  // A NaN shape parameter, against a half-space too (found by the contact_manifold fuzz
  // target: a NaN sphere radius on a plane gave a point with a NaN separation).
  HalfSpace const plane{{0, 1, 0}};
  for (Manifold const& m : {contact_manifold(Sphere{nan}, at({0, 0.5f, 0}), plane, Iso3{}),
                            contact_manifold(plane, Iso3{}, Sphere{nan}, at({0, 0.5f, 0})),
                            contact_manifold(Cuboid{{1, nan, 1}}, at({0, 0.5f, 0}), plane, Iso3{}),
                            contact_manifold(Capsule{nan, 0.5f}, Iso3{}, box, at({0, 0.5f, 0})),
                            contact_manifold(box, Iso3{}, Cuboid{{nan, 1, 1}}, at({0, 0.5f, 0})),
                            contact_manifold(HalfSpace{{nan, 1, 0}}, Iso3{}, box, Iso3{})}) {
    CHECK(m.failed);
    CHECK(m.count == 0);
  }
}

TEST_CASE("manifold: spheres and capsules", "[collision][manifold]") {
  Cuboid const ground{{5, 1, 5}};
  Iso3 const ground_pose = at({0, -1, 0});
  // A sphere: one point.
  auto const sp = contact_manifold(Sphere{0.5f}, at({1, 0.45f, 0}), ground, ground_pose);
  check_manifold(sp);
  REQUIRE(sp.count == 1);
  CHECK(sp.points[0].separation == Approx(-0.05f).margin(1e-5));
  CHECK(sp.points[0].point_a.y == Approx(-0.05f).margin(1e-5));
  // A capsule lying down (axis along x): two points at the segment ends.
  Quat const lie = Quat::from_rotation_z(float(std::numbers::pi / 2));
  auto const lying =
      contact_manifold(Capsule{1, 0.25f}, at({0, 0.24f, 0}, lie), ground, ground_pose);
  check_manifold(lying);
  REQUIRE(lying.count == 2);
  for (auto const& c : lying) {
    CHECK(c.separation == Approx(-0.01f).margin(1e-5));
    CHECK(std::abs(c.point_a.x) == Approx(1).margin(1e-5));
  }
  // ... hanging over the ground's edge: clipped at the edge (x = 5).
  auto const over =
      contact_manifold(Capsule{1, 0.25f}, at({5.5f, 0.24f, 0}, lie), ground, ground_pose);
  check_manifold(over);
  REQUIRE(over.count == 2);
  float maxx = -1e9f;
  for (auto const& c : over)
    maxx = std::max(maxx, c.point_a.x);
  CHECK(maxx == Approx(5).margin(1e-5));
  // Standing: one point.
  auto const standing = contact_manifold(Capsule{1, 0.25f}, at({0, 1.24f, 0}), ground, ground_pose);
  check_manifold(standing);
  CHECK(standing.count == 1);
  // Ground first: the same contact with the normal flipped.
  auto const flipped =
      contact_manifold(ground, ground_pose, Capsule{1, 0.25f}, at({0, 0.24f, 0}, lie));
  check_manifold(flipped);
  CHECK(flipped.count == 2);
  CHECK(flipped.normal.y == Approx(1).margin(1e-5));
  // Parallel capsules side by side: two points; crossing: one.
  auto const side =
      contact_manifold(Capsule{1, 0.3f}, at({0, 0, 0}), Capsule{0.5f, 0.3f}, at({0.55f, 0.7f, 0}));
  check_manifold(side);
  REQUIRE(side.count == 2);
  CHECK(side.normal.x == Approx(1).margin(1e-5));
  for (auto const& c : side)
    CHECK(c.separation == Approx(-0.05f).margin(1e-5));
  for (auto const& c : side) { // within both segments' extents: B's upper end is clipped to A's
    CHECK(std::abs(c.point_a.y) <= 1 + 1e-6f);
    CHECK(c.point_b.y >= 0.2f - 1e-6f);
    CHECK(c.point_b.y <= 1 + 1e-6f);
  }
  auto const crossing =
      contact_manifold(Capsule{1, 0.3f}, at({0, 0, 0}), Capsule{1, 0.3f}, at({0, 0, 0.55f}, lie));
  check_manifold(crossing);
  CHECK(crossing.count == 1);
  // A long capsule across a small box: clipped at both of the face's sides, two points with
  // distinct ids at x = +-0.5.
  auto const across = contact_manifold(Capsule{2, 0.25f}, at({0, 0.74f, 0}, lie),
                                       Cuboid{{0.5f, 0.5f, 0.5f}}, Iso3{});
  check_manifold(across);
  REQUIRE(across.count == 2);
  CHECK(std::abs(across.points[0].point_a.x) == Approx(0.5f).margin(1e-5));
  CHECK(across.points[0].point_a.x * across.points[1].point_a.x < 0);
  // Tilted by more than the face alignment (1.1 degrees; 3 here): one point, the lower end,
  // even though the upper end is within the prediction distance too.
  float const tilt = 3 * float(std::numbers::pi) / 180;
  Quat const tilted = Quat::from_rotation_z(float(std::numbers::pi / 2) - tilt);
  float const low_end = 0.2f * std::sin(tilt); // the core's lower end below its centre
  auto const leaning = contact_manifold(Capsule{0.2f, 0.25f}, at({0, 0.24f + low_end, 0}, tilted),
                                        ground, ground_pose);
  check_manifold(leaning);
  CHECK(leaning.count == 1);
  CHECK(leaning.min_separation() == Approx(-0.01f).margin(1e-5));
}

TEST_CASE("manifold: half-spaces, triangles and the 4-point reduction", "[collision][manifold]") {
  HalfSpace const floor{{0, 1, 0}};
  Cuboid const box{{0.5f, 0.5f, 0.5f}};
  auto const hb = contact_manifold(box, at({0, 0.48f, 0}), floor, Iso3{});
  check_manifold(hb);
  REQUIRE(hb.count == 4);
  CHECK(hb.normal.y == Approx(-1));
  for (auto const& c : hb)
    CHECK(c.separation == Approx(-0.02f).margin(1e-5));
  auto const hf = contact_manifold(floor, Iso3{}, box, at({0, 0.48f, 0}));
  CHECK(hf.count == 4);
  CHECK(hf.normal.y == Approx(1));
  auto const hs = contact_manifold(Sphere{1}, at({0, 0.9f, 0}), floor, Iso3{});
  check_manifold(hs);
  CHECK(hs.count == 1);
  CHECK(hs.points[0].separation == Approx(-0.1f).margin(1e-5));
  CHECK(hs.points[0].point_b.y == Approx(0).margin(1e-6));     // on the plane
  CHECK(hs.points[0].point_a.y == Approx(-0.1f).margin(1e-6)); // the sphere's lowest point
  auto const hsf = contact_manifold(floor, Iso3{}, Sphere{1}, at({0, 0.9f, 0})); // plane first
  check_manifold(hsf);
  CHECK(hsf.points[0].point_a.y == Approx(0).margin(1e-6));
  CHECK(hsf.points[0].point_b.y == Approx(-0.1f).margin(1e-6));
  Quat const lie = Quat::from_rotation_z(float(std::numbers::pi / 2));
  CHECK(contact_manifold(Capsule{1, 0.25f}, at({0, 0.2f, 0}, lie), floor, Iso3{}).count == 2);
  // A tilted floor (pose rotates the plane) and a cylinder (generic: one point).
  Iso3 const slope = at({0, 0, 0}, Quat::from_rotation_z(0.3f));
  auto const cyl = contact_manifold(Cylinder{0.5f, 0.5f}, at({0, 0.4f, 0}), floor, Iso3{});
  CHECK(cyl.count == 1);
  auto const sl = contact_manifold(box, at({0, 0.3f, 0}), floor, slope);
  check_manifold(sl);
  CHECK(sl.normal.dot(slope.transform_vector({0, -1, 0})) == Approx(1));
  // A 32-gon disc hull, slightly tilted, on the floor: reduced to 4 points, the deepest kept,
  // spread over the disc (large area).
  ConvexHull const puck = disc_hull(32);
  Iso3 const puck_pose = at({0, 0.04f, 0}, Quat::from_rotation_x(0.01f));
  auto const pm = contact_manifold(puck, puck_pose, floor, Iso3{});
  check_manifold(pm);
  REQUIRE(pm.count == 4);
  float const deepest = lowest_y(puck, puck_pose);
  CHECK(pm.min_separation() == Approx(deepest).margin(1e-5));
  // A 100-gon disc: 100 vertices within reach of the floor, more than the 64 candidates kept
  // (the deepest 64 are): the deepest vertex is still among the manifold's points.
  ConvexHull const wheel = disc_hull(100);
  for (int k = 0; k < 8; ++k) { // turned, then tilted: the deepest vertex goes round
    Iso3 const wheel_pose =
        at({0, 0.045f, 0}, Quat::from_rotation_x(0.003f) * Quat::from_rotation_y(0.8f * float(k)));
    float const deepest100 = lowest_y(wheel, wheel_pose);
    auto const wm = contact_manifold(wheel, wheel_pose, floor, Iso3{});
    INFO("tilt direction " << k);
    check_manifold(wm);
    REQUIRE(wm.count == 4);
    CHECK(wm.min_separation() == Approx(deepest100).margin(1e-6));
  }
  // The 4 points span most of the disc: their quadrilateral's area > 1.5 (the disc's is pi).
  // (The hull area of 4 points in convex position is the largest of the three diagonal
  // pairings' |d1 x d2| / 2.)
  auto const& p = pm.points;
  auto const diag = [&](int a, int b, int c, int d) {
    return 0.5f * std::abs((p[std::size_t(c)].point_a - p[std::size_t(a)].point_a)
                               .cross(p[std::size_t(d)].point_a - p[std::size_t(b)].point_a)
                               .y);
  };
  float const area = std::max({diag(0, 1, 2, 3), diag(0, 2, 1, 3), diag(0, 1, 3, 2)});
  // Deepest at +z (the tilt), farthest from it at -z, the largest triangle adds +-x, and the
  // point most outside that triangle is the other of +-x: the inscribed square, area 2.
  CHECK(area == Approx(2).margin(1e-4));
  // ... and the same puck on a box: the reference-face clipping path reduces too.
  auto const pb = contact_manifold(puck, puck_pose, Cuboid{{5, 1, 5}}, at({0, -1, 0}));
  check_manifold(pb);
  CHECK(pb.count == 4);
  CHECK(pb.min_separation() == Approx(deepest).margin(1e-5));
  // A box on a large triangle (two-sided: from below too).
  Triangle const tri{{-5, 0, -5}, {0, 0, 5}, {5, 0, -5}};
  auto const bt = contact_manifold(box, at({0, 0.49f, 0}), tri, Iso3{});
  check_manifold(bt);
  CHECK(bt.count == 4);
  CHECK(bt.normal.y == Approx(-1).margin(1e-5));
  auto const below = contact_manifold(box, at({0, -0.49f, 0}), tri, Iso3{});
  check_manifold(below);
  CHECK(below.count == 4);
  CHECK(below.normal.y == Approx(1).margin(1e-5));
  // A sphere on a triangle's edge region: one point.
  CHECK(contact_manifold(Sphere{0.5f}, at({0, 0.45f, 0}), tri, Iso3{}).count == 1);
}

TEST_CASE("manifold: the boxes' separating-axis path agrees with GJK/EPA on the same boxes "
          "as hulls",
          "[collision][manifold]") {
  // Random box pairs near contact: resting (small tilts) and arbitrary orientations. The box
  // pair takes the SAT path, the same boxes as hulls the GJK/EPA path; both are exact, so
  // they must agree on whether they touch, on the deepest separation and (for face contacts)
  // on the normal.
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), ext(0.2f, 0.8f);
  int compared = 0, faces = 0;
  for (int k = 0; k < 400; ++k) {
    Vec3 const ea{ext(rng), ext(rng), ext(rng)}, eb{ext(rng), ext(rng), ext(rng)};
    bool const resting = k % 2 == 0;
    float const tilt = resting ? 0.01f : 3.14159f;
    Quat const qa =
        Quat::from_axis_angle(Vec3{u(rng), u(rng), u(rng)}.normalize_or(Vec3::X), tilt * u(rng));
    Quat const qb =
        Quat::from_axis_angle(Vec3{u(rng), u(rng), u(rng)}.normalize_or(Vec3::X), tilt * u(rng));
    Iso3 const pa{qa, Vec3{}};
    // B placed along a random direction at about touching distance (+- 3 cm).
    Vec3 const dir = resting ? Vec3::Y : Vec3{u(rng), u(rng), u(rng)}.normalize_or(Vec3::Y);
    Iso3 pb{qb, dir * 3.0f};
    for (int i = 0; i < 40; ++i) { // bisect to the surface distance ~0, then offset
      float const dist = closest_points(Cuboid{ea}, pa, Cuboid{eb}, pb).distance;
      pb.translation = pb.translation - dir * (dist > 0 ? dist * 0.5f : -0.01f);
    }
    pb.translation = pb.translation + dir * (0.03f * u(rng));
    Manifold const sat = contact_manifold(Cuboid{ea}, pa, Cuboid{eb}, pb);
    Manifold const gjk = contact_manifold(box_hull(ea), pa, box_hull(eb), pb);
    check_manifold(sat);
    INFO("pair " << k << ": counts " << sat.count << " / " << gjk.count << ", min separation "
                 << sat.min_separation() << " / " << gjk.min_separation());
    CHECK((sat.count > 0) == (gjk.count > 0));
    if (sat.count == 0 || gjk.count == 0) continue;
    ++compared;
    CHECK(std::abs(sat.min_separation() - gjk.min_separation()) < 2e-3f);
    if (sat.count >= 3 && gjk.count >= 3) {
      ++faces;
      CHECK(std::abs(sat.normal.dot(gjk.normal)) > 0.9998f);
    }
  }
  CHECK(compared > 200);
  CHECK(faces > 100);
}

TEST_CASE("configs: scaled() multiplies the length-valued fields only", "[collision][config]") {
  GjkConfig gjk;
  gjk.tolerance = 2e-5f;
  gjk.relative_tolerance = 3e-6f;
  gjk.max_iterations = 17;
  GjkConfig const g = gjk.scaled(100);
  CHECK(g.tolerance == 2e-5f * 100);
  CHECK(g.relative_tolerance == 3e-6f); // a ratio
  CHECK(g.max_iterations == 17);

  EpaConfig epa;
  epa.tolerance = 4e-5f;
  epa.max_iterations = 9;
  epa.gjk = gjk;
  EpaConfig const e = epa.scaled(100);
  CHECK(e.tolerance == 4e-5f * 100);
  CHECK(e.max_iterations == 9);
  CHECK(e.gjk.tolerance == g.tolerance);
  CHECK(e.gjk.relative_tolerance == g.relative_tolerance);

  ManifoldConfig manifold;
  manifold.prediction = 0.03f;
  manifold.face_alignment = 0.999f;
  manifold.epa = epa;
  ManifoldConfig const m = manifold.scaled(100);
  CHECK(m.prediction == 0.03f * 100);
  CHECK(m.face_alignment == 0.999f); // a cosine
  CHECK(m.epa.tolerance == e.tolerance);
  CHECK(m.epa.gjk.tolerance == g.tolerance);
  // The original is unchanged (a const member function returning a copy).
  CHECK(manifold.prediction == 0.03f);
}

TEST_CASE("manifold: degenerate boxes and flat differences give points on both shapes",
          "[collision][manifold][fuzz]") {
  Iso3 const pose{Quat{-0.5f, -0.5f, -0.5f, -0.5f}, {-4, -4, -4}};
  // A capsule's core through a box of zero extents (a point): the clip against the box's face,
  // which has no area, kept the whole segment, and the points lay 1 m from the box (a fuzz
  // finding, contact_manifold regress-degenerate-face-clip). Now: one point, on the box.
  Manifold const m = contact_manifold(Capsule{0x1.02cd02p+0f, 0}, pose, Cuboid{Vec3{0, 0, 0}}, pose,
                                      ManifoldConfig{});
  REQUIRE(m.count >= 1);
  for (auto const& c : m) {
    CHECK((c.point_b - pose.translation).length() <= 1e-5f);
    CHECK(((c.point_b - c.point_a) - m.normal * c.separation).length() <= 1e-5f);
  }
  // A sphere whose centre lies on a box flattened to a segment: EPA's flat fallback put the
  // box's point at a vertex of the segment, 0.67 from the sphere's (a fuzz finding,
  // contact_manifold regress-flat-fallback-points). Now where GJK found the cores meeting.
  Manifold const f = contact_manifold(Sphere{0x1.80018p+0f}, pose,
                                      Cuboid{Vec3{0, 0, 0x1.555556p-1f}}, pose, ManifoldConfig{});
  REQUIRE(f.count == 1);
  CHECK(f.begin()->separation == Approx(-0x1.80018p+0f).margin(1e-5));
  CHECK(((f.begin()->point_b - f.begin()->point_a) - f.normal * f.begin()->separation).length() <=
        1e-5f);
  CHECK((f.begin()->point_b - pose.translation).length() <= 1e-5f);
}

TEST_CASE("manifold: a face far from the shape's origin still clips", "[collision][manifold]") {
  // A 2 m triangle 1,000 m from its shape's origin (a mesh triangle in mesh coordinates): the
  // area test of a reference face once measured against its distance from the origin, took
  // it for a face without area and left a box resting on it one point.
  Triangle const tri{{1000, 0, 1000}, {1000, 0, 1002}, {1002, 0, 1000}};
  Manifold const m =
      contact_manifold(tri, Iso3{}, Cuboid{Vec3{0.25f, 0.25f, 0.25f}},
                       Iso3::from_translation({1000.5f, 0.24f, 1000.5f}), ManifoldConfig{});
  CHECK(m.count == 4);
  CHECK(m.normal.distance(Vec3{0, 1, 0}) <= 1e-5f);
}

namespace {

/// The closed-form sphere pairs against the penetration query (GJK, EPA) on the same shapes:
/// n random poses of b around a sphere (centres within 2.5 of each other, so apart, touching
/// and deep), both orders, float and double.
template <ScalarReal S, class B, class MakeB>
void sphere_pair_agrees(MakeB make_b, std::uint32_t seed, int n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), r(0.1, 1);
  auto const quat = [&] {
    return GQuat<S>::from_axis_angle(
        GVec3<S>{S(u(rng)), S(u(rng)), S(u(rng))}.normalize_or(GVec3<S>{1, 0, 0}),
        S(3.14159 * u(rng)));
  };
  ManifoldConfig cfg;
  cfg.prediction = 10; // every pair gets its point
  int deep = 0, apart = 0;
  for (int k = 0; k < n; ++k) {
    GSphere<S> const a{S(r(rng))};
    B const b = make_b(rng);
    GIso3<S> const pa{quat(), {S(u(rng)), S(u(rng)), S(u(rng))}};
    GIso3<S> const pb{quat(), pa.translation + GVec3<S>{S(u(rng)), S(u(rng)), S(u(rng))} * S(1.4)};
    GManifold<S> const m = contact_manifold(a, pa, b, pb, cfg);
    GManifold<S> const w = contact_manifold(b, pb, a, pa, cfg);
    GPenetrationResult<S> const p = penetration(a, pa, b, pb);
    INFO("pair " << k << ": depth " << double(p.depth) << ", status " << int(p.status));
    REQUIRE(p.status != PenetrationStatus::failed);
    REQUIRE(m.count == 1);
    REQUIRE(w.count == 1);
    auto const& c = m.points[0];
    CHECK(std::abs(c.separation + p.depth) <= S(2e-5));
    CHECK(std::abs(m.normal.length() - S(1)) <= S(1e-5));
    CHECK(((c.point_b - c.point_a) - m.normal * c.separation).length() <= S(2e-5));
    // The other order: the same contact seen from b.
    CHECK(w.normal.distance(-m.normal) <= S(1e-6));
    CHECK(w.points[0].point_a.distance(c.point_b) <= S(1e-6));
    CHECK(w.points[0].point_b.distance(c.point_a) <= S(1e-6));
    CHECK(w.points[0].separation == c.separation);
    // The points lie on the surfaces (A's at its radius from its centre, B's at depth 0 in B,
    // by the penetration query of a point), and they are joined by the separation along the
    // normal, which is GJK/EPA's distance: apart, they are therefore the nearest points, and
    // those are unique for a sphere. (GJK's own points are not the oracle: its distance
    // tolerance, 1e-5, lets them slide 5e-4 along the surfaces of shapes 1 m apart.)
    CHECK(std::abs(c.point_a.distance(pa.translation) - a.radius) <= S(2e-5));
    GPenetrationResult<S> const on_b =
        penetration(GSphere<S>{S(0)}, GIso3<S>{{}, c.point_b}, b, pb);
    CHECK(std::abs(on_b.depth) <= S(2e-5));
    if (p.depth < S(-1e-3)) {
      ++apart;
      CHECK(m.normal.dot(p.normal) >= S(1) - S(1e-5));
    } else if (p.depth > S(1e-3)) {
      ++deep; // the least deep direction: the depth only (near ties, EPA's may be the other)
    }
  }
  CHECK(apart > n / 10);
  CHECK(deep > n / 10);
}

} // namespace

TEST_CASE("manifold: spheres against spheres, capsules and cuboids in closed form agree with "
          "GJK/EPA",
          "[collision][manifold]") {
  auto const run = [](auto s) {
    using S = decltype(s);
    auto const size = [](std::mt19937& rng) {
      return S(std::uniform_real_distribution<double>(0.05, 1)(rng));
    };
    sphere_pair_agrees<S, GSphere<S>>([&](std::mt19937& rng) { return GSphere<S>{size(rng)}; }, 11,
                                      500);
    sphere_pair_agrees<S, GCapsule<S>>(
        [&](std::mt19937& rng) {
          return GCapsule<S>{size(rng), S(0.5) * size(rng)};
        },
        12, 500);
    sphere_pair_agrees<S, GCuboid<S>>(
        [&](std::mt19937& rng) {
          return GCuboid<S>{{size(rng), size(rng), size(rng)}};
        },
        13, 2000);
  };
  run(float{});
  run(double{});
}

TEST_CASE("manifold: closed-form sphere pairs at coincident centres and inside boxes",
          "[collision][manifold]") {
  ManifoldConfig const cfg;
  // Coincident centres: +Y, depth the sum of the radii, points on both surfaces.
  Manifold const ss = contact_manifold(Sphere{0.5f}, at({1, 2, 3}), Sphere{0.25f}, at({1, 2, 3}));
  REQUIRE(ss.count == 1);
  CHECK(ss.normal.distance(Vec3::Y) == 0);
  CHECK(ss.points[0].separation == -0.75f);
  CHECK(ss.points[0].point_a.distance(Vec3{1, 2.5f, 3}) == 0);
  check_manifold(ss);
  // A sphere centred on a capsule's core: a normal across the core, never along it.
  Quat const q = Quat::from_rotation_z(0.7f);
  Manifold const sc =
      contact_manifold(Capsule{1, 0.2f}, at({0, 0, 0}, q), Sphere{0.3f}, at(q * Vec3{0, 0.6f, 0}));
  REQUIRE(sc.count == 1);
  CHECK(std::abs(sc.normal.dot(q * Vec3::Y)) <= 1e-6f);
  CHECK(sc.points[0].separation == Approx(-0.5f).margin(1e-6));
  check_manifold(sc);
  // ... 1,000 m away, where the core point's rounding (6e-5) is larger than the offset.
  Vec3 const far{1000, -1000, 1000};
  for (float along : {-0.9f, -0.3f, 0.2f, 0.7f}) {
    Manifold const fc = contact_manifold(Sphere{0.3f}, at(far + q * Vec3{0, along, 0}),
                                         Capsule{1, 0.2f}, at(far, q));
    REQUIRE(fc.count == 1);
    CHECK(std::abs(fc.normal.dot(q * Vec3::Y)) <= 1e-6f);
    CHECK(fc.points[0].separation == Approx(-0.5f).margin(1e-4));
  }
  // Inside a box: the face the centre is least deep behind, here -z of a rotated box (0.1
  // behind it); the box's point on that face.
  Cuboid const box{{1, 0.6f, 0.4f}};
  Iso3 const bp = at({5, 0, 0}, q);
  Manifold const sb =
      contact_manifold(box, bp, Sphere{0.2f}, at(bp.transform_point({0.5f, 0.3f, -0.3f})));
  REQUIRE(sb.count == 1);
  CHECK(sb.normal.distance(q * Vec3{0, 0, -1}) <= 1e-6f);
  CHECK(sb.points[0].separation == Approx(-0.3f).margin(1e-6));
  CHECK(sb.points[0].point_a.distance(bp.transform_point({0.5f, 0.3f, -0.4f})) <= 1e-6f);
  check_manifold(sb);
  // Ties go to the first face in the order +x, -x, +y, -y, +z, -z: the centre of a cube.
  Manifold const tie = contact_manifold(Sphere{0.1f}, Iso3{}, Cuboid{{1, 1, 1}}, Iso3{});
  REQUIRE(tie.count == 1);
  CHECK(tie.normal.distance(Vec3::NEG_X) == 0); // from the sphere (A) toward the box: -(+x)
  // Squares that overflow are `failed`, as in GJK; a shape beyond the prediction, no point.
  CHECK(contact_manifold(Sphere{1}, at({0, 0, 0}), Sphere{1}, at({3e19f, 0, 0})).failed);
  CHECK(contact_manifold(Sphere{1}, at({0, 3e19f, 0}), box, Iso3{}).failed);
  CHECK(contact_manifold(Capsule{1, 0.2f}, Iso3{}, Sphere{1}, at({3e19f, 0, 0})).failed);
  CHECK(contact_manifold(Sphere{1}, at({0, -3e19f, 0}), Capsule{1, 0.2f}, Iso3{}).failed);
  CHECK(contact_manifold(Sphere{1}, at({0, 0, 0}), Sphere{1}, at({2 + 2 * cfg.prediction, 0, 0}))
            .count == 0);
}

TEST_CASE("manifold: capsules parallel within the tolerance join their points along the normal",
          "[collision][manifold]") {
  // B tilted about the normal's axis by up to 0.015 rad (inside face_alignment's 0.02): its
  // ends sit across the normal from A's line, 1 m x 0.015 = 1.5 cm at most. Each point
  // takes its radius' share of that offset and leaves its surface by no more than 1e-3 of
  // its radius (a zero radius: it stays on the core).
  Vec3 const x{1, 0, 0};
  for (float tilt : {0.005f, 0.01f, 0.015f, -0.015f}) {
    Quat const q = Quat::from_axis_angle(x, tilt);
    for (auto [ra, rb] : {std::pair{0.0f, 1.0f}, {0.3f, 1.0f}, {1.0f, 1.0f}, {1.0f, 0.2f}}) {
      // B beside A along x, overlapping by 0.1.
      Iso3 const pb = at({ra + rb - 0.1f, 0.1f, 0}, q);
      Manifold const m = contact_manifold(Capsule{1, ra}, at({0, 0, 0}), Capsule{1, rb}, pb);
      INFO("tilt " << tilt << ", ra " << ra << ", rb " << rb);
      check_manifold(m);
      REQUIRE(m.count == 2);
      for (auto const& c : m) {
        CHECK(((c.point_b - c.point_a) - m.normal * c.separation).length() <= 1e-5f);
        // The distance to its core (the capsule's y axis).
        float const da = std::sqrt(c.point_a.x * c.point_a.x + c.point_a.z * c.point_a.z);
        Vec3 const local_b = pb.inverse_transform_point(c.point_b);
        float const db = std::sqrt(local_b.x * local_b.x + local_b.z * local_b.z);
        CHECK(std::abs(da - ra) <= 1e-3f * ra + 2e-6f);
        CHECK(std::abs(db - rb) <= 1e-3f * rb + 2e-6f);
      }
    }
  }
  // Longer or thinner capsules at the same tilt would leave their surfaces by more: one
  // point. Capsules of half height 2 and radius 0.2: ends 1 cm across at 0.005 rad keep two
  // points, 3 cm across at 0.015 rad (0.9e-3 squared, above 2e-3 x 0.4^2) one.
  for (auto [tilt, count] : {std::pair{0.005f, 2}, {0.015f, 1}}) {
    Manifold const m = contact_manifold(Capsule{2, 0.2f}, at({0, 0, 0}), Capsule{2, 0.2f},
                                        at({0.35f, 0, 0}, Quat::from_axis_angle(x, tilt)));
    INFO("tilt " << tilt);
    check_manifold(m);
    CHECK(m.count == count);
  }
  Manifold const thin = contact_manifold(Capsule{1, 0.01f}, at({0, 0, 0}), Capsule{1, 0.01f},
                                         at({0.015f, 0, 0}, Quat::from_axis_angle(x, 0.015f)));
  check_manifold(thin);
  CHECK(thin.count == 1);
  // Exactly parallel segments (radius 0) still get two points.
  Manifold const segments =
      contact_manifold(Capsule{1, 0.0f}, at({0, 0, 0}), Capsule{1, 0.0f}, at({0.01f, 0.5f, 0}));
  check_manifold(segments);
  CHECK(segments.count == 2);
}

TEST_CASE("manifold: a clipped face never keeps two points with one feature id",
          "[collision][manifold]") {
  // Boxes and hulls turned about the contact normal cut the incident face at the reference
  // face's corners: a point made where the clipped polygon runs along a reference side names
  // that side, not the incident edge the polygon left.
  std::mt19937 rng(91);
  std::uniform_real_distribution<float> angle(-3.2f, 3.2f), small(-0.01f, 0.01f), size(0.2f, 1.5f),
      off(-0.8f, 0.8f);
  ConvexHull const disc = disc_hull(7);
  int clipped = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Cuboid const a{Vec3{size(rng), 0.5f, size(rng)}};
    Quat const q = Quat::from_axis_angle(Vec3{0, 1, 0}, angle(rng)) *
                   Quat::from_axis_angle(Vec3{1, 0, 0}, small(rng));
    Iso3 const pb = at({off(rng), 1.0f, off(rng)}, q);
    Manifold const boxes =
        contact_manifold(a, at({0, 0, 0}), Cuboid{Vec3{size(rng), 0.51f, size(rng)}}, pb);
    Manifold const hull =
        contact_manifold(a, at({0, 0, 0}), disc, at({off(rng), 0.54f, off(rng)}, q));
    for (Manifold const* m : {&boxes, &hull}) {
      INFO("trial " << trial);
      REQUIRE(m->count <= 4);
      CHECK(ids_of(*m).size() == std::size_t(m->count));
      clipped += m->count >= 3;
    }
  }
  CHECK(clipped > 1000); // the trials reach the clipping path
}

TEST_CASE("manifold: the 4-point reduction keeps what it picked when distances are NaN",
          "[collision][manifold]") {
  // Candidates whose positions overflowed to NaN: no point is farther from the deepest than
  // -1 or has a larger area, so the picks find nothing; the reduction must not read past
  // them (index -1 before: the sanitizer build reports it) and keeps the deepest.
  detail::candidates<float> c;
  float const nan = std::numeric_limits<float>::quiet_NaN();
  for (int i = 0; i < 6; ++i) {
    Vec3 const p = i == 2 ? Vec3{0, 0, 0} : Vec3{nan, nan, nan};
    c.add({p, p, i == 2 ? -0.5f : -0.1f, std::uint64_t(i)});
  }
  Manifold m;
  detail::reduce_into(c, Vec3::Y, m);
  REQUIRE(m.count >= 1);
  REQUIRE(m.count <= 2);
  CHECK(m.points[0].id == 2u); // the deepest
  // One finite far point: the first two picks exist, the area pick finds nothing.
  c.pts[4].point_a = c.pts[4].point_b = Vec3{1, 0, 0};
  detail::reduce_into(c, Vec3::Y, m);
  CHECK(m.count == 2);
}

TEST_CASE("manifold: a clip that misses the pair's depth gives the deepest point instead",
          "[collision][manifold][fuzz]") {
  // Fuzz finding contact_manifold regress-clip-misses-depth: a thin triangle stands edge-on
  // (about 60 degrees) into a hull's face. That face is aligned with EPA's normal and became
  // the reference; the triangle's part inside its sides reached 0.087 deep, while the pair's
  // depth is 0.372. The manifold now keeps the pair's deepest point there.
  Triangle const tri{{-0x1.4ffb5p+0f, -0x1.4f4f5p+0f, -0x1.4bff4cp+0f},
                     {-0x1.4f4f5p+0f, -0x1.fc03fcp+0f, -0x1.4f235p+0f},
                     {0x1.2de32cp+0f, 0x1.2f2f3p+0f, 0x1.2f2f3p+0f}};
  std::vector<Vec3> const pts{{0x1.c6c6c8p-1f, 0x1.a2c6ap-1f, 0x1.c366cp-1f},
                              {-0x1.3ced4p-3f, -0x1.6f907p-1f, -0x1.8p-16f},
                              {-0x1.8p+0f, -0x1.f6f6f6p-1f, -0x1.a2f6a2p-1f},
                              {-0x1.09cf08p-2f, 0x1.7d86fcp+0f, 0x1.8p+0f},
                              {-0x1.f77af8p-1f, -0x1.8p+0f, -0x1.8p+0f},
                              {-0x1.8p+0f, -0x1.f7fef8p-1f, -0x1.09cf08p-2f},
                              {-0x1.13ff94p+0f, -0x1.7abb78p-2f, -0x1.8p+0f},
                              {-0x1.f6f6f6p-1f, -0x1.f6f6f6p-1f, -0x1.7d02fep+0f},
                              {-0x1.8p+0f, -0x1.8p+0f, -0x1.8p+0f}};
  auto const hull = ConvexHull::build(pts);
  REQUIRE(hull);
  Iso3 const pose{Quat{-0.5f, -0.5f, -0.5f, -0.5f}, Vec3{-4, -4, -4}};
  PenetrationResult const p = penetration(tri, pose, hull.hull, pose);
  REQUIRE(p.status != PenetrationStatus::failed);
  CHECK(p.depth == Approx(0.3723).margin(1e-3));
  // The depth itself, without EPA: B moved by it (plus or minus 1 cm) along the normal
  // just separates the shapes (GJK's distance, not the manifold under test).
  auto const moved = [&](float d) { return Iso3{pose.rotation, pose.translation + p.normal * d}; };
  CHECK(closest_points(tri, pose, hull.hull, moved(p.depth + 0.01f)).distance > 0.005f);
  CHECK(closest_points(tri, pose, hull.hull, moved(p.depth - 0.01f)).distance <= 0.0f);
  Manifold const m = contact_manifold(tri, pose, hull.hull, pose);
  REQUIRE(m.count > 0);
  CHECK(m.min_separation() <= -p.depth + 1e-4f);
  for (auto const& c : m)
    CHECK(((c.point_b - c.point_a) - m.normal * c.separation).length() < 1e-4f);
}
