// The world's spatial queries (include/plume/solver/world/world.hpp): candidates from the
// broad phase's trees, then the exact query on each candidate's shape at its pose. The batch
// forms' entry points are in entry_points.cpp; a PLUME_DISPATCH=ON build also compiles this
// file once per carried set (world_kernels.cpp).
#include <plume/solver/world/world.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace plume {

namespace {

constexpr float big = std::numeric_limits<float>::max();

/// The ray against one body's shape: analytic where collision/ray_cast.hpp has the shape, GJK
/// for hulls. Solid: a ray from inside hits at 0.
RayHit cast_ray(BodyShape const& shape, Iso3 const& pose, Ray3 const& ray, float max_toi) {
  return std::visit(
      [&](auto const& s) -> RayHit {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, ConvexHull>) {
          return ray_cast_gjk(s, pose, ray, max_toi);
        } else if constexpr (is_triangle_shape_v<S>) {
          MeshRayHit const h = s.source()->ray_cast(pose, ray, max_toi);
          RayHit r{h.hit(), h.toi, h.hit() ? h.normal : Vec3{},
                   h.hit() ? float(h.triangle) : -1.0f};
          return r;
        } else
          return ray_cast(s, pose, ray, max_toi);
      },
      shape);
}

/// The half-space's normal and a point of its plane, in world space.
struct WorldPlane {
  Vec3 normal, origin;
  float height(Vec3 const& p) const { return normal.dot(p - origin); }
};
WorldPlane world_plane(HalfSpace const& h, Iso3 const& pose) {
  return {pose.transform_vector(h.normal), pose.translation};
}

/// A convex query shape's deepest point along -n (its support in direction -n).
template <class Q>
Vec3 support_world(Q const& q, Iso3 const& pose, Vec3 const& dir) {
  Vec3 const local = pose.inverse_transform_vector(dir);
  Vec3 const core = pose.transform_point(q.core_support(local));
  return core + dir * q.core_radius();
}

template <class F>
decltype(auto) with_convex(BodyShape const& shape, F&& f) {
  return std::visit(
      [&](auto const& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, HalfSpace> || is_triangle_shape_v<S>)
          return f(Sphere{0.0f}, false); // not a query shape: callers stop on `false`
        else
          return f(s, true);
      },
      shape);
}

Aabb3 clamp_box(Aabb3 const& b) { // infinite query boxes become the largest finite one
  return {b.min.max(Vec3::splat(-big)), b.max.min(Vec3::splat(big))};
}

} // namespace

void World::sync_trees(TaskSystem* tasks) const {
  if (trees_synced_) return;
  auto const refit = [&](std::uint32_t i) { bvh_.set_box(i, grown_aabb(i), moving_kind(i)); };
  if (all_moving_stale_) {
    // The boxes on the tasks' threads, then the trees, in body order.
    std::uint32_t const n = std::uint32_t(moving_bodies_.size());
    moving_boxes_.resize(n);
    parallel_for(tasks, n, 256, [&](std::uint32_t begin, std::uint32_t end) {
      for (std::uint32_t k = begin; k < end; ++k)
        moving_boxes_[k] = grown_aabb(moving_bodies_[k]);
    });
    for (std::uint32_t k = 0; k < n; ++k)
      bvh_.set_box(moving_bodies_[k], moving_boxes_[k], moving_kind(moving_bodies_[k]));
  } else { // only what was edited, in index order as the full pass would meet them
    std::sort(stale_moving_.begin(), stale_moving_.end());
    stale_moving_.erase(std::unique(stale_moving_.begin(), stale_moving_.end()),
                        stale_moving_.end());
    for (std::uint32_t i : stale_moving_)
      if (bodies_[i].alive && bodies_[i].type != BodyType::static_body) refit(i);
  }
  stale_moving_.clear();
  all_moving_stale_ = false;
  for (std::uint32_t i : stale_statics_) // every new or teleported static body or collider
    if (bodies_[i].alive)
      bvh_.set_box(i, grown_aabb(i),
                   bodies_[i].standalone ? ProxyKind::standalone : ProxyKind::static_body);
  stale_statics_.clear();
  // Sort and sweep never asks the trees for pairs: keep their quality here. The BVH broad
  // phase optimises the trees in the step; until then, after static edits, queries walk the
  // static tree itself (its wide copy is stale), so that a query never rebuilds a level.
  if (config_.broad_phase == BroadPhaseKind::sort_and_sweep) bvh_.optimize();
  trees_synced_ = true;
}

bool World::passes(std::uint32_t i, QueryFilter const& filter) const {
  if ((bodies_[i].layers.memberships & filter.mask) == 0) return false;
  if (!filter.sensors && bodies_[i].sensor) return false;
  for (BodyId const e : filter.exclude) // a stale id excludes nothing (not the slot's new body)
    if (e.index == i && e.generation == bodies_[i].generation && !bodies_[i].standalone)
      return false;
  return !filter.predicate || filter.predicate(collider_at(i));
}

void World::candidates(Aabb3 const& box, QueryFilter const& filter,
                       std::vector<std::uint32_t>& out) const {
  out.clear();
  sync_trees();
  Aabb3 const q = clamp_box(box);
  if (!bool(q.is_valid())) return;
  for (AabbTree const* tree : bvh_.trees()) {
    auto const take = [&](ProxyId p) {
      auto const i = std::uint32_t(tree->user(p));
      if (bool(bvh_.box(i).intersects(q)) && passes(i, filter)) out.push_back(i);
      return true;
    };
    if (tree == &bvh_.tree(ProxyKind::static_body))
      bvh_.query_static(q, take); // the wide copy: most bodies of a level are static
    else
      tree->query(q, take);
  }
  for (std::uint32_t i : bvh_.unbounded())
    if (bool(bvh_.box(i).intersects(q)) && passes(i, filter)) out.push_back(i);
  std::sort(out.begin(), out.end());
}

BodyError World::set_layers(BodyId id, CollisionLayers const& layers) {
  if (!is_alive(id)) return BodyError::bad_body;
  wake_around(id.index);
  bodies_[id.index].layers = layers;
  wake_in(id.index); // pairs the new layers allow
  return BodyError::none;
}

BodyError World::set_bullet(BodyId id, bool bullet) {
  if (!is_alive(id)) return BodyError::bad_body;
  wake(id.index);
  bodies_[id.index].bullet = bullet;
  return BodyError::none;
}

// ------------------------------------------------------------------------ rays

namespace {
/// The closest-hit rule of every ray form: a hit replaces the best when it is nearer, or as
/// near on a lower body index (so the answer does not depend on the order bodies are met).
bool nearer(float toi, std::uint32_t i, float best_toi, std::uint32_t best_i) {
  return toi < best_toi || (toi == best_toi && i < best_i);
}
/// Finite origin and direction, a direction that is not zero, max_toi >= 0 (not NaN).
bool usable(Ray3 const& ray, float max_toi) {
  return bool(ray.origin.is_finite()) && bool(ray.dir.is_finite()) &&
         ray.dir.length_squared() > 0.0f && max_toi >= 0.0f;
}
} // namespace

void World::ray_cast_all(Ray3 const& ray, float max_toi,
                         std::function<bool(WorldRayHit const&)> const& f,
                         QueryFilter const& filter) const {
  if (!usable(ray, max_toi)) return;
  sync_trees();
  float const limit = std::min(max_toi, big);
  std::vector<WorldRayHit> hits;
  auto const test = [&](std::uint32_t i) {
    if (!passes(i, filter)) return;
    Body const& b = bodies_[i];
    RayHit const h = cast_ray(b.shape, b.pose, ray, limit);
    if (h.hit) hits.push_back(ray_hit(i, h.toi, ray.at(h.toi), h.normal));
  };
  for (AabbTree const* tree : bvh_.trees()) {
    auto const visit = [&](ProxyId p, float) {
      test(std::uint32_t(tree->user(p)));
      return limit;
    };
    if (tree == &bvh_.tree(ProxyKind::static_body))
      bvh_.ray_static(ray, limit, visit);
    else
      tree->ray_query(ray, limit, visit);
  }
  for (std::uint32_t i : bvh_.unbounded())
    test(i);
  std::sort(hits.begin(), hits.end(), [](WorldRayHit const& a, WorldRayHit const& b) {
    return a.toi < b.toi || (a.toi == b.toi && a.collider.index < b.collider.index);
  });
  for (WorldRayHit const& h : hits)
    if (!f(h)) return;
}

std::optional<WorldRayHit> World::ray_cast(Ray3 const& ray, float max_toi,
                                           QueryFilter const& filter) const {
  if (!usable(ray, max_toi)) return {};
  sync_trees();
  std::optional<WorldRayHit> best;
  float limit = std::min(max_toi, big);
  auto const test = [&](std::uint32_t i) {
    if (!passes(i, filter)) return;
    Body const& b = bodies_[i];
    RayHit const h = cast_ray(b.shape, b.pose, ray, limit);
    if (!h.hit || h.toi > limit) return;
    if (best && !nearer(h.toi, i, best->toi, best->collider.index)) return;
    best = ray_hit(i, h.toi, ray.at(h.toi), h.normal);
    limit = h.toi;
  };
  // Closest first: each tree's traversal skips boxes entered beyond the best toi so far.
  for (AabbTree const* tree : bvh_.trees()) {
    auto const visit = [&](ProxyId p, float) {
      test(std::uint32_t(tree->user(p)));
      return limit;
    };
    if (tree == &bvh_.tree(ProxyKind::static_body))
      bvh_.ray_static(ray, limit, visit);
    else
      tree->ray_query(ray, limit, visit);
  }
  for (std::uint32_t i : bvh_.unbounded())
    test(i);
  return best;
}

namespace {
/// A shape of kind S in the lanes of T, lane k from at(k) (sizes may differ by lane): the
/// batch queries' query shapes, and a body's shape in every lane.
template <class T, class S, class At>
auto shape_lanes(At&& at) {
  constexpr std::size_t W = lanes_v<T>;
  std::array<float, W> a{}, b{}, c{};
  for (std::size_t k = 0; k < W; ++k) {
    S const& s = at(k);
    if constexpr (std::is_same_v<S, Sphere>) {
      a[k] = s.radius;
    } else if constexpr (std::is_same_v<S, Cuboid>) {
      a[k] = s.half_extents.x, b[k] = s.half_extents.y, c[k] = s.half_extents.z;
    } else if constexpr (std::is_same_v<S, HalfSpace>) {
      a[k] = s.normal.x, b[k] = s.normal.y, c[k] = s.normal.z;
    } else { // capsule, cylinder
      a[k] = s.half_height, b[k] = s.radius;
    }
  }
  auto const lanes = [](std::array<float, W> const& v) { return plume::load<T>(v.data()); };
  if constexpr (std::is_same_v<S, Sphere>)
    return GSphere<T>{lanes(a)};
  else if constexpr (std::is_same_v<S, Cuboid>)
    return GCuboid<T>{GVec3<T>{lanes(a), lanes(b), lanes(c)}};
  else if constexpr (std::is_same_v<S, HalfSpace>)
    return GHalfSpace<T>{GVec3<T>{lanes(a), lanes(b), lanes(c)}};
  else if constexpr (std::is_same_v<S, Capsule>)
    return GCapsule<T>{lanes(a), lanes(b)};
  else
    return GCylinder<T>{lanes(a), lanes(b)};
}
/// A body's shape in every lane of T.
template <class T, class S>
auto widen(S const& s) {
  return shape_lanes<T, S>([&](std::size_t) -> S const& { return s; });
}
} // namespace

template <class T>
void World::ray_cast_with(std::span<Ray3 const> rays, float max_toi,
                          std::span<std::optional<WorldRayHit>> out,
                          QueryFilter const& filter) const {
  if (out.size() != rays.size())
    throw std::invalid_argument("World::ray_cast: out and rays differ in length");
  constexpr std::size_t W = lanes_v<T>;
  sync_trees();
  float const limit0 = std::min(max_toi, big);
  for (std::size_t first = 0; first < rays.size(); first += W) {
    std::size_t const n = std::min(W, rays.size() - first);
    // The packet: unusable rays and the tail's empty lanes take no part (limit -1) and carry
    // a harmless ray.
    std::array<Vec3, W> origin, dir;
    alignas(64) std::array<float, W> limit;
    for (std::size_t k = 0; k < W; ++k) {
      bool const live = k < n && usable(rays[first + k], max_toi);
      origin[k] = live ? rays[first + k].origin : Vec3{};
      dir[k] = live ? rays[first + k].dir : Vec3::Y;
      limit[k] = live ? limit0 : -1.0f;
    }
    // Rays that start far apart walk different parts of the trees, and a packet would visit
    // the union of their paths: they (and a packet of one usable ray) run the single form,
    // which walks the static bodies' wide copy. Rays from within batch_ray_spread of each
    // other walk together.
    Aabb3 from = Aabb3::EMPTY;
    std::size_t live = 0;
    for (std::size_t k = 0; k < n; ++k)
      if (limit[k] >= 0.0f) {
        from = from.merge(Aabb3{origin[k], origin[k]});
        ++live;
      }
    if (live < 2 || !(from.max - from.min).cmple(Vec3::splat(batch_ray_spread)).all()) {
      for (std::size_t k = 0; k < n; ++k)
        out[first + k] = ray_cast(rays[first + k], max_toi, filter);
      continue;
    }
    GRay3<T> const packet{pack<T>(origin.data()), pack<T>(dir.data())};
    std::array<std::uint32_t, W> best_body;
    std::array<float, W> best_toi;
    std::array<Vec3, W> best_normal;
    best_body.fill(~std::uint32_t(0));
    // The single form's rule, per lane: a hit within the lane's limit that is nearer, or as
    // near on a lower body index, becomes the best and the new limit.
    auto const offer = [&](std::size_t k, std::uint32_t i, float toi, Vec3 const& normal) {
      if (toi > limit[k]) return;
      if (best_body[k] != ~std::uint32_t(0) && !nearer(toi, i, best_toi[k], best_body[k])) return;
      best_body[k] = i;
      best_toi[k] = toi;
      best_normal[k] = normal;
      limit[k] = toi;
    };
    auto const test = [&](std::uint32_t i, std::uint64_t lanes) {
      if (!passes(i, filter)) return;
      Body const& b = bodies_[i];
      std::visit(
          [&](auto const& s) {
            using S = std::decay_t<decltype(s)>;
            if (is_triangle_shape_v<S> || std::is_same_v<S, ConvexHull> ||
                std::popcount(lanes) == 1) {
              // Lane by lane, as the single form: meshes, hulls (a hull's support walks its
              // own edges), and a body only one ray reaches (one scalar cast is cheaper).
              for (std::uint64_t m = lanes; m; m &= m - 1) {
                auto const k = std::size_t(std::countr_zero(m));
                RayHit const h = cast_ray(b.shape, b.pose, {origin[k], dir[k]}, limit[k]);
                if (h.hit) offer(k, i, h.toi, h.normal);
              }
            } else if constexpr (!is_triangle_shape_v<S> && !std::is_same_v<S, ConvexHull>) {
              GIso3<T> const pose(b.pose);
              T const lim = plume::load_aligned<T>(limit.data());
              GRayHit<T> const h = plume::ray_cast(widen<T>(s), pose, packet, lim);
              alignas(64) std::array<float, W> toi, nx, ny, nz; // stored once, read by lane
              plume::store_aligned(toi.data(), h.toi);
              plume::store_aligned(nx.data(), h.normal.x);
              plume::store_aligned(ny.data(), h.normal.y);
              plume::store_aligned(nz.data(), h.normal.z);
              for (std::uint64_t m = lanes & plume::bitmask(h.hit); m; m &= m - 1) {
                auto const k = std::size_t(std::countr_zero(m));
                offer(k, i, toi[k], {nx[k], ny[k], nz[k]});
              }
            }
          },
          b.shape);
    };
    T lim = plume::load_aligned<T>(limit.data());
    for (AabbTree const* tree : bvh_.trees()) {
      auto const visit = [&](ProxyId p, std::uint64_t lanes) {
        test(std::uint32_t(tree->user(p)), lanes);
        lim = plume::load_aligned<T>(limit.data());
      };
      tree->ray_query_lanes(packet, lim, visit);
    }
    std::uint64_t all = 0;
    for (std::size_t k = 0; k < W; ++k)
      all |= limit[k] >= 0.0f ? std::uint64_t(1) << k : 0;
    if (all)
      for (std::uint32_t i : bvh_.unbounded())
        test(i, all);
    for (std::size_t k = 0; k < n; ++k) {
      auto& o = out[first + k];
      o.reset();
      if (best_body[k] == ~std::uint32_t(0)) continue;
      Ray3 const& ray = rays[first + k];
      std::uint32_t const i = best_body[k];
      o = ray_hit(i, best_toi[k], ray.at(best_toi[k]), best_normal[k]);
    }
  }
}

#define PLUME_INSTANTIATE_RAYS(T, lanes)                                                           \
  template void World::ray_cast_with<T>(std::span<Ray3 const>, float,                              \
                                        std::span<std::optional<WorldRayHit>>, QueryFilter const&) \
      const;
#if defined(PLUME_DISPATCH_ISA) // one set's copy of the queries (world_kernels.cpp)
PLUME_INSTANTIATE_RAYS(f32xN, 0)
#else
PLUME_FOR_EACH_F32_TYPE(PLUME_INSTANTIATE_RAYS)
#endif

// ------------------------------------------------------------------------ shapes

namespace {

/// The inputs every shape cast needs: a finite pose and motion, finite non-negative max_toi
/// and target distance.
bool usable_cast(Iso3 const& pose, Vec3 const& motion, ShapeCastConfig const& cfg) {
  return pose.is_finite() && bool(motion.is_finite()) && cfg.max_toi >= 0.0f &&
         std::isfinite(cfg.max_toi) && cfg.target_distance >= 0.0f &&
         std::isfinite(cfg.target_distance);
}

/// The box a cast's candidates are found in: the shape's boxes at both ends, grown by the
/// target distance.
template <class Q>
Aabb3 swept_box(Q const& q, Iso3 const& pose, Vec3 const& motion, ShapeCastConfig const& cfg) {
  Aabb3 const start = q.aabb(pose);
  Aabb3 const end = q.aabb(Iso3{pose.rotation, pose.translation + motion * cfg.max_toi});
  return start.merge(end).grow(cfg.target_distance);
}

/// A convex body's hit from lane k of a shape cast (the query shape is A, the body B): the
/// point on the body, the normal out of it; none for a miss or failed input.
template <class T>
std::optional<WorldShapeHit> body_hit(GShapeCastHit<T> const& c, std::size_t k) {
  if (!(plume::bitmask(c.hit) >> k & 1) || (plume::bitmask(c.failed) >> k & 1)) return {};
  WorldShapeHit h{};
  h.toi = plume::lane(c.toi, k);
  h.point = {plume::lane(c.point_b.x, k), plume::lane(c.point_b.y, k), plume::lane(c.point_b.z, k)};
  h.normal = -Vec3{plume::lane(c.normal.x, k), plume::lane(c.normal.y, k),
                   plume::lane(c.normal.z, k)}; // out of the body, toward the cast shape
  h.penetrating = bool(plume::bitmask(c.penetrating) >> k & 1);
  return h;
}

/// The convex shape q at `pose`, moving by t motion, against one body's shape at body_pose
/// (hit: toi, the point on the body, the normal out of it; the body id is the caller's).
template <class Q>
std::optional<WorldShapeHit> cast_against_body(BodyShape const& body, Iso3 const& body_pose,
                                               Q const& q, Iso3 const& pose, Vec3 const& motion,
                                               ShapeCastConfig const& cfg) {
  WorldShapeHit h{};
  bool hit = false;
  if (auto const* hs = std::get_if<HalfSpace>(&body)) {
    WorldPlane const plane = world_plane(*hs, body_pose);
    Vec3 const deepest = support_world(q, pose, -plane.normal);
    float const gap = plane.height(deepest) - cfg.target_distance;
    float const closing = -plane.normal.dot(motion);
    if (gap <= 0.0f) {
      // As the GJK cast: a start in contact is ignored when the motion leaves the plane
      // or runs along it.
      hit = cfg.stop_at_penetration || moves_into_surface(closing, motion.dot(motion));
      h.toi = 0.0f;
      h.penetrating = true;
    } else if (closing > 0.0f && gap <= closing * cfg.max_toi) {
      hit = true;
      h.toi = gap / closing;
    }
    Vec3 const at = deepest + motion * h.toi;
    h.point = at - plane.normal * plane.height(at);
    h.normal = plane.normal;
  } else {
    std::visit(
        [&](auto const& s) {
          using S = std::decay_t<decltype(s)>;
          if constexpr (is_triangle_shape_v<S>) {
            MeshShapeHit const c = mesh_shape_cast(*s.source(), body_pose, q, pose, motion, cfg);
            if (!c.hit()) return;
            hit = true;
            h.toi = c.toi;
            h.point = c.point;
            h.normal = c.normal;
            h.penetrating = c.penetrating;
          } else if constexpr (!std::is_same_v<S, HalfSpace>) {
            auto const c = body_hit(plume::shape_cast(q, pose, motion, s, body_pose, cfg), 0);
            if (!c) return;
            hit = true;
            h = *c;
          }
        },
        body);
  }
  if (!hit) return {};
  return h;
}

/// The shapes a batch cast packs into lanes (one kind per packet), and the body shapes it
/// casts against in lanes (the others go lane by lane).
template <class S>
inline constexpr bool lane_shape_v = std::is_same_v<S, Sphere> || std::is_same_v<S, Capsule> ||
                                     std::is_same_v<S, Cuboid> || std::is_same_v<S, Cylinder>;

} // namespace

std::optional<WorldShapeHit> detail::cast_against(BodyShape const& body, Iso3 const& body_pose,
                                                  BodyShape const& shape, Iso3 const& pose,
                                                  Vec3 const& motion, ShapeCastConfig const& cfg) {
  if (!usable_cast(pose, motion, cfg)) return {};
  return with_convex(shape, [&](auto const& q, bool convex) -> std::optional<WorldShapeHit> {
    if (!convex) return {};
    return cast_against_body(body, body_pose, q, pose, motion, cfg);
  });
}

std::optional<WorldShapeHit> World::shape_cast(BodyShape const& shape, Iso3 const& pose,
                                               Vec3 const& motion, ShapeCastConfig const& cfg,
                                               QueryFilter const& filter) const {
  if (!usable_cast(pose, motion, cfg)) return {};
  return with_convex(shape, [&](auto const& q, bool convex) -> std::optional<WorldShapeHit> {
    if (!convex) return {};
    std::vector<std::uint32_t> near;
    candidates(swept_box(q, pose, motion, cfg), filter, near);
    std::optional<WorldShapeHit> best;
    for (std::uint32_t i : near) {
      Body const& b = bodies_[i];
      auto h = cast_against_body(b.shape, b.pose, q, pose, motion, cfg);
      if (!h) continue;
      h->collider = collider_at(i);
      h->body = h->collider.body();
      if (!best || h->toi < best->toi) best = h; // ties: the lower index, visited first
    }
    return best;
  });
}

template <class T>
void World::shape_cast_with(std::span<BodyShape const> shapes, std::span<Iso3 const> poses,
                            std::span<Vec3 const> motions, ShapeCastConfig const& cfg,
                            std::span<std::optional<WorldShapeHit>> out,
                            QueryFilter const& filter) const {
  std::size_t const count = shapes.size();
  if (poses.size() != count || motions.size() != count || out.size() != count)
    throw std::invalid_argument(
        "World::shape_cast: shapes, poses, motions and out differ in length");
  constexpr std::size_t W = lanes_v<T>;
  std::vector<std::uint32_t> near;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> lane_of; // (body, lane)
  for (std::size_t first = 0; first < count; first += W) {
    lane_of.clear();
    std::size_t const n = std::min(W, count - first);
    for (std::size_t k = 0; k < n; ++k)
      out[first + k].reset();
    // A packet: consecutive queries of one lane kind; any other run goes one at a time.
    std::size_t const kind = shapes[first].index();
    bool const packable =
        std::visit([](auto const& s) { return lane_shape_v<std::decay_t<decltype(s)>>; },
                   shapes[first]) &&
        std::all_of(shapes.begin() + std::ptrdiff_t(first),
                    shapes.begin() + std::ptrdiff_t(first + n),
                    [&](BodyShape const& s) { return s.index() == kind; });
    if (!packable || !usable_cast(Iso3{}, Vec3{}, cfg)) {
      for (std::size_t k = 0; k < n; ++k)
        out[first + k] =
            shape_cast(shapes[first + k], poses[first + k], motions[first + k], cfg, filter);
      continue;
    }
    std::visit(
        [&](auto const& first_shape) {
          using S = std::decay_t<decltype(first_shape)>;
          if constexpr (lane_shape_v<S>) {
            // Each lane's swept box, as the single form's; unusable lanes take no part.
            std::uint64_t live = 0;
            std::array<Iso3, W> pose;
            std::array<Vec3, W> motion;
            for (std::size_t k = 0; k < W; ++k) {
              std::size_t const q = first + (k < n ? k : 0);
              pose[k] = poses[q];
              motion[k] = motions[q];
              if (k >= n || !usable_cast(pose[k], motion[k], cfg)) {
                pose[k] = Iso3{}; // harmless values for lanes that take no part
                motion[k] = Vec3{};
                continue;
              }
              // The lane's own candidates, found as the single form finds them.
              candidates(swept_box(std::get<S>(shapes[q]), pose[k], motion[k], cfg), filter, near);
              for (std::uint32_t i : near)
                lane_of.push_back({i, std::uint32_t(k)});
              live |= std::uint64_t(1) << k;
            }
            if (!live) return;
            // Each body once, with the lanes that have it, in increasing body index (the
            // order each lane's single form visits them).
            std::sort(lane_of.begin(), lane_of.end());
            auto const lanes_shape = shape_lanes<T, S>([&](std::size_t k) -> S const& {
              return std::get<S>(shapes[first + (k < n ? k : 0)]); // the tail repeats lane 0
            });
            std::array<Quat, W> rot;
            std::array<Vec3, W> at;
            for (std::size_t k = 0; k < W; ++k) {
              rot[k] = pose[k].rotation;
              at[k] = pose[k].translation;
            }
            GIso3<T> const lanes_pose{pack<T>(rot.data()), pack<T>(at.data())};
            GVec3<T> const lanes_motion = pack<T>(motion.data());
            for (std::size_t g = 0; g < lane_of.size();) {
              std::uint32_t const i = lane_of[g].first;
              std::uint64_t lanes = 0; // the lanes whose own candidates include body i
              for (; g < lane_of.size() && lane_of[g].first == i; ++g)
                lanes |= std::uint64_t(1) << lane_of[g].second;
              Body const& b = bodies_[i];
              ColliderId const id = collider_at(i);
              auto const offer = [&](std::size_t k, WorldShapeHit h) {
                h.collider = id;
                h.body = id.body();
                auto& best = out[first + k];
                if (!best || h.toi < best->toi) best = h; // ties: the lower index, first
              };
              std::visit(
                  [&](auto const& bs) {
                    using B = std::decay_t<decltype(bs)>;
                    if constexpr (lane_shape_v<B>) {
                      if (std::popcount(lanes) == 1) { // one lane: the single form, cheaper
                        auto const k = std::size_t(std::countr_zero(lanes));
                        auto const h =
                            cast_against_body(b.shape, b.pose, std::get<S>(shapes[first + k]),
                                              pose[k], motion[k], cfg);
                        if (h) offer(k, *h);
                        return;
                      }
                      GShapeCastHit<T> const c =
                          plume::shape_cast(lanes_shape, lanes_pose, lanes_motion, widen<T>(bs),
                                            GIso3<T>(b.pose), cfg);
                      for (std::uint64_t m = lanes; m; m &= m - 1) {
                        auto const k = std::size_t(std::countr_zero(m));
                        if (auto const h = body_hit(c, k)) offer(k, *h);
                      }
                    } else { // half-spaces, hulls, meshes: lane by lane, as the single form
                      for (std::uint64_t m = lanes; m; m &= m - 1) {
                        auto const k = std::size_t(std::countr_zero(m));
                        auto const h =
                            cast_against_body(b.shape, b.pose, std::get<S>(shapes[first + k]),
                                              pose[k], motion[k], cfg);
                        if (h) offer(k, *h);
                      }
                    }
                  },
                  b.shape);
            }
          }
        },
        shapes[first]);
  }
}

#define PLUME_INSTANTIATE_SHAPES(T, lanes)                                                         \
  template void World::shape_cast_with<T>(                                                         \
      std::span<BodyShape const>, std::span<Iso3 const>, std::span<Vec3 const>,                    \
      ShapeCastConfig const&, std::span<std::optional<WorldShapeHit>>, QueryFilter const&) const;
#if defined(PLUME_DISPATCH_ISA)
PLUME_INSTANTIATE_SHAPES(f32xN, 0)
#else
PLUME_FOR_EACH_F32_TYPE(PLUME_INSTANTIATE_SHAPES)
#endif

void World::overlap_aabb(Aabb3 const& box, std::function<bool(ColliderId)> const& f,
                         QueryFilter const& filter) const {
  std::vector<std::uint32_t> near;
  candidates(box, filter, near);
  for (std::uint32_t i : near)
    if (!f(collider_at(i))) return;
}

namespace {

/// Whether the convex shape q at pose touches body shape b at pose_b.
template <class Q>
bool touches(Q const& q, Iso3 const& pose, BodyShape const& b, Iso3 const& pose_b) {
  if (auto const* hs = std::get_if<HalfSpace>(&b)) {
    WorldPlane const plane = world_plane(*hs, pose_b);
    return plane.height(support_world(q, pose, -plane.normal)) <= 0.0f;
  }
  return std::visit(
      [&](auto const& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, HalfSpace>) {
          return false;
        } else if constexpr (is_triangle_shape_v<S>) {
          return mesh_intersects(*s.source(), pose_b, q, pose);
        } else {
          ClosestPoints const c = closest_points(q, pose, s, pose_b);
          return !c.failed && (c.overlap || c.distance <= 0.0f);
        }
      },
      b);
}

} // namespace

bool World::shapes_touch(std::uint32_t a, std::uint32_t b) const {
  Body const& x = bodies_[a];
  Body const& y = bodies_[b];
  if (!is_convex_shape(x.shape)) {               // the convex one queries
    if (!is_convex_shape(y.shape)) return false; // two half-spaces or meshes: no answer
    return shapes_touch(b, a);
  }
  return with_convex(x.shape,
                     [&](auto const& q, bool) { return touches(q, x.pose, y.shape, y.pose); });
}

void World::overlap_shape(BodyShape const& shape, Iso3 const& pose,
                          std::function<bool(ColliderId)> const& f,
                          QueryFilter const& filter) const {
  if (!pose.is_finite()) return;
  with_convex(shape, [&](auto const& q, bool convex) {
    if (!convex) return 0;
    std::vector<std::uint32_t> near;
    candidates(q.aabb(pose), filter, near);
    for (std::uint32_t i : near)
      if (touches(q, pose, bodies_[i].shape, bodies_[i].pose) && !f(collider_at(i))) break;
    return 0;
  });
}

void World::contact_query(BodyShape const& shape, Iso3 const& pose, float distance,
                          std::function<bool(ColliderId, Manifold const&)> const& f,
                          QueryFilter const& filter) const {
  if (!pose.is_finite() || !(distance >= 0.0f) || !std::isfinite(distance) ||
      !is_convex_shape(shape))
    return;
  Aabb3 const box = with_convex(shape, [&](auto const& q, bool) { return q.aabb(pose); });
  if (!bool(box.min.is_finite()) || !bool(box.max.is_finite())) return;
  ManifoldConfig cfg = config_.manifold;
  cfg.prediction = distance;
  std::vector<std::uint32_t> near;
  candidates(box.grow(distance), filter, near);
  std::array<Manifold, max_mesh_manifolds> ms;
  for (std::uint32_t i : near) {
    int const n = detail::collide(bodies_[i].shape, bodies_[i].pose, shape, pose, cfg, ms);
    for (int k = 0; k < n; ++k) {
      Manifold const& m = ms[std::size_t(k)];
      if (m.empty() || m.failed) continue;
      if (!f(collider_at(i), m)) return;
    }
  }
}

void World::point_query(Vec3 const& point, std::function<bool(ColliderId)> const& f,
                        QueryFilter const& filter) const {
  if (!bool(point.is_finite())) return;
  std::vector<std::uint32_t> near;
  candidates({point, point}, filter, near);
  Iso3 const at = Iso3::from_translation(point);
  for (std::uint32_t i : near)
    if (touches(Sphere{0.0f}, at, bodies_[i].shape, bodies_[i].pose) && !f(collider_at(i))) return;
}

std::optional<WorldPointHit> World::project_point(Vec3 const& point, float max_distance,
                                                  QueryFilter const& filter) const {
  if (!bool(point.is_finite()) || !(max_distance >= 0.0f)) return {};
  float const reach = std::min(max_distance, big);
  std::vector<std::uint32_t> near;
  candidates(clamp_box(Aabb3{point, point}.grow(reach)), filter, near);
  Iso3 const at = Iso3::from_translation(point);
  std::optional<WorldPointHit> best;
  for (std::uint32_t i : near) {
    Body const& b = bodies_[i];
    WorldPointHit h{collider_at(i).body(), 0.0f, {}, collider_at(i)};
    if (auto const* hs = std::get_if<HalfSpace>(&b.shape)) {
      WorldPlane const plane = world_plane(*hs, b.pose);
      float const d = plane.height(point);
      h.distance = std::max(d, 0.0f);
      h.point = d > 0.0f ? point - plane.normal * d : point;
    } else if (!is_convex_shape(b.shape)) { // a mesh or height field
      MeshClosestPoint const c = std::visit(
          [&](auto const& s) -> MeshClosestPoint {
            if constexpr (is_triangle_shape_v<std::decay_t<decltype(s)>>)
              return s.source()->closest_point(b.pose, point, reach);
            else
              return {};
          },
          b.shape);
      if (!c.found()) continue;
      h.distance = c.distance;
      h.point = c.point;
    } else {
      ClosestPoints const c = std::visit(
          [&](auto const& s) -> ClosestPoints {
            using S = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<S, HalfSpace> || is_triangle_shape_v<S>)
              return {};
            else
              return closest_points(Sphere{0.0f}, at, s, b.pose);
          },
          b.shape);
      if (c.failed) continue;
      bool const inside = c.overlap || c.distance <= 0.0f;
      h.distance = inside ? 0.0f : c.distance;
      h.point = inside ? point : c.point_b;
    }
    if (h.distance > reach) continue;
    if (!best || h.distance < best->distance) best = h;
  }
  return best;
}

} // namespace plume
