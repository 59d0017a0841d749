// Convex shapes against a TriangleMesh (spatial/mesh_queries.hpp): contacts, shape casts and
// overlaps against brute force over the same triangles as separate shapes; internal edges
// (no ghost normals over a flat grid, edge normals kept on ridges, one manifold per slope in
// a valley, the rules mirrored behind the triangles); bad input.
#include "mesh_support.hpp"

#include <plume/collision/epa.hpp>
#include <plume/collision/gjk.hpp>
#include <plume/collision/manifold.hpp>
#include <plume/collision/shapes.hpp>
#include <plume/spatial/mesh_queries.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <variant>
#include <vector>

using namespace plume;
using namespace plume::test;

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();
constexpr float qnan = std::numeric_limits<float>::quiet_NaN();

using AnyShape = std::variant<Sphere, Capsule, Cuboid>;

AnyShape random_shape(std::mt19937& g) {
  std::uniform_real_distribution<float> u(0.1f, 0.8f);
  switch (g() % 3) {
  case 0:
    return Sphere{u(g)};
  case 1:
    return Capsule{u(g), 0.5f * u(g)};
  default:
    return Cuboid{Vec3{u(g), u(g), u(g)}};
  }
}

Iso3 random_pose(std::mt19937& g, float lo, float hi, float y_lo, float y_hi) {
  std::uniform_real_distribution<float> u(-1, 1), x(lo, hi), y(y_lo, y_hi);
  Quat const q = Quat{u(g), u(g), u(g), u(g) + 0.1f}.normalize();
  return {q, Vec3{x(g), y(g), x(g)}};
}

/// The angle between two unit vectors, radians.
float angle(Vec3 const& a, Vec3 const& b) { return std::atan2(a.cross(b).length(), a.dot(b)); }

/// The least-toi hit of casting against every triangle of m as a separate shape (ties to the
/// lower triangle): the brute force mesh_shape_cast must equal.
template <class Shape>
MeshShapeHit brute_cast(TriangleMesh const& m, Iso3 const& mp, Shape const& shape, Iso3 const& pose,
                        Vec3 const& motion, ShapeCastConfig const& cfg) {
  MeshShapeHit want;
  for (std::uint32_t t = 0; t < m.triangle_count(); ++t) {
    ShapeCastHit const c = shape_cast(shape, pose, motion, m.triangle(t), mp, cfg);
    if (c.hit && !c.failed && c.toi < want.toi) {
      want.triangle = t;
      want.toi = c.toi;
      want.normal = -c.normal;
    }
  }
  return want;
}

/// A mesh placed off the origin and turned, so that every query also tests the frames.
Iso3 const mesh_pose{Quat::from_axis_angle(Vec3{0.3f, 1.0f, -0.2f}.normalize(), 0.4f),
                     Vec3{1.5f, -0.25f, 2.0f}};

} // namespace

TEST_CASE("mesh_contacts: the deepest point and the triangles touched equal brute force",
          "[spatial][mesh]") {
  TriangleMesh const m = make(grid(16, 0.5f, terrain_height));
  std::mt19937 g(11);
  MeshContactConfig cfg;
  cfg.correct_internal_edges = false;
  cfg.merge_cosine = 2.0f; // never merge: one group per triangle
  int touching_cases = 0;
  for (int k = 0; k < 300; ++k) {
    AnyShape const shape = random_shape(g);
    // In the mesh's frame over the terrain (heights within +-0.9), then placed by mesh_pose.
    Iso3 const local = random_pose(g, 0.5f, 7.5f, -1.0f, 1.0f);
    Iso3 const pose = mesh_pose * local;
    std::visit(
        [&](auto const& s) {
          MeshContacts const got = mesh_contacts(m, mesh_pose, s, pose, cfg);
          REQUIRE_FALSE(got.failed);
          float want = inf;
          std::uint32_t want_tri = no_triangle;
          int touched = 0;
          for (std::uint32_t t = 0; t < m.triangle_count(); ++t) {
            Manifold const b = contact_manifold(m.triangle(t), mesh_pose, s, pose, cfg.manifold);
            if (b.empty()) continue;
            ++touched;
            if (b.min_separation() < want) {
              want = b.min_separation();
              want_tri = t;
            }
          }
          REQUIRE(got.count == std::min(touched, max_mesh_manifolds));
          if (touched == 0) return;
          ++touching_cases;
          REQUIRE(same_bits(got.manifolds[0].manifold.min_separation(), want));
          REQUIRE(got.manifolds[0].triangle == want_tri);
          for (MeshManifold const& mm : got) {
            REQUIRE(mm.manifold.count >= 1);
            REQUIRE(mm.manifold.normal.length() == Approx(1.0f).margin(1e-5));
            for (ContactPoint const& c : mm.manifold)
              REQUIRE(c.separation <= cfg.manifold.prediction);
          }
        },
        shape);
  }
  REQUIRE(touching_cases > 50);
}

TEST_CASE("mesh_contacts: no ghost normals over the internal edges of a flat grid and a "
          "flat height field",
          "[spatial][mesh]") {
  TriangleMesh const mesh = make(grid(8, 1.0f, [](float, float) { return 0.0f; }));
  std::vector<float> const zeros(81, 0.0f);
  auto built = HeightField::build(9, 9, zeros, 1.0f, 1.0f);
  REQUIRE(built.ok());
  HeightField const field = std::move(built.field);
  Vec3 const up = mesh_pose.transform_vector(Vec3::Y);
  std::mt19937 g(12);
  std::uniform_real_distribution<float> u(0, 1);
  auto const run = [&](auto const& m, bool correct) {
    MeshContactConfig cfg;
    cfg.correct_internal_edges = correct;
    float worst = 0.0f;
    int cases = 0;
    for (int k = 0; k < 400; ++k) {
      // Resting 1-4 mm deep, anywhere over the inner cells (edges and vertices included:
      // one position in four snapped onto a grid line), turned about the vertical.
      float x = 1.0f + 6.0f * u(g), z = 1.0f + 6.0f * u(g);
      if (k % 4 == 0) x = std::round(x);
      if (k % 8 == 0) z = std::round(z);
      float const depth = 0.001f + 0.003f * u(g);
      Quat const yaw = Quat::from_axis_angle(Vec3::Y, 6.2832f * u(g));
      auto const check = [&](auto const& shape, float bottom, Quat const& turn) {
        Iso3 const local{yaw * turn, Vec3{x, bottom - depth, z}};
        MeshContacts const c = mesh_contacts(m, mesh_pose, shape, mesh_pose * local, cfg);
        REQUIRE(c.count >= 1);
        if (correct) REQUIRE(c.count == 1); // one plane: one manifold
        for (MeshManifold const& mm : c)
          worst = std::max(worst, angle(mm.manifold.normal, up));
        ++cases;
      };
      check(Cuboid{Vec3{0.5f, 0.5f, 0.3f}}, 0.5f, Quat::IDENTITY);
      // A capsule lying on its side: its axis (local y) turned onto x.
      check(Capsule{0.6f, 0.3f}, 0.3f, Quat::from_axis_angle(Vec3::Z, 1.5707964f));
      check(Sphere{0.4f}, 0.4f, Quat::IDENTITY);
    }
    REQUIRE(cases == 1200);
    return worst;
  };
  CHECK(run(mesh, true) <= 1e-3f);
  CHECK(run(field, true) <= 1e-3f);
  // The test sees ghost normals when they are there: without the correction, shapes over
  // the internal edges get normals far from the surface's.
  CHECK(run(mesh, false) > 0.1f);
  CHECK(run(field, false) > 0.1f);
}

namespace {

/// Two triangles meeting along the z axis edge x = 0, y = 0, each rising (ridge: falling)
/// at `slope` radians away from it; front faces up.
TriangleMesh roof(float slope) {
  float const c = std::cos(slope) * 4.0f, s = std::sin(slope) * 4.0f;
  // Vertices 0, 1 on the shared edge; 2 on the -x side, 3 on the +x side.
  std::vector<Vec3> const v{{0, 0, -4}, {0, 0, 4}, {-c, s, 0}, {c, s, 0}};
  // Each triangle wound so (b - a) x (c - a) has +y: the shared edge runs opposite ways.
  std::vector<std::uint32_t> const idx{0, 2, 1, 0, 1, 3};
  auto r = TriangleMesh::build(v, idx);
  REQUIRE(r.ok());
  return std::move(r.mesh);
}

} // namespace

TEST_CASE("mesh_contacts: a convex ridge keeps its edge normal, a valley gives one manifold "
          "per slope, and behind the triangles the rules swap",
          "[spatial][mesh]") {
  float const slope = 0.5f; // about 29 degrees
  SECTION("a sphere on a ridge") {
    TriangleMesh const m = roof(-slope); // falling away from the edge: convex
    REQUIRE(m.edges(0).kind[std::size_t(
                std::find(m.edges(0).neighbour.begin(), m.edges(0).neighbour.end(), 1u) -
                m.edges(0).neighbour.begin())] == EdgeKind::convex);
    Iso3 const pose = mesh_pose * Iso3::from_translation({0.0f, 0.3f - 0.002f, 0.0f});
    MeshContacts const c = mesh_contacts(m, mesh_pose, Sphere{0.3f}, pose);
    REQUIRE(c.count == 1);
    // The edge's normal, straight up: neither face's (each 0.5 rad off it).
    CHECK(angle(c.manifolds[0].manifold.normal, mesh_pose.transform_vector(Vec3::Y)) < 1e-3f);
  }
  SECTION("a sphere in a valley") {
    TriangleMesh const m = roof(slope); // rising away from the edge: concave
    // Touching both slopes: centre on the bisector, at r / cos(slope) above the edge.
    float const r = 0.3f;
    Iso3 const pose =
        mesh_pose * Iso3::from_translation({0.0f, r / std::cos(slope) - 0.002f, 0.0f});
    MeshContacts const c = mesh_contacts(m, mesh_pose, Sphere{r}, pose);
    REQUIRE(c.count == 2);
    for (MeshManifold const& mm : c) {
      Vec3 const face = mesh_pose.transform_vector(m.face_normal(mm.triangle));
      CHECK(angle(mm.manifold.normal, face) < 1e-3f);
    }
    CHECK(angle(c.manifolds[0].manifold.normal, c.manifolds[1].manifold.normal) > 0.9f);
  }
  SECTION("below a valley (a ridge seen from behind) the edge normal is kept") {
    TriangleMesh const m = roof(slope);
    Iso3 const pose = mesh_pose * Iso3::from_translation({0.0f, -0.3f + 0.002f, 0.0f});
    MeshContacts const c = mesh_contacts(m, mesh_pose, Sphere{0.3f}, pose);
    REQUIRE(c.count == 1);
    CHECK(angle(c.manifolds[0].manifold.normal, mesh_pose.transform_vector(-Vec3::Y)) < 1e-3f);
  }
  SECTION("below a ridge (a valley seen from behind): one manifold per face, facing down") {
    TriangleMesh const m = roof(-slope);
    float const r = 0.3f;
    Iso3 const pose =
        mesh_pose * Iso3::from_translation({0.0f, -r / std::cos(slope) + 0.002f, 0.0f});
    MeshContacts const c = mesh_contacts(m, mesh_pose, Sphere{r}, pose);
    REQUIRE(c.count == 2);
    for (MeshManifold const& mm : c) {
      Vec3 const face = mesh_pose.transform_vector(m.face_normal(mm.triangle));
      CHECK(angle(mm.manifold.normal, -face) < 1e-3f);
    }
  }
  SECTION("a box edge-on over a boundary edge keeps the edge's normal") {
    TriangleMesh const m = make(grid(1, 2.0f, [](float, float) { return 0.0f; }));
    // A box turned 45 degrees about z, left of the mesh's x = 0 boundary edge, its lower
    // right face through that edge and 2 mm into the mesh: the contact is with the boundary
    // edge, its normal along the box's face (up and to -x), not the mesh's face.
    Quat const q = Quat::from_axis_angle(Vec3::Z, 0.7853982f);
    float const cx = -0.3f, cy = cx + 0.5f * std::sqrt(2.0f) - 0.002f;
    Iso3 const pose = mesh_pose * Iso3{q, Vec3{cx, cy, 1.0f}};
    MeshContacts const c = mesh_contacts(m, mesh_pose, Cuboid{Vec3::splat(0.5f)}, pose);
    REQUIRE(c.count == 1);
    Vec3 const n = mesh_pose.inverse_transform_vector(c.manifolds[0].manifold.normal);
    CHECK(n.x < -0.1f); // not the face normal: the boundary edge is active
  }
}

TEST_CASE("mesh_contacts: a shape straddling a lone triangle's plane, clipped by its edge",
          "[spatial][mesh]") {
  // A box whose centre lies in a lone triangle's plane (x = y), its corner clipped 0.0107
  // deep by a boundary edge; EPA's normal (0.74, 0, -0.68) leans across the plane (the
  // move_and_slide fuzz target's deeper-after-depenetration). The mesh turned it to the face
  // normal and measured the witness points' gap along it, +0.0056: a gap where the shapes
  // overlap, and each depenetration slid the box further over the edge.
  std::vector<Vec3> const v{{-3, -3, -2.7647059f},
                            {-2.7647059f, -2.7647059f, 1.14941645f},
                            {1.16470623f, 1.16470623f, 1.77409029f}};
  auto built = TriangleMesh::build(v, std::vector<std::uint32_t>{0, 1, 2});
  REQUIRE(built.ok());
  Iso3 const at = Iso3::from_translation({-3, -3, -3});
  Cuboid const box{{0.431764722f, 0.652848065f, 0.05f}};
  Vec3 const face = built.mesh.face_normal(0);
  Triangle const tri = built.mesh.triangle(0);
  auto const contact = [&](float off) {
    Iso3 const pose = Iso3::from_translation(Vec3{-3, -3, -3} + face * off);
    MeshContacts const c = mesh_contacts(built.mesh, at, box, pose);
    REQUIRE(c.count == 1);
    return std::pair{c.manifolds[0].manifold, penetration(box, pose, tri, at)};
  };
  // Centre in the plane: on neither side, so the edge's own normal and depth. (With the
  // centre in front, the normal still leans back and is kept at this boundary edge: the next
  // test.)
  for (float off : {0.0f, 1e-6f, -1e-6f}) { // within the rounding of the centre's height
    INFO("off " << off);
    auto const [m, p] = contact(off);
    REQUIRE(p.depth == Approx(0.0107f).margin(1e-4f));
    CHECK(m.normal.dot(face) == Approx(-0.521f).margin(1e-3f));
    CHECK(m.min_separation() == Approx(-p.depth).margin(1e-5f));
  }
  // A box centred in a floor's plane, away from its boundary: EPA's normal against a floor
  // triangle points down for most turns (48 of these 63 poses), and the box must still go up
  // (its side is decided by the edge rule only at an edge it straddles).
  std::vector<Vec3> const floor_v{{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}};
  auto floor = TriangleMesh::build(floor_v, std::vector<std::uint32_t>{0, 2, 1, 0, 3, 2});
  REQUIRE(floor.ok());
  REQUIRE(floor.mesh.face_normal(0).y == 1.0f);
  Cuboid const brick{{0.5f, 0.3f, 0.4f}};
  int down = 0, manifolds = 0;
  for (float deg : {0.0f, 3.0f, 10.0f, 20.0f, 30.0f, 40.0f, 44.0f})
    for (Vec3 const axis : {Vec3{1, 0, 0}, Vec3{0, 0, 1}, Vec3{1, 0, 1}.normalize()})
      for (float x : {0.0f, 0.37f, -1.3f}) {
        Iso3 const pose{Quat::from_axis_angle(axis, deg * std::numbers::pi_v<float> / 180),
                        {x, 0, 0.21f}};
        MeshContacts const c = mesh_contacts(floor.mesh, Iso3::IDENTITY, brick, pose);
        for (int i = 0; i < c.count; ++i, ++manifolds)
          down += c.manifolds[std::size_t(i)].manifold.normal.y <= 0.0f;
      }
  // 21 of the poses get no floor contact at all: EPA's normal turned to the face's and its
  // gap measured along it is beyond the prediction while the box overlaps (the open
  // "turned normal's gap" case of docs/fuzzing.md). A fix there should raise this to 63.
  CHECK(manifolds >= 42);
  CHECK(down == 0);
}

TEST_CASE("mesh_contacts: a shape in front of a triangle, hanging over its boundary edge, keeps "
          "EPA's normal",
          "[spatial][mesh]") {
  // The move_and_slide fuzz target's deeper-after-depenetration-3: the box above, its centre
  // 0.071 in front of the triangle's plane, overlapping the boundary edge c-a 0.0738 deep.
  // EPA's normal (0.73, 0, -0.69) leans to the back (cosine -0.50 with the face normal). The
  // mesh turned it to the face normal and measured the gap along it: +0.037 where the shapes
  // overlap, and each depenetration pushed the box along the face, further over the edge.
  // A normal toward the far side is kept at a boundary edge.
  std::vector<Vec3> const v{{-3, -3, -2.7647059f},
                            {-2.7647059f, -2.7647059f, 1.14941645f},
                            {1.30533314f, 1.16470623f, 1.77409029f},
                            {1.77647066f, 1.77647066f, 1.77647066f}};
  auto built = TriangleMesh::build(v, std::vector<std::uint32_t>{0, 1, 2, 2, 1, 3});
  REQUIRE(built.ok());
  REQUIRE(built.mesh.edges(0).kind[2] == EdgeKind::boundary); // c-a
  Iso3 const at = Iso3::from_translation({-3, -3, -3});
  Cuboid const box{{0.431764722f, 0.652848065f, 0.05f}};
  Vec3 const face = built.mesh.face_normal(0);
  Triangle const tri = built.mesh.triangle(0);
  for (float off : {0.0f, -0.069f, -0.05f, -0.02f, 0.01f}) { // centre 0.002 to 0.081 in front
    INFO("off " << off);
    Iso3 const pose = Iso3::from_translation(Vec3{-3, -3, -3} + face * off);
    PenetrationResult const p = penetration(box, pose, tri, at);
    REQUIRE(p.depth > 0.03f);
    MeshContacts const c = mesh_contacts(built.mesh, at, box, pose);
    REQUIRE(c.count == 1);
    Manifold const& m = c.manifolds[0].manifold;
    CHECK(m.normal.dot(face) < -0.4f);
    CHECK(m.min_separation() == Approx(-p.depth).margin(1e-5f));
  }

  // The floor continued past c-a by a coplanar triangle: wound consistently the edge is flat,
  // wound the other way it is non-manifold; either way the surface goes on, and no normal
  // leaning to the back may push the box into it (the review's case: with non-manifold edges
  // counted as open, a manifold 0.0738 deep along (0.73, 0, -0.69)).
  Vec3 const dir = (v[2] - v[0]).normalize();
  Vec3 const foot = v[0] + dir * (v[1] - v[0]).dot(dir);
  std::vector<Vec3> w = v;
  w.push_back(foot * 2.0f - v[1]); // v[1] mirrored across the line of c-a
  for (bool flipped : {false, true}) {
    INFO("flipped " << flipped);
    std::vector<std::uint32_t> idx{0, 1, 2, 2, 1, 3};
    if (flipped)
      idx.insert(idx.end(), {2, 0, 4});
    else
      idx.insert(idx.end(), {0, 2, 4});
    auto floor = TriangleMesh::build(w, idx);
    REQUIRE(floor.ok());
    REQUIRE(floor.mesh.edges(0).kind[2] == (flipped ? EdgeKind::non_manifold : EdgeKind::flat));
    MeshContacts const c =
        mesh_contacts(floor.mesh, at, box, Iso3::from_translation(Vec3{-3, -3, -3}));
    for (int k = 0; k < c.count; ++k)
      CHECK(c.manifolds[std::size_t(k)].manifold.normal.dot(face) > -0.4f);
  }
}

TEST_CASE("mesh_contacts: a group keeps its deepest points however many triangles it spans",
          "[spatial][mesh]") {
  // A 3 m box tilted 0.5 degrees over a grid of 0.2 m cells: about 450 triangles under it,
  // over 1,000 candidate points in one group; the deepest corner lies over the last cells.
  TriangleMesh const m = make(grid(20, 0.2f, [](float, float) { return 0.0f; }));
  Quat const tilt = Quat::from_axis_angle(Vec3{1.0f, 0.0f, -1.0f}.normalize(), 0.0087f);
  Iso3 const local{tilt, {2.0f, 0.5f - 0.005f, 2.0f}};
  Cuboid const box{Vec3{1.5f, 0.5f, 1.5f}};
  MeshContacts const c = mesh_contacts(m, Iso3{}, box, local);
  REQUIRE(c.count == 1);
  float want = inf;
  for (std::uint32_t t = 0; t < m.triangle_count(); ++t)
    want = std::min(want, contact_manifold(m.triangle(t), Iso3{}, box, local).min_separation());
  CHECK(want < -0.02f); // the deep corner is well below the rest
  CHECK(c.manifolds[0].manifold.min_separation() == want);
  CHECK(c.manifolds[0].manifold.count == 4);
}

TEST_CASE("mesh_contacts: a large box resting on many small triangles keeps points across its "
          "footprint",
          "[spatial][mesh]") {
  // 3 m box flat on a grid of 0.2 m cells: about 450 triangles and 1,350 candidate points in
  // one group. Found in review: keeping only the first 64 candidates left all four points on
  // the cells of one edge of the box.
  TriangleMesh const m = make(grid(20, 0.2f, [](float, float) { return 0.0f; }));
  Cuboid const box{Vec3{1.5f, 0.5f, 1.5f}};
  for (float const yaw : {0.0f, 0.3f}) {
    Iso3 const local{Quat::from_axis_angle(Vec3::Y, yaw), {2.0f, 0.5f - 0.005f, 2.0f}};
    MeshContacts const c = mesh_contacts(m, mesh_pose, box, mesh_pose * local);
    REQUIRE(c.count == 1);
    Manifold const& mf = c.manifolds[0].manifold;
    REQUIRE(mf.count == 4);
    // The quadrilateral of the four points (in the floor's plane) covers most of the 9 m^2
    // footprint.
    std::array<Vec3, 4> p;
    for (std::size_t k = 0; k < 4; ++k)
      p[k] = mesh_pose.inverse_transform_point(mf.points[k].point_a);
    float best = 0.0f; // the largest of the quadrilateral's areas over the orders of its points
    for (auto const& o : {std::array<int, 4>{0, 1, 2, 3}, std::array<int, 4>{0, 2, 1, 3},
                          std::array<int, 4>{0, 1, 3, 2}}) {
      Vec3 const d1 = p[std::size_t(o[2])] - p[std::size_t(o[0])];
      Vec3 const d2 = p[std::size_t(o[3])] - p[std::size_t(o[1])];
      best = std::max(best, 0.5f * std::abs(d1.z * d2.x - d1.x * d2.z));
    }
    CHECK(best > 0.8f * 9.0f);
  }
}

TEST_CASE("mesh_shape_cast equals the least cast over every triangle", "[spatial][mesh]") {
  TriangleMesh const m = make(grid(16, 0.5f, terrain_height));
  std::mt19937 g(13);
  std::uniform_real_distribution<float> u(-1, 1);
  int hits = 0;
  for (int k = 0; k < 300; ++k) {
    AnyShape const shape = random_shape(g);
    Iso3 const pose = mesh_pose * random_pose(g, 0.5f, 7.5f, 1.5f, 3.0f);
    Vec3 const motion = mesh_pose.transform_vector(Vec3{u(g), -1.0f - 2.0f * (u(g) + 1.0f), u(g)});
    ShapeCastConfig cfg;
    cfg.max_toi = 1.0f;
    cfg.target_distance = k % 3 == 0 ? 0.01f : 0.0f;
    std::visit(
        [&](auto const& s) {
          MeshShapeHit const got = mesh_shape_cast(m, mesh_pose, s, pose, motion, cfg);
          MeshShapeHit const want = brute_cast(m, mesh_pose, s, pose, motion, cfg);
          REQUIRE(got.triangle == want.triangle);
          if (!want.hit()) return;
          ++hits;
          REQUIRE(same_bits(got.toi, want.toi));
          REQUIRE(same_bits(got.normal, want.normal));
          REQUIRE(got.normal.dot(motion) <= 0.0f); // out of the mesh, against the motion
        },
        shape);
  }
  REQUIRE(hits > 100);
}

TEST_CASE("mesh_shape_cast with a target distance near float's range still finds triangles",
          "[spatial][mesh][fuzz]") {
  // A target distance of 3.26e38 grew the shape's box to +-inf, whose centre and rotated
  // extents were NaN: no candidate, no hit, where every triangle is within reach at the start
  // (a fuzz finding, triangle_mesh regress-huge-target-distance).
  std::vector<Vec3> const v{{0, -1, 0}, {0, -1, 1}, {1, -0.5f, 0}};
  std::vector<std::uint32_t> const i{0, 1, 2};
  auto const built = TriangleMesh::build(v, i);
  REQUIRE(built.ok());
  Iso3 const mesh_at{Quat::from_rotation_z(0.4f), {-0.166f, -1.977f, -2}};
  Iso3 const at = Iso3::from_translation({2.44f, -11.68f, -1.0f});
  ShapeCastConfig cfg;
  cfg.target_distance = 3.26e38f;
  for (Vec3 const motion : {Vec3{}, Vec3{1, 2, 0}}) {
    MeshShapeHit const got = mesh_shape_cast(built.mesh, mesh_at, Sphere{0}, at, motion, cfg);
    MeshShapeHit const want = brute_cast(built.mesh, mesh_at, Sphere{0}, at, motion, cfg);
    REQUIRE(want.hit());
    CHECK(got.hit());
    CHECK(got.triangle == want.triangle);
    CHECK(got.toi == 0.0f);
    CHECK(got.penetrating);
  }
}

TEST_CASE("mesh_shape_cast finds triangles when shape and mesh are both near float's range",
          "[spatial][mesh][fuzz]") {
  // A cylinder and a mesh both at y = 1.7e38: the world box was clamped to +-2^125 before it
  // was taken into the mesh's frame, which moved it 1.3e38 from the mesh, so the candidate
  // search found nothing where the cast against the triangle starts penetrating (a fuzz
  // finding, triangle_mesh regress-shape-cast-far-pose).
  std::vector<Vec3> const v{{0, 0, 0}, {0, -1, 1}, {1, -1, 0}};
  std::vector<std::uint32_t> const i{0, 1, 2};
  auto const built = TriangleMesh::build(v, i);
  REQUIRE(built.ok());
  Quat const q{-0.5f, -0.5f, -0.5f, -0.5f};
  Iso3 const mesh_at{q, {-0x1.0101p-7f, 0x1.fefefep+127f, -0x1.0101p-7f}};
  Iso3 const at{q, {-0x1.8182p-5f, 0x1.fefefep+127f, -0x1.8182p-5f}};
  Cylinder const cyl{0x1.fdfdfep-1f, 0x1.fdfdfep-2f};
  ShapeCastConfig cfg;
  cfg.max_toi = 0x1.fdfdfep-1f;
  cfg.stop_at_penetration = true;
  for (Vec3 const motion : {Vec3{}, Vec3::splat(-0x1.8182p-4f)}) {
    MeshShapeHit const want = brute_cast(built.mesh, mesh_at, cyl, at, motion, cfg);
    REQUIRE(want.hit());
    MeshShapeHit const got = mesh_shape_cast(built.mesh, mesh_at, cyl, at, motion, cfg);
    CHECK(got.triangle == want.triangle);
    CHECK(got.toi == want.toi);
    ShapeCastHit const c = shape_cast(cyl, at, motion, built.mesh.triangle(0), mesh_at, cfg);
    CHECK(got.penetrating == bool(c.penetrating));
  }
  // The contacts' candidate search takes the same path.
  CHECK(mesh_intersects(built.mesh, mesh_at, cyl, at));
}

TEST_CASE("mesh_shape_cast agrees with brute force next to a triangle 3e11 long",
          "[spatial][mesh][fuzz]") {
  // With a vertex at 3e11, GJK's rounding floor near that triangle is 16 eps * 3e11 = 6e5: a
  // sphere a few metres away is "in contact" at the start. The candidate boxes grew only by the
  // floor of the poses, so the mesh skipped the triangle brute force hits (a fuzz finding,
  // triangle_mesh regress-shape-cast-big-triangle); they now grow by the mesh's extent too.
  std::vector<Vec3> const v{{-2, 3, 0.5f},
                            {-0.5f, -2.5f, 1},
                            {0x1.7500f8p+2f, 0x1.1e3c04p+38f, -0x1.3fcb8p+3f},
                            {0, 3, -1},
                            {0x1.86bd08p+2f, -0x1.5a93dap+2f, -0x1.2000ap+2f}};
  std::vector<std::uint32_t> const i{0, 1, 2, 2, 3, 4};
  auto const built = TriangleMesh::build(v, i);
  REQUIRE(built.ok());
  Iso3 const mesh_at = Iso3::from_translation({-2, -2, -2});
  Iso3 const at = Iso3::from_translation({-0x1.9c5a9cp+2f, -0x1.1882p-5f, 0x1.60606p+2f});
  ShapeCastConfig cfg;
  cfg.stop_at_penetration = false;
  // The finding's ball and motion, and larger ones around it (which of them GJK's rounding
  // calls a hit there depends on its arithmetic): every one as brute force, some hitting.
  int hits = 0;
  for (float grow : {1.0f, 2.0f, 4.0f, 16.0f})
    for (float reach : {1.0f, 4.0f, 64.0f, 1024.0f}) {
      INFO("radius x" << grow << ", motion x" << reach);
      Sphere const ball{0x1.d579d6p-2f * grow};
      Vec3 const motion = Vec3{-24, -24, -24} * reach;
      MeshShapeHit const want = brute_cast(built.mesh, mesh_at, ball, at, motion, cfg);
      MeshShapeHit const got = mesh_shape_cast(built.mesh, mesh_at, ball, at, motion, cfg);
      hits += want.hit();
      CHECK(got.hit() == want.hit());
      CHECK(got.triangle == want.triangle);
      CHECK(got.toi == want.toi);
    }
  CHECK(hits > 0);
}

TEST_CASE("mesh_shape_cast onto a flat grid, where many triangles tie, equals brute force",
          "[spatial][mesh]") {
  // Shapes falling onto a flat floor meet several coplanar triangles at once (over a vertex,
  // six): the casts' rounding and tolerance decide the least toi, so the candidates must not
  // be pruned at the first toi found.
  TriangleMesh const m = make(grid(8, 1.0f, [](float, float) { return 0.0f; }));
  std::mt19937 g(15);
  std::uniform_real_distribution<float> u(0, 1);
  int differ = 0;
  for (int k = 0; k < 400; ++k) {
    float const x = std::round(1.0f + 6.0f * u(g)) + (k % 2 ? 0.0f : 0.5f * u(g));
    float const z = std::round(1.0f + 6.0f * u(g));
    Iso3 const pose =
        mesh_pose * Iso3{Quat::from_axis_angle(Vec3::Y, 6.28f * u(g)), Vec3{x, 1.0f + u(g), z}};
    // Straight down, or glancing (1 to 5 degrees below the horizontal, across the seams),
    // and every fifth with max_toi just past the contact.
    float const glance = 0.017f + 0.07f * u(g);
    Vec3 const local_motion =
        k % 2 ? Vec3{0.01f * (u(g) - 0.5f), -3.0f, 0.0f}
              : Vec3{3.0f * std::cos(0.7f * u(g)), -3.0f * glance, 3.0f * std::sin(0.7f * u(g))};
    Vec3 const motion = mesh_pose.transform_vector(local_motion);
    ShapeCastConfig cfg;
    cfg.target_distance = k % 3 == 0 ? 0.02f : 0.0f;
    if (k % 2 == 0) cfg.max_toi = 2.0f; // glancing: the fall takes longer than one motion
    auto const check = [&](auto const& shape) {
      MeshShapeHit const got = mesh_shape_cast(m, mesh_pose, shape, pose, motion, cfg);
      MeshShapeHit const want = brute_cast(m, mesh_pose, shape, pose, motion, cfg);
      if (k % 5 == 0 && want.hit()) { // again, with max_toi just past the contact
        ShapeCastConfig tight = cfg;
        tight.max_toi = want.toi * 1.0001f;
        MeshShapeHit const near = mesh_shape_cast(m, mesh_pose, shape, pose, motion, tight);
        REQUIRE(near.triangle == want.triangle);
      }
      REQUIRE(got.triangle == want.triangle);
      REQUIRE(same_bits(got.toi, want.toi));
      differ += got.toi != want.toi;
    };
    check(Sphere{0.3f});
    check(Cuboid{Vec3{0.4f, 0.3f, 0.2f}});
    check(Capsule{0.3f, 0.2f});
  }
  CHECK(differ == 0);
}

TEST_CASE("mesh_overlaps reports exactly the triangles the shape touches", "[spatial][mesh]") {
  TriangleMesh const m = make(grid(16, 0.5f, terrain_height));
  std::mt19937 g(14);
  int any = 0;
  for (int k = 0; k < 300; ++k) {
    AnyShape const shape = random_shape(g);
    Iso3 const pose = mesh_pose * random_pose(g, 0.5f, 7.5f, -1.0f, 1.0f);
    std::visit(
        [&](auto const& s) {
          std::vector<std::uint32_t> got, want;
          bool const touched =
              mesh_overlaps(m, mesh_pose, s, pose, [&](std::uint32_t t) { got.push_back(t); });
          for (std::uint32_t t = 0; t < m.triangle_count(); ++t) {
            ClosestPoints const c = closest_points(s, pose, m.triangle(t), mesh_pose);
            if (c.overlap || c.distance <= 0.0f) want.push_back(t);
          }
          REQUIRE(got == want);
          REQUIRE(touched == !want.empty());
          REQUIRE(mesh_intersects(m, mesh_pose, s, pose) == !want.empty());
          any += touched;
        },
        shape);
  }
  REQUIRE(any > 50);
}

TEST_CASE("mesh queries: bad input finds nothing", "[spatial][mesh]") {
  TriangleMesh const m = make(grid(4, 1.0f, [](float, float) { return 0.0f; }));
  Sphere const s{0.5f};
  Iso3 const on = Iso3::from_translation({2.0f, 0.4f, 2.0f});
  Iso3 bad = on;
  bad.translation.x = qnan;
  REQUIRE(mesh_contacts(m, Iso3{}, s, on).count == 1);
  REQUIRE(mesh_contacts(m, Iso3{}, s, bad).failed);
  REQUIRE(mesh_contacts(m, bad, s, on).failed);
  REQUIRE(mesh_contacts(m, bad, s, on).count == 0);
  REQUIRE(mesh_contacts(TriangleMesh{}, Iso3{}, s, on).count == 0);

  Vec3 const down{0.0f, -1.0f, 0.0f};
  Iso3 const above = Iso3::from_translation({2.0f, 2.0f, 2.0f});
  REQUIRE(mesh_shape_cast(m, Iso3{}, s, above, down, {.max_toi = 2.0f}).hit());
  REQUIRE(mesh_shape_cast(m, Iso3{}, s, above, down, {.max_toi = 2.0f}).toi ==
          Approx(1.5f).margin(1e-4));
  REQUIRE_FALSE(mesh_shape_cast(m, Iso3{}, s, above, down, {.max_toi = inf}).hit());
  REQUIRE_FALSE(mesh_shape_cast(m, Iso3{}, s, above, down, {.max_toi = qnan}).hit());
  REQUIRE_FALSE(mesh_shape_cast(m, Iso3{}, s, above, down, {.max_toi = -1.0f}).hit());
  REQUIRE_FALSE(mesh_shape_cast(m, Iso3{}, s, above, down, {.target_distance = inf}).hit());
  REQUIRE_FALSE(mesh_shape_cast(m, Iso3{}, s, above, down, {.target_distance = qnan}).hit());
  REQUIRE_FALSE(mesh_shape_cast(m, Iso3{}, s, above, Vec3{0.0f, qnan, 0.0f}, {}).hit());
  REQUIRE_FALSE(mesh_shape_cast(m, Iso3{}, s, bad, down, {}).hit());
  REQUIRE_FALSE(mesh_shape_cast(TriangleMesh{}, Iso3{}, s, above, down, {.max_toi = 2.0f}).hit());

  REQUIRE(mesh_intersects(m, Iso3{}, s, on));
  // Touching counts: a sphere resting exactly on the floor.
  REQUIRE(mesh_intersects(m, Iso3{}, s, Iso3::from_translation({2.0f, 0.5f, 2.0f})));
  REQUIRE_FALSE(mesh_intersects(m, Iso3{}, s, Iso3::from_translation({2.0f, 0.5001f, 2.0f})));
  REQUIRE_FALSE(mesh_intersects(m, Iso3{}, s, bad));
  REQUIRE_FALSE(mesh_intersects(m, bad, s, on));
  REQUIRE_FALSE(mesh_intersects(TriangleMesh{}, Iso3{}, s, on));
}
