// tests/fuzz/mesh_checks.hpp - what the triangle_mesh and height_field fuzz targets share: the
// queries of a triangle source (TriangleMesh, HeightField) decoded from the fuzzer's bytes and
// checked against brute force over its triangles, as spatial/triangle_mesh.hpp,
// spatial/height_field.hpp and spatial/mesh_queries.hpp document them:
//  - ray_cast: the least (toi, triangle) of ray_cast_local over every triangle, bit for bit
//    (normal and back face included; for meshes whose triangles' float cross products do not
//    overflow); nothing for a non-finite or zero direction, a non-finite origin, or a NaN or
//    negative max_toi; the posed form is the local one of the ray moved into the mesh frame;
//  - closest_point: the least (squared distance, triangle) of closest_point_on_triangle within
//    max_distance, bit for bit; nothing for a non-finite point or a NaN or negative distance;
//  - query_aabb: exactly the triangles whose boxes meet the box (none with a NaN), each once,
//    stopping when told to;
//  - mesh_overlaps / mesh_intersects: only triangles GJK finds touching, in increasing order,
//    and every touching triangle well inside the shape's box; nothing for a non-finite pose;
//  - mesh_shape_cast: the least (toi, triangle) of shape_cast over every triangle, bit for bit,
//    unless a triangle's cast hit GJK's iteration cap (the header's exception);
//  - mesh_contacts: at most max_mesh_manifolds manifolds, unit normals, real triangles, finite
//    points within the prediction distance; failed exactly for a non-finite pose.
#pragma once

#include "fuzz_input.hpp"

#include <plume/collision/gjk.hpp>
#include <plume/collision/ray_cast.hpp>
#include <plume/collision/shapes.hpp>
#include <plume/spatial/mesh_queries.hpp>
#include <plume/spatial/triangle_mesh.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <variant>
#include <vector>

namespace plume::fuzz {

inline bool same_bits(float a, float b) noexcept { return a == b || (a != a && b != b); }
inline bool same_bits(Vec3 const& a, Vec3 const& b) noexcept {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}
inline bool same_hit(MeshRayHit const& a, MeshRayHit const& b) noexcept {
  return a.triangle == b.triangle && same_bits(a.toi, b.toi) && same_bits(a.normal, b.normal) &&
         a.back == b.back;
}
inline bool same_point(MeshClosestPoint const& a, MeshClosestPoint const& b) noexcept {
  return a.triangle == b.triangle && same_bits(a.point, b.point) &&
         same_bits(a.distance, b.distance);
}
inline bool unit(Vec3 const& n, float tol = 1e-4f) noexcept {
  return finite(n) && std::abs(n.length() - 1.0f) <= tol;
}

/// Whether every triangle's float cross product (b - a) x (c - a) has a finite squared length:
/// beyond that (coordinates past about 1e9 apart) the watertight triangle cast overflows and
/// its toi is no longer at or beyond the triangle's box, so ray casts are compared only here.
template <class Mesh>
bool ordinary(Mesh const& mesh) {
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t)
    if (!std::isfinite(Triangle(mesh.triangle(t)).scaled_normal().length_squared())) return false;
  return true;
}

/// The mesh's documented ray cast: the least (toi, triangle) over every triangle.
template <class Mesh>
MeshRayHit brute_ray(Mesh const& mesh, Ray3 const& ray, float max_toi) {
  MeshRayHit best;
  Vec3 const d = ray.dir;
  if (!finite(ray.origin) || !finite(d) || (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f) ||
      !(max_toi >= 0.0f))
    return best;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    RayHit const h = ray_cast_local(Triangle(mesh.triangle(t)), ray, max_toi);
    if (!bool(h.hit)) continue;
    if (h.toi < best.toi || (h.toi == best.toi && t < best.triangle)) {
      best.triangle = t;
      best.toi = h.toi;
      best.normal = h.normal;
      best.back = h.feature == 1.0f;
    }
  }
  return best;
}

/// The mesh's documented closest point: the least (squared distance, triangle).
template <class Mesh>
MeshClosestPoint brute_closest(Mesh const& mesh, Vec3 const& p, float max_distance) {
  MeshClosestPoint best;
  if (!finite(p) || !(max_distance >= 0.0f)) return best;
  float best_d2 = std::isinf(max_distance) ? max_distance : max_distance * max_distance;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    Vec3 const c = closest_point_on_triangle(Triangle(mesh.triangle(t)), p);
    float const d2 = (p - c).length_squared();
    if (d2 < best_d2 || (d2 == best_d2 && t < best.triangle)) {
      best_d2 = d2;
      best.triangle = t;
      best.point = c;
    }
  }
  if (best.found()) best.distance = std::sqrt(best_d2);
  return best;
}

template <class Mesh>
void check_ray(Mesh const& mesh, Ray3 const& ray, float max_toi) {
  MeshRayHit const got = mesh.ray_cast(ray, max_toi);
  MeshRayHit const want = brute_ray(mesh, ray, max_toi);
  if (ordinary(mesh)) PLUME_FUZZ_CHECK(same_hit(got, want));
  if (got.hit()) {
    PLUME_FUZZ_CHECK(got.triangle < mesh.triangle_count());
    PLUME_FUZZ_CHECK(got.toi >= 0.0f && got.toi <= max_toi);
    // A unit normal facing the ray, and back when the ray came from behind the front face
    // (where the float cross product of the triangle, which the cast uses, does not overflow).
    bool const ordinary =
        std::isfinite(Triangle(mesh.triangle(got.triangle)).scaled_normal().length_squared());
    if (ordinary) {
      PLUME_FUZZ_CHECK(unit(got.normal));
      PLUME_FUZZ_CHECK(got.normal.dot(ray.dir) <= 0.0f);
    }
    float const facing = mesh.face_normal(got.triangle).dot(ray.dir);
    if (ordinary && std::abs(facing) > 1e-3f * ray.dir.length())
      PLUME_FUZZ_CHECK(got.back == (facing > 0.0f));
  } else {
    PLUME_FUZZ_CHECK(got.triangle == no_triangle && std::isinf(got.toi));
  }
  // The identity pose gives the same bits; another pose is the cast of the moved ray.
  PLUME_FUZZ_CHECK(same_hit(mesh.ray_cast(Iso3{}, ray, max_toi), got));
}

template <class Mesh>
void check_posed_ray(Mesh const& mesh, Iso3 const& pose, Ray3 const& ray, float max_toi) {
  MeshRayHit const got = mesh.ray_cast(pose, ray, max_toi);
  Ray3 const local{pose.inverse_transform_point(ray.origin),
                   pose.inverse_transform_vector(ray.dir)};
  MeshRayHit want = brute_ray(mesh, local, max_toi);
  if (want.hit()) want.normal = pose.transform_vector(want.normal);
  if (ordinary(mesh)) PLUME_FUZZ_CHECK(same_hit(got, want));
  if (got.hit() &&
      std::isfinite(Triangle(mesh.triangle(got.triangle)).scaled_normal().length_squared()))
    PLUME_FUZZ_CHECK(unit(got.normal, 1e-3f));
}

template <class Mesh>
void check_closest(Mesh const& mesh, Vec3 const& p, float max_distance) {
  MeshClosestPoint const got = mesh.closest_point(p, max_distance);
  MeshClosestPoint const want = brute_closest(mesh, p, max_distance);
  PLUME_FUZZ_CHECK(same_point(got, want));
  if (got.found()) {
    PLUME_FUZZ_CHECK(got.triangle < mesh.triangle_count());
    PLUME_FUZZ_CHECK(finite(got.point));
    PLUME_FUZZ_CHECK(got.distance >= 0.0f && !(got.distance > max_distance));
  } else {
    PLUME_FUZZ_CHECK(got.triangle == no_triangle && std::isinf(got.distance));
  }
  PLUME_FUZZ_CHECK(same_point(mesh.closest_point(Iso3{}, p, max_distance), got));
}

template <class Mesh>
void check_posed_closest(Mesh const& mesh, Iso3 const& pose, Vec3 const& p, float max_distance) {
  MeshClosestPoint const got = mesh.closest_point(pose, p, max_distance);
  MeshClosestPoint want = brute_closest(mesh, pose.inverse_transform_point(p), max_distance);
  if (want.found()) want.point = pose.transform_point(want.point);
  PLUME_FUZZ_CHECK(same_point(got, want));
}

template <class Mesh>
void check_box(Mesh const& mesh, Aabb3 const& box, int stop_after) {
  std::vector<std::uint32_t> got;
  mesh.query_aabb(box, [&](std::uint32_t t) { got.push_back(t); });
  std::sort(got.begin(), got.end());
  PLUME_FUZZ_CHECK(std::adjacent_find(got.begin(), got.end()) == got.end());
  std::vector<std::uint32_t> want;
  bool const nan = std::isnan(box.min.x) || std::isnan(box.min.y) || std::isnan(box.min.z) ||
                   std::isnan(box.max.x) || std::isnan(box.max.y) || std::isnan(box.max.z);
  if (!nan && bool(box.min.cmple(box.max).all()))
    for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t)
      if (bool(Triangle(mesh.triangle(t)).local_aabb().intersects(box))) want.push_back(t);
  PLUME_FUZZ_CHECK(got == want);
  // f returning false stops the walk.
  std::size_t calls = 0;
  mesh.query_aabb(box, [&](std::uint32_t) { return ++calls < std::size_t(stop_after); });
  PLUME_FUZZ_CHECK(calls == std::min(std::size_t(stop_after), want.size()));
}

/// The convex shapes the mesh queries are fuzzed with.
using QueryShape = std::variant<Sphere, Capsule, Cuboid, Cylinder>;

inline QueryShape query_shape(Input& in) {
  std::uint8_t const k = in.byte();
  switch (k % 4) {
  case 0:
    return Sphere{in.real(0, 2)};
  case 1:
    return Capsule{in.real(0, 2), in.real(0, 1)};
  case 2:
    return Cuboid{in.vec3(0, 2)};
  default:
    return Cylinder{in.real(0, 2), in.real(0, 1)};
  }
}

/// A pose: mostly reasonable, at times the identity, at times not finite.
inline Iso3 query_pose(Input& in, float reach) {
  std::uint8_t const k = in.byte();
  Iso3 p{(k & 1) ? in.rotation() : Quat::IDENTITY, in.vec3(-reach, reach)};
  if ((k & 0x1e) == 0x1e) p.translation.y = in.any_float();
  if ((k & 0xe0) == 0xe0) p.rotation.x = std::numeric_limits<float>::quiet_NaN();
  return p;
}

template <class Mesh>
void check_overlaps(Mesh const& mesh, Iso3 const& mesh_pose, QueryShape const& qs,
                    Iso3 const& pose) {
  std::visit(
      [&](auto const& shape) {
        std::vector<std::uint32_t> got;
        bool const any = mesh_overlaps(mesh, mesh_pose, shape, pose, [&](std::uint32_t t) {
          got.push_back(t);
          return true;
        });
        PLUME_FUZZ_CHECK(any == !got.empty());
        PLUME_FUZZ_CHECK(mesh_intersects(mesh, mesh_pose, shape, pose) == any);
        PLUME_FUZZ_CHECK(std::is_sorted(got.begin(), got.end()));
        PLUME_FUZZ_CHECK(std::adjacent_find(got.begin(), got.end()) == got.end());
        if (!bool(mesh_pose.is_finite()) || !bool(pose.is_finite())) {
          PLUME_FUZZ_CHECK(got.empty());
          return;
        }
        // Only touching triangles, and every touching one well inside the shape's box.
        Aabb3 const local = detail::to_mesh_local(shape.aabb(pose), mesh_pose);
        float const scale =
            1.0f + std::max(local.min.abs().max_element(), local.max.abs().max_element());
        Aabb3 const inner = local.grow(-1e-3f * scale);
        for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
          ClosestPoints const c =
              closest_points(shape, pose, Triangle(mesh.triangle(t)), mesh_pose);
          bool const touches = !bool(c.failed) && (bool(c.overlap) || c.distance <= 0.0f);
          bool const reported = std::binary_search(got.begin(), got.end(), t);
          if (reported) PLUME_FUZZ_CHECK(touches);
          if (touches && bool(inner.is_valid()) &&
              bool(Triangle(mesh.triangle(t)).local_aabb().intersects(inner)))
            PLUME_FUZZ_CHECK(reported);
        }
      },
      qs);
}

template <class Mesh>
void check_shape_cast(Mesh const& mesh, Iso3 const& mesh_pose, QueryShape const& qs,
                      Iso3 const& pose, Vec3 const& motion, ShapeCastConfig const& cfg) {
  std::visit(
      [&](auto const& shape) {
        MeshShapeHit const got = mesh_shape_cast(mesh, mesh_pose, shape, pose, motion, cfg);
        bool const bad = !bool(mesh_pose.is_finite()) || !bool(pose.is_finite()) ||
                         !bool(motion.is_finite()) || !(cfg.max_toi >= 0.0f) ||
                         !std::isfinite(cfg.max_toi) || !(cfg.target_distance >= 0.0f) ||
                         !std::isfinite(cfg.target_distance);
        if (bad) {
          PLUME_FUZZ_CHECK(!got.hit());
          return;
        }
        MeshShapeHit want;
        bool capped = false;
        for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
          ShapeCastHit const c =
              shape_cast(shape, pose, motion, Triangle(mesh.triangle(t)), mesh_pose, cfg);
          capped = capped || bool(c.out_of_iterations);
          if (!bool(c.hit) || bool(c.failed)) continue;
          if (!(c.toi < want.toi || (c.toi == want.toi && t < want.triangle))) continue;
          want.triangle = t;
          want.toi = c.toi;
          want.point = c.point_b;
          want.normal = -c.normal;
          want.penetrating = bool(c.penetrating);
        }
        if (got.hit()) {
          PLUME_FUZZ_CHECK(got.triangle < mesh.triangle_count());
          PLUME_FUZZ_CHECK(got.toi >= 0.0f && got.toi <= cfg.max_toi);
          PLUME_FUZZ_CHECK(finite(got.point) && finite(got.normal));
        }
        if (capped) return; // the documented exception: a capped cast's early toi
        PLUME_FUZZ_CHECK(got.triangle == want.triangle);
        PLUME_FUZZ_CHECK(same_bits(got.toi, want.toi));
        PLUME_FUZZ_CHECK(same_bits(got.point, want.point));
        PLUME_FUZZ_CHECK(same_bits(got.normal, want.normal));
        PLUME_FUZZ_CHECK(got.penetrating == want.penetrating);
      },
      qs);
}

template <class Mesh>
void check_contacts(Mesh const& mesh, Iso3 const& mesh_pose, QueryShape const& qs, Iso3 const& pose,
                    float prediction) {
  std::visit(
      [&](auto const& shape) {
        MeshContactConfig cfg;
        cfg.manifold.prediction = prediction;
        MeshContacts const c = mesh_contacts(mesh, mesh_pose, shape, pose, cfg);
        bool const bad = !bool(mesh_pose.is_finite()) || !bool(pose.is_finite());
        PLUME_FUZZ_CHECK(c.failed == bad);
        PLUME_FUZZ_CHECK(c.count >= 0 && c.count <= max_mesh_manifolds);
        if (bad) PLUME_FUZZ_CHECK(c.count == 0);
        for (MeshManifold const& m : c) {
          PLUME_FUZZ_CHECK(m.triangle < mesh.triangle_count());
          PLUME_FUZZ_CHECK(m.manifold.count >= 1 && m.manifold.count <= 4);
          // Unit (for a triangle whose float cross product does not overflow).
          if (std::isfinite(Triangle(mesh.triangle(m.triangle)).scaled_normal().length_squared()))
            PLUME_FUZZ_CHECK(unit(m.manifold.normal, 1e-3f));
          for (ContactPoint const& p : m.manifold) {
            PLUME_FUZZ_CHECK(finite(p.point_a) && finite(p.point_b) && finite(p.separation));
            PLUME_FUZZ_CHECK(p.separation <= prediction + 1e-3f);
          }
        }
      },
      qs);
}

/// A ray aimed at the mesh: from anywhere, through a vertex or an edge of a triangle, or bad.
template <class Mesh>
Ray3 mesh_ray(Input& in, Mesh const& mesh, float reach) {
  std::uint8_t const k = in.byte();
  Vec3 o = in.vec3(-reach, reach);
  Vec3 d = in.vec3(-1, 1);
  if ((k & 3) != 0 && mesh.triangle_count() > 0) {
    Triangle const t =
        mesh.triangle(std::uint32_t(in.integer(0, 0x7fff)) % std::uint32_t(mesh.triangle_count()));
    Vec3 target = (k & 3) == 1 ? t.a : (k & 3) == 2 ? (t.a + t.b) * 0.5f : (t.a + t.b + t.c) / 3.0f;
    d = target - o;
    if (k & 4) d = d * in.real(0.5f, 4.0f);
  }
  if ((k & 0x18) == 0x08) d = Vec3{0.0f, -1.0f, 0.0f}; // straight down
  switch (k >> 5) {
  case 0:
    d = Vec3{}; // zero direction
    break;
  case 1:
    if (k & 4)
      o.x = in.any_float();
    else
      d.y = in.any_float();
    break;
  default:
    break;
  }
  return {o, d};
}

inline float mesh_max(Input& in) {
  std::uint8_t const k = in.byte();
  switch (k % 8) {
  case 0:
    return std::numeric_limits<float>::infinity();
  case 1:
    return (k & 8) ? std::numeric_limits<float>::quiet_NaN() : -in.real(0, 1);
  case 2:
    return 0.0f;
  default:
    return in.real(0, 40);
  }
}

inline Aabb3 mesh_box(Input& in, float reach) {
  std::uint8_t const k = in.byte();
  Vec3 const c = in.vec3(-reach, reach), h = in.vec3(0, reach * 0.5f);
  Aabb3 b{c - h, c + h};
  float const inf = std::numeric_limits<float>::infinity();
  switch (k % 8) {
  case 0:
    b.min.y = -inf;
    if (k & 8) b = {Vec3::splat(-inf), Vec3::splat(inf)};
    break;
  case 1:
    if (k & 8)
      b.max.x = std::numeric_limits<float>::quiet_NaN();
    else
      b.min.z = b.max.z + 1.0f;
    break;
  case 2:
    b = {c, c};
    break;
  default:
    break;
  }
  return b;
}

/// One decoded query of any kind against the mesh (placed at mesh_pose for the world forms).
template <class Mesh>
void fuzz_query(Input& in, Mesh const& mesh, float reach) {
  std::uint8_t const k = in.byte();
  switch (k % 7) {
  case 0:
  case 1: {
    Ray3 const ray = mesh_ray(in, mesh, reach);
    check_ray(mesh, ray, mesh_max(in));
    break;
  }
  case 2: {
    Iso3 const pose = query_pose(in, reach);
    Ray3 const ray = mesh_ray(in, mesh, reach);
    check_posed_ray(mesh, pose, ray, mesh_max(in));
    break;
  }
  case 3: {
    Vec3 p = in.vec3(-reach, reach);
    if ((k & 0x18) == 0x18) p.z = in.any_float();
    if ((k & 0x60) == 0x20 && mesh.triangle_count() > 0) // exactly on a vertex
      p = Triangle(mesh.triangle(std::uint32_t(in.byte()) % std::uint32_t(mesh.triangle_count())))
              .b;
    float const maxd = mesh_max(in);
    check_closest(mesh, p, maxd);
    if (k & 0x80) check_posed_closest(mesh, query_pose(in, reach), p, maxd);
    break;
  }
  case 4: { // the box first, then the stop count (function arguments are unsequenced)
    Aabb3 const box = mesh_box(in, reach);
    check_box(mesh, box, in.integer(1, 4));
    break;
  }
  case 5: {
    Iso3 const mesh_pose = (k & 8) ? query_pose(in, 2.0f) : Iso3{};
    QueryShape const s = query_shape(in);
    Iso3 const pose = query_pose(in, reach);
    check_overlaps(mesh, mesh_pose, s, pose);
    check_contacts(mesh, mesh_pose, s, pose, in.real(0, 0.1f));
    break;
  }
  default: {
    Iso3 const mesh_pose = (k & 8) ? query_pose(in, 2.0f) : Iso3{};
    QueryShape const s = query_shape(in);
    Iso3 const pose = query_pose(in, reach);
    Vec3 motion = in.vec3(-2.0f * reach, 2.0f * reach);
    if ((k & 0x30) == 0x30) motion = Vec3{};
    ShapeCastConfig cfg;
    cfg.max_toi = (k & 0x40) ? in.maybe_bad(0, 2) : 1.0f;
    cfg.target_distance = (k & 0x80) ? in.maybe_bad(0, 0.1f) : 0.0f;
    cfg.stop_at_penetration = in.flag();
    check_shape_cast(mesh, mesh_pose, s, pose, motion, cfg);
    break;
  }
  }
}

} // namespace plume::fuzz
