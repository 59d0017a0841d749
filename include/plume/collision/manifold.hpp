// plume/collision/manifold.hpp - contact manifolds: up to 4 contact points with one shared
// normal between two shapes, for the contact solver, depenetration and move-and-slide.
// Scalar (float or double): the solver gathers manifolds into lanes afterwards.
//
//   GManifold<S> m = contact_manifold(a, pose_a, b, pose_b, cfg);
//   for (auto const& c : m) ... c.point_a, c.point_b, c.separation, c.id
//
// Conventions:
//  - normal: unit, world, from A toward B (moving B along it separates them).
//  - separation per point: the signed gap along the normal, negative = overlap; only points
//    with separation <= cfg.prediction are kept (speculative contacts). point_a is on A's
//    surface, point_b on B's; point_b - point_a = separation * normal (up to rounding).
//  - id: a feature key (reference face, incident face, incident vertex or clipped edge) that
//    stays the same while the same features touch, so a solver can match points across
//    frames for warm starting. Ids are unique within a manifold.
//  - count = 0: apart by more than the prediction distance (or failed: non-finite input).
//
// Pairs: spheres, capsules, cuboids, convex hulls and triangles against each other, and each
// of them against a half-space (either order); any other convex shape (cylinder, polytope
// view) gets one point from the penetration query.
//  - Two cuboids: box_pair_manifold (box_manifold.hpp), the same code the world's narrow
//    phase runs W pairs at a time: a separating-axis test over the 15 axes; a face axis (A's
//    faces win ties) gives the reference face, and the incident face's clip against it is
//    found as a fixed set of candidates; an edge axis gives the closest points of the two
//    edges. A reference face without area, or a clip that keeps nothing while the boxes are
//    within the prediction distance along the axis, takes the general polytope path.
//  - Polytope pairs (cuboid, hull, triangle): the normal from GJK/EPA (collision/epa.hpp);
//    when it is within cfg.face_alignment of a face normal, that face is the reference face,
//    the most anti-parallel face of the other shape is the incident face, the incident face is
//    clipped against the reference face's side planes (Sutherland-Hodgman) and the normal is
//    the reference face's. Otherwise (edge against edge) one point. Triangles are two-sided.
//  - Capsules: two points when the core segment lies parallel to a reference face (or to the
//    other capsule), else one. Spheres: one point; against a sphere, a capsule or a cuboid
//    in closed form (the nearest core points; a sphere's centre inside a cuboid takes the
//    face it is least deep behind), against anything else from the penetration query.
//  - More than 4 points are reduced to 4: the deepest, the farthest from it, the one making
//    the largest triangle with them, and the one adding the most area to that triangle.
#pragma once

#include <plume/collision/box_manifold.hpp>
#include <plume/collision/convex_hull.hpp>
#include <plume/collision/epa.hpp>
#include <plume/collision/shapes.hpp>
#include <plume/math/iso3.hpp>
#include <plume/math/mat3.hpp>
#include <plume/math/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <type_traits>
#include <utility>

namespace plume {

template <ScalarReal S>
struct GContactPoint {
  GVec3<S> point_a; ///< world, on A's surface
  GVec3<S> point_b; ///< world, on B's surface
  S separation;     ///< along the normal; negative = overlap
  std::uint64_t id; ///< feature key, stable while the same features touch
};

template <ScalarReal S>
struct GManifold {
  GVec3<S> normal{}; ///< unit, from A toward B
  std::array<GContactPoint<S>, 4> points{};
  int count = 0;
  bool failed = false; ///< non-finite input (count 0)

  GContactPoint<S> const* begin() const noexcept { return points.data(); }
  GContactPoint<S> const* end() const noexcept { return points.data() + count; }
  bool empty() const noexcept { return count == 0; }
  /// The most negative separation (+infinity when empty).
  S min_separation() const noexcept {
    S m = std::numeric_limits<S>::infinity();
    for (auto const& c : *this)
      m = c.separation < m ? c.separation : m;
    return m;
  }
};

struct ManifoldConfig {
  /// Keep points up to this separation (speculative contacts), length units.
  float prediction = 0.02f;
  /// cos of the largest angle between the contact normal and a face normal for which the
  /// contact is treated as face contact (clipping); about 1.1 degrees.
  float face_alignment = 0.9998f;
  EpaConfig epa{};

  /// This config with every length-valued field (prediction, epa's) multiplied by
  /// length_unit; face_alignment is a cosine and stays.
  ManifoldConfig scaled(float length_unit) const noexcept {
    ManifoldConfig c = *this;
    c.prediction *= length_unit;
    c.epa = c.epa.scaled(length_unit);
    return c;
  }
};

namespace detail {

/// The faces of a polytope shape, in its local frame.
template <ScalarReal S>
struct face_set {
  std::span<GVec3<S> const> verts;
  std::span<GHullFace<S> const> faces;
  std::span<std::uint32_t const> index;
  std::span<std::uint32_t const> face(std::size_t f) const noexcept {
    return index.subspan(faces[f].first, faces[f].count);
  }
};

template <ScalarReal S>
struct box_faces {
  std::array<GVec3<S>, 8> verts;
  std::array<GHullFace<S>, 6> faces;
  static constexpr std::array<std::uint32_t, 24> index{
      // -x, +x, -y, +y, -z, +z; vertex i has x = bit 0, y = bit 1, z = bit 2 (set = +);
      // counter-clockwise seen from outside.
      0, 4, 6, 2, 1, 3, 7, 5, 0, 1, 5, 4, 2, 6, 7, 3, 0, 2, 3, 1, 4, 5, 7, 6};
  explicit box_faces(GVec3<S> const& e) noexcept {
    for (std::uint32_t i = 0; i < 8; ++i)
      verts[i] = {(i & 1) ? e.x : -e.x, (i & 2) ? e.y : -e.y, (i & 4) ? e.z : -e.z};
    S const ex[3] = {e.x, e.y, e.z};
    for (std::uint32_t k = 0; k < 6; ++k) {
      GVec3<S> n{};
      S const sign = (k & 1) ? S(1) : S(-1);
      if (k / 2 == 0) n.x = sign;
      if (k / 2 == 1) n.y = sign;
      if (k / 2 == 2) n.z = sign;
      faces[k] = {n, ex[k / 2], 4 * k, 4};
    }
  }
  face_set<S> view() const noexcept { return {verts, faces, index}; }
};

template <ScalarReal S>
struct triangle_faces {
  std::array<GVec3<S>, 3> verts;
  std::array<GHullFace<S>, 2> faces;
  static constexpr std::array<std::uint32_t, 6> index{0, 1, 2, 0, 2, 1};
  explicit triangle_faces(GTriangle<S> const& t) noexcept : verts{t.a, t.b, t.c} {
    GVec3<S> const n = t.scaled_normal().normalize_or_zero();
    faces[0] = {n, n.dot(t.a), 0, 3};
    faces[1] = {-n, -n.dot(t.a), 3, 3};
  }
  face_set<S> view() const noexcept { return {verts, faces, index}; }
};

template <class Shape>
struct shape_kind {
  static constexpr bool polytope = false, sphere = false, capsule = false, half_space = false;
};
template <ScalarReal S>
struct shape_kind<GCuboid<S>> {
  static constexpr bool polytope = true, sphere = false, capsule = false, half_space = false;
};
template <ScalarReal S>
struct shape_kind<GConvexHull<S>> {
  static constexpr bool polytope = true, sphere = false, capsule = false, half_space = false;
};
template <ScalarReal S>
struct shape_kind<GTriangle<S>> {
  static constexpr bool polytope = true, sphere = false, capsule = false, half_space = false;
};
template <ScalarReal S>
struct shape_kind<GSphere<S>> {
  static constexpr bool polytope = false, sphere = true, capsule = false, half_space = false;
};
template <ScalarReal S>
struct shape_kind<GCapsule<S>> {
  static constexpr bool polytope = false, sphere = false, capsule = true, half_space = false;
};
template <ScalarReal S>
struct shape_kind<GHalfSpace<S>> {
  static constexpr bool polytope = false, sphere = false, capsule = false, half_space = true;
};

/// Calls f with the face set of a polytope shape (built on the stack for boxes/triangles).
template <ScalarReal S, class F>
decltype(auto) with_faces(GCuboid<S> const& s, F&& f) {
  box_faces<S> const b(s.half_extents);
  return f(b.view());
}
template <ScalarReal S, class F>
decltype(auto) with_faces(GTriangle<S> const& s, F&& f) {
  triangle_faces<S> const t(s);
  return f(t.view());
}
template <ScalarReal S, class F>
decltype(auto) with_faces(GConvexHull<S> const& s, F&& f) {
  return f(face_set<S>{s.vertices(), s.faces(), s.face_vertex_indices()});
}

/// A manifold under construction: up to 64 candidate points, reduced to 4 at the end.
template <ScalarReal S>
struct candidates {
  static constexpr int capacity = 64;
  std::array<GContactPoint<S>, capacity> pts{};
  int n = 0;
  void add(GContactPoint<S> const& c) noexcept {
    if (n < capacity) pts[std::size_t(n++)] = c;
  }
};

/// Keeps at most 4 of the candidates: deepest, farthest from it, largest triangle, largest
/// area added (Gregorius' reduction).
template <ScalarReal S>
void reduce_into(candidates<S> const& c, GVec3<S> const& normal, GManifold<S>& m) noexcept {
  m.count = 0;
  if (c.n <= 4) {
    for (int i = 0; i < c.n; ++i)
      m.points[std::size_t(m.count++)] = c.pts[std::size_t(i)];
    return;
  }
  auto const pos = [&](int i) { return c.pts[std::size_t(i)].point_b; };
  int i0 = 0;
  for (int i = 1; i < c.n; ++i)
    if (c.pts[std::size_t(i)].separation < c.pts[std::size_t(i0)].separation) i0 = i;
  int i1 = -1;
  S best = S(-1);
  for (int i = 0; i < c.n; ++i) {
    S const d = (pos(i) - pos(i0)).length_squared();
    if (i != i0 && d > best) best = d, i1 = i;
  }
  int i2 = -1;
  best = S(-1);
  for (int i = 0; i < c.n && i1 >= 0; ++i) {
    S const a = std::abs((pos(i1) - pos(i0)).cross(pos(i) - pos(i0)).dot(normal));
    if (i != i0 && i != i1 && a > best) best = a, i2 = i;
  }
  // Distances or areas that are NaN (points or a normal that overflowed) pick nothing: keep
  // what was picked.
  if (i1 < 0 || i2 < 0) {
    for (int i : {i0, i1})
      if (i >= 0) m.points[std::size_t(m.count++)] = c.pts[std::size_t(i)];
    return;
  }
  // Orient the triangle counter-clockwise around the normal, then take the point most outside
  // one of its edges (the most negative edge area).
  if ((pos(i1) - pos(i0)).cross(pos(i2) - pos(i0)).dot(normal) < S(0)) std::swap(i1, i2);
  int i3 = -1;
  best = S(0);
  int const tri[3] = {i0, i1, i2};
  for (int i = 0; i < c.n; ++i) {
    if (i == i0 || i == i1 || i == i2) continue;
    for (int e = 0; e < 3; ++e) {
      S const a = (pos(tri[(e + 1) % 3]) - pos(tri[e])).cross(pos(i) - pos(tri[e])).dot(normal);
      if (a < best) best = a, i3 = i;
    }
  }
  for (int i : {i0, i1, i2, i3})
    if (i >= 0) m.points[std::size_t(m.count++)] = c.pts[std::size_t(i)];
}

/// The bit fields of a feature id (GContactPoint::id), high to low: whether the reference
/// face is B's, the reference face, the incident face, and the key of the point on the
/// incident side. The key is an incident vertex or a segment end (0, 1), or, with `clipped`
/// set, a point made by clipping: the edge cut (an incident edge, or with side_edge set a
/// reference side: a corner of the reference face) and the reference side that cut it for a
/// face against a face (clip_key), the reference side alone for a segment against a face
/// (segment_clip_key).
namespace id_bits {
inline constexpr int ref_is_b_shift = 63; ///< bit 63: the reference face is B's
inline constexpr int ref_face_shift = 40; ///< bits 40..62: the reference face
inline constexpr std::uint32_t ref_face_mask = 0x7fffff;
inline constexpr int inc_face_shift = 20; ///< bits 20..39: the incident face
inline constexpr std::uint32_t inc_face_mask = 0xfffff;
inline constexpr std::uint32_t key_mask = 0xfffff; ///< bits 0..19: the point's key
inline constexpr std::uint32_t no_face = 0xfffff;  ///< the incident face of a segment: none
inline constexpr std::uint32_t clipped = 0x80000;  ///< key bit 19: made by clipping
inline constexpr int edge_shift = 8;               ///< key bits 8..17: the edge cut
inline constexpr std::uint32_t edge_mask = 0x3ff;
inline constexpr std::uint32_t side_edge = 0x200; ///< edge bit 9: the edge cut is a reference side
inline constexpr std::uint32_t side_mask = 0xff;  ///< key bits 0..7: the reference side
} // namespace id_bits

inline std::uint64_t feature_id(bool ref_is_b, std::uint32_t ref_face, std::uint32_t inc_face,
                                std::uint32_t key) noexcept {
  using namespace id_bits;
  return (std::uint64_t(ref_is_b) << ref_is_b_shift) |
         (std::uint64_t(ref_face & ref_face_mask) << ref_face_shift) |
         (std::uint64_t(inc_face & inc_face_mask) << inc_face_shift) |
         std::uint64_t(key & key_mask);
}
/// The key of the point where polygon edge `edge` (an incident edge, or side_edge | a
/// reference side) crosses reference side `side`.
inline std::uint32_t clip_key(std::uint32_t edge, std::uint32_t side) noexcept {
  using namespace id_bits;
  return clipped | ((edge & edge_mask) << edge_shift) | (side & side_mask);
}
/// The key of a segment end clipped at reference side `side`.
inline std::uint32_t segment_clip_key(std::uint32_t side) noexcept {
  return id_bits::clipped | side;
}

/// The face of fs (at pose) whose world normal is most along dir; its alignment.
template <ScalarReal S>
std::pair<std::uint32_t, S> best_face(face_set<S> const& fs, GIso3<S> const& pose,
                                      GVec3<S> const& dir) noexcept {
  GVec3<S> const local = pose.inverse_transform_vector(dir);
  std::uint32_t best = 0;
  S align = -std::numeric_limits<S>::infinity();
  for (std::uint32_t f = 0; f < fs.faces.size(); ++f) {
    S const a = fs.faces[f].normal.dot(local);
    if (a > align) align = a, best = f;
  }
  return {best, align};
}

/// One point from a penetration result.
template <ScalarReal S>
void single_point(GPenetrationResult<S> const& p, GManifold<S>& m, ManifoldConfig const& cfg) {
  m.normal = p.normal;
  if (-p.depth <= S(cfg.prediction)) {
    m.points[0] = {p.point_a, p.point_b, -p.depth, 0};
    m.count = 1;
  }
}

/// The contact point with on_ref on the reference shape and on_other on the other one, in
/// A, B order.
template <ScalarReal S>
GContactPoint<S> ordered_point(bool ref_is_b, GVec3<S> const& on_ref, GVec3<S> const& on_other,
                               S separation, std::uint64_t id) noexcept {
  return ref_is_b ? GContactPoint<S>{on_other, on_ref, separation, id}
                  : GContactPoint<S>{on_ref, on_other, separation, id};
}

/// Adds to c the contact of p (world), a point of the other shape's core of radius r_other,
/// with the reference plane (world unit normal rn through r0, the reference shape's radius
/// r_ref) when its separation is within the prediction distance.
template <ScalarReal S>
void add_plane_contact(candidates<S>& c, GVec3<S> const& p, GVec3<S> const& rn, GVec3<S> const& r0,
                       S r_ref, S r_other, bool ref_is_b, std::uint64_t id,
                       ManifoldConfig const& cfg) noexcept {
  S const height = (p - r0).dot(rn);
  S const s = height - r_ref - r_other;
  if (s > S(cfg.prediction)) return;
  GVec3<S> const on_other = p - rn * r_other;
  GVec3<S> const on_ref = p - rn * (height - r_ref);
  c.add(ordered_point(ref_is_b, on_ref, on_other, s, id));
}

/// A vertex of the incident polygon while it is clipped: world position, feature key, and
/// the edge of the polygon that starts at it: a piece of incident edge i (from incident
/// vertex i to i + 1) or, after a side cut the polygon, a piece of reference side k
/// (id_bits::side_edge | k). A clipped point's key names the edge it cut and the side that
/// cut it: the same features every frame, and never two points of one polygon (a straight
/// edge of a convex polygon crosses a side's plane once).
template <ScalarReal S>
struct clip_vertex {
  GVec3<S> p;
  std::uint32_t key;
  std::uint32_t edge;
};

/// Whether face f of fs has an area: its vector area, from the edges out of its first vertex,
/// above 64 eps of the face's size times its coordinates (the rounding of those edges). A face
/// of zero area (a box with zero extents, a point or a segment) bounds nothing, and clipping
/// against its degenerate sides would keep everything.
template <ScalarReal S>
bool face_has_area(face_set<S> const& fs, std::uint32_t f) noexcept {
  auto const v = fs.face(f);
  GVec3<S> const& o = fs.verts[v[0]];
  GVec3<S> area{};
  S size = S(0), coords = o.abs().max_element();
  for (std::size_t k = 1; k + 1 < v.size(); ++k) {
    GVec3<S> const e1 = fs.verts[v[k]] - o, e2 = fs.verts[v[k + 1]] - o;
    area += e1.cross(e2);
    size = std::max(size, std::max(e1.abs().max_element(), e2.abs().max_element()));
    coords = std::max(coords, fs.verts[v[k]].abs().max_element());
  }
  S const floor = S(64) * std::numeric_limits<S>::epsilon() * size * std::max(size, coords);
  return area.length() > floor;
}

/// One Sutherland-Hodgman pass over the polygon in[0, n): the vertices on the inner side of
/// reference side k (the plane through a with inward normal `side`) and a new vertex where
/// an edge crosses it, at most 64, into out; returns their count.
template <ScalarReal S>
int clip_side(clip_vertex<S> const* in, int n, GVec3<S> const& a, GVec3<S> const& side,
              std::uint32_t k, clip_vertex<S>* out) noexcept {
  int no = 0;
  for (int i = 0; i < n; ++i) {
    clip_vertex<S> const& p = in[i];
    clip_vertex<S> const& q = in[(i + 1) % n];
    S const dp = (p.p - a).dot(side), dq = (q.p - a).dot(side);
    if (dp >= S(0) && no < 64) out[no++] = p;
    if ((dp >= S(0)) != (dq >= S(0)) && no < 64) {
      S const t = dp / (dp - dq);
      // A new point where edge p.edge crosses reference side k. Leaving the side's inner
      // half, the polygon now runs along side k to where it comes back; entering, it goes on
      // along p.edge.
      std::uint32_t const next = dp >= S(0) ? (id_bits::side_edge | k) : p.edge;
      out[no++] = {p.p + (q.p - p.p) * t, clip_key(p.edge, k), next};
    }
  }
  return no;
}

/// Clips the incident polygon (face inf of inc) against the side planes of the reference face
/// (face rf of ref); keeps the points within the prediction distance, at most 4. A reference
/// face without area keeps none (the callers fall back to one point).
template <ScalarReal S>
void clip_faces(face_set<S> const& ref, GIso3<S> const& ref_pose, std::uint32_t rf,
                face_set<S> const& inc, GIso3<S> const& inc_pose, std::uint32_t inf, bool ref_is_b,
                S r_ref, S r_inc, ManifoldConfig const& cfg, GManifold<S>& m) {
  if (!face_has_area(ref, rf)) return;
  std::array<clip_vertex<S>, 64> buf_a{}, buf_b{};
  int n = 0;
  auto const iv = inc.face(inf);
  for (std::uint32_t i = 0; i < iv.size() && n < 64; ++i)
    buf_a[std::size_t(n++)] = {inc_pose.transform_point(inc.verts[iv[i]]), i, i};
  auto const rv = ref.face(rf);
  GVec3<S> const rn = ref_pose.transform_vector(ref.faces[rf].normal);
  GVec3<S> const r0 = ref_pose.transform_point(ref.verts[rv[0]]);
  clip_vertex<S>* in = buf_a.data();
  clip_vertex<S>* out = buf_b.data();
  for (std::uint32_t k = 0; k < rv.size() && n > 0; ++k) {
    GVec3<S> const a = ref_pose.transform_point(ref.verts[rv[k]]);
    GVec3<S> const b = ref_pose.transform_point(ref.verts[rv[(k + 1) % rv.size()]]);
    n = clip_side(in, n, a, rn.cross(b - a), k, out); // rn x (b - a) points into the face
    std::swap(in, out);
  }
  candidates<S> c;
  for (int i = 0; i < n; ++i)
    add_plane_contact(c, in[i].p, rn, r0, r_ref, r_inc, ref_is_b,
                      feature_id(ref_is_b, rf, inf, in[i].key), cfg);
  m.normal = ref_is_b ? -rn : rn;
  reduce_into(c, m.normal, m);
}

/// The core segment of a capsule clipped against a reference face (two points), with the
/// feature key of each end; none against a face without area.
template <ScalarReal S>
void clip_segment(face_set<S> const& ref, GIso3<S> const& ref_pose, std::uint32_t rf, GVec3<S> p0,
                  GVec3<S> p1, bool ref_is_b, S r_seg, ManifoldConfig const& cfg, GManifold<S>& m) {
  if (!face_has_area(ref, rf)) return;
  auto const rv = ref.face(rf);
  GVec3<S> const rn = ref_pose.transform_vector(ref.faces[rf].normal);
  GVec3<S> const r0 = ref_pose.transform_point(ref.verts[rv[0]]);
  S t0 = S(0), t1 = S(1);
  std::uint32_t k0 = 0, k1 = 1; // end keys: 0/1 = the segment's own ends, else clipped
  GVec3<S> const d = p1 - p0;
  for (std::uint32_t k = 0; k < rv.size(); ++k) {
    GVec3<S> const a = ref_pose.transform_point(ref.verts[rv[k]]);
    GVec3<S> const b = ref_pose.transform_point(ref.verts[rv[(k + 1) % rv.size()]]);
    GVec3<S> const side = rn.cross(b - a);
    S const s0 = (p0 - a).dot(side), sd = d.dot(side);
    // Keep s0 + t sd >= 0.
    if (sd == S(0)) {
      if (s0 < S(0)) t1 = S(-1); // outside and parallel: nothing left
      continue;
    }
    S const t = -s0 / sd;
    if (sd > S(0) && t > t0) t0 = t, k0 = segment_clip_key(k);
    if (sd < S(0) && t < t1) t1 = t, k1 = segment_clip_key(k);
  }
  m.normal = ref_is_b ? -rn : rn;
  if (t1 < t0) return;
  candidates<S> c;
  for (int e = 0; e < 2; ++e)
    add_plane_contact(c, p0 + d * (e == 0 ? t0 : t1), rn, r0, S(0), r_seg, ref_is_b,
                      feature_id(ref_is_b, rf, id_bits::no_face, e == 0 ? k0 : k1), cfg);
  reduce_into(c, m.normal, m);
}

/// The vertices of fs (at pose) within the prediction distance of the plane (world normal n
/// through o), the 64 deepest when there are more: (separation, vertex) pairs into deepest;
/// returns their count.
template <ScalarReal S>
int deepest_vertices(face_set<S> const& fs, GIso3<S> const& pose, GVec3<S> const& n,
                     GVec3<S> const& o, ManifoldConfig const& cfg,
                     std::array<std::pair<S, std::uint32_t>, candidates<S>::capacity>& deepest) {
  constexpr int cap = candidates<S>::capacity;
  int nd = 0;
  for (std::uint32_t i = 0; i < fs.verts.size(); ++i) {
    S const sep = (pose.transform_point(fs.verts[i]) - o).dot(n);
    if (sep > S(cfg.prediction)) continue;
    if (nd < cap) {
      deepest[std::size_t(nd++)] = {sep, i};
    } else {
      std::size_t worst = 0;
      for (std::size_t k = 1; k < std::size_t(cap); ++k)
        if (deepest[k].first > deepest[worst].first) worst = k;
      if (sep < deepest[worst].first) deepest[worst] = {sep, i};
    }
  }
  return nd;
}

/// The points of a shape below a half-space (plane normal n through point o, world).
template <ScalarReal S, class Shape>
void against_plane(GVec3<S> const& n, GVec3<S> const& o, Shape const& s, GIso3<S> const& pose,
                   bool plane_is_b, ManifoldConfig const& cfg, GManifold<S>& m) {
  candidates<S> c;
  // The plane is the reference; the ids' first field is set the other way round (kept: a
  // change would renumber every plane contact).
  auto const add = [&](GVec3<S> const& core_local, S radius, std::uint32_t key) {
    add_plane_contact(c, pose.transform_point(core_local), n, o, S(0), radius, plane_is_b,
                      feature_id(!plane_is_b, 0, 0, key), cfg);
  };
  using K = shape_kind<Shape>;
  if constexpr (K::sphere) {
    add(GVec3<S>{}, s.radius, 0);
  } else if constexpr (K::capsule) {
    add(GVec3<S>{S(0), -s.half_height, S(0)}, s.radius, 0);
    add(GVec3<S>{S(0), s.half_height, S(0)}, s.radius, 1);
  } else if constexpr (K::polytope) {
    with_faces(s, [&](face_set<S> const& fs) {
      std::array<std::pair<S, std::uint32_t>, candidates<S>::capacity> deepest{};
      int const nd = deepest_vertices(fs, pose, n, o, cfg, deepest);
      for (int k = 0; k < nd; ++k)
        add(fs.verts[deepest[std::size_t(k)].second], S(0), deepest[std::size_t(k)].second);
      return 0;
    });
  } else {
    GVec3<S> const local = pose.inverse_transform_vector(-n);
    add(s.core_support(local), s.core_radius(), 0);
  }
  m.normal = plane_is_b ? -n : n;
  reduce_into(c, m.normal, m);
}

/// sin of the angle in [0, pi/2] whose cosine is c.
template <ScalarReal S>
S sine_of(S c) noexcept {
  return std::sqrt(std::max(S(1) - c * c, S(0)));
}

/// The ends of a capsule's core segment, world: (0, -h, 0) and (0, h, 0) placed by pose.
template <ScalarReal S, class Cap>
std::pair<GVec3<S>, GVec3<S>> core_segment(Cap const& cap, GIso3<S> const& pose) noexcept {
  return {pose.transform_point({S(0), -cap.half_height, S(0)}),
          pose.transform_point({S(0), cap.half_height, S(0)})};
}

/// Two boxes by the separating-axis test. True when that decides the manifold: apart by more
/// than the prediction distance, or a face contact whose clip kept points. False (m empty)
/// for an edge axis, an empty clip or a non-finite separation: the general path decides.
/// Two cuboids through box_pair_manifold (box_manifold.hpp) at S; false when it leaves the
/// pair to the general path.
template <ScalarReal S>
bool box_pair(GCuboid<S> const& a, GIso3<S> const& pose_a, GCuboid<S> const& b,
              GIso3<S> const& pose_b, ManifoldConfig const& cfg, GManifold<S>& m) {
  GBoxPairManifold<S> const w =
      box_pair_manifold(a.half_extents, pose_a, b.half_extents, pose_b, S(cfg.prediction));
  if (w.general) return false;
  m = w.lane(0);
  return true;
}

/// Whether a clipped manifold misses the pair's depth (p): its deepest point shallower than
/// p's by more than the reference face (face rf of fs) tilted by the largest angle
/// face_alignment allows can explain (sin of it x the face's diameter), plus 1e-3 of the
/// diameter. The incident face may stand steeply to the reference one (a thin triangle edge-on
/// into a hull face), and then its part inside the reference face's sides is not its deepest.
template <ScalarReal S>
bool clip_misses_depth(face_set<S> const& fs, std::uint32_t rf, GPenetrationResult<S> const& p,
                       ManifoldConfig const& cfg, GManifold<S> const& m) noexcept {
  // The diameter (pairs of vertices: up to 2,016 for a 64-gon) only when the clip is shallower
  // at all, which a resting contact is not.
  if (m.count == 0 || !(m.min_separation() > -p.depth)) return false;
  auto const v = fs.face(rf);
  S diameter = S(0);
  for (std::size_t i = 0; i < v.size(); ++i)
    for (std::size_t j = i + 1; j < v.size(); ++j)
      diameter = std::max(diameter, (fs.verts[v[i]] - fs.verts[v[j]]).length());
  S const allowance = (sine_of(S(cfg.face_alignment)) + S(1e-3)) * diameter;
  return m.min_separation() > -p.depth + allowance;
}

/// Two polytopes in contact (p): the face of either whose normal is within cfg.face_alignment
/// of p's is the reference (A's unless B's is better aligned by 1e-5), the other shape's most
/// anti-parallel face is clipped against it; else, or when the clip loses every point (a
/// sliver) or misses p's depth (clip_misses_depth), p's one point.
template <ScalarReal S, class A, class B>
void polytope_pair(A const& a, GIso3<S> const& pose_a, B const& b, GIso3<S> const& pose_b,
                   GPenetrationResult<S> const& p, ManifoldConfig const& cfg, GManifold<S>& m) {
  S const cos_face = S(cfg.face_alignment);
  with_faces(a, [&](face_set<S> const& fa) {
    return with_faces(b, [&](face_set<S> const& fb) {
      auto const [ia, align_a] = best_face(fa, pose_a, p.normal);
      auto const [ib, align_b] = best_face(fb, pose_b, -p.normal);
      if (std::max(align_a, align_b) < cos_face) {
        single_point(p, m, cfg);
        return 0;
      }
      bool const ref_is_b = align_b > align_a + S(1e-5);
      bool missed;
      if (!ref_is_b) {
        GVec3<S> const rn = pose_a.transform_vector(fa.faces[ia].normal);
        auto const inc = best_face(fb, pose_b, -rn).first;
        clip_faces(fa, pose_a, ia, fb, pose_b, inc, false, S(0), S(0), cfg, m);
        missed = clip_misses_depth(fa, ia, p, cfg, m);
      } else {
        GVec3<S> const rn = pose_b.transform_vector(fb.faces[ib].normal);
        auto const inc = best_face(fa, pose_a, -rn).first;
        clip_faces(fb, pose_b, ib, fa, pose_a, inc, true, S(0), S(0), cfg, m);
        missed = clip_misses_depth(fb, ib, p, cfg, m);
      }
      if (m.count == 0 || missed) {
        m = GManifold<S>{};
        single_point(p, m, cfg);
      }
      return 0;
    });
  });
}

/// A capsule against a polytope in contact (p; CapIsA: the capsule is shape A): the core
/// segment clipped to the polytope's face (the reference) when that face is within
/// cfg.face_alignment of the normal and the segment parallel to it, two points; else, or when
/// the clip keeps nothing, p's one point.
template <bool CapIsA, ScalarReal S, class Cap, class Poly>
void capsule_on_polytope(Cap const& cap, GIso3<S> const& cap_pose, Poly const& poly,
                         GIso3<S> const& poly_pose, GPenetrationResult<S> const& p,
                         ManifoldConfig const& cfg, GManifold<S>& m) {
  S const cos_face = S(cfg.face_alignment);
  GVec3<S> const to_poly = CapIsA ? p.normal : -p.normal; // from the capsule toward it
  auto const seg = core_segment(cap, cap_pose); // not a structured binding: the lambda captures
  GVec3<S> const p0 = seg.first, p1 = seg.second;
  GVec3<S> const axis = (p1 - p0).normalize_or_zero();
  with_faces(poly, [&](face_set<S> const& fs) {
    auto const [f, align] = best_face(fs, poly_pose, -to_poly);
    if (align < cos_face || std::abs(axis.dot(to_poly)) > sine_of(cos_face) ||
        cap.half_height == S(0)) {
      single_point(p, m, cfg);
      return 0;
    }
    // The polytope's face is the reference: it is B's when the capsule is A.
    clip_segment(fs, poly_pose, f, p0, p1, CapIsA, cap.radius, cfg, m);
    if (m.count == 0) single_point(p, m, cfg);
    return 0;
  });
}

/// Two capsules in contact (p): when the core segments are parallel within
/// cfg.face_alignment and perpendicular to the normal, B's segment clipped to A's extent
/// along A's axis, each end against A's line (two points, each pair joined along the normal);
/// else, or when they do not overlap along the axis, or when the segments' offset across the
/// normal would put the points off their surfaces by more than 1e-3 of the radii's sum,
/// p's one point.
template <ScalarReal S, class CA, class CB>
void capsule_pair(CA const& a, GIso3<S> const& pose_a, CB const& b, GIso3<S> const& pose_b,
                  GPenetrationResult<S> const& p, ManifoldConfig const& cfg, GManifold<S>& m) {
  auto const [a0, a1] = core_segment(a, pose_a);
  auto const [b0, b1] = core_segment(b, pose_b);
  GVec3<S> const da = a1 - a0, db = b1 - b0;
  S const la = da.length(), lb = db.length();
  S const sin_face = sine_of(S(cfg.face_alignment));
  bool const parallel = la > S(0) && lb > S(0) && da.cross(db).length() <= sin_face * la * lb &&
                        std::abs(da.dot(p.normal)) <= sin_face * la;
  if (!parallel) return single_point(p, m, cfg);
  GVec3<S> const ua = da / la;
  S const tb0 = (b0 - a0).dot(ua), tb1 = (b1 - a0).dot(ua);
  S const lo = std::max(std::min(tb0, tb1), S(0)), hi = std::min(std::max(tb0, tb1), la);
  if (hi < lo) return single_point(p, m, cfg);
  candidates<S> c;
  S const span = tb1 - tb0;
  for (int e = 0; e < 2; ++e) {
    S const t = e == 0 ? lo : hi;
    S const u = span != S(0) ? (t - tb0) / span : S(0);
    GVec3<S> const pb = b0 + db * u;
    GVec3<S> const pa = a0 + ua * t;
    GVec3<S> const d = pb - pa;
    S const along = d.dot(p.normal);
    S const sep = along - a.radius - b.radius;
    if (sep > S(cfg.prediction)) continue;
    // Segments parallel only within the tolerance are offset across the normal too (by up to
    // their length times the tolerance's sine). The points share that offset in proportion
    // to the radii, so point_b - point_a is separation x normal, the anchor midway does not
    // move, and together they leave their surfaces by about |across|^2 / (2 (ra + rb)); more
    // than 1e-3 (ra + rb) of that (thin capsules, or long ones at the tolerance's angle) and
    // the pair is not parallel enough for two points.
    GVec3<S> const across = d - p.normal * along;
    S const rsum = a.radius + b.radius;
    if (!(across.length_squared() <= S(2e-3) * rsum * rsum)) {
      c.n = 0;
      break;
    }
    S const wa = rsum > S(0) ? a.radius / rsum : S(0.5);
    c.add({pa + p.normal * a.radius + across * wa, pb - p.normal * b.radius - across * (S(1) - wa),
           sep, feature_id(false, 0, 0, std::uint32_t(e))});
  }
  m.normal = p.normal;
  reduce_into(c, m.normal, m);
  if (m.count == 0) single_point(p, m, cfg);
}

/// Two round cores that are points: ca on A's (radius ra), cb on B's (radius rb), world, d =
/// cb - ca (given: a caller may know it better than the difference of the rounded points).
/// One point along d; shorter than the least normal square (about 1e-19 m in float), the
/// fallback normal (the cores count as coincident). A square that overflows is `failed`, as
/// in GJK.
template <ScalarReal S>
void round_points(GVec3<S> const& ca, S ra, GVec3<S> const& cb, S rb, GVec3<S> const& d,
                  GVec3<S> const& fallback, ManifoldConfig const& cfg, GManifold<S>& m) noexcept {
  S const d2 = d.dot(d);
  if (!std::isfinite(d2)) {
    m.failed = true;
    return;
  }
  bool const apart = d2 >= std::numeric_limits<S>::min();
  S const dist = apart ? std::sqrt(d2) : S(0);
  GVec3<S> const n = apart ? d / dist : fallback;
  S const sep = dist - (ra + rb); // the same in either order
  m.normal = n;
  if (!(sep <= S(cfg.prediction))) return;
  m.points[0] = {ca + n * ra, cb - n * rb, sep, 0};
  m.count = 1;
}

/// A sphere (s at ps) and a capsule (c at pc): the capsule's core point nearest the sphere's
/// centre, then round_points. Between the core's ends, the offset from the core is the
/// centre's offset from the capsule's centre rejected from the axis (the pose's y axis, not
/// the difference of the rounded ends) twice, so that rounding leaves no part along the axis:
/// a centre on the core gets a normal across it, never along it (a fixed one when the offset
/// is zero; +Y for a capsule of zero height).
template <bool SphereIsA, ScalarReal S>
void sphere_capsule(GSphere<S> const& s, GIso3<S> const& ps, GCapsule<S> const& c,
                    GIso3<S> const& pc, ManifoldConfig const& cfg, GManifold<S>& m) noexcept {
  GVec3<S> const axis = pc.rotation * GVec3<S>{S(0), S(1), S(0)};
  GVec3<S> const centre = ps.translation, w = centre - pc.translation;
  S const along = w.dot(axis), h = c.half_height;
  // Overflow needs no test of its own: a non-finite offset or square fails in round_points.
  GVec3<S> q, off; // the core point nearest the centre, and centre - q
  if (along <= -h || along >= h) {
    q = pc.transform_point({S(0), along <= -h ? -h : h, S(0)});
    off = centre - q;
  } else {
    off = w - axis * along;
    off = off - axis * off.dot(axis);
    q = centre - off;
  }
  GVec3<S> const across = h > S(0) ? axis.any_orthonormal_vector() : GVec3<S>{S(0), S(1), S(0)};
  if constexpr (SphereIsA)
    round_points(centre, s.radius, q, c.radius, -off, across, cfg, m);
  else
    round_points(q, c.radius, centre, s.radius, off, across, cfg, m);
}

/// A sphere (s at ps) and a cuboid (b at pb), in the box's frame. Centre outside the box:
/// along the centre minus its nearest box point. Inside (or closer to the surface than about
/// 1e-19 m in float): the face the centre is least deep behind (order +x, -x, +y, -y, +z,
/// -z; the first on ties), as EPA's least-penetration axis.
template <bool SphereIsA, ScalarReal S>
void sphere_cuboid(GSphere<S> const& s, GIso3<S> const& ps, GCuboid<S> const& b, GIso3<S> const& pb,
                   ManifoldConfig const& cfg, GManifold<S>& m) noexcept {
  GVec3<S> const c = pb.inverse_transform_point(ps.translation), h = b.half_extents;
  GVec3<S> const q = c.clamp(-h, h), d = c - q;
  S const d2 = d.dot(d);
  if (!std::isfinite(c.dot(c))) {
    m.failed = true;
    return;
  }
  GVec3<S> n_local, on_box; // box toward sphere
  S sep;
  if (d2 >= std::numeric_limits<S>::min()) {
    S const dist = std::sqrt(d2);
    n_local = d / dist;
    on_box = q;
    sep = dist - s.radius;
  } else {
    std::array<S, 3> const cc{c.x, c.y, c.z}, hh{h.x, h.y, h.z};
    int axis = 0;
    S sign = S(1), depth = hh[0] - cc[0];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 2; ++k) {
        S const sg = k == 0 ? S(1) : S(-1);
        S const di = hh[i] - sg * cc[i];
        if (di < depth) depth = di, axis = i, sign = sg;
      }
    std::array<S, 3> nn{S(0), S(0), S(0)}, pp = cc;
    nn[axis] = sign;
    pp[axis] = sign * hh[axis];
    n_local = {nn[0], nn[1], nn[2]};
    on_box = {pp[0], pp[1], pp[2]};
    sep = -depth - s.radius;
  }
  GVec3<S> const n = pb.rotation * n_local;
  m.normal = SphereIsA ? -n : n;
  if (!(sep <= S(cfg.prediction))) return;
  GVec3<S> const point_box = pb.transform_point(on_box),
                 point_sphere = ps.translation - n * s.radius;
  m.points[0] = SphereIsA ? GContactPoint<S>{point_sphere, point_box, sep, 0}
                          : GContactPoint<S>{point_box, point_sphere, sep, 0};
  m.count = 1;
}

/// The general path of contact_manifold for finite input: GJK/EPA's penetration, then the
/// face clip, segment clip or single point its kinds allow.
template <ScalarReal S, class A, class B>
GManifold<S> penetration_manifold(A const& a, GIso3<S> const& pose_a, B const& b,
                                  GIso3<S> const& pose_b, ManifoldConfig const& cfg) {
  using KA = shape_kind<A>;
  using KB = shape_kind<B>;
  GManifold<S> m;
  GPenetrationResult<S> const p = penetration(a, pose_a, b, pose_b, cfg.epa);
  if (p.status == PenetrationStatus::failed) {
    m.failed = true;
    return m;
  }
  m.normal = p.normal;
  if (-p.depth > S(cfg.prediction)) return m;
  if constexpr (KA::polytope && KB::polytope)
    polytope_pair(a, pose_a, b, pose_b, p, cfg, m);
  else if constexpr (KA::capsule && KB::polytope)
    capsule_on_polytope<true>(a, pose_a, b, pose_b, p, cfg, m);
  else if constexpr (KA::polytope && KB::capsule)
    capsule_on_polytope<false>(b, pose_b, a, pose_a, p, cfg, m);
  else if constexpr (KA::capsule && KB::capsule)
    capsule_pair(a, pose_a, b, pose_b, p, cfg, m);
  else
    single_point(p, m, cfg);
  return m;
}

} // namespace detail

/// The contact manifold between shape a (at pose_a) and shape b (at pose_b). See the top of
/// this header for the conventions and the pairs handled.
template <ScalarReal S, class A, class B>
GManifold<S> contact_manifold(A const& a, GIso3<S> const& pose_a, B const& b,
                              GIso3<S> const& pose_b, ManifoldConfig const& cfg = {}) {
  using KA = detail::shape_kind<A>;
  using KB = detail::shape_kind<B>;
  GManifold<S> m;
  if (!(pose_a.is_finite() && pose_b.is_finite() && detail::shape_finite<S>(a) &&
        detail::shape_finite<S>(b))) {
    m.failed = true;
    return m;
  }
  if constexpr (KA::half_space && KB::half_space) {
    return m; // two half-spaces: no manifold (they always overlap unless parallel)
  } else if constexpr (KA::half_space) {
    GVec3<S> const n = pose_a.transform_vector(a.normal);
    detail::against_plane(n, pose_a.translation, b, pose_b, false, cfg, m);
    return m;
  } else if constexpr (KB::half_space) {
    GVec3<S> const n = pose_b.transform_vector(b.normal);
    detail::against_plane(n, pose_b.translation, a, pose_a, true, cfg, m);
    return m;
  } else {
    // Spheres against spheres, capsules and cuboids in closed form: the nearest core points
    // exactly, where GJK + EPA find them within their tolerance.
    if constexpr (std::is_same_v<A, GSphere<S>> && std::is_same_v<B, GSphere<S>>) {
      detail::round_points(pose_a.translation, a.radius, pose_b.translation, b.radius,
                           pose_b.translation - pose_a.translation, GVec3<S>{S(0), S(1), S(0)}, cfg,
                           m);
      return m;
    } else if constexpr (std::is_same_v<A, GSphere<S>> && std::is_same_v<B, GCapsule<S>>) {
      detail::sphere_capsule<true>(a, pose_a, b, pose_b, cfg, m);
      return m;
    } else if constexpr (std::is_same_v<A, GCapsule<S>> && std::is_same_v<B, GSphere<S>>) {
      detail::sphere_capsule<false>(b, pose_b, a, pose_a, cfg, m);
      return m;
    } else if constexpr (std::is_same_v<A, GSphere<S>> && std::is_same_v<B, GCuboid<S>>) {
      detail::sphere_cuboid<true>(a, pose_a, b, pose_b, cfg, m);
      return m;
    } else if constexpr (std::is_same_v<A, GCuboid<S>> && std::is_same_v<B, GSphere<S>>) {
      detail::sphere_cuboid<false>(b, pose_b, a, pose_a, cfg, m);
      return m;
    } else {
      if constexpr (std::is_same_v<A, GCuboid<S>> && std::is_same_v<B, GCuboid<S>>) {
        // Boxes: box_pair_manifold's closed forms (a face clip or an edge pair), the general
        // path for the few it leaves (a face without area, an empty clip).
        if (detail::box_pair(a, pose_a, b, pose_b, cfg, m)) return m;
      }
      return detail::penetration_manifold(a, pose_a, b, pose_b, cfg);
    }
  }
}

namespace detail {

/// What contact_manifold gives a pair of cuboids that box_pair_manifold left to the general
/// path (a lane with `general` set): the world's narrow phase calls this for such lanes.
template <ScalarReal S>
GManifold<S> box_pair_general(GCuboid<S> const& a, GIso3<S> const& pose_a, GCuboid<S> const& b,
                              GIso3<S> const& pose_b, ManifoldConfig const& cfg) {
  GManifold<S> m;
  if (!(pose_a.is_finite() && pose_b.is_finite() && shape_finite<S>(a) && shape_finite<S>(b))) {
    m.failed = true;
    return m;
  }
  return penetration_manifold(a, pose_a, b, pose_b, cfg);
}

} // namespace detail

template <Float T>
GManifold<scalar_t<T>> GBoxPairManifold<T>::lane(std::size_t i) const noexcept {
  using S = scalar_t<T>;
  using namespace detail::id_bits;
  GManifold<S> m;
  m.normal = plume::lane(normal, i);
  m.count = int(plume::lane(count, i));
  bool const ref_b = ((bitmask(ref_is_b) >> i) & 1u) != 0;
  auto const rf = std::uint32_t(plume::lane(ref_face, i));
  auto const inf = std::uint32_t(plume::lane(inc_face, i));
  for (int k = 0; k < m.count; ++k) {
    auto const c = std::uint32_t(plume::lane(key[std::size_t(k)], i));
    std::uint32_t const feature = c < 4    ? c
                                  : c < 20 ? detail::clip_key((c - 4) / 4, (c - 4) % 4)
                                  : c < 24 ? detail::clip_key(side_edge | (c - 20), c - 20)
                                           : 0;
    m.points[std::size_t(k)] = {
        plume::lane(point_a[std::size_t(k)], i), plume::lane(point_b[std::size_t(k)], i),
        plume::lane(separation[std::size_t(k)], i), detail::feature_id(ref_b, rf, inf, feature)};
  }
  return m;
}

using ContactPoint = GContactPoint<float>;
using Manifold = GManifold<float>;

} // namespace plume
