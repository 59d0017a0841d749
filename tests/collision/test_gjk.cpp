// The GJK family: closest points against double-precision oracles (closed forms for spheres
// and capsules, feature-pair brute force for polytopes), shape casts against closed forms up
// to 1,000 m targets, GJK ray casts against the closed-form casts, bad input, warm starts and
// lane-exactness of every wide query.
#include "collision_support.hpp"

#include <plume/collision/convex_hull.hpp>
#include <plume/collision/detail/simplex.hpp>
#include <plume/collision/gjk.hpp>
#include <plume/collision/ray_cast.hpp>
#include <plume/collision/shapes.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace plume;
using namespace plume::test;

namespace {

/// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
D3 closest_on_triangle(D3 p, D3 a, D3 b, D3 c) {
  D3 const ab = b - a, ac = c - a, ap = p - a;
  double const d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  D3 const bp = p - b;
  double const d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  double const vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  D3 const cp = p - c;
  double const d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  double const vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  double const va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  double const den = 1 / (va + vb + vc);
  return a + ab * (vb * den) + ac * (vc * den);
}

/// Squared distance between segments p1q1 and p2q2 (Ericson 5.1.9).
double segment_distance2(D3 p1, D3 q1, D3 p2, D3 q2) {
  D3 const d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  double const a = d1.dot(d1), e = d2.dot(d2), f = d2.dot(r);
  double s, t;
  if (a <= 1e-300 && e <= 1e-300) return r.dot(r);
  if (a <= 1e-300) {
    s = 0, t = std::clamp(f / e, 0.0, 1.0);
  } else {
    double const c = d1.dot(r);
    if (e <= 1e-300) {
      t = 0, s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      double const b = d1.dot(d2), den = a * e - b * b;
      s = den != 0 ? std::clamp((b * f - c * e) / den, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0)
        t = 0, s = std::clamp(-c / a, 0.0, 1.0);
      else if (t > 1)
        t = 1, s = std::clamp((b - c) / a, 0.0, 1.0);
    }
  }
  D3 const k = (p1 + d1 * s) - (p2 + d2 * t);
  return k.dot(k);
}

/// Distance between two separated convex polytopes given as hulls at poses: the minimum over
/// vertex-face, face-vertex and edge-edge feature pairs, in double.
double polytope_distance(ConvexHull const& a, Iso3 const& pa, ConvexHull const& b, Iso3 const& pb) {
  auto const va = world_vertices(a, pa), vb = world_vertices(b, pb);
  double best = std::numeric_limits<double>::infinity();
  auto faces_vs_points = [&](ConvexHull const& h, std::vector<D3> const& hv,
                             std::vector<D3> const& pts) {
    for (std::size_t f = 0; f < h.faces().size(); ++f) {
      auto const fv = h.face_vertices(f);
      for (std::size_t i = 1; i + 1 < fv.size(); ++i)
        for (D3 const& p : pts) {
          D3 const q = closest_on_triangle(p, hv[fv[0]], hv[fv[i]], hv[fv[i + 1]]);
          best = std::min(best, (p - q).length());
        }
    }
  };
  faces_vs_points(a, va, vb);
  faces_vs_points(b, vb, va);
  for (HullEdge const& ea : a.edges())
    for (HullEdge const& eb : b.edges())
      best = std::min(best, std::sqrt(segment_distance2(va[ea.a], va[ea.b], vb[eb.a], vb[eb.b])));
  return best;
}

ConvexHull random_hull(rng& r, int n, float size) {
  std::vector<Vec3> pts;
  for (int k = 0; k < n; ++k)
    pts.push_back(r.vec3<float>(-1, 1) * size);
  return hull_of(pts);
}

Iso3 random_pose(rng& r, float spread) { return {r.quat<float>(), r.vec3<float>(-spread, spread)}; }

} // namespace

TEST_CASE("the simplex step finds the closest point of triangles and tetrahedra",
          "[collision][gjk]") {
  // closest_on_simplex against Ericson's closest point on a triangle (double), and the
  // inside flag against the tetrahedron's barycentric signs.
  rng r(61);
  double worst = 0;
  int tested = 0;
  for (int k = 0; k < 2000; ++k) {
    detail::simplex<float> s;
    Vec3 const p[4] = {r.vec3<float>(-2, 2), r.vec3<float>(-2, 2), r.vec3<float>(-2, 2),
                       r.vec3<float>(-2, 2)};
    bool const tet = k % 2 == 1;
    s.v[0] = {p[1], {}, {}}, s.v[1] = {p[2], {}, {}}, s.v[2] = {p[3], {}, {}};
    s.present = {true, true, tet};
    detail::simplex_vertex<float> const w{p[0], {}, {}};
    auto const step = detail::closest_on_simplex(s, w, Vec3{});
    // y_i = 0 - p_i: the closest point of conv{-p_i} to the origin.
    D3 const y0 = to_d(-p[0]), y1 = to_d(-p[1]), y2 = to_d(-p[2]), y3 = to_d(-p[3]);
    D3 want = closest_on_triangle(D3{}, y0, y1, y2);
    bool inside = false;
    if (tet) {
      for (auto const& f :
           {std::array{y0, y1, y3}, std::array{y0, y2, y3}, std::array{y1, y2, y3}}) {
        D3 const c = closest_on_triangle(D3{}, f[0], f[1], f[2]);
        if (c.length() < want.length()) want = c;
      }
      // Inside when the origin is on the same side of every face as the opposite vertex.
      auto const side = [](D3 a, D3 b, D3 c, D3 q) { return (b - a).cross(c - a).dot(q - a); };
      inside = side(y0, y1, y2, y3) * side(y0, y1, y2, D3{}) > 0 &&
               side(y0, y1, y3, y2) * side(y0, y1, y3, D3{}) > 0 &&
               side(y0, y2, y3, y1) * side(y0, y2, y3, D3{}) > 0 &&
               side(y1, y2, y3, y0) * side(y1, y2, y3, D3{}) > 0;
      if (inside) want = D3{};
    }
    // GJK's step only looks at sub-simplices holding the newest point w (the closest point
    // always involves it in GJK): skip cases whose closest point lies on the face opposite w.
    D3 const opposite =
        tet ? closest_on_triangle(D3{}, y1, y2, y3) : closest_on_triangle(D3{}, y1, y2, y2);
    if (!inside && (opposite - want).length() <= 1e-9) continue;
    ++tested;
    CHECK(step.inside == inside);
    // The distance is accurate to rounding; the point only to sqrt(eps) |v|: candidates are
    // ranked by |v|^2, which is flat (quadratic) around the minimum, so a vertex a hair from
    // the true edge point ties with it in float.
    double const err = std::abs(double(step.v.length()) - want.length());
    worst = std::max(worst, err);
    CHECK(err <= 2e-6 * (1 + want.length()));
    double const sqrt_eps = std::sqrt(double(std::numeric_limits<float>::epsilon()));
    CHECK((to_d(step.v) - want).length() <= 2 * sqrt_eps * (1 + want.length()));
    // The weights reproduce v and sum to 1.
    Vec3 const rebuilt = -(p[0] * step.lambda[0] + p[1] * step.lambda[1] + p[2] * step.lambda[2] +
                           p[3] * step.lambda[3]);
    if (!inside) CHECK((rebuilt - step.v).length() <= 1e-5f);
    CHECK(std::abs(step.lambda[0] + step.lambda[1] + step.lambda[2] + step.lambda[3] - 1) <= 1e-5f);
  }
  CHECK(tested > 1000);
  WARN("simplex step: " << tested << " simplices, worst distance error " << worst);
}

TEST_CASE("closest points: spheres and capsules against closed forms", "[collision][gjk]") {
  rng r(21);
  double worst = 0;
  for (int k = 0; k < 500; ++k) {
    float const ra = float(r.uniform(0, 1)), rb = float(r.uniform(0, 1));
    float const ha = float(r.uniform(0, 2)), hb = float(r.uniform(0, 2));
    Iso3 const pa = random_pose(r, 4), pb = random_pose(r, 4);
    // Sphere - sphere.
    auto const ss = closest_points(Sphere{ra}, pa, Sphere{rb}, pb);
    double const dss = (to_d(pa.translation) - to_d(pb.translation)).length() - ra - rb;
    REQUIRE(ss.converged);
    CHECK(std::abs(ss.distance - dss) <= 1e-5 * (1 + std::abs(dss)));
    // Capsule - capsule: the segment distance minus the radii (negative = overlap depth).
    auto const cc = closest_points(Capsule{ha, ra}, pa, Capsule{hb, rb}, pb);
    D3 const a0 = to_d(pa.transform_point({0, -ha, 0})), a1 = to_d(pa.transform_point({0, ha, 0}));
    D3 const b0 = to_d(pb.transform_point({0, -hb, 0})), b1 = to_d(pb.transform_point({0, hb, 0}));
    double const core = std::sqrt(segment_distance2(a0, a1, b0, b1));
    if (core < 1e-3) continue; // the cores (nearly) touch: covered by the overlap test
    REQUIRE(cc.converged);
    CHECK(!cc.overlap);
    double const err = std::abs(cc.distance - (core - ra - rb));
    worst = std::max(worst, err);
    CHECK(err <= 1e-4);
    // The points are on the surfaces and the normal joins them.
    CHECK(std::abs((cc.point_b - cc.point_a).dot(cc.normal) - cc.distance) <= 1e-4f);
    CHECK(std::abs(cc.normal.length() - 1) <= 1e-5f);
  }
  WARN("capsule-capsule worst |distance - closed form|: " << worst);
}

TEST_CASE("closest points between polytopes against feature-pair brute force", "[collision][gjk]") {
  // At 1 m and at 100 m: with coordinates near 100, float rounding keeps GJK's distance from
  // meeting the tolerances, and only the no-progress stop ends some of these queries.
  rng r(22);
  for (float scale : {1.0f, 100.0f}) {
    double worst = 0;
    int separated = 0;
    for (int k = 0; k < 300; ++k) {
      ConvexHull const a = random_hull(r, 12 + k % 20, scale),
                       b = random_hull(r, 8 + k % 25, 1.5f * scale);
      Iso3 const pa = random_pose(r, 3 * scale), pb = random_pose(r, 3 * scale);
      auto const cp = closest_points(a, pa, b, pb);
      INFO("scale " << scale << ", pair " << k);
      REQUIRE(cp.converged);
      CHECK(cp.iterations <= 20);
      if (cp.overlap) continue;
      ++separated;
      double const want = polytope_distance(a, pa, b, pb);
      double const err = std::abs(cp.distance - want);
      worst = std::max(worst, err);
      CHECK(err <= 2e-4 * (scale + want));
      // The reported points are on (the surface of) their shapes: within the hull's planes.
      for (auto const& f : a.faces())
        CHECK(f.normal.dot(pa.inverse_transform_point(cp.point_a)) - f.offset <= 1e-4f * scale);
      for (auto const& f : b.faces())
        CHECK(f.normal.dot(pb.inverse_transform_point(cp.point_b)) - f.offset <= 1e-4f * scale);
    }
    CHECK(separated > 100);
    WARN("polytope distance at scale " << scale << ": " << separated
                                       << " separated pairs, worst error " << worst);
  }
}

TEST_CASE("closest points: overlap, touching, warm starts, bad input", "[collision][gjk]") {
  ConvexHull const box = box_hull({1, 1, 1});
  // Overlapping boxes: overlap, distance 0, zero normal.
  auto const ov = closest_points(box, Iso3::from_translation({0.5f, 0.2f, 0}), box, Iso3{});
  CHECK(ov.overlap);
  CHECK(ov.converged);
  CHECK(ov.distance == 0);
  CHECK(ov.normal.length_squared() == 0);
  // Spheres whose radii overlap but centres are apart: exact negative distance.
  auto const ss =
      closest_points(Sphere{1}, Iso3::from_translation({1.5f, 0, 0}), Sphere{1}, Iso3{});
  CHECK(!ss.overlap);
  CHECK(ss.distance == Approx(-0.5f));
  CHECK(ss.normal.x == Approx(-1));
  // Concentric spheres: the cores coincide (overlap).
  CHECK(closest_points(Sphere{1}, Iso3{}, Sphere{2}, Iso3{}).overlap);
  // Boxes exactly touching face to face.
  auto const touch = closest_points(box, Iso3::from_translation({2, 0.3f, 0}), box, Iso3{});
  CHECK(std::abs(touch.distance) <= 1e-6f);
  // Warm start: the same pair moved slightly converges in fewer iterations.
  rng r(5);
  int cold = 0, warm = 0;
  for (int k = 0; k < 100; ++k) {
    ConvexHull const a = random_hull(r, 30, 1), b = random_hull(r, 30, 1);
    Iso3 const pa{r.quat<float>(), {3, 0.5f, 0}}, pb = random_pose(r, 0.5f);
    auto const first = closest_points(a, pa, b, pb);
    Iso3 const moved{pa.rotation, pa.translation + Vec3{0.01f, 0.01f, 0}};
    auto const again = closest_points(a, moved, b, pb);
    auto const warmed = closest_points(a, moved, b, pb, GjkConfig{}, first.axis);
    cold += int(again.iterations), warm += int(warmed.iterations);
    CHECK(warmed.distance == Approx(again.distance).margin(2e-4));
  }
  CHECK(warm < cold);
  WARN("iterations over 100 slightly moved pairs: cold " << cold << ", warm-started " << warm);
  // Non-finite input: failed, NaN distance, no hang.
  float const nan = std::numeric_limits<float>::quiet_NaN();
  float const inf = std::numeric_limits<float>::infinity();
  auto const bad = closest_points(box, Iso3::from_translation({nan, 0, 0}), box, Iso3{});
  CHECK(bad.failed);
  CHECK(!bad.converged);
  CHECK(std::isnan(bad.distance));
  CHECK(closest_points(Sphere{inf}, Iso3{}, box, Iso3{}).failed);
  CHECK(closest_points(Cuboid{{nan, 1, 1}}, Iso3{}, box, Iso3::from_translation({5, 0, 0})).failed);
  // A NaN vertex that support never picks (its dot products are NaN: never the largest) is
  // still failed input (found by the gjk_distance fuzz target).
  Triangle const nan_tri{{0, 0, 0}, {1, 0, 0}, {nan, 1, 0}};
  CHECK(closest_points(nan_tri, Iso3{}, box, Iso3::from_translation({5, 0, 0})).failed);
  Vec3 const pts[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, nan}};
  CHECK(closest_points(ConvexPolytope{pts}, Iso3{}, box, Iso3::from_translation({5, 0, 0})).failed);
  CHECK(closest_points(Segment{{0, 0, 0}, {nan, 0, 0}}, Iso3{}, box, Iso3{}).failed);
  // A capped iteration count reports out of iterations (not converged).
  GjkConfig one_step;
  one_step.max_iterations = 1;
  ConvexHull const round = random_hull(r, 200, 1);
  auto const capped =
      closest_points(round, Iso3::from_translation({4, 1, 0.5f}), round, Iso3{}, one_step);
  CHECK(!capped.converged);
  CHECK(!capped.failed);
}

TEST_CASE("shape casts against closed forms, targets up to 1,000 m", "[collision][gjk][cast]") {
  rng r(31);
  for (float size : {1.0f, 10.0f, 100.0f, 1000.0f}) {
    double worst_sphere = 0, worst_box = 0, worst_box_hull = 0;
    for (int k = 0; k < 200; ++k) {
      // A unit sphere cast at a sphere of radius `size` from 0.5..3 sizes away, aimed at a
      // random point of the target's front half.
      D3 const aim = to_d(r.unit3<float>()) * (0.9 * size);
      D3 const from_dir = to_d(r.unit3<float>());
      D3 const start = from_dir * (size * r.uniform(1.5, 4.0) + 2.0);
      D3 const motion_d = (aim - start) * 1.25;
      Vec3 const motion{float(motion_d.x), float(motion_d.y), float(motion_d.z)};
      Vec3 const s{float(start.x), float(start.y), float(start.z)};
      // Closed form: the ray s + t m against a sphere of radius size + 1 (double, float inputs).
      D3 const sd = to_d(s), md = to_d(motion);
      double const R = double(size) + 1.0;
      double const a = md.dot(md), b = sd.dot(md), c = sd.dot(sd) - R * R;
      double const disc = b * b - a * c;
      ShapeCastConfig cfg;
      cfg.max_toi = 10;
      auto const hit =
          shape_cast(Sphere{1}, Iso3::from_translation(s), motion, Sphere{size}, Iso3{}, cfg);
      if (disc < 0) {
        CHECK(!hit.hit);
        continue;
      }
      double const t = (-b - std::sqrt(disc)) / a;
      REQUIRE(hit.hit);
      CHECK(hit.converged);
      worst_sphere = std::max(worst_sphere, std::abs(hit.toi - t) / t);
    }
    for (int k = 0; k < 200; ++k) {
      // A unit cube (axis-aligned, as a cuboid and as a hull) cast at a cube of half extent
      // `size`, hitting the +x face inside its face: toi = gap / |m_x|.
      double const gap = size * r.uniform(0.5, 3.0);
      D3 const start{size + 1 + gap, r.uniform(-0.5, 0.5) * size, r.uniform(-0.5, 0.5) * size};
      D3 const target{size, r.uniform(-0.4, 0.4) * size, r.uniform(-0.4, 0.4) * size};
      D3 const md = (target - D3{start.x - 1, start.y, start.z}) * 1.5;
      Vec3 const motion{float(md.x), float(md.y), float(md.z)};
      Vec3 const s{float(start.x), float(start.y), float(start.z)};
      double const t = (double(s.x) - 1 - size) / -double(motion.x);
      ShapeCastConfig cfg;
      cfg.max_toi = 10;
      auto const hit = shape_cast(Cuboid{{1, 1, 1}}, Iso3::from_translation(s), motion,
                                  Cuboid{Vec3::splat(size)}, Iso3{}, cfg);
      REQUIRE(hit.hit);
      CHECK(hit.converged);
      worst_box = std::max(worst_box, std::abs(hit.toi - t) / t);
      CHECK(hit.normal.x == Approx(-1).margin(1e-5));
      ConvexHull const unit = box_hull({1, 1, 1}), big = box_hull(Vec3::splat(size));
      auto const hh = shape_cast(unit, Iso3::from_translation(s), motion, big, Iso3{}, cfg);
      REQUIRE(hh.hit);
      worst_box_hull = std::max(worst_box_hull, std::abs(hh.toi - t) / t);
    }
    INFO("target size " << size << " m: worst relative toi error sphere " << worst_sphere
                        << ", box " << worst_box << ", box hull " << worst_box_hull);
    CHECK(worst_sphere <= 1e-4);
    CHECK(worst_box <= 1e-4);
    CHECK(worst_box_hull <= 1e-4);
    WARN("target " << size << " m: worst relative toi error sphere " << worst_sphere << ", box "
                   << worst_box << ", box hull " << worst_box_hull);
  }
}

TEST_CASE("shape casts of spheres at capsules and boxes equal ray casts at inflated shapes",
          "[collision][gjk][cast]") {
  // A sphere of radius s cast at a capsule (h, r) is a ray cast at the capsule (h, r + s); at
  // a box hull, the rounded box's toi is at least the box's own (inflated by s along the
  // hit face normal when the contact is inside a face).
  rng r(55);
  double worst = 0;
  int hits = 0;
  for (int k = 0; k < 500; ++k) {
    float const h = float(r.uniform(0, 2)), rad = float(r.uniform(0.1, 1)),
                s = float(r.uniform(0.05, 0.5));
    Iso3 const pose = random_pose(r, 1);
    Vec3 const from = r.vec3<float>(-5, 5);
    Vec3 const aim = pose.translation + r.vec3<float>(-1, 1);
    Vec3 const motion = (aim - from) * 1.5f;
    auto const want = ray_cast(Capsule{h, rad + s}, pose, Ray3{from, motion}, 1.0f);
    ShapeCastConfig cfg;
    cfg.max_toi = 1;
    auto const got =
        shape_cast(Sphere{s}, Iso3::from_translation(from), motion, Capsule{h, rad}, pose, cfg);
    if (want.hit && want.toi == 0) continue; // starts inside: covered by the contact tests
    if (want.hit != got.hit) {
      // Only at a grazing angle (the two disagree within tolerance of the surface).
      float const t = want.hit ? want.toi : got.toi;
      CHECK(std::abs(closest_points(Sphere{s}, Iso3::from_translation(from + motion * t),
                                    Capsule{h, rad}, pose)
                         .distance) <= 1e-4f);
      continue;
    }
    if (!want.hit) continue;
    ++hits;
    // The error of the contact point across the surface (along the normal): the stop rule's
    // measure; along the motion it grows by 1 / cos(incidence) at grazing angles.
    double const along = std::abs(double(got.toi) - double(want.toi)) * motion.length();
    double const err = along * std::abs(want.normal.dot(motion.normalize()));
    worst = std::max(worst, err);
    CHECK(err <= 2e-5);
    CHECK(got.normal.dot(-want.normal) >= 0.999f); // got: A toward B; want: out of the capsule
  }
  CHECK(hits > 250);
  WARN("sphere-capsule casts vs inflated-capsule rays: " << hits
                                                         << " hits, worst error across the "
                                                            "surface "
                                                         << worst << " m");
}

TEST_CASE("shape casts: skins, starting in contact, misses, bad input", "[collision][gjk][cast]") {
  ShapeCastConfig cfg;
  cfg.max_toi = 1;
  // A sphere 3 m from a wall moving 10 m: toi 0.3; with a 0.5 skin 0.25.
  Iso3 const at{Quat::IDENTITY, {5, 0, 0}};
  auto const wall = Cuboid{{1, 10, 10}};
  auto const plain = shape_cast(Sphere{1}, at, Vec3{-10, 0, 0}, wall, Iso3{}, cfg);
  CHECK(plain.toi == Approx(0.3f).margin(1e-5));
  CHECK(plain.point_b.x == Approx(1).margin(1e-4));
  CHECK(plain.point_a.x == Approx(1).margin(1e-4));
  cfg.target_distance = 0.5f;
  auto const skin = shape_cast(Sphere{1}, at, Vec3{-10, 0, 0}, wall, Iso3{}, cfg);
  CHECK(skin.toi == Approx(0.25f).margin(1e-5));
  cfg.target_distance = 0;
  // Moving away, or not far enough: miss with toi +inf.
  auto const away = shape_cast(Sphere{1}, at, Vec3{10, 0, 0}, wall, Iso3{}, cfg);
  CHECK(!away.hit);
  CHECK(away.converged);
  CHECK(std::isinf(away.toi));
  CHECK(!shape_cast(Sphere{1}, at, Vec3{-2.9f, 0, 0}, wall, Iso3{}, cfg).hit);
  // Exactly reaching at max_toi hits.
  CHECK(shape_cast(Sphere{1}, at, Vec3{-3, 0, 0}, wall, Iso3{}, cfg).hit);
  // Zero motion: hit only when already in contact.
  CHECK(!shape_cast(Sphere{1}, at, Vec3{}, wall, Iso3{}, cfg).hit);
  // Starting in contact within the radii (cores apart): toi 0, penetrating, normal known.
  Iso3 const touching{Quat::IDENTITY, {1.5f, 0, 0}};
  auto const start = shape_cast(Sphere{1}, touching, Vec3{-1, 0, 0}, wall, Iso3{}, cfg);
  CHECK(start.hit);
  CHECK(start.toi == 0);
  CHECK(start.penetrating);
  CHECK(!start.converged);
  CHECK(start.normal.x == Approx(-1));
  // ... moving out: ignored when stop_at_penetration is false, reported otherwise.
  CHECK(shape_cast(Sphere{1}, touching, Vec3{1, 0, 0}, wall, Iso3{}, cfg).hit);
  ShapeCastConfig lenient = cfg;
  lenient.stop_at_penetration = false;
  CHECK(!shape_cast(Sphere{1}, touching, Vec3{1, 0, 0}, wall, Iso3{}, lenient).hit);
  CHECK(shape_cast(Sphere{1}, touching, Vec3{-1, 0, 0}, wall, Iso3{}, lenient).hit);
  // ... moving along the surface: it does not go further in, so the same rule as moving out.
  CHECK(shape_cast(Sphere{1}, touching, Vec3{0, 1, 0}, wall, Iso3{}, cfg).hit);
  CHECK(!shape_cast(Sphere{1}, touching, Vec3{0, 1, 0}, wall, Iso3{}, lenient).hit);
  // Deep penetration (cores overlap): toi 0, penetrating, zero normal.
  auto const deep = shape_cast(Cuboid{{1, 1, 1}}, Iso3{}, Vec3{1, 0, 0}, wall, Iso3{}, cfg);
  CHECK(deep.hit);
  CHECK(deep.penetrating);
  CHECK(deep.normal.length_squared() == 0);
  // Non-finite input: failed, no hit, no hang.
  float const nan = std::numeric_limits<float>::quiet_NaN();
  auto const bad = shape_cast(Sphere{1}, at, Vec3{nan, 0, 0}, wall, Iso3{}, cfg);
  CHECK(bad.failed);
  CHECK(!bad.hit);
  CHECK(
      shape_cast(Sphere{1}, Iso3::from_translation({nan, 0, 0}), Vec3{-1, 0, 0}, wall, Iso3{}, cfg)
          .failed);
  CHECK(shape_cast(Sphere{1}, at, Vec3{-1, 0, 0}, Cuboid{{nan, 1, 1}}, Iso3{}, cfg).failed);
  CHECK(shape_cast(Capsule{nan, 0.5f}, at, Vec3{-1, 0, 0}, wall, Iso3{}, cfg).failed);
  CHECK(shape_cast(Sphere{1}, at, Vec3{-1, 0, 0}, Triangle{{0, 0, 0}, {1, 0, 0}, {0, nan, 0}},
                   Iso3{}, cfg)
            .failed);
  // Infinite max_toi: a hit far away is found.
  ShapeCastConfig unlimited = cfg;
  unlimited.max_toi = std::numeric_limits<float>::infinity();
  CHECK(shape_cast(Sphere{1}, at, Vec3{-1e-3f, 0, 0}, wall, Iso3{}, unlimited).toi ==
        Approx(3000).epsilon(1e-5));
}

TEST_CASE("casts stopped by the iteration cap report a conservative hit",
          "[collision][gjk][cast]") {
  // A sphere cast and a ray cast at a round 200-point hull take several iterations. Capped
  // below that, they stop early and report a hit at a toi no later than the converged one (x
  // never enters the swept set): a caller that stops there cannot pass through the hull.
  rng r(5);
  ConvexHull const round = random_hull(r, 200, 1);
  Iso3 const from = Iso3::from_translation({4, 0.3f, -0.2f});
  Vec3 const motion{-4, 0, 0};
  ShapeCastConfig full;
  full.max_toi = 2;
  auto const ref = shape_cast(Sphere{0.25f}, from, motion, round, Iso3{}, full);
  REQUIRE(ref.hit);
  REQUIRE(ref.converged);
  REQUIRE(ref.iterations > 3);
  Ray3 const ray{from.translation, motion};
  auto const ray_ref = ray_cast_gjk(round, Iso3{}, ray, 2.0f);
  REQUIRE(ray_ref.hit);
  // Passing the hull by: a miss when converged; capped, a conservative hit.
  Vec3 const by{-4, 1.3f, 0};
  REQUIRE(!shape_cast(Sphere{0.25f}, from, by, round, Iso3{}, full).hit);
  for (int cap = 1; cap <= 3; ++cap) {
    INFO("cap " << cap);
    ShapeCastConfig cfg = full;
    cfg.gjk.max_iterations = cap;
    for (Vec3 const m : {motion, by}) {
      auto const c = shape_cast(Sphere{0.25f}, from, m, round, Iso3{}, cfg);
      CHECK(c.out_of_iterations);
      CHECK(int(c.converged) + int(c.penetrating) + int(c.out_of_iterations) + int(c.failed) == 1);
      CHECK(c.hit);
      CHECK(c.toi >= 0);
      if (m.y == motion.y) CHECK(c.toi <= ref.toi); // (the other motion has no time of impact)
    }
    auto const rc = ray_cast_gjk(round, Iso3{}, ray, 2.0f, true, cfg.gjk);
    CHECK(rc.hit);
    CHECK(rc.toi <= ray_ref.toi);
  }
  // A hollow cast from inside: the exit. Capped, it is never reported later than the true
  // exit (an exit search that runs out is no hit: no exit time is a safe bound).
  Ray3 const out{{0.1f, -0.05f, 0.02f}, {0.3f, 1, -0.2f}};
  auto const exit_ref = ray_cast_gjk(round, Iso3{}, out, 10.0f, false);
  REQUIRE(exit_ref.hit);
  int exits = 0;
  for (int cap = 1; cap <= 12; ++cap) {
    INFO("hollow, cap " << cap);
    GjkConfig g;
    g.max_iterations = cap;
    auto const e = ray_cast_gjk(round, Iso3{}, out, 10.0f, false, g);
    if (e.hit) CHECK(e.toi <= exit_ref.toi + 1e-5f);
    exits += e.hit && e.toi > 0;
  }
  CHECK(exits > 0); // some caps let the exit search finish: the check above is not vacuous
}

TEST_CASE("GJK ray casts honour a negative max_toi like the closed forms",
          "[collision][gjk][cast]") {
  // From inside a solid shape the hit is at toi 0, which a max_toi below 0 excludes (found by
  // the ray_cast fuzz target: ray_cast_gjk hit at 0 with max_toi = -1).
  ConvexHull const box = box_hull({1, 1, 1});
  Ray3 const inside{{0.2f, 0, 0}, {1, 0, 0}};
  CHECK(ray_cast_gjk(box, Iso3{}, inside, 0.0f).hit);
  CHECK(ray_cast(Cuboid{{1, 1, 1}}, Iso3{}, inside, 0.0f).hit);
  for (float max_toi : {-1.0f, -1e-30f}) {
    INFO("max_toi " << max_toi);
    auto const g = ray_cast_gjk(box, Iso3{}, inside, max_toi);
    CHECK(!g.hit);
    CHECK(g.toi == std::numeric_limits<float>::infinity());
    CHECK(!ray_cast(Cuboid{{1, 1, 1}}, Iso3{}, inside, max_toi).hit);
    CHECK(!ray_cast_gjk(box, Iso3{}, Ray3{{-5, 0, 0}, {1, 0, 0}}, max_toi).hit);
  }
}

TEST_CASE("a GJK cast whose time of impact overflows float misses", "[collision][gjk][cast]") {
  // Found by the ray_cast fuzz target: a ray starting 1.75e18 from a point cylinder, moving
  // along z with an x component of 1.4e-35 toward it (it never reaches it: it passes 4 away
  // in y). The conservative advance jumped to x = 1e38, where the rounding floor (16 eps |x|)
  // exceeds the true gap, and the cast reported a hit there (or at t = +inf, which max_toi =
  // +inf let through).
  float const inf = std::numeric_limits<float>::infinity();
  Cylinder const point{0, 0};
  Iso3 const pose = Iso3::from_translation({0, -4, 0.01f});
  Ray3 const slow{{-1.75e18f, 1e-4f, 0}, {1.4e-35f, 0, 2}};
  for (bool solid : {true, false}) {
    INFO("solid " << solid);
    auto const h = ray_cast_gjk(point, pose, slow, inf, solid);
    CHECK(!h.hit);
    CHECK(h.toi == inf);
  }
  // A ray passing 1e18 from a box, across the offset but for the box's 0.01 along it: the
  // first advance jumped to x = 1e38, where float's rounding floor (16 eps |x|) exceeds the
  // true gap, and the cast hit there.
  ConvexHull const box = box_hull({1, 1, 1});
  Iso3 const nudged = Iso3::from_translation({0, 0, 0.01f});
  for (float speed : {0.0f, 1e-30f}) {
    INFO("speed " << speed);
    auto const h = ray_cast_gjk(box, nudged, Ray3{{-1e18f, 0, 0}, {speed, 0, 1}}, inf);
    CHECK(!h.hit);
    ShapeCastConfig cfg;
    cfg.max_toi = inf;
    auto const sc = shape_cast(Sphere{0.5f}, Iso3::from_translation({-1e18f, 0, 0}),
                               Vec3{speed, 0, 1}, box, nudged, cfg);
    CHECK(!sc.hit);
  }
  // A slow cast whose time stays in range still hits.
  auto const near = ray_cast_gjk(box, Iso3{}, Ray3{{-5, 0, 0}, {1e-30f, 0, 0}}, inf);
  CHECK(near.hit);
  CHECK(near.toi == Approx(4e30f).epsilon(1e-4));
}

TEST_CASE("casts moving parallel to a face, outside it, miss", "[collision][gjk][cast]") {
  // The separating direction is then perpendicular to the motion (v . r = 0 exactly): the
  // motion never closes the gap, whatever the distance travelled.
  ConvexHull const box = box_hull({1, 1, 1});
  for (float gap : {0.5f, 1e-3f}) {
    INFO("gap " << gap);
    auto const rc = ray_cast_gjk(box, Iso3{}, Ray3{{-5, 1 + gap, 0}, {1, 0, 0}}, 100.0f);
    CHECK(!rc.hit);
    ShapeCastConfig cfg;
    cfg.max_toi = 10;
    auto const sc =
        shape_cast(Cuboid{{0.5f, 0.5f, 0.5f}}, Iso3::from_translation({-5, 1.5f + gap, 0}),
                   Vec3{1, 0, 0}, box, Iso3{}, cfg);
    CHECK(!sc.hit);
    CHECK(sc.converged);
  }
}

TEST_CASE("a cast grazing a rounded shape within the tolerance stops at its closest approach",
          "[collision][gjk][ray][cast][fuzz]") {
  // Fuzz finding ray_cast regress-grazing-normal-past-tangent: a ray passing a capsule outside
  // it but within the tolerance. The advance stepped to the inflated core's support plane,
  // which such a ray meets past its closest approach; there it was within the tolerance, a
  // hit, with a normal leaning along the ray (1.2e-3). The hit now moves back to the closest
  // approach, with the normal across the ray. Spheres and capsules of radius 0.05-2 at random
  // poses; rays and moving spheres passing 0-90 % of the tolerance outside, across the
  // shape's surface.
  rng r(7);
  float const tol = GjkConfig{}.tolerance;
  int hits = 0, casts = 0, cast_hits = 0;
  double worst_along = -1, worst_off = 0, worst_cast_along = -1;
  for (int k = 0; k < 2000; ++k) {
    float const radius = float(r.uniform(0.05, 2.0));
    float const half = float(r.uniform(0.0, 1.0));
    Iso3 const pose{r.quat<float>(), r.vec3<float>(-3, 3)};
    Capsule const capsule{half, radius};
    // A point of the core (the segment on y) and a direction out of the surface there: across
    // the axis on the side, or any direction into the end cap's half space.
    float const along_axis = float(r.uniform(-half, half));
    Vec3 out_dir = r.unit3<float>();
    Vec3 core{0, along_axis, 0};
    if (k % 2 == 0) {
      out_dir = Vec3{out_dir.x, 0, out_dir.z};
      if (out_dir.length() < 0.1f) continue;
      out_dir = out_dir.normalize();
    } else {
      float const end = along_axis < 0 ? -1.0f : 1.0f;
      core = Vec3{0, end * half, 0};
      out_dir.y = end * std::abs(out_dir.y);
    }
    // A direction across out_dir (tangent to the surface there).
    Vec3 tangent = out_dir.cross(r.unit3<float>());
    if (tangent.length() < 0.1f) continue;
    tangent = tangent.normalize();
    float const gap = tol * float(r.uniform(0.0, 0.9));
    Vec3 const pass = core + out_dir * (radius + gap); // the ray's closest approach (local)
    Vec3 const from_l = pass - tangent * 3.0f;
    Ray3 const ray{pose.transform_point(from_l), pose.transform_vector(tangent * 2.0f)};
    RayHit const h = ray_cast_gjk(capsule, pose, ray, 10.0f);
    if (h.hit) {
      ++hits;
      Vec3 const p = pose.inverse_transform_point(ray.at(h.toi));
      Vec3 const n = pose.inverse_transform_vector(h.normal);
      INFO("k " << k << " radius " << radius << " gap " << gap << " toi " << h.toi << " n " << n);
      // Not past the tangent: the normal does not lean along the ray.
      double const along = double(n.dot(tangent));
      worst_along = std::max(worst_along, along);
      CHECK(along <= 1e-5);
      // On the surface within the tolerance (anywhere the ray is within it is a hit).
      float const c = std::clamp(p.y, -half, half);
      double const off = double((p - Vec3{0, c, 0}).length()) - radius;
      worst_off = std::max(worst_off, std::abs(off));
      CHECK(std::abs(off) <= 2 * tol);
    }
    // The same with a sphere of radius 0.1 moving past it (shape_cast's cast).
    Sphere const ball{0.1f};
    Vec3 const ball_from =
        pose.transform_point(core + out_dir * (radius + 0.1f + gap) - tangent * 3.0f);
    ShapeCastConfig cfg;
    cfg.max_toi = 10;
    ++casts;
    auto const sc = shape_cast(ball, Iso3::from_translation(ball_from),
                               pose.transform_vector(tangent * 2.0f), capsule, pose, cfg);
    if (sc.hit && !sc.penetrating) {
      ++cast_hits;
      // The normal points from A to B (from the ball into the capsule): past the tangent, it
      // would lean against the motion.
      double const along = -double(pose.inverse_transform_vector(sc.normal).dot(tangent));
      worst_cast_along = std::max(worst_cast_along, along);
      INFO("cast k " << k << " toi " << sc.toi);
      CHECK(along <= 1e-5);
      Vec3 const pb = pose.inverse_transform_point(sc.point_b);
      float const c = std::clamp(pb.y, -half, half);
      CHECK(std::abs(double((pb - Vec3{0, c, 0}).length()) - radius) <= 2 * tol);
    }
  }
  // A graze whose closest approach is at or before the start: the start is within reach, a
  // start in contact (penetrating, toi 0; a motion along the surface is then ignored), never
  // a converged hit at toi 0 with a normal across the motion, which sliding cannot leave (the
  // review's case; the first version of the rule moved toi back to 0 and left it so).
  {
    Capsule const cap{0x1.c7cc12p-11f, 0x1.e589dcp+0f};
    Sphere const ball{0x1.91ac56p-2f};
    Vec3 const from{0x1.159e9p+1f, -0x1.c1fdbap-11f, -0x1.76767ap-1f};
    Vec3 const motion{0x1.7cfff8p-13f, 0x1.16ad06p+1f, -0x1.00f3f8p-14f};
    for (bool stop : {false, true}) {
      ShapeCastConfig cfg;
      cfg.max_toi = 1;
      cfg.stop_at_penetration = stop;
      auto const sc = shape_cast(ball, Iso3::from_translation(from), motion, cap, Iso3{}, cfg);
      INFO("stop_at_penetration " << stop << " hit " << sc.hit << " toi " << sc.toi);
      CHECK(!(sc.hit && sc.toi == 0.0f && !sc.penetrating));
    }
  }
  INFO("worst along " << worst_along << " off " << worst_off << " cast " << worst_cast_along);
  CHECK(hits > 500);
  CHECK(cast_hits > 500);
  CHECK(casts > 1000);
}

TEST_CASE("GJK ray casts agree with the closed forms", "[collision][gjk][ray]") {
  rng r(41);
  int hits = 0;
  double worst = 0;
  // The closed form on `shape`, GJK on `as_gjk` (the same set: the shape itself or its hull).
  auto const compare_as = [&](auto const& shape, auto const& as_gjk, Iso3 const& pose,
                              Ray3 const& ray, bool solid) {
    auto const want = ray_cast(shape, pose, ray, 100.0f, solid);
    auto const got = ray_cast_gjk(as_gjk, pose, ray, 100.0f, solid);
    if (want.hit != got.hit) {
      // Only grazing rays may differ: then the two answers are within tolerance of a tangent.
      float const t = want.hit ? want.toi : got.toi;
      auto const near_miss =
          closest_points(Sphere{0}, Iso3::from_translation(ray.at(t)), shape, pose);
      CHECK(std::abs(near_miss.distance) <= 2e-4f);
      return;
    }
    if (!want.hit) return;
    ++hits;
    double const err = std::abs(double(got.toi) - double(want.toi)) * ray.dir.length();
    worst = std::max(worst, err);
    CHECK(err <= 2e-4);
    if (solid) { // entering: the GJK cast stops short, never late (up to rounding: the two
                 // casts place the rotated shape with different float roundings)
      INFO("ray " << ray.origin << " + t " << ray.dir << " pose " << pose.translation << " / "
                  << pose.rotation << " want " << want.toi << " got " << got.toi);
      CHECK((got.toi - want.toi) * ray.dir.length() <=
            32 * std::numeric_limits<float>::epsilon() *
                (1 + ray.origin.length() + pose.translation.length()));
    }
    if (want.toi > 0 && std::abs(want.normal.dot(ray.dir.normalize())) > 0.05f)
      CHECK(got.normal.dot(want.normal) >= 0.999f);
  };
  auto const compare = [&](auto const& shape, Iso3 const& pose, Ray3 const& ray, bool solid) {
    compare_as(shape, shape, pose, ray, solid);
  };
  for (int k = 0; k < 400; ++k) {
    Iso3 const pose = random_pose(r, 1);
    // Rays from around the shape aimed near its centre (most hit, some graze or miss).
    Vec3 const origin = r.vec3<float>(-4, 4);
    Vec3 const aim = pose.translation + r.vec3<float>(-1.5, 1.5);
    Ray3 const ray{origin, (aim - origin) * float(r.uniform(0.1, 2))};
    bool const solid = k % 3 != 0;
    compare(Sphere{float(r.uniform(0.2, 2))}, pose, ray, solid);
    compare(Capsule{float(r.uniform(0, 1.5)), float(r.uniform(0.2, 1))}, pose, ray, solid);
    compare(Cuboid{r.vec3<float>(0.2, 2)}, pose, ray, solid);
    compare(Cylinder{float(r.uniform(0.2, 1.5)), float(r.uniform(0.2, 1))}, pose, ray, solid);
    Vec3 const e = r.vec3<float>(0.2, 2);
    compare_as(Cuboid{e}, box_hull(e), pose, ray, solid); // a box expressed as a hull
  }
  CHECK(hits > 750); // coverage: most aimed rays hit
  WARN("GJK ray casts vs closed forms: " << hits << " hits, worst |toi error| " << worst);
  // A hull: the solid cast from inside hits at 0, the hollow one at the exit face.
  ConvexHull const box = box_hull({1, 2, 3});
  auto const inside = ray_cast_gjk(box, Iso3{}, Ray3{{0, 0, 0}, {0, 0, 2}}, 10.0f, true);
  CHECK(inside.hit);
  CHECK(inside.toi == 0);
  CHECK(inside.normal.length_squared() == 0);
  auto const exit = ray_cast_gjk(box, Iso3{}, Ray3{{0, 0, 0}, {0, 0, 2}}, 10.0f, false);
  CHECK(exit.hit);
  CHECK(exit.toi == Approx(1.5f).margin(1e-4));
  CHECK(exit.normal.z == Approx(1).margin(1e-5));
  CHECK(!ray_cast_gjk(box, Iso3{}, Ray3{{0, 0, 0}, {0, 0, 2}}, 1.0f, false).hit);
  // Bad input.
  float const nan = std::numeric_limits<float>::quiet_NaN();
  CHECK(!ray_cast_gjk(box, Iso3{}, Ray3{{nan, 0, 0}, {1, 0, 0}}, 10.0f).hit);
  CHECK(!ray_cast_gjk(box, Iso3{}, Ray3{{5, 0, 0}, {-1, 0, 0}}, nan).hit);
  CHECK(!ray_cast_gjk(box, Iso3{}, Ray3{{5, 0, 0}, {0, 0, 0}}, 10.0f).hit);
  CHECK(
      ray_cast_gjk(box, Iso3{}, Ray3{{5, 0, 0}, {-1, 0, 0}}, std::numeric_limits<float>::infinity())
          .toi == Approx(4).margin(1e-4));
}

TEST_CASE("GJK family: far coordinates, degenerate shapes, starting on the surface",
          "[collision][gjk]") {
  // Far from the origin: two unit boxes 0.5 apart at 1e4, 1e5, 1e6. Float resolves
  // coordinates there to ulp(x); the answers must be within a few ulps, and never hang.
  for (float far : {1e4f, 1e5f, 1e6f}) {
    float const ulp = std::nextafter(far, 2 * far) - far;
    Vec3 const at{far, -far, far};
    auto const cp = closest_points(Cuboid{{1, 1, 1}}, Iso3::from_translation(at), Cuboid{{1, 1, 1}},
                                   Iso3::from_translation(at + Vec3{2.5f, 0.3f, 0}));
    INFO("at " << far);
    CHECK(cp.converged);
    CHECK(std::abs(cp.distance - 0.5f) <= 4 * ulp);
    ShapeCastConfig cfg;
    cfg.max_toi = 1;
    auto const sc =
        shape_cast(Sphere{1}, Iso3::from_translation(at), Vec3{10, 0, 0}, Cuboid{{1, 1, 1}},
                   Iso3::from_translation(at + Vec3{5, 0.5f, 0}), cfg);
    CHECK(sc.hit);
    CHECK(!sc.out_of_iterations);
    CHECK(std::abs(sc.toi * 10 - 3) <= 8 * ulp);
    auto const rc = ray_cast_gjk(box_hull({1, 1, 1}), Iso3::from_translation(at),
                                 Ray3{at + Vec3{-5, 0.2f, 0.1f}, {1, 0, 0}}, 100.0f);
    CHECK(rc.hit);
    CHECK(std::abs(rc.toi - 4) <= 8 * ulp);
  }
  // Degenerate shapes: a point box, a zero-height capsule (a sphere), a zero-radius sphere (a
  // point), segments, a collinear triangle.
  Iso3 const here{}, there = Iso3::from_translation({3, 4, 0});
  CHECK(closest_points(Cuboid{{0, 0, 0}}, here, Sphere{1}, there).distance == Approx(4));
  CHECK(closest_points(Capsule{0, 1}, here, Sphere{1}, there).distance == Approx(3));
  CHECK(closest_points(Sphere{0}, here, Sphere{0}, there).distance == Approx(5));
  CHECK(closest_points(Cuboid{{1, 0, 1}}, here, Sphere{1}, Iso3::from_translation({0, 3, 0}))
            .distance == Approx(2)); // a flat box
  rng r(12);
  for (int k = 0; k < 200; ++k) {
    Segment const s1{r.vec3<float>(-2, 2), r.vec3<float>(-2, 2)};
    Segment const s2{r.vec3<float>(-2, 2), r.vec3<float>(-2, 2)};
    double const want =
        std::sqrt(segment_distance2(to_d(s1.a), to_d(s1.b), to_d(s2.a), to_d(s2.b)));
    auto const cp = closest_points(s1, here, s2, here);
    if (want < 1e-3) {
      CHECK(cp.distance <= 2e-3f);
      continue;
    }
    CHECK(cp.distance == Approx(want).margin(2e-5));
  }
  Triangle const flat{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}; // collinear: a segment
  CHECK(closest_points(flat, here, Sphere{0}, Iso3::from_translation({1, 1, 2})).distance ==
        Approx(std::sqrt(2.0 / 3.0)).margin(1e-5));
  // A shape cast starting exactly in contact, moving in and moving out.
  ShapeCastConfig cfg;
  auto const in = shape_cast(Sphere{1}, Iso3::from_translation({2, 0, 0}), Vec3{-1, 0, 0},
                             Cuboid{{1, 1, 1}}, here, cfg);
  CHECK(in.hit);
  CHECK(in.toi == 0);
  CHECK(in.penetrating);
  cfg.stop_at_penetration = false;
  auto const out = shape_cast(Sphere{1}, Iso3::from_translation({2, 0, 0}), Vec3{1, 0, 0},
                              Cuboid{{1, 1, 1}}, here, cfg);
  CHECK(!out.hit);
  // A GJK ray cast starting on the surface: solid hits at 0 going in, misses going out.
  ConvexHull const box = box_hull({1, 1, 1});
  auto const on_in = ray_cast_gjk(box, here, Ray3{{1, 0.5f, 0}, {-1, 0, 0}}, 10.0f);
  CHECK(on_in.hit);
  CHECK(on_in.toi == 0);
  auto const on_out = ray_cast_gjk(box, here, Ray3{{1, 0.5f, 0}, {1, 0, 0}}, 10.0f);
  // Touching at the start counts as inside (closed shapes), as in the closed-form cast.
  CHECK(on_out.hit);
  CHECK(on_out.toi == 0);
  CHECK(ray_cast(Cuboid{{1, 1, 1}}, here, Ray3{{1, 0.5f, 0}, {1, 0, 0}}, 10.0f).toi == 0);
  // A grazing ray along a face at distance 0 hits; 1e-3 outside misses.
  CHECK(ray_cast_gjk(box, here, Ray3{{-5, 1, 0}, {1, 0, 0}}, 10.0f).hit);
  CHECK(!ray_cast_gjk(box, here, Ray3{{-5, 1.001f, 0}, {1, 0, 0}}, 10.0f).hit);
}

// Inputs the fuzz targets found (tests/fuzz/corpus: gjk_distance and shape_cast
// regress-*). Each failed before its fix.
TEST_CASE("GJK steps float cannot resolve do not end the query", "[collision][gjk][fuzz]") {
  // A point 4.9e-4 from a polytope whose nearest edge runs 0.25 and 1.75 from it: from the
  // edge next to it (1.9e-3 away), the step to the right one is a long, thin triangle whose
  // gain is below the projection's rounding, and GJK used to stop there, converged, at a
  // distance 4x too large. Exact distance (double, every triangle of the points): 4.928515e-4.
  Quat const q{-0.5f, -0.5f, -0.5f, -0.5f};
  Iso3 const pose{q, {-4, -4, -4}};
  std::vector<Vec3> const pts{{0x1.030308p-2f, -0x1.7b40fcp+0f, -0x1.7ffb8p-2f},
                              {0x1.00f3p-2f, 0x1.030308p-2f, 0x1.030308p-2f},
                              {0x1.030308p-2f, 0x1.030308p-2f, 0x1.030308p-2f},
                              {0x1.f8p-12f, 0x1.8p+0f, -0x1.7f28p+0f},
                              {-0x1.7bdffcp+0f, -0x1.8p+0f, -0x1.8p+0f},
                              {0x1.7ffdp+0f, -0x1.7dc2fep+0f, -0x1.8p+0f}};
  ConvexPolytope const poly{pts};
  auto const ab = closest_points(poly, pose, Sphere{0}, pose, GjkConfig{}, Vec3{-1, -1, -1});
  auto const ba = closest_points(Sphere{0}, pose, poly, pose);
  CHECK(ab.converged);
  CHECK(ba.converged);
  CHECK(ab.distance == Approx(4.928515e-4).margin(2e-6));
  CHECK(ba.distance == Approx(4.928515e-4).margin(2e-6));

  // The same rule in the cast: a hollow cast's back cast (from beyond the hull toward the
  // start) stalled and counted as a hit, and the exit came 1.2e-3 late, 2.3e-3 outside the
  // hull (ray_cast regress-gjk-hollow-exit-late).
  ConvexHull const hull = hull_of(std::vector<Vec3>{{0x1.8p+0f, 0x1.8p+0f, 0x1.8p+0f},
                                                    {-0x1.7d02fep+0f, -0x1.8p+0f, 0x1.da04d8p-1f},
                                                    {-0x1.7d02fep+0f, -0x1.8p+0f, -0x1.8p+0f},
                                                    {-0x1.8p+0f, -0x1.8p+0f, -0x1.8p+0f}});
  Iso3 const hp{{-0x1.00287ep-1f, -0x1.00287ep-1f, -0x1.ff0cc6p-2f, -0x1.00287ep-1f}, {-4, -4, -4}};
  Ray3 const ray{{-0x1.094e1ep+2f, -0x1.2faca2p+2f, -0x1.2fedfcp+2f}, {-2, -2, -2}};
  RayHit const exit = ray_cast_gjk(hull, hp, ray, std::numeric_limits<float>::infinity(), false);
  REQUIRE(exit.hit);
  Vec3 const at = hp.inverse_transform_point(ray.at(exit.toi));
  float worst = -1e30f;
  for (auto const& f : hull.faces())
    worst = std::max(worst, f.normal.dot(at) - f.offset);
  CHECK(std::abs(worst) <= 2e-5f); // on the surface
}

TEST_CASE("a point inside a sliver tetrahedron is found inside", "[collision][gjk][fuzz]") {
  // Fuzz finding ray_cast regress-point-inside-sliver-tetrahedron: a tetrahedron 3 m long, 11 mm
  // wide and 6 mm thick, a point 1.46 mm inside it. The simplex step skipped the tetrahedron as
  // flat (|det| below sqrt(eps) of its edges' product), so GJK never found the point inside:
  // it cycled between two faces 1.5e-3 away until the iteration cap, and the solid ray cast
  // from there reported a hit at toi 0 with a face's normal instead of a start inside. Now
  // only a tetrahedron within 64 eps is flat for the inside test (the weights of one flatter
  // than sqrt(eps) still do not make the points: the next test).
  std::vector<Vec3> const pts{{1.5f, -1.49963379f, -1.5f},
                              {-0.908194065f, -1.49848938f, -1.49414051f},
                              {1.48832679f, -1.48832691f, -1.5f},
                              {-1.5f, -1.5f, -1.5f}};
  ConvexHull const hull = hull_of(pts);
  Iso3 const pose{Quat::from_xyzw(0.827299297f, -0.213684261f, 0.420613676f, -0.304957271f),
                  Vec3::splat(-2.58823538f)};
  Vec3 const from{-3.60076141f, -2.08190966f, -0.792430639f};
  Vec3 const local = pose.inverse_transform_point(from);
  for (auto const& f : hull.faces())
    REQUIRE(f.normal.dot(local) - f.offset < -1e-3f); // inside, 1.46e-3 from the nearest face
  RayHit const h = ray_cast_gjk(hull, pose, Ray3{from, {-2, -2, -2}}, 0.0f);
  CHECK(h.hit);
  CHECK(h.toi == 0.0f);
  CHECK(h.normal.length() == 0.0f); // a start inside
  auto const c = closest_points(Sphere{0}, Iso3::from_translation(from), hull, pose);
  CHECK(c.overlap);
  CHECK(c.converged);

  // Slivers 1-3 m long, 0.5-3 % as thick (a tetrahedron: three points on a base line's sides,
  // one above), each with points inside at 20-80 % of the depth of its deepest inner point:
  // every point found inside by closest_points and by the solid ray cast.
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int cases = 0, missed_cp = 0, missed_ray = 0;
  for (int k = 0; k < 400; ++k) {
    float const len = 1.0f + 2.0f * u(rng), wide = len * (0.005f + 0.025f * u(rng));
    float const thick = wide * (0.3f + 0.7f * u(rng));
    std::vector<Vec3> const t{{-0.5f * len, 0, 0},
                              {0.5f * len, -0.5f * wide, 0},
                              {0.5f * len * (u(rng) - 0.5f), 0.5f * wide, 0},
                              {0.5f * len * (u(rng) - 0.5f), 0.1f * wide, thick}};
    ConvexHull const sliver = hull_of(t);
    REQUIRE(sliver.faces().size() == 4);
    Quat const q = Quat::from_axis_angle(
        Vec3{u(rng) - 0.5f, u(rng) - 0.5f, u(rng) + 0.1f}.normalize(), 6.0f * u(rng));
    Iso3 const at{q, {4 * u(rng) - 2, 4 * u(rng) - 2, 4 * u(rng) - 2}};
    for (int j = 0; j < 4; ++j) {
      // A point of the tetrahedron (random barycentric weights), kept if deep enough.
      float w[4], sum = 0;
      for (float& x : w)
        sum += (x = 0.1f + u(rng));
      Vec3 p{};
      for (int i = 0; i < 4; ++i)
        p = p + t[std::size_t(i)] * (w[i] / sum);
      float depth = 1e30f;
      for (auto const& f : sliver.faces())
        depth = std::min(depth, f.offset - f.normal.dot(p));
      if (depth < 2e-4f * len) continue; // 20 times GJK's tolerance (1e-5): clearly inside
      ++cases;
      Vec3 const pw = at.transform_point(p);
      missed_cp += !closest_points(Sphere{0}, Iso3::from_translation(pw), sliver, at).overlap;
      RayHit const r = ray_cast_gjk(sliver, at, Ray3{pw, {0.3f, -1, 0.2f}}, 10.0f);
      missed_ray += !(r.hit && r.toi == 0.0f && r.normal.length() == 0.0f);
    }
  }
  CHECK(cases > 400);
  CHECK(missed_cp == 0);
  CHECK(missed_ray == 0);
}

TEST_CASE("a cast's contact points do not come from a sliver tetrahedron's weights",
          "[collision][gjk][cast][fuzz]") {
  // The other half of the sliver rule: the origin inside a tetrahedron flatter than sqrt(eps)
  // is detected, but its weights are sums of supports metres apart whose error grows as it
  // flattens, so the points stay those of the nearest face. Taken from the tetrahedron, a
  // sliver triangle cast into a cylinder got points 1.05e-2 apart at a contact
  // (shape_cast regress-near-flat-tetra-witness); over these 60,000 casts, 8 contacts got points
  // more than 1e-3 apart (6.4e-3 the worst), against 1.25e-4 with the rule.
  std::mt19937 g(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int const casts = 60000; // (the failures without the rule are at k >= 11,975: all builds)
  int hits = 0;
  double worst = 0;
  for (int k = 0; k < casts; ++k) {
    float const len = 1 + 3 * u(g), w = len * (0.002f + 0.02f * u(g));
    Triangle const tri{
        {-0.5f * len, 0, 0}, {0.5f * len, -0.5f * w, 0}, {0.5f * len * (u(g) - 0.5f), 0.5f * w, 0}};
    Cylinder const cyl{0.2f + u(g), 0.1f + u(g)};
    auto const turn = [&] {
      return Quat::from_axis_angle(Vec3{u(g) - 0.5f, u(g) - 0.5f, u(g) + 0.1f}.normalize(),
                                   6.0f * u(g));
    };
    Iso3 const pa{turn(), {4 * u(g) - 2, 4 * u(g) - 2, 4 * u(g) - 2}};
    Iso3 const pb{turn(), {4 * u(g) - 2, 4 * u(g) - 2, 4 * u(g) - 2}};
    Vec3 const motion =
        (pb.translation - pa.translation) * 2.0f + Vec3{u(g) - 0.5f, u(g) - 0.5f, u(g) - 0.5f};
    ShapeCastConfig cfg;
    cfg.max_toi = 1;
    auto const h = shape_cast(tri, pa, motion, cyl, pb, cfg);
    if (!h.hit || h.penetrating || !h.converged) continue;
    ++hits;
    double const apart = double((h.point_a - h.point_b).length());
    worst = std::max(worst, apart);
    INFO("cast " << k);
    CHECK(apart <= 1e-3);
  }
  INFO("worst " << worst);
  CHECK(hits > casts * 9 / 10);
}

TEST_CASE("an edge passing near the origin with far ends gives a perpendicular v",
          "[collision][gjk][fuzz]") {
  // Fuzz finding gjk_distance regress-edge-v-off-perpendicular: a point and a thin polytope at
  // one turned pose. GJK's edge from (0.7, 0.70078, 0.7) to (-1.49995, -1.5, -1.5) passes
  // 4.27e-4 from the point; v = y0 + t e cancelled with an error of the ends' rounding, 1.7e-4
  // rad off the perpendicular, which made the edge's own end the support along -v: "nothing
  // left to learn", converged at 4.27e-4 where the edge to (0.7, 0.7, 0.7) passes 1.19e-5 away
  // (the other order said 0). Exact distances of every edge: long double.
  std::vector<Vec3> const pts{{0x1.666668p-1f, 0x1.666668p-1f, 0x1.666668p-1f},
                              {0x1.666668p-1f, 0x1.66cc68p-1f, 0x1.666668p-1f},
                              {0x1.31954p-3f, 0x1.0ccd9p+0f, -0x1.33273p-2f},
                              {0x1.7d9bfcp+0f, 0x1.37fb38p-2f, -0x1.caf8ccp-1f},
                              {-0x1.7ffdp+0f, -0x1.8p+0f, -0x1.8p+0f}};
  ConvexPolytope const poly{pts};
  Iso3 const pose{Quat{-0.5f, -0.5f, -0.5f, -0.5f}, {-4, -4, -4}};
  for (Vec3 const axis : {Vec3{-1, -1, -1}, Vec3{}}) {
    INFO("axis " << axis.x);
    auto const ab = closest_points(poly, pose, Cylinder{0, 0}, pose, GjkConfig{}, axis);
    CHECK(ab.converged);
    CHECK(ab.distance <= 1.2e-5f + 2e-5f);
  }

  // Edges of length 2-5 passing 1e-4 to 1e-2 from a point, the rest of a thin polytope on
  // the far side or across it: GJK's distance within the tolerance of the exact one (long
  // double, every vertex, edge and triangle), from four warm starts. Before: 97 of the
  // queries off by more than 8e-5, up to 2.8e-4; after, at most 5.8e-7.
  rng r(71);
  int bad = 0, checked = 0;
  double worst = 0;
  for (int i = 0; i < 2000; ++i) {
    Vec3 const dir =
        Vec3{float(r.uniform(-1, 1)), float(r.uniform(-1, 1)), float(r.uniform(-1, 1))};
    if (dir.length() < 0.1f) continue;
    Vec3 const u = dir.normalize();
    Vec3 const side = u.any_orthonormal_vector();
    float const gap = float(std::pow(10.0, r.uniform(-4, -2)));
    Vec3 const p0 = u * float(r.uniform(0.5, 2.5)) + side * gap;
    Vec3 const p1 = u * float(-r.uniform(0.5, 2.5)) + side * gap;
    Vec3 const p2 =
        p0 + side * float(r.uniform(-4, 1) * gap) + u.cross(side) * float(r.uniform(-1e-3, 1e-3));
    Vec3 const p3 =
        Vec3{float(r.uniform(-1, 1)), float(r.uniform(-1, 1)), float(r.uniform(-1, 1))} +
        side * 2.0f;
    std::vector<Vec3> const q{p0, p1, p2, p3};
    // Exact distance from the origin to conv(q): the nearest of its vertices, edges and
    // triangles in long double, zero when a tetrahedron holds the origin.
    using L = long double;
    auto const ld = [](Vec3 const& v) { return std::array<L, 3>{v.x, v.y, v.z}; };
    auto const dotl = [](std::array<L, 3> const& a, std::array<L, 3> const& b) {
      return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    };
    L best = 1e30L;
    for (Vec3 const& v : q)
      best = std::min(best, std::sqrt(dotl(ld(v), ld(v))));
    for (std::size_t a = 0; a < 4; ++a)
      for (std::size_t b = a + 1; b < 4; ++b) {
        auto const A = ld(q[a]), B = ld(q[b]);
        std::array<L, 3> const e{B[0] - A[0], B[1] - A[1], B[2] - A[2]};
        L const t = std::clamp(-dotl(A, e) / dotl(e, e), L(0), L(1));
        std::array<L, 3> const c{A[0] + t * e[0], A[1] + t * e[1], A[2] + t * e[2]};
        best = std::min(best, std::sqrt(dotl(c, c)));
      }
    for (std::size_t a = 0; a < 4; ++a)
      for (std::size_t b = a + 1; b < 4; ++b)
        for (std::size_t c = b + 1; c < 4; ++c) {
          auto const A = ld(q[a]), B = ld(q[b]), C = ld(q[c]);
          std::array<L, 3> const e1{B[0] - A[0], B[1] - A[1], B[2] - A[2]};
          std::array<L, 3> const e2{C[0] - A[0], C[1] - A[1], C[2] - A[2]};
          std::array<L, 3> const n{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                   e1[0] * e2[1] - e1[1] * e2[0]};
          L const nn = dotl(n, n);
          if (!(nn > 0)) continue;
          L const h = dotl(n, A) / nn; // the origin's projection: h n
          std::array<L, 3> const pr{n[0] * h, n[1] * h, n[2] * h};
          auto const w = [&](std::array<L, 3> const& P, std::array<L, 3> const& Q) {
            std::array<L, 3> const a2{P[0] - pr[0], P[1] - pr[1], P[2] - pr[2]};
            std::array<L, 3> const b2{Q[0] - pr[0], Q[1] - pr[1], Q[2] - pr[2]};
            std::array<L, 3> const x{a2[1] * b2[2] - a2[2] * b2[1], a2[2] * b2[0] - a2[0] * b2[2],
                                     a2[0] * b2[1] - a2[1] * b2[0]};
            return dotl(x, n);
          };
          if (w(A, B) >= 0 && w(B, C) >= 0 && w(C, A) >= 0)
            best = std::min(best, std::sqrt(dotl(pr, pr)));
        }
    for (Vec3 const axis : {Vec3{}, Vec3{1, 1, 1}, p0, p1}) {
      auto const g =
          closest_points(ConvexPolytope{q}, Iso3{}, Sphere{0}, Iso3{}, GjkConfig{}, axis);
      if (!g.converged) continue;
      // (A point inside the hull: distance 0 against an exact value the edges and triangles
      // do not give; the hull holds the origin only where p2 crosses it, which GJK reports.)
      if (g.overlap) continue;
      ++checked;
      double const err = std::abs(double(g.distance) - double(best));
      worst = std::max(worst, err);
      bad += err > 2e-5 * 4;
    }
  }
  INFO("worst " << worst << " over " << checked << " queries");
  CHECK(checked > 4000);
  CHECK(bad == 0);
}

TEST_CASE("a sliver face of D far from the origin: v and the points from a near point",
          "[collision][gjk][fuzz]") {
  // Fuzz finding gjk_distance regress-sliver-face-far-from-origin: a triangle and a 5-vertex
  // hull at one pose, the triangle's edge to (2, 2, 2) nearly parallel to the hull's edge along
  // the diagonal (sine 3.5e-4), 3.0534e-4 apart (exact: rationals over the 15 points of D). The
  // last simplex was the sliver of D = B - A those edges span, 6 units from the origin: the
  // plane through its vertex y0 took n's rounding (eps / sin rad) times 6, a distance of
  // 1.64e-4, and weights from cross products with y0 put the points 6.7e-4 off distance x
  // normal.
  Triangle const tri{{-0x1.575758p+0f, -0x1.575758p+0f, -0x1.57fb58p+0f},
                     {-0x1.575758p+0f, 0x1.fc1bfcp+0f, -0x1.4bff4cp+0f},
                     {0x1p+1f, 0x1p+1f, 0x1p+1f}};
  ConvexHull const hull =
      hull_of(std::vector<Vec3>{{0x1.666668p-1f, -0x1.7d02fep+0f, 0x1.7e83p+0f},
                                {0x1.8p+0f, 0x1.8p+0f, 0x1.8p+0f},
                                {-0x1.7d02fep+0f, -0x1.7d02fep+0f, -0x1.52ffd4p+0f},
                                {-0x1.7ebefep+0f, -0x1.8p+0f, -0x1.8p+0f},
                                {-0x1.8p+0f, -0x1.8p+0f, -0x1.8p+0f}});
  Iso3 const pose{Quat{-0.5f, -0.5f, -0.5f, -0.5f}, {-4, -4, -4}};
  for (Vec3 const axis : {Vec3{-1, -1, -1}, Vec3{}}) {
    INFO("axis " << axis.x);
    auto const g = closest_points(tri, pose, hull, pose, GjkConfig{}, axis);
    REQUIRE(g.converged);
    REQUIRE(!g.overlap);
    CHECK(std::abs(double(g.distance) - 3.0533667e-4) <= 1e-6); // 1.2e-8 measured
    D3 const off = (to_d(g.point_b) - to_d(g.point_a)) - to_d(g.normal) * double(g.distance);
    CHECK(off.length() <= 1e-6); // 5.8e-8 measured
  }

  // Sliver triangles (sine 3.5e-4 to 1e-2, edges 2 to 8 long) 1e-4 to 1e-2 from a point that
  // projects near them, from four warm starts: the distance within the tolerance of the
  // exact one (Ericson's closest point, double) and the points distance x normal apart. Before:
  // 64 of 12,000 distances off by more than 2e-5 (up to 5.0e-5) and 168 point pairs (up to
  // 2.3e-4); after, at most 2.9e-7 and 5.5e-7.
  rng r(73);
  int bad_distance = 0, bad_points = 0, checked = 0;
  double worst_distance = 0, worst_points = 0;
  for (int i = 0; i < 3000; ++i) {
    Vec3 const u = r.unit3<float>();
    Vec3 const side = u.any_orthonormal_vector();
    Vec3 const up = u.cross(side);
    float const h = float(std::pow(10.0, r.uniform(-4, -2)));
    double const sine = std::pow(10.0, r.uniform(-3.45, -2));
    double const l1 = r.uniform(1, 4), l2 = r.uniform(1, 4), l3 = r.uniform(-l2, l1);
    double const width = sine * (l1 + l2), f = r.uniform(0.2, 0.8);
    std::vector<Vec3> q{up * h + u * float(l1) - side * float(width * f),
                        up * h - u * float(l2) - side * float(width * f),
                        up * h + u * float(l3) + side * float(width * (1 - f))};
    std::swap(q[0], q[std::size_t(i % 3)]);
    double const exact = closest_on_triangle(D3{}, to_d(q[0]), to_d(q[1]), to_d(q[2])).length();
    for (Vec3 const axis : {Vec3{}, Vec3{1, 1, 1}, q[0], q[2]}) {
      auto const g =
          closest_points(ConvexPolytope{q}, Iso3{}, Sphere{0}, Iso3{}, GjkConfig{}, axis);
      REQUIRE(g.converged);
      REQUIRE(!g.overlap);
      ++checked;
      double const err = std::abs(double(g.distance) - exact);
      double const off =
          ((to_d(g.point_b) - to_d(g.point_a)) - to_d(g.normal) * double(g.distance)).length();
      worst_distance = std::max(worst_distance, err);
      worst_points = std::max(worst_points, off);
      bad_distance += err > 2e-6; // worst measured 2.9e-7
      bad_points += off > 2e-6;   // worst measured 5.5e-7
    }
  }
  INFO("worst distance error " << worst_distance << ", points " << worst_points << " over "
                               << checked << " queries");
  CHECK(bad_distance == 0);
  CHECK(bad_points == 0);
}

TEST_CASE("shape casts report contact points on their shapes and the contact normal",
          "[collision][gjk][cast][fuzz]") {
  // A point cast into a cylinder: the last simplex is a sliver triangle 7 units from the ray
  // point, whose barycentric weights (from cross products of the long vectors) summed to
  // 1 - 8e-4 and put point_a 5e-3 off the point.
  Iso3 const pa{{0x1.027d2ep-1f, 0x1.027d2ep-1f, -0x1.027b2ap-1f, -0x1.f0c882p-2f}, {4, 4, 4}};
  Iso3 const pb{{-0x1.d448b4p-2f, -0x1.06df2ap-1f, -0x1.06e344p-1f, -0x1.06e344p-1f}, {-4, -4, -4}};
  Vec3 const motion{-8, -8, -8};
  auto const c = shape_cast(Sphere{0}, pa, motion, Cylinder{0x1.fe03fep+0f, 0x1.8p+0f}, pb);
  REQUIRE(c.hit);
  REQUIRE(c.converged);
  Vec3 const at = pa.translation + motion * c.toi;
  CHECK((c.point_a - at).length() <= 1e-5f);
  CHECK((c.point_b - c.point_a).length() <= 1e-4f);

  // A capsule grazing a sphere: the normal was the last advance direction, 2.4e-3 rad off the
  // direction between the shapes at the time of impact (3e-3 off for the contact points).
  Capsule const cap{0x1.0001p-1f, 0x1.333134p-2f};
  Sphere const ball{0x1.0001p+0f};
  Iso3 const pc{{-0x1.3a076cp-2f, -0x1.7ea478p-3f, -0x1.d48adp-1f, 0x1.7765bcp-3f},
                {0x1p-14f, -0x1.fc1bfcp+1f, -0x1.ff8p+1f}};
  Iso3 const ps{{-0x1.271f1ap-1f, -0x1.26a29ap-1f, -0x1.25f7fap-1f, 0x1.55468ep-4f},
                {0x1p-14f, 0x1.ff02p-6f, -0x1.57f558p+0f}};
  Vec3 const m2{-0x1.fc1bfcp-2f, 0x1.2019p+2f, 0x1.6867a8p+1f};
  ShapeCastConfig cfg;
  cfg.max_toi = 2;
  auto const g = shape_cast(cap, pc, m2, ball, ps, cfg);
  REQUIRE(g.hit);
  REQUIRE(g.converged);
  auto const there = closest_points(cap, Iso3{pc.rotation, pc.translation + m2 * g.toi}, ball, ps);
  REQUIRE(there.converged);
  CHECK(there.distance <= 2e-5f);
  CHECK(g.normal.dot(there.normal) >= std::cos(1e-4f));
  CHECK((g.point_b - g.point_a).length() <= 1e-4f);
}

TEST_CASE("GJK fails coordinates whose squares overflow", "[collision][gjk][fuzz]") {
  // 1.5e29 away: |v|^2 overflowed, the cast saw "within reach" and hit at 0.
  Iso3 const far = Iso3::from_translation({0, 1.5e29f, 0});
  Triangle const tri{{0, -1, 0}, {0, 0.5f, 1}, {1, 0, 0}};
  auto const c =
      shape_cast(Sphere{0}, Iso3::from_translation({-12, -12, -12}), Vec3{-24, -24, -24}, tri, far);
  CHECK(c.failed);
  CHECK(!c.hit);
  auto const d = closest_points(Sphere{0}, Iso3{}, tri, far);
  CHECK(d.failed);
  auto const r = ray_cast_gjk(tri, far, Ray3{{0, 0, 0}, {0, 1, 0}}, 1e30f);
  CHECK(!r.hit);
  // 1e18 is still a query float can answer (its squares are 1e36).
  auto const ok =
      closest_points(Sphere{0}, Iso3{}, Sphere{1}, Iso3::from_translation({0, 1e18f, 0}));
  CHECK(!ok.failed);
  CHECK(ok.distance == Approx(1e18f));
}

PLUME_WIDE_TEST_CASE("GJK queries are lane-exact", "[collision][gjk][lanes]", wide_real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  rng r(77);
  // lanes_v<T> different hulls packed into one wide polytope, plus wide spheres/capsules.
  packed_hulls<T> const ph([](std::size_t i) { return 10 + 2 * i; },
                           [&](std::size_t) { return r.vec3<S>(-1, 1); });
  GConvexPolytope<T> const wide = ph.wide();
  S const nan = std::numeric_limits<S>::quiet_NaN();
  int failures = 0;
  for (int k = 0; k < 40; ++k) {
    GIso3<T> pa{r.quat<T>(), r.vec3<T>(-3, 3)};
    GIso3<T> const pb{r.quat<T>(), r.vec3<T>(-1, 1)};
    GVec3<T> motion = r.vec3<T>(-4, 4);
    if (k % 5 == 0) // a NaN lane
      pa.translation.x = plume::with_lane(pa.translation.x, std::size_t(k) % lanes_v<T>, nan);
    if (k % 7 == 0) motion = GVec3<T>{};
    T const radius = r.elem<T>(0, 1), hh = r.elem<T>(0, 1);
    auto const cp = closest_points(GCapsule<T>{hh, radius}, pa, wide, pb);
    ShapeCastConfig cfg;
    cfg.max_toi = 2;
    cfg.target_distance = k % 2 ? 0.05f : 0.0f;
    if (k % 4 == 1) cfg.gjk.max_iterations = 2; // lanes capped beside lanes that finish
    auto const sc = shape_cast(GSphere<T>{radius}, pa, motion, wide, pb, cfg);
    GRay3<T> const ray{pa.translation, motion};
    auto const rc = ray_cast_gjk(wide, pb, ray, splat<T>(S(3)), k % 3 != 0, cfg.gjk);
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      GConvexPolytope<S> const hull = ph.lane_polytope(i);
      GIso3<S> const la = lane(pa, i), lb = lane(pb, i);
      auto const cps = closest_points(GCapsule<S>{lane(hh, i), lane(radius, i)}, la, hull, lb);
      bool const ok_cp =
          same(cps.distance, lane(cp.distance, i)) && same(cps.point_a, lane(cp.point_a, i)) &&
          same(cps.normal, lane(cp.normal, i)) && cps.overlap == lane(cp.overlap, i) &&
          cps.converged == lane(cp.converged, i) && same(cps.iterations, lane(cp.iterations, i));
      auto const scs = shape_cast(GSphere<S>{lane(radius, i)}, la, lane(motion, i), hull, lb, cfg);
      bool const ok_sc = same(scs.toi, lane(sc.toi, i)) && same(scs.normal, lane(sc.normal, i)) &&
                         same(scs.point_a, lane(sc.point_a, i)) && scs.hit == lane(sc.hit, i) &&
                         scs.penetrating == lane(sc.penetrating, i) &&
                         scs.failed == lane(sc.failed, i) &&
                         scs.out_of_iterations == lane(sc.out_of_iterations, i) &&
                         scs.converged == lane(sc.converged, i);
      auto const rcs = ray_cast_gjk(hull, lb, GRay3<S>{la.translation, lane(motion, i)}, S(3),
                                    k % 3 != 0, cfg.gjk);
      bool const ok_rc = same(rcs.toi, lane(rc.toi, i)) && same(rcs.normal, lane(rc.normal, i)) &&
                         rcs.hit == lane(rc.hit, i);
      if (!(ok_cp && ok_sc && ok_rc) && failures++ < 5)
        FAIL_CHECK("case " << k << " lane " << i << ": closest " << ok_cp << " cast " << ok_sc
                           << " ray " << ok_rc << " (wide d " << lane(cp.distance, i) << " scalar "
                           << cps.distance << "; toi " << lane(sc.toi, i) << " vs " << scs.toi
                           << ")");
    }
  }
  CHECK(failures == 0);
}

TEST_CASE("moves_into_surface: inward and steeper than 1e-3 rad; NaN keeps the contact",
          "[gjk][cast]") {
  float const nan = std::numeric_limits<float>::quiet_NaN();
  CHECK(moves_into_surface(1.0f, 1.0f));
  CHECK(!moves_into_surface(-1.0f, 1.0f));   // leaves
  CHECK(!moves_into_surface(0.0f, 1.0f));    // along
  CHECK(!moves_into_surface(0.5e-3f, 1.0f)); // along within 1e-3 rad
  CHECK(moves_into_surface(2e-3f, 1.0f));
  CHECK(moves_into_surface(nan, 1.0f)); // unknown: kept, never passed through
  CHECK(moves_into_surface(1.0f, nan));
  plume::for_each_type<test::f32_types>([&]<class T>() {
    T const closing = plume::from_array<T>([nan] {
      std::array<float, lanes_v<T>> a{};
      for (std::size_t i = 0; i < a.size(); ++i)
        a[i] = i % 4 == 0 ? 1.0f : i % 4 == 1 ? -1.0f : i % 4 == 2 ? 0.5e-3f : nan;
      return a;
    }());
    auto const m = moves_into_surface(closing, plume::splat<T>(1.0f));
    for (std::size_t i = 0; i < lanes_v<T>; ++i)
      CHECK(bool((plume::bitmask(m) >> i) & 1) ==
            moves_into_surface(plume::lane(closing, i), 1.0f));
  });
}
