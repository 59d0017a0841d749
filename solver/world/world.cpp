// The rigid-body world (include/plume/solver/world/world.hpp). Compiled once per build, with
// World::step_with instantiated for float and every f32 width the build enables.
#include <plume/solver/world/world.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace plume {

std::string_view to_string(BodyError e) noexcept {
  switch (e) {
  case BodyError::none:
    return "none";
  case BodyError::non_finite:
    return "non-finite pose, velocity or material value";
  case BodyError::zero_mass:
    return "dynamic body without a positive finite mass";
  case BodyError::bad_material:
    return "negative density, friction, restitution or damping";
  case BodyError::bad_body:
    return "no such body (or no such standalone collider)";
  case BodyError::bad_shape:
    return "a mesh or height field without triangles, or on a dynamic body";
  }
  return "unknown";
}

namespace {

bool finite(float x) { return std::isfinite(x); }
bool finite(Vec3 const& v) { return v.is_finite(); }

MassProperties shape_mass(BodyShape const& shape, float density) {
  return std::visit(
      [&](auto const& s) -> MassProperties {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, HalfSpace> || is_triangle_shape_v<S>)
          return {0.0f, Vec3{}, Mat3::ZERO};
        else
          return s.mass_properties(density);
      },
      shape);
}

/// The distance from c (in the shape's frame) to the nearest point of the shape's surface, for
/// c inside the shape (its centre of mass): exact for the primitives, the nearest face plane
/// for a hull; 0 for shapes without an inside.
float shape_min_extent(BodyShape const& shape, Vec3 const& c) {
  return std::visit(
      [&](auto const& s) -> float {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Sphere> || std::is_same_v<S, Capsule>) {
          return s.radius;
        } else if constexpr (std::is_same_v<S, Cuboid>) {
          return std::min({s.half_extents.x, s.half_extents.y, s.half_extents.z});
        } else if constexpr (std::is_same_v<S, Cylinder>) {
          return std::min(s.half_height, s.radius);
        } else if constexpr (std::is_same_v<S, ConvexHull>) {
          float d = std::numeric_limits<float>::infinity();
          for (HullFace const& f : s.faces())
            d = std::min(d, f.offset - f.normal.dot(c));
          return s.faces().empty() ? 0.0f : std::max(d, 0.0f);
        } else {
          return 0.0f;
        }
      },
      shape);
}

/// The distance from c (in the shape's frame: its centre of mass) to the farthest point of the
/// shape: exact for the primitives and hulls; 0 for shapes without an inside.
float shape_max_extent(BodyShape const& shape, Vec3 const& c) {
  return std::visit(
      [&](auto const& s) -> float {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Sphere>) {
          return c.length() + s.radius;
        } else if constexpr (std::is_same_v<S, Capsule>) {
          Vec3 const top{0.0f, s.half_height, 0.0f};
          return std::max((c - top).length(), (c + top).length()) + s.radius;
        } else if constexpr (std::is_same_v<S, Cuboid>) {
          return (c.abs() + s.half_extents).length();
        } else if constexpr (std::is_same_v<S, Cylinder>) {
          float const rim = std::sqrt(c.x * c.x + c.z * c.z) + s.radius;
          float const cap = std::abs(c.y) + s.half_height;
          return std::sqrt(rim * rim + cap * cap);
        } else if constexpr (std::is_same_v<S, ConvexHull>) {
          float d = 0.0f;
          for (Vec3 const& v : s.vertices())
            d = std::max(d, (v - c).length());
          return d;
        } else {
          return 0.0f;
        }
      },
      shape);
}

/// The pose with its rotation normalised; none when it is not finite or its rotation has no
/// finite non-zero length.
std::optional<Iso3> normalised(Iso3 const& pose) {
  float const qlen = pose.rotation.length();
  if (!pose.is_finite() || !(qlen > 0.0f) || !std::isfinite(qlen)) return std::nullopt;
  return Iso3{pose.rotation * (1.0f / qlen), pose.translation};
}

/// Whether the shape is a mesh or height field (no_source: without triangles).
bool triangle_shape(BodyShape const& shape, bool no_source = false) {
  return std::visit(
      [&](auto const& s) {
        if constexpr (is_triangle_shape_v<std::decay_t<decltype(s)>>)
          return !no_source || s.source() == nullptr || s.source()->empty();
        else
          return false;
      },
      shape);
}

Aabb3 shape_aabb(BodyShape const& shape, Iso3 const& pose) {
  return std::visit([&](auto const& s) { return s.aabb(pose); }, shape);
}

/// The distance from the shape's origin to its farthest point: exact for the primitives and
/// hulls, the farthest corner of the local bounds for a mesh or height field, infinite for a
/// half-space.
float shape_reach(BodyShape const& shape) {
  if (std::holds_alternative<HalfSpace>(shape)) return std::numeric_limits<float>::infinity();
  if (!triangle_shape(shape)) return shape_max_extent(shape, Vec3{});
  Aabb3 const box = shape_aabb(shape, Iso3::IDENTITY);
  if (!box.is_valid()) return 0.0f; // an empty mesh: never touches anything
  return box.min.abs().max(box.max.abs()).length();
}

std::uint64_t fnv(std::uint64_t h, float x) {
  std::uint32_t const b = std::bit_cast<std::uint32_t>(x);
  for (int i = 0; i < 4; ++i) {
    h ^= (b >> (8 * i)) & 0xffu;
    h *= 1099511628211ull;
  }
  return h;
}

} // namespace

bool World::give_mass(Body& b) {
  MassProperties const mp = shape_mass(b.shape, b.density);
  if (!(mp.mass > 0.0f) || !std::isfinite(mp.mass) || !finite(mp.center) || !mp.inertia.is_finite())
    return false;
  b.mass = mp.mass;
  b.inv_mass = 1.0f / mp.mass;
  b.local_center = mp.center;
  b.inertia_local = mp.inertia;
  auto const inv = mp.inertia.try_inverse();
  b.inv_inertia_local = inv.valid && inv.value.is_finite() ? inv.value : Mat3::ZERO;
  b.min_extent = shape_min_extent(b.shape, b.local_center);
  b.max_extent = shape_max_extent(b.shape, b.local_center);
  return true;
}

BodyError World::set_type(BodyId id, BodyType type) {
  if (!is_alive(id)) return BodyError::bad_body;
  std::uint32_t const i = id.index;
  Body& b = bodies_[i];
  if (b.type == type && !b.frozen) return BodyError::none;
  if (type == BodyType::dynamic) { // checked before anything wakes: a refusal changes nothing
    if (triangle_shape(b.shape)) return BodyError::bad_shape;
    Body probe = b;
    if (!give_mass(probe)) return BodyError::zero_mass;
  }
  wake_around(i);
  if (type == BodyType::dynamic) {
    if (triangle_shape(b.shape)) return BodyError::bad_shape;
    Body probe = b;
    if (!give_mass(probe)) return BodyError::zero_mass;
    b = std::move(probe);
  } else {
    b.mass = b.inv_mass = 0.0f;
    b.local_center = Vec3{};
    b.inertia_local = b.inv_inertia_local = b.inv_inertia_world = Mat3::ZERO;
  }
  b.center = b.pose.transform_point(b.local_center);
  // The contacts' colours were taken under the old type: release them; the next step finds
  // the contacts again.
  std::uint32_t const one[] = {i};
  cache_.remove_bodies(one);
  reset_joint_impulses(one); // its joints' impulses were for the old type
  BodyType const was = b.type;
  b.type = type;
  if (b.frozen) { // a frozen body set to any type starts afresh, at rest where it stopped
    b.frozen = false;
    states_[i] = BodyState{};
  }
  if (type == BodyType::static_body) {
    states_[i] = BodyState{}; // stopped
    moving_bodies_.erase(std::remove(moving_bodies_.begin(), moving_bodies_.end(), i),
                         moving_bodies_.end());
    stale_moving_.erase(std::remove(stale_moving_.begin(), stale_moving_.end(), i),
                        stale_moving_.end());
    mark_stale_static(i); // the next sync moves it to the static tree
  } else {
    if (was == BodyType::static_body) {
      stale_statics_.erase(std::remove(stale_statics_.begin(), stale_statics_.end(), i),
                           stale_statics_.end());
      moving_bodies_.insert(std::lower_bound(moving_bodies_.begin(), moving_bodies_.end(), i), i);
    }
    mark_stale_moving(i); // the next sync files it under its new kind
  }
  trees_synced_ = false;
  return BodyError::none;
}

World::World(WorldConfig const& cfg) : config_(cfg) {
  config_.manifold.prediction = cfg.speculative_distance;
  states_.push_back(BodyState{}); // the identity record static bodies share
}

CreateBodyResult World::create_body(BodyDef const& def) {
  if (!def.pose.is_finite() || !finite(def.linear_velocity) || !finite(def.angular_velocity) ||
      !finite(def.density) || !finite(def.friction) || !finite(def.restitution) ||
      !finite(def.linear_damping) || !finite(def.angular_damping) || !finite(def.gravity_scale) ||
      !finite(def.sleep_threshold))
    return {{}, BodyError::non_finite};
  if (def.density < 0.0f || def.friction < 0.0f || def.restitution < 0.0f ||
      def.linear_damping < 0.0f || def.angular_damping < 0.0f || def.sleep_threshold < 0.0f)
    return {{}, BodyError::bad_material};
  if (triangle_shape(def.shape, true) ||
      (def.type == BodyType::dynamic && triangle_shape(def.shape)))
    return {{}, BodyError::bad_shape};
  std::optional<Iso3> const pose = normalised(def.pose);
  if (!pose) return {{}, BodyError::non_finite};

  Body b;
  b.type = def.type;
  b.pose = *pose;
  b.shape = def.shape;
  b.friction = def.friction;
  b.restitution = def.restitution;
  b.linear_damping = def.linear_damping;
  b.angular_damping = def.angular_damping;
  b.gravity_scale = def.gravity_scale;
  b.layers = def.layers;
  b.sensor = def.sensor;
  b.bullet = def.bullet;
  b.density = def.density;
  b.sleep_enabled = def.enable_sleep;
  b.sleep_threshold = def.sleep_threshold;
  if (def.type == BodyType::dynamic && !give_mass(b)) return {{}, BodyError::zero_mass};
  b.center = b.pose.transform_point(b.local_center);

  BodyState s;
  if (def.type != BodyType::static_body) {
    s.linear_velocity = def.linear_velocity;
    s.angular_velocity = def.angular_velocity;
  }
  std::uint32_t const index = take_slot(std::move(b), s);
  BodyId const id{index, bodies_[index].generation};
  if (bodies_[id.index].type == BodyType::static_body) {
    mark_stale_static(id.index);
  } else { // kept in index order: the step visits moving bodies in it
    moving_bodies_.insert(std::lower_bound(moving_bodies_.begin(), moving_bodies_.end(), id.index),
                          id.index);
    mark_stale_moving(id.index);
  }
  trees_synced_ = false;
  if (def.type != BodyType::dynamic) {
    wake_in(id.index); // what it appears on must move out of it
  } else if (!def.awake && def.enable_sleep && config_.sleep) {
    sleep_islands({{id.index}});
  }
  return {id, BodyError::none};
}

std::uint32_t World::take_slot(Body&& b, BodyState const& s) {
  b.reach = shape_reach(b.shape);
  if (!free_slots_.empty()) { // the last freed slot, at its next generation
    std::uint32_t const i = free_slots_.back();
    free_slots_.pop_back();
    b.generation = bodies_[i].generation;
    bodies_[i] = std::move(b);
    states_[i] = s;
    return i;
  }
  auto const i = std::uint32_t(bodies_.size());
  b.generation = 0;
  bodies_.push_back(std::move(b));
  states_.back() = s;
  states_.push_back(BodyState{}); // the identity record moves up one
  cache_.reserve_bodies(bodies_.size());
  return i;
}

CreateColliderResult World::create_collider(ColliderDef const& def) {
  if (!def.pose.is_finite() || !finite(def.friction) || !finite(def.restitution))
    return {{}, BodyError::non_finite};
  if (def.friction < 0.0f || def.restitution < 0.0f) return {{}, BodyError::bad_material};
  if (triangle_shape(def.shape, true)) return {{}, BodyError::bad_shape};
  std::optional<Iso3> const pose = normalised(def.pose);
  if (!pose) return {{}, BodyError::non_finite};
  Body b;
  b.type = BodyType::static_body;
  b.standalone = true;
  b.pose = *pose;
  b.center = b.pose.translation;
  b.shape = def.shape;
  b.friction = def.friction;
  b.restitution = def.restitution;
  b.layers = def.layers;
  b.sensor = def.sensor;
  std::uint32_t const i = take_slot(std::move(b), BodyState{});
  ++standalone_count_;
  mark_stale_static(i); // filed in the standalone tree at the next sync
  trees_synced_ = false;
  wake_in(i);
  return {collider_at(i), BodyError::none};
}

BodyError World::destroy_collider(ColliderId id) {
  if (!is_alive(id) || !id.standalone) return BodyError::bad_body;
  release_slot(id.index);
  --standalone_count_;
  return BodyError::none;
}

World::Body const& World::slot(ColliderId id) const {
  if (!is_alive(id))
    throw std::out_of_range("plume::World: the collider id (slot " + std::to_string(id.index) +
                            ", generation " + std::to_string(id.generation) +
                            (id.standalone ? ", standalone" : ", a body's") +
                            ") names no live collider (never created, or destroyed)");
  return bodies_[id.index];
}

ColliderId World::collider_id(std::uint32_t index) const {
  if (index >= bodies_.size() || !bodies_[index].alive)
    throw std::out_of_range("plume::World::collider_id: slot " + std::to_string(index) +
                            " holds no live collider");
  return collider_at(index);
}

Aabb3 World::aabb(ColliderId id) const {
  Body const& b = slot(id);
  return shape_aabb(b.shape, b.pose);
}

BodyError World::set_collider_pose(ColliderId id, Iso3 const& pose) {
  if (!is_alive(id) || !id.standalone) return BodyError::bad_body;
  std::optional<Iso3> const unit = normalised(pose);
  if (!unit) return BodyError::non_finite;
  wake_around(id.index);
  Body& b = bodies_[id.index];
  b.pose = *unit;
  b.center = b.pose.translation;
  mark_stale_static(id.index);
  trees_synced_ = false;
  wake_in(id.index);
  return BodyError::none;
}

BodyError World::set_collider_layers(ColliderId id, CollisionLayers const& layers) {
  if (!is_alive(id) || !id.standalone) return BodyError::bad_body;
  wake_around(id.index);
  bodies_[id.index].layers = layers;
  wake_in(id.index);
  return BodyError::none;
}

World::Body const& World::body(BodyId id) const {
  if (!is_alive(id))
    throw std::out_of_range("plume::World: the body id (slot " + std::to_string(id.index) +
                            ", generation " + std::to_string(id.generation) +
                            ") names no live body (never created, or destroyed)");
  return bodies_[id.index];
}

BodyId World::body_id(std::uint32_t index) const {
  if (index >= bodies_.size() || !bodies_[index].alive || bodies_[index].standalone)
    throw std::out_of_range("plume::World::body_id: slot " + std::to_string(index) +
                            " holds no live body");
  return {index, bodies_[index].generation};
}

BodyError World::destroy_body(BodyId id) {
  if (!is_alive(id)) return BodyError::bad_body;
  for (JointId const j : body_joints(id)) // its joints go first (they hold its colours)
    destroy_joint(j);
  frozen_.erase(std::remove(frozen_.begin(), frozen_.end(), id), frozen_.end());
  release_slot(id.index);
  return BodyError::none;
}

void World::release_slot(std::uint32_t i) {
  wake_around(i); // what it held up, or touched, moves on; its own island too
  flush_woken();  // its contacts, woken or not, end below
  // Its contacts and sensor overlaps end now: the next step reports them.
  auto const end_pairs = [&](std::vector<std::uint64_t>& keys, std::vector<ColliderPair>& ended) {
    std::erase_if(keys, [&](std::uint64_t k) {
      if (body_pair_first(k) != i && body_pair_second(k) != i) return false;
      ended.push_back(pair_ids(k));
      return true;
    });
  };
  end_pairs(touching_now_, pending_.contact_end);
  end_pairs(sensor_now_, pending_.sensor_end);
  std::uint32_t const one[] = {i};
  cache_.remove_bodies(one);
  bvh_.remove(i);
  auto const drop = [i](std::vector<std::uint32_t>& v) {
    v.erase(std::remove(v.begin(), v.end(), i), v.end());
  };
  drop(moving_bodies_);
  drop(stale_statics_);
  drop(stale_moving_);
  Body& b = bodies_[i];
  Body dead;
  dead.alive = false;
  dead.generation = b.generation + 1;
  b = std::move(dead);
  states_[i] = BodyState{};
  free_slots_.push_back(i);
}

Aabb3 World::aabb(BodyId id) const {
  Body const& b = body(id);
  return shape_aabb(b.shape, b.pose);
}

BodyError World::set_pose(BodyId id, Iso3 const& pose) {
  if (!is_alive(id)) return BodyError::bad_body;
  std::optional<Iso3> const unit = normalised(pose);
  if (!unit) return BodyError::non_finite;
  wake_around(id.index);
  Body& b = bodies_[id.index];
  b.pose = *unit;
  b.center = b.pose.transform_point(b.local_center);
  if (b.type == BodyType::static_body)
    mark_stale_static(id.index);
  else
    mark_stale_moving(id.index);
  trees_synced_ = false;
  wake_in(id.index);
  return BodyError::none;
}

BodyError World::set_velocity(BodyId id, Vec3 const& linear, Vec3 const& angular) {
  if (!is_alive(id)) return BodyError::bad_body;
  if (!finite(linear) || !finite(angular)) return BodyError::non_finite;
  if (bodies_[id.index].type == BodyType::static_body) return BodyError::none;
  wake(id.index);
  states_[id.index].linear_velocity = linear;
  states_[id.index].angular_velocity = angular;
  return BodyError::none;
}

Vec3 World::velocity_at(BodyId id, Vec3 const& point) const {
  Body const& b = body(id);
  if (b.type == BodyType::static_body) return {};
  BodyState const& s = states_[id.index];
  return s.linear_velocity + s.angular_velocity.cross(point - b.center);
}

BodyError World::apply_impulse(BodyId id, Vec3 const& impulse, Vec3 const& point) {
  if (!is_alive(id)) return BodyError::bad_body;
  if (!finite(impulse) || !finite(point)) return BodyError::non_finite;
  Body const& b = bodies_[id.index];
  if (!b.is_dynamic()) return BodyError::none;
  wake(id.index);
  Mat3 const inv_inertia = b.inv_inertia_local.rotate_inertia(Mat3::from_quat(b.pose.rotation));
  BodyState& s = states_[id.index];
  s.linear_velocity = s.linear_velocity + impulse * b.inv_mass;
  s.angular_velocity = s.angular_velocity + inv_inertia.mul_vec3((point - b.center).cross(impulse));
  return BodyError::none;
}

double World::kinetic_energy() const {
  double e = 0.0;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Body const& b = bodies_[i];
    if (!b.is_dynamic()) continue;
    Vec3 const v = states_[i].linear_velocity, w = states_[i].angular_velocity;
    Mat3 const r = Mat3::from_quat(b.pose.rotation);
    Vec3 const iw = b.inertia_local.rotate_inertia(r).mul_vec3(w);
    e += 0.5 * double(b.mass) * double(v.dot(v)) + 0.5 * double(w.dot(iw));
  }
  return e;
}

std::uint64_t World::state_hash() const {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (!bodies_[i].alive) continue;
    Iso3 const& p = bodies_[i].pose;
    for (float x : {p.translation.x, p.translation.y, p.translation.z, p.rotation.x, p.rotation.y,
                    p.rotation.z, p.rotation.w})
      h = fnv(h, x);
    BodyState const& s = states_[i];
    for (float x : {s.linear_velocity.x, s.linear_velocity.y, s.linear_velocity.z,
                    s.angular_velocity.x, s.angular_velocity.y, s.angular_velocity.z})
      h = fnv(h, x);
  }
  return h;
}

} // namespace plume
