// CharacterController (include/plume/solver/world/character_controller.hpp).
#include <plume/solver/world/character_controller.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <type_traits>
#include <variant>

namespace plume {

std::string_view to_string(GroundState s) noexcept {
  switch (s) {
  case GroundState::on_ground:
    return "on ground";
  case GroundState::on_steep_ground:
    return "on steep ground";
  case GroundState::not_supported:
    return "not supported";
  case GroundState::in_air:
    return "in air";
  }
  return "?";
}

std::string_view to_string(CharacterError e) noexcept {
  switch (e) {
  case CharacterError::none:
    return "none";
  case CharacterError::bad_shape:
    return "not a convex shape of finite positive size";
  case CharacterError::overlap:
    return "the new shape would overlap something";
  case CharacterError::non_finite:
    return "non-finite position, velocity or rotation";
  }
  return "?";
}

namespace {

/// Normals whose up component is at most this are walls or ceilings, not ground.
constexpr float ground_facing = 1e-3f;

/// A convex shape with a finite, positive size in every direction.
bool shape_ok(BodyShape const& shape) {
  if (!is_convex_shape(shape)) return false;
  Aabb3 const box = std::visit([](auto const& s) { return s.aabb(Iso3{}); }, shape);
  Vec3 const size = box.max - box.min;
  return bool(box.min.is_finite()) && bool(box.max.is_finite()) && size.x > 0.0f && size.y > 0.0f &&
         size.z > 0.0f;
}

/// How far the shape reaches from its frame's origin along the unit world direction `dir`
/// (its support distance), at rotation q.
float reach(BodyShape const& shape, Quat const& q, Vec3 const& dir) {
  Vec3 const d = q.inverse() * dir;
  return std::visit(
      [&](auto const& s) -> float {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, HalfSpace> || is_triangle_shape_v<S>) {
          return 0.0f;
        } else {
          return s.core_support(d).dot(d) + s.core_radius();
        }
      },
      shape);
}

Vec3 horizontal(Vec3 const& v, Vec3 const& up) { return v - up * v.dot(up); }

} // namespace

CharacterController::CharacterController(World& world, CharacterConfig const& cfg) : cfg_(cfg) {
  float const up_len = cfg.up.length();
  if (!(up_len > 0.0f) || !std::isfinite(up_len))
    throw std::invalid_argument("CharacterController: up must be a finite non-zero vector");
  cfg_.up = cfg.up / up_len;
  if (!shape_ok(cfg.shape))
    throw std::invalid_argument("CharacterController: the shape must be convex, of finite "
                                "positive size");
  if (!bool(cfg.position.is_finite()))
    throw std::invalid_argument("CharacterController: non-finite position");
  for (float x : {cfg.max_slope, cfg.ground_tolerance, cfg.step_height, cfg.min_step_forward,
                  cfg.step_forward_test, cfg.step_contact_angle, cfg.stick_to_floor, cfg.mass,
                  cfg.max_strength})
    if (!(x >= 0.0f) || !std::isfinite(x))
      throw std::invalid_argument("CharacterController: lengths, angles, mass and strength "
                                  "must be finite and non-negative");
  if (!(cfg.max_slope < 1.5707963f))
    throw std::invalid_argument("CharacterController: max_slope must be below 90 degrees");
  cos_slope_ = std::cos(cfg_.max_slope);
  position_ = cfg.position;
  rotation_ = Quat::from_rotation_arc(Vec3{0.0f, 1.0f, 0.0f}, cfg_.up);
  if (cfg_.proxy && !make_proxy(world))
    throw std::invalid_argument("CharacterController: the proxy body was refused");
}

CharacterController::CharacterController(CharacterController&& o) noexcept
    : cfg_(std::move(o.cfg_)), cos_slope_(o.cos_slope_), position_(o.position_),
      velocity_(o.velocity_), rotation_(o.rotation_), platform_rotation_(o.platform_rotation_),
      ground_(o.ground_), ground_pose_(o.ground_pose_), proxy_(o.proxy_),
      touched_(std::move(o.touched_)), pushes_(std::move(o.pushes_)), last_(o.last_) {
  o.proxy_ = BodyId{};
}

bool CharacterController::make_proxy(World& world) {
  BodyDef def;
  def.type = BodyType::kinematic;
  def.pose = pose_at(position_);
  def.shape = cfg_.shape;
  def.layers = CollisionLayers{cfg_.proxy_layers, 0u}; // filters 0: the step ignores it
  CreateBodyResult const made = world.create_body(def);
  proxy_ = made ? made.id : BodyId{};
  return bool(made);
}

QueryFilter CharacterController::own_filter() const {
  return filter(proxy_.valid() ? std::span<BodyId const>(&proxy_, 1) : std::span<BodyId const>());
}

QueryFilter CharacterController::filter(std::span<BodyId const> exclude) const {
  QueryFilter f;
  f.mask = cfg_.collides_with;
  f.exclude = exclude;
  f.sensors = cfg_.sensors_block; // sensors are triggers, not floors or walls
  return f;
}

Vec3 CharacterController::world_velocity() const noexcept {
  return ground_.state == GroundState::on_ground ? velocity_ + ground_.velocity : velocity_;
}

CharacterError CharacterController::set_velocity(Vec3 const& v) noexcept {
  if (!bool(v.is_finite())) return CharacterError::non_finite;
  velocity_ = v;
  return CharacterError::none;
}

CharacterError CharacterController::set_position(World& world, Vec3 const& p) {
  if (!bool(p.is_finite())) return CharacterError::non_finite;
  position_ = p;
  ground_ = CharacterGround{};
  if (proxy_.valid()) world.set_pose(proxy_, pose_at(position_));
  return CharacterError::none;
}

CharacterError CharacterController::set_rotation(World& world, Quat const& q) {
  float const len = q.length();
  if (!bool(q.is_finite()) || !(len > 0.0f) || !std::isfinite(len))
    return CharacterError::non_finite;
  rotation_ = q * (1.0f / len);
  if (proxy_.valid()) world.set_pose(proxy_, pose_at(position_));
  return CharacterError::none;
}

bool CharacterController::overlaps(World const& world, BodyShape const& shape, Vec3 const& position,
                                   float max_penetration) const {
  bool found = false;
  world.contact_query(
      shape, pose_at(position), 0.0f,
      [&](ColliderId, Manifold const& m) {
        for (auto const& c : m)
          if (c.separation < -max_penetration) found = true;
        return !found;
      },
      own_filter());
  return found;
}

CharacterError CharacterController::set_shape(World& world, BodyShape const& shape,
                                              float max_penetration) {
  if (!shape_ok(shape) || !(max_penetration >= 0.0f)) return CharacterError::bad_shape;
  Vec3 const down = -cfg_.up;
  Vec3 const p =
      position_ + cfg_.up * (reach(shape, rotation_, down) - reach(cfg_.shape, rotation_, down));
  if (overlaps(world, shape, p, max_penetration)) return CharacterError::overlap;
  cfg_.shape = shape;
  position_ = p;
  if (proxy_.valid()) { // a body's shape is fixed: a new proxy of the new shape
    world.destroy_body(proxy_);
    make_proxy(world);
  }
  return CharacterError::none;
}

void CharacterController::destroy(World& world) {
  if (proxy_.valid() && world.is_alive(proxy_)) world.destroy_body(proxy_);
  proxy_ = BodyId{};
}

std::optional<Vec3> CharacterController::surface_normal(World const& world, ColliderId collider,
                                                        Vec3 const& point, Vec3 const& p) const {
  // Short rays down just beside the contact point, toward the character's axis and away from
  // it: on an edge, one of them meets the face the edge bounds.
  Vec3 const up = cfg_.up;
  Vec3 toward = horizontal(p - point, up);
  float const len = toward.length();
  if (!(len > 0.0f)) return std::nullopt;
  toward = toward / len;
  float const probe = 2.0f * cfg_.move.skin;
  QueryFilter f;
  f.predicate = [collider](ColliderId id) { return id == collider; };
  for (float side : {1.0f, -1.0f}) {
    std::optional<WorldRayHit> const hit =
        world.ray_cast(Ray3{point + toward * (side * probe) + up * probe, -up}, 2.0f * probe, f);
    if (hit && walkable(hit->normal)) return hit->normal;
  }
  return std::nullopt;
}

CharacterGround CharacterController::find_ground(World const& world, Vec3 const& p) const {
  WorldMoveQuery const scene(world);
  QueryFilter const f = own_filter();
  Vec3 const up = cfg_.up;
  // The flattest walkable contact; else the flattest upward-facing one; else any.
  MoveContact<ColliderId> walk{}, steep{}, any{};
  bool has_walk = false, has_steep = false, has_any = false;
  float walk_up = -2.0f, steep_up = -2.0f;
  Vec3 steep_sum{};
  int steep_count = 0;
  scene.contacts(cfg_.shape, pose_at(p), cfg_.move.skin + cfg_.ground_tolerance, f,
                 [&](MoveContact<ColliderId> const& found) {
                   MoveContact<ColliderId> c = found;
                   float u = c.normal.dot(up);
                   // Resting on a ledge's edge, the contact's normal tilts with the shape's
                   // rounding: the face under the edge is what holds the character, and what
                   // its walk follows (not the rounding, which would steer it upward).
                   if (u > ground_facing && u < 1.0f - 1e-4f) {
                     if (std::optional<Vec3> const n =
                             surface_normal(world, c.collider, c.point, p)) {
                       c.normal = *n;
                       u = c.normal.dot(up);
                     }
                   }
                   if (!has_any) any = c;
                   has_any = true;
                   if (u >= cos_slope_ && u > ground_facing) {
                     // The nearest walkable contact holds it (ties: the flattest).
                     if (!has_walk || c.separation < walk.separation ||
                         (c.separation == walk.separation && u > walk_up))
                       walk = c, walk_up = u;
                     has_walk = true;
                   } else if (u > ground_facing) {
                     if (u > steep_up) steep = c, steep_up = u;
                     has_steep = true;
                     steep_sum = steep_sum + c.normal;
                     ++steep_count;
                   }
                   return true;
                 });
  CharacterGround g;
  MoveContact<ColliderId> const* from = nullptr;
  if (has_walk) {
    g.state = GroundState::on_ground;
    from = &walk;
  } else if (has_steep) {
    from = &steep;
    g.state = GroundState::on_steep_ground;
    // Wedged in a V of steep slopes whose normals together hold it up: it stands.
    float const len = steep_sum.length();
    if (steep_count >= 2 && len > 0.0f && walkable(steep_sum / len)) {
      g.state = GroundState::on_ground;
      g.collider = steep.collider;
      g.body = g.collider.body();
      g.point = steep.point;
      g.normal = steep_sum / len;
      g.separation = steep.separation;
      g.velocity = g.body.valid() ? world.velocity_at(g.body, g.point) : Vec3{};
      return g;
    }
  } else if (has_any) {
    g.state = GroundState::not_supported;
    from = &any;
  }
  if (from) {
    g.collider = from->collider;
    g.body = g.collider.body();
    g.point = from->point;
    g.normal = from->normal;
    g.separation = from->separation;
    g.velocity = g.body.valid() ? world.velocity_at(g.body, g.point) : Vec3{};
  }
  return g;
}

void CharacterController::carry(World& world, WorldMoveQuery const& scene) {
  if (ground_.state != GroundState::on_ground || !world.is_alive(ground_.body) ||
      world.type(ground_.body) == BodyType::static_body)
    return;
  Iso3 const now = world.pose(ground_.body);
  Iso3 const delta = now.mul_iso(ground_pose_.inverse()); // last update's world -> today's
  Vec3 const motion = delta.transform_point(position_) - position_;
  // The character turns with the platform about up only (it stays upright).
  Quat const q = delta.rotation;
  Vec3 const axis = cfg_.up * Vec3{q.x, q.y, q.z}.dot(cfg_.up);
  Quat twist = Quat::from_xyzw(axis.x, axis.y, axis.z, q.w);
  float const tl = twist.length();
  twist = tl > 0.0f ? twist * (1.0f / tl) : Quat::IDENTITY;
  if (!bool(motion.is_finite()) || !bool(twist.is_finite())) return;
  bool const turned = twist.x != 0.0f || twist.y != 0.0f || twist.z != 0.0f;
  if (turned) {
    platform_rotation_ = twist;
    rotation_ = (twist * rotation_).normalize();
    last_.carried = true;
  }
  if (!(motion.length_squared() > 0.0f)) return;
  BodyId const exclude[2] = {proxy_, ground_.body};
  QueryFilter const f = filter(proxy_.valid() ? std::span<BodyId const>(exclude)
                                              : std::span<BodyId const>(exclude + 1, 1));
  MoveAndSlideResult<ColliderId> const r =
      move_and_slide(scene, cfg_.shape, pose_at(position_), motion, 1.0f, cfg_.move, f);
  if (r.invalid_input) return;
  position_ = r.position;
  last_.carried = true;
}

bool CharacterController::walk_stairs(WorldMoveQuery const& scene, Vec3 const& forward) {
  Vec3 const up = cfg_.up;
  QueryFilter const f = own_filter();
  float const fwd_len = forward.length();
  if (!(fwd_len > 0.0f)) return false;
  Vec3 const dir = forward / fwd_len;
  // Up, as far as the ceiling lets it.
  CastMove<ColliderId> const rise =
      cast_move(scene, cfg_.shape, pose_at(position_), up * cfg_.step_height, cfg_.move, f);
  if (!(rise.safe > 0.0f)) return false;
  Vec3 const high = position_ + up * rise.safe;
  // Forward on the raised level: a step too high stops this at once.
  float const want = std::max(fwd_len, cfg_.min_step_forward);
  CastMove<ColliderId> const ahead =
      cast_move(scene, cfg_.shape, pose_at(high), dir * want, cfg_.move, f);
  if (!(ahead.safe >= 0.5f * cfg_.min_step_forward)) return false;
  Vec3 const fwd = high + dir * ahead.safe;
  // Down onto the ledge: it must be there (no stepping over a gap) and walkable.
  CastMove<ColliderId> const land =
      cast_move(scene, cfg_.shape, pose_at(fwd), -up * rise.safe, cfg_.move, f);
  if (!land.hit) return false;
  MoveCastHit<ColliderId> ledge = *land.hit;
  if (!walkable(ledge.normal)) {
    // The landing may be the ledge's rounded edge: probe further on.
    Vec3 const probe = fwd + dir * cfg_.step_forward_test;
    CastMove<ColliderId> const on =
        cast_move(scene, cfg_.shape, pose_at(probe), -up * rise.safe, cfg_.move, f);
    if (!on.hit || !walkable(on.hit->normal)) return false;
    ledge = *on.hit;
  }
  // What it lands on must be no higher than step_height above the feet (a shape raised less
  // than a ledge's height can still rest on its edge).
  Vec3 const feet = position_ - up * reach(cfg_.shape, rotation_, -up);
  if ((ledge.point - feet).dot(up) > cfg_.step_height) return false;
  Vec3 const landed = fwd - up * land.safe;
  if (!((landed - position_).dot(up) > cfg_.move.skin)) return false; // no higher: not a step
  position_ = landed;
  return true;
}

bool CharacterController::stick(World const& world, WorldMoveQuery const& scene) {
  QueryFilter const f = own_filter();
  Vec3 const down = -cfg_.up * cfg_.stick_to_floor;
  CastMove<ColliderId> const cast =
      cast_move(scene, cfg_.shape, pose_at(position_), down, cfg_.move, f);
  if (!cast.hit) return false; // nothing within reach: it falls
  Vec3 const landed = position_ - cfg_.up * cast.safe;
  if (find_ground(world, landed).state == GroundState::on_ground) {
    position_ = landed;
    return true;
  }
  // Grazing a ledge's edge on the way down stops a straight cast at once (the skin cannot be
  // kept past it): step clear of the edge by two skins, then cast again.
  Vec3 side = horizontal(cast.hit->normal, cfg_.up);
  float const side_len = side.length();
  if (!(side_len > 0.0f)) return false;
  side = side * (2.0f * cfg_.move.skin / side_len);
  CastMove<ColliderId> const clear =
      cast_move(scene, cfg_.shape, pose_at(position_), side, cfg_.move, f);
  if (clear.hit) return false;
  Vec3 const beside = position_ + side;
  CastMove<ColliderId> const again =
      cast_move(scene, cfg_.shape, pose_at(beside), down, cfg_.move, f);
  if (!again.hit) return false;
  Vec3 const low = beside - cfg_.up * again.safe;
  if (find_ground(world, low).state != GroundState::on_ground) return false;
  position_ = low;
  return true;
}

void CharacterController::push(World& world, float dt, Vec3 const& frame_velocity) {
  // The strongest push per dynamic body walked into (ground contacts excluded: the weight
  // below pushes those). Hits carry the velocity relative to the ground: the approach is
  // measured in the world (frame_velocity: the ground's, when the move was on it).
  for (MoveHit<ColliderId> const& h : touched_) {
    BodyId const body = h.collider.body(); // touched_ holds dynamic bodies' colliders only
    if (walkable(h.normal) || !world.is_alive(body)) continue;
    float const approach =
        (world.velocity_at(body, h.point) - (h.velocity + frame_velocity)).dot(h.normal);
    if (!(approach > 0.0f)) continue;
    float const j = std::min(cfg_.mass * approach, cfg_.max_strength * dt);
    CharacterPush const p{body, -h.normal * j, h.point};
    auto same = std::find_if(pushes_.begin(), pushes_.end(),
                             [&](CharacterPush const& q) { return q.body == body; });
    if (same == pushes_.end())
      pushes_.push_back(p);
    else if (p.impulse.length_squared() > same->impulse.length_squared())
      *same = p;
  }
  if (dt > 0.0f && ground_.state == GroundState::on_ground && world.is_alive(ground_.body) &&
      world.type(ground_.body) == BodyType::dynamic)
    pushes_.push_back({ground_.body, world.config().gravity * (cfg_.mass * dt), ground_.point});
  for (CharacterPush const& p : pushes_)
    world.apply_impulse(p.body, p.impulse, p.point);
}

CharacterUpdate const& CharacterController::update(World& world, float dt) {
  last_ = CharacterUpdate{};
  pushes_.clear();
  touched_.clear();
  platform_rotation_ = Quat::IDENTITY;
  if (!std::isfinite(dt) || !(dt >= 0.0f) || !bool(position_.is_finite()) ||
      !bool(velocity_.is_finite())) {
    last_.invalid_input = true;
    last_.move.invalid_input = true;
    return last_;
  }
  WorldMoveQuery const scene(world);
  Vec3 const start = position_;
  Vec3 const up = cfg_.up;
  bool const grounded = ground_.state == GroundState::on_ground;
  // velocity_ is relative to the ground while on it, and in the world off it.
  Vec3 const frame_velocity = grounded ? ground_.velocity : Vec3{};

  // 1. Carried by the platform.
  carry(world, scene);

  // 2. On the ground and not rising: follow it.
  Vec3 v = velocity_;
  bool rising = !grounded;
  Vec3 follow = v;
  if (grounded) {
    Vec3 const n = ground_.normal;
    float const c = n.dot(up);
    Vec3 const vh = horizontal(v, up);
    follow = vh - up * (vh.dot(n) / c);
    float const vu = v.dot(up);
    // Rising: more up than walking along the ground (or on the flat) would go: a jump.
    rising = vu - std::max(follow.dot(up), 0.0f) > cfg_.move.projection.epsilon;
    if (!rising) v = follow + n * (std::min(vu, 0.0f) * c);
  }

  // 3. The move; too-steep slopes become walls.
  QueryFilter const f = own_filter();
  bool blocked = false;
  Vec3 const along = horizontal(v, up);
  float const along_len = along.length();
  float const cos_contact = std::cos(cfg_.step_contact_angle);
  Vec3 const before = position_;
  auto on_hit = [&](MoveHit<ColliderId>& h) {
    float const u = h.normal.dot(up);
    if (u < cos_slope_) {
      Vec3 const wall = horizontal(h.normal, up);
      float const wl = wall.length();
      // A too-steep slope is a wall; the edge of walkable ground is not (it is rolled over).
      if (u > ground_facing && wl > 0.0f && !surface_normal(world, h.collider, h.point, h.position))
        h.extra_normal = wall / wl;
      // A wall or too-steep slope facing the motion: stairs may get over it.
      if (wl > 0.0f && along_len > 0.0f && h.touching &&
          -(wall / wl).dot(along / along_len) >= cos_contact)
        blocked = true;
    }
    if (h.touching && world.is_alive(h.collider.body()) &&
        world.type(h.collider.body()) == BodyType::dynamic)
      touched_.push_back(h);
    return HitResponse::accept;
  };
  last_.move = move_and_slide(scene, cfg_.shape, pose_at(position_), v, dt, cfg_.move, f, on_hit);
  MoveAndSlideResult<ColliderId> const& r = last_.move;
  position_ = r.position;
  if (bool(r.velocity.is_finite())) velocity_ = r.velocity;
  // Walking, what the move rolled up (an edge) is not kept: fed back, it would launch.
  if (grounded && !rising) {
    float const over = velocity_.dot(up) - std::max(follow.dot(up), 0.0f);
    if (over > 0.0f) velocity_ = velocity_ - up * over;
  }

  // 4. Stairs: the rest of the horizontal motion, from where the wall stopped it.
  if (grounded && !rising && blocked && cfg_.step_height > 0.0f && along_len > 0.0f) {
    Vec3 const dir = along / along_len;
    float const done = (position_ - before).dot(dir);
    float const rest = along_len * dt - done;
    if (rest > cfg_.move.min_sweep && walk_stairs(scene, dir * rest)) {
      last_.stepped = true;
      velocity_ = follow;
    }
  }

  // 5. Stick to the floor on leaving it (or on finding it further than the skin).
  if (grounded && !rising && !last_.stepped && dt > 0.0f && cfg_.stick_to_floor > 0.0f) {
    CharacterGround const g = find_ground(world, position_);
    if (g.state != GroundState::on_ground ||
        g.separation > cfg_.move.skin + cfg_.move.touch_tolerance)
      last_.stuck_to_floor = stick(world, scene);
  }

  // 6. The ground; the proxy; the pushes.
  ground_ = find_ground(world, position_);
  if (ground_.body.valid()) ground_pose_ = world.pose(ground_.body);
  // Leaving the ground, the velocity takes the ground's with it (a jump off a moving
  // platform keeps its momentum); landing, it becomes relative to the new ground.
  Vec3 const new_frame = ground_.state == GroundState::on_ground ? ground_.velocity : Vec3{};
  velocity_ = velocity_ + frame_velocity - new_frame;
  last_.displacement = position_ - start;
  // The proxy keeps zero velocity: the step would move a kinematic body by it.
  if (proxy_.valid() && world.is_alive(proxy_)) world.set_pose(proxy_, pose_at(position_));
  push(world, dt, frame_velocity);
  return last_;
}

} // namespace plume
