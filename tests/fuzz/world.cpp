// tests/fuzz/world.cpp - fuzzes World (solver/world/world.hpp) with a decoded command sequence:
// create and destroy bodies (every shape kind - sphere, capsule, cuboid, cylinder, hull,
// half-space, mesh, height field, and empty meshes - as static, kinematic or dynamic bodies,
// with bad poses, velocities and materials at times), create and destroy joints of every kind
// (fixed, revolute, prismatic, spherical, distance; bad frames, limits, motors and break
// thresholds at times), set motors and targets, set poses, velocities, types and layers (NaN and
// infinities at times), apply impulses, step with dt > 0, 0, negative, NaN or infinite, and run
// queries; create, teleport, re-layer and destroy standalone colliders (sensors at times); put
// bodies to sleep and wake them, create them asleep, change their sleep settings (bad
// thresholds at times; a short time_to_sleep so that islands fall asleep within 8 steps); mirrored
// by the list of ids it created and destroyed. At most 16 bodies, 8 colliders, 8 joints and 8 steps
// per input. Properties:
//  - every call returns the documented error for the input it got (a refused call leaves the
//    world unchanged: counts, state hash and the body's own values), and none otherwise;
//    accessors throw std::out_of_range for stale body and joint ids;
//  - is_alive (bodies, colliders and joints) agrees with the mirror; alive_count, collider_count,
//    body_count and joint_count agree; a collider's slot names no body; destroying a body destroys
//    its joints; a reused slot has the next generation and the old id stays dead;
//  - setters do what they say (pose, velocity, layers, type, motor; a static body has no
//    velocity; an impulse changes a dynamic body's velocity by J / m);
//  - step ignores dt outside [World::min_dt, World::max_dt] (NaN too; state hash unchanged);
//    after a step every live body's pose and velocities are finite, static bodies and colliders
//    have not moved,
//    frozen bodies are listed, events list live-at-the-time pairs in increasing order with the
//    lower slot first, and joint states are finite; step_with<T> gives the world step() gives for
//    float and every f32 width the build has, and so does a step whose parallel stages run as
//    one-item tasks in reverse order;
//  - sleeping: sleeping_count() counts the sleeping bodies, each dynamic, unfrozen and stopped;
//    a body created asleep (or put to sleep) is asleep, a woken one awake; fell_asleep lists,
//    by index, bodies asleep after the step;
//  - queries see only live colliders (a hit's body is its collider's); the closest ray hit is
//    the first of ray_cast_all and the batch ray cast gives the single one's bits; non-finite
//    queries find nothing.
#include "fuzz_input.hpp"

#include <plume/world.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace plume::fuzz {
/// f.template operator()<T>() for float and every f32 width the build enables.
template <class F>
void for_each_width(F&& f) {
#define PLUME_FUZZ_WIDTH(T, lanes) f.template operator()<T>();
  PLUME_FOR_EACH_F32_TYPE(PLUME_FUZZ_WIDTH)
#undef PLUME_FUZZ_WIDTH
}
} // namespace plume::fuzz

namespace {

using plume::BodyError;
using plume::BodyId;
using plume::ColliderId;
using plume::Iso3;
using plume::JointError;
using plume::JointId;
using plume::Quat;
using plume::Vec3;
using plume::fuzz::Input;

bool same(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same(Vec3 const& a, Vec3 const& b) {
  return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z);
}
bool same(Quat const& a, Quat const& b) {
  return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z) && same(a.w, b.w);
}
bool same(Iso3 const& a, Iso3 const& b) {
  return same(a.rotation, b.rotation) && same(a.translation, b.translation);
}
bool finite(Quat const& q) {
  return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w);
}

template <class E, class F>
bool throws(F&& f) {
  try {
    f();
  } catch (E const&) {
    return true;
  } catch (...) {
    return false;
  }
  return false;
}

// ------------------------------------------------------------------------ decoding

std::shared_ptr<plume::TriangleMesh const> small_mesh(Input& in) {
  std::vector<Vec3> v{{-2, 0, -2}, {2, 0, -2}, {-2, 0, 2}, {2, 0, 2}};
  for (Vec3& p : v)
    p.y = in.real(-0.5f, 0.5f);
  std::vector<std::uint32_t> const idx{0, 2, 1, 1, 2, 3};
  plume::MeshBuildResult r = plume::TriangleMesh::build(v, idx);
  if (!r.ok()) return nullptr;
  return std::make_shared<plume::TriangleMesh const>(std::move(r.mesh));
}

std::shared_ptr<plume::HeightField const> small_field(Input& in) {
  std::vector<float> h(9);
  for (float& x : h)
    x = in.real(-0.5f, 0.5f);
  plume::HeightFieldBuildResult r = plume::HeightField::build(3, 3, h, 1.5f, 1.5f);
  if (!r.ok()) return nullptr;
  return std::make_shared<plume::HeightField const>(std::move(r.field));
}

plume::BodyShape body_shape(Input& in) {
  std::uint8_t const k = in.byte();
  bool const tiny = (k & 0xf0) == 0xf0; // zero size: no mass
  switch (k % 10) {
  case 0:
    return plume::Sphere{tiny ? 0.0f : in.real(0.05f, 1)};
  case 1:
    return plume::Capsule{in.real(0, 1), tiny ? 0.0f : in.real(0.05f, 0.5f)};
  case 2:
  case 3:
    return plume::Cuboid{tiny ? Vec3{0.5f, 0.0f, 0.5f} : in.vec3(0.05f, 1)};
  case 4:
    return plume::Cylinder{in.real(0.05f, 1), tiny ? 0.0f : in.real(0.05f, 1)};
  case 5: {
    std::vector<Vec3> pts;
    for (int i = 0; i < 6; ++i)
      pts.push_back(in.vec3(-0.7f, 0.7f));
    plume::HullBuild b = plume::ConvexHull::build(std::span<Vec3 const>(pts));
    if (b) return std::move(b.hull);
    return plume::Sphere{0.3f};
  }
  case 6:
    return plume::HalfSpace{in.vec3(-1, 1).normalize_or(Vec3::Y)};
  case 7:
    return plume::MeshShape{(k & 16) ? nullptr : small_mesh(in)};
  case 8:
    return plume::HeightFieldShape{(k & 16) ? nullptr : small_field(in)};
  default:
    return plume::Cuboid{in.vec3(0.1f, 0.8f)};
  }
}

Quat decode_rotation(Input& in, std::uint8_t k) {
  Quat q = (k & 1) ? in.rotation() : Quat::IDENTITY;
  if ((k & 6) == 6) q = Quat{q.x * 3.0f, q.y * 3.0f, q.z * 3.0f, q.w * 3.0f}; // not unit: accepted
  return q;
}

/// A pose: mostly good, at times with a NaN or infinite part.
Iso3 decode_pose(Input& in, bool& bad) {
  std::uint8_t const k = in.byte();
  Iso3 p{decode_rotation(in, k), in.vec3(-4, 4)};
  bad = false;
  if ((k & 0x38) == 0x38) {
    p.translation.z = (k & 0x40) ? std::numeric_limits<float>::infinity()
                                 : std::numeric_limits<float>::quiet_NaN();
    bad = true;
  }
  if ((k & 0xc0) == 0xc0) {
    p.rotation.y = std::numeric_limits<float>::quiet_NaN();
    bad = true;
  }
  return p;
}

Vec3 decode_vec(Input& in, float lo, float hi, bool& bad) {
  std::uint8_t const k = in.byte();
  Vec3 v = in.vec3(lo, hi);
  bad = false;
  if ((k & 15) == 15) {
    v.y =
        (k & 16) ? std::numeric_limits<float>::infinity() : std::numeric_limits<float>::quiet_NaN();
    bad = true;
  }
  return v;
}

/// A material value: good, negative, or not finite.
struct Faults {
  bool negative = false, non_finite = false;
};
float material(Input& in, float lo, float hi, Faults& fault) {
  std::uint8_t const k = in.byte();
  switch (k % 16) {
  case 0:
    fault.negative = true;
    return -in.real(0.01f, 1);
  case 1:
    fault.non_finite = true;
    return (k & 16) ? std::numeric_limits<float>::quiet_NaN()
                    : -std::numeric_limits<float>::infinity();
  case 2:
    return 0.0f;
  default:
    return in.real(lo, hi);
  }
}

plume::Motor decode_motor(Input& in, bool& valid) {
  plume::Motor m;
  std::uint8_t const k = in.byte();
  m.enabled = (k & 1) != 0;
  m.model = static_cast<plume::MotorModel>((k >> 1) % 4);
  m.target_velocity = in.real(-5, 5);
  m.target_position = in.real(-4, 4);
  m.max_force = (k & 8) ? std::numeric_limits<float>::infinity() : in.real(0, 1000);
  m.frequency = in.real(0, 20);
  m.damping_ratio = in.real(0, 2);
  m.stiffness = in.real(0, 100);
  m.damping = in.real(0, 10);
  switch (k >> 5) {
  case 0:
    m.target_velocity = std::numeric_limits<float>::quiet_NaN();
    break;
  case 1:
    m.max_force = -1.0f;
    break;
  case 2:
    m.frequency = -in.real(0.1f, 1);
    break;
  default:
    break;
  }
  valid = m.valid();
  return m;
}

plume::JointType decode_joint_type(Input& in) {
  std::uint8_t const k = in.byte();
  float const pi = 3.14159265f;
  bool bad = (k & 0xe0) == 0xe0; // limits out of range or inverted
  switch (k % 5) {
  case 0:
    return plume::FixedJoint{};
  case 1: {
    plume::RevoluteJoint j;
    j.limit_enabled = (k & 8) != 0;
    j.lower_angle = in.real(-pi, 0);
    j.upper_angle = in.real(0, pi);
    if (bad) j.lower_angle = j.upper_angle + 0.5f;
    bool ok;
    j.motor = decode_motor(in, ok);
    return j;
  }
  case 2: {
    plume::PrismaticJoint j;
    j.limit_enabled = (k & 8) != 0;
    j.lower_translation = in.real(-2, 0);
    j.upper_translation = in.real(0, 2);
    if (bad) j.upper_translation = std::numeric_limits<float>::quiet_NaN();
    bool ok;
    j.motor = decode_motor(in, ok);
    return j;
  }
  case 3: {
    plume::SphericalJoint j;
    j.cone_enabled = (k & 8) != 0;
    j.cone_angle = in.real(0, pi);
    j.twist_limit_enabled = (k & 16) != 0;
    j.lower_twist = in.real(-pi, 0);
    j.upper_twist = in.real(0, pi);
    if (bad) j.cone_angle = 4.0f;
    return j;
  }
  default: {
    plume::DistanceJoint j;
    j.rest_length = in.real(0, 3);
    j.spring_enabled = (k & 8) != 0;
    j.min_length = in.real(0, 1);
    j.max_length = (k & 16) ? std::numeric_limits<float>::infinity() : in.real(1, 4);
    j.frequency = in.real(0, 10);
    j.damping_ratio = in.real(0, 2);
    if (bad) j.rest_length = -1.0f;
    return j;
  }
  }
}

// ------------------------------------------------------------------------ the mirror

struct MirrorBody {
  BodyId id;
  bool alive = true;
  plume::BodyType type = plume::BodyType::dynamic;
  bool triangles = false; ///< a mesh or height field
  bool massless = false;  ///< its shape and density give no positive finite mass
};

struct MirrorCollider {
  ColliderId id;
  bool alive = true;
};

struct MirrorJoint {
  JointId id;
  bool alive = true;
  BodyId a, b;
  bool has_motor = false;
};

/// How many entries of a mirror list are alive.
template <class Item>
std::size_t count_alive(std::vector<Item> const& items) {
  return std::size_t(
      std::count_if(items.begin(), items.end(), [](Item const& x) { return x.alive; }));
}
/// The live entry with this id, or null.
template <class Item, class Id>
Item* find_alive(std::vector<Item>& items, Id id) {
  for (Item& x : items)
    if (x.id == id && x.alive) return &x;
  return nullptr;
}
/// The ids of a mirror list, live and dead apart, in creation order.
template <class Item>
auto live_and_dead(std::vector<Item> const& items) {
  std::pair<std::vector<decltype(Item::id)>, std::vector<decltype(Item::id)>> out;
  for (Item const& x : items)
    (x.alive ? out.first : out.second).push_back(x.id);
  return out;
}

struct Mirror {
  std::vector<MirrorBody> bodies; ///< every body ever created, in creation order
  std::vector<MirrorJoint> joints;
  std::vector<MirrorCollider> colliders; ///< every standalone collider ever created
  std::vector<std::uint32_t> free_slots; ///< bodies' and colliders' (they share the slots)

  std::size_t alive_colliders() const { return count_alive(colliders); }
  MirrorCollider* find_collider(ColliderId id) { return find_alive(colliders, id); }
  /// A live collider, a stale one, a body's, or one never made.
  ColliderId pick_collider(Input& in) const {
    std::uint8_t const k = in.byte();
    auto const [live, dead] = live_and_dead(colliders);
    if (!live.empty() && (k & 7) > 1) return live[std::size_t(k >> 3) % live.size()];
    if (!dead.empty() && (k & 8)) return dead[std::size_t(k >> 4) % dead.size()];
    if (!bodies.empty() && (k & 7) == 1) return bodies[std::size_t(k >> 3) % bodies.size()].id;
    return ColliderId{std::uint32_t(40 + (k >> 4)), 0, true};
  }

  std::size_t alive() const { return count_alive(bodies); }
  std::size_t alive_joints() const { return count_alive(joints); }
  MirrorBody* find(BodyId id) { return find_alive(bodies, id); }
  /// A live id (when there is one and the byte says so) or a stale, forged or never-made one.
  BodyId pick(Input& in) const {
    std::uint8_t const k = in.byte();
    auto const [live, dead] = live_and_dead(bodies);
    if (!live.empty() && (k & 7) != 0) return live[std::size_t(k >> 3) % live.size()];
    if (!dead.empty() && (k & 8)) return dead[std::size_t(k >> 4) % dead.size()];
    if (!colliders.empty() && (k & 16)) { // a BodyId forged from a collider's slot
      ColliderId const c = colliders[std::size_t(k >> 5) % colliders.size()].id;
      return BodyId{c.index, c.generation};
    }
    return BodyId{std::uint32_t(40 + (k >> 4)), 0};
  }
  JointId pick_joint(Input& in) const {
    std::uint8_t const k = in.byte();
    auto const [live, dead] = live_and_dead(joints);
    if (!live.empty() && (k & 7) != 0) return live[std::size_t(k >> 3) % live.size()];
    if (!dead.empty() && (k & 8)) return dead[std::size_t(k >> 4) % dead.size()];
    return JointId{std::uint32_t(20 + (k >> 4)), 0};
  }
};

void check_mirror(plume::World const& w, Mirror const& m) {
  PLUME_FUZZ_CHECK(w.alive_count() == m.alive());
  std::size_t sleeping = 0;
  for (MirrorBody const& b : m.bodies)
    if (b.alive && w.is_sleeping(b.id)) {
      ++sleeping;
      PLUME_FUZZ_CHECK(w.type(b.id) == plume::BodyType::dynamic && !w.is_frozen(b.id));
      PLUME_FUZZ_CHECK(same(w.linear_velocity(b.id), Vec3{}) &&
                       same(w.angular_velocity(b.id), Vec3{}));
    }
  PLUME_FUZZ_CHECK(w.sleeping_count() == sleeping);
  PLUME_FUZZ_CHECK(w.collider_count() == m.alive_colliders());
  PLUME_FUZZ_CHECK(w.joint_count() == m.alive_joints());
  std::size_t slots = 0;
  std::vector<bool> used, standalone;
  for (MirrorBody const& b : m.bodies) {
    PLUME_FUZZ_CHECK(w.is_alive(b.id) == b.alive);
    PLUME_FUZZ_CHECK(w.is_alive(ColliderId(b.id)) == b.alive);
    slots = std::max<std::size_t>(slots, b.id.index + 1);
    used.resize(slots);
    if (b.alive) {
      used[b.id.index] = true;
      PLUME_FUZZ_CHECK(w.body_id(b.id.index) == b.id);
      PLUME_FUZZ_CHECK(w.collider_id(b.id.index) == ColliderId(b.id));
      PLUME_FUZZ_CHECK(w.type(b.id) == b.type);
    }
  }
  for (MirrorCollider const& c : m.colliders) {
    PLUME_FUZZ_CHECK(w.is_alive(c.id) == c.alive);
    PLUME_FUZZ_CHECK(!w.is_alive(BodyId{c.id.index, c.id.generation}));
    slots = std::max<std::size_t>(slots, c.id.index + 1);
    used.resize(slots);
    standalone.resize(slots);
    if (c.alive) {
      PLUME_FUZZ_CHECK(!used[c.id.index]);
      used[c.id.index] = standalone[c.id.index] = true;
      PLUME_FUZZ_CHECK(w.collider_id(c.id.index) == c.id);
      PLUME_FUZZ_CHECK(plume::fuzz::finite(w.pose(c.id).translation));
    }
  }
  standalone.resize(slots);
  for (std::uint32_t i = 0; i < used.size(); ++i) { // a free slot names no body or collider
    if (!used[i]) PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)w.collider_id(i); }));
    if (!used[i] || standalone[i])
      PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)w.body_id(i); }));
  }
  PLUME_FUZZ_CHECK(w.body_count() == slots);
  for (MirrorJoint const& j : m.joints)
    PLUME_FUZZ_CHECK(w.is_alive(j.id) == j.alive);
  PLUME_FUZZ_CHECK(!w.is_alive(BodyId{}));
  PLUME_FUZZ_CHECK(!w.is_alive(JointId{}));
}

/// A task system that runs every range as one item, last first, inline: below the world's
/// minimum ranges and in reverse, which must not change the world (tasks.hpp).
struct ReversedTasks final : plume::TaskSystem {
  std::uint32_t worker_count() const noexcept override { return 4; }
  void* enqueue(plume::TaskFn fn, std::uint32_t count, std::uint32_t, void* context) override {
    for (std::uint32_t i = count; i-- > 0;)
      fn(i, i + 1, i % 4, context);
    return nullptr;
  }
  void wait(void*) override {}
};

/// A snapshot of what a refused call must leave alone.
struct Snapshot {
  std::uint64_t hash;
  std::size_t alive, slots, joints, colliders;
  explicit Snapshot(plume::World const& w)
      : hash(w.state_hash()), alive(w.alive_count()), slots(w.body_count()),
        joints(w.joint_count()), colliders(w.collider_count()) {}
  bool operator==(Snapshot const& o) const {
    return hash == o.hash && alive == o.alive && slots == o.slots && joints == o.joints &&
           colliders == o.colliders;
  }
};

// ------------------------------------------------------------------------ the commands

void create_body(plume::World& w, Mirror& m, Input& in) {
  if (m.alive() >= 16) return;
  plume::BodyDef def;
  std::uint8_t const k = in.byte();
  def.type = static_cast<plume::BodyType>(k % 3);
  def.shape = body_shape(in);
  bool bad_pose = false, bad_v = false, bad_w = false;
  def.pose = decode_pose(in, bad_pose);
  def.linear_velocity = decode_vec(in, -5, 5, bad_v);
  def.angular_velocity = decode_vec(in, -3, 3, bad_w);
  Faults f;
  def.density = (k & 8) ? material(in, 100, 3000, f) : 1000.0f;
  def.friction = (k & 16) ? material(in, 0, 1, f) : 0.6f;
  def.restitution = (k & 16) ? material(in, 0, 1, f) : 0.0f;
  def.linear_damping = (k & 32) ? material(in, 0, 1, f) : 0.0f;
  def.angular_damping = (k & 32) ? material(in, 0, 1, f) : 0.0f;
  Faults g; // a negative gravity scale is allowed
  def.gravity_scale = (k & 64) ? material(in, 0, 2, g) : 1.0f;
  def.layers.memberships = (in.byte() & 3) == 0 ? 2u : 1u;
  def.sensor = (k & 0x80) && (in.byte() & 7) == 0;
  // Fast bodies and bullets: continuous collision's sweeps.
  std::uint8_t const fast = in.byte();
  def.bullet = (fast & 1) != 0;
  if (fast & 2) def.linear_velocity = def.linear_velocity * 60.0f; // up to 300 m/s
  // Sleep settings: created asleep, never sleeping, a threshold (bad at times).
  std::uint8_t const sleepy = in.byte();
  def.awake = (sleepy & 3) != 0;
  def.enable_sleep = (sleepy & 4) == 0;
  if (sleepy & 8) def.sleep_threshold = material(in, 0, 2, f);

  // The documented errors this definition has.
  bool const non_finite = bad_pose || bad_v || bad_w || f.non_finite || g.non_finite;
  bool const bad_material = f.negative;
  bool const triangles = std::visit(
      [](auto const& s) { return plume::is_triangle_shape_v<std::decay_t<decltype(s)>>; },
      def.shape);
  bool const empty_triangles = std::visit(
      [](auto const& s) {
        if constexpr (plume::is_triangle_shape_v<std::decay_t<decltype(s)>>)
          return s.source() == nullptr || s.source()->empty();
        else
          return false;
      },
      def.shape);
  bool const bad_shape = triangles && (empty_triangles || def.type == plume::BodyType::dynamic);
  float const mass = std::visit(
      [&](auto const& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, plume::HalfSpace> || plume::is_triangle_shape_v<S>)
          return 0.0f;
        else
          return s.mass_properties(def.density).mass;
      },
      def.shape);
  bool const massless = !(mass > 0.0f) || !std::isfinite(mass);
  bool const zero_mass = def.type == plume::BodyType::dynamic && massless;

  Snapshot const before(w);
  plume::CreateBodyResult const r = w.create_body(def);
  switch (r.error) {
  case BodyError::none:
    PLUME_FUZZ_CHECK(!non_finite && !bad_material && !bad_shape && !zero_mass);
    break;
  case BodyError::non_finite:
    PLUME_FUZZ_CHECK(non_finite);
    break;
  case BodyError::bad_material:
    PLUME_FUZZ_CHECK(bad_material);
    break;
  case BodyError::bad_shape:
    PLUME_FUZZ_CHECK(bad_shape);
    break;
  case BodyError::zero_mass:
    PLUME_FUZZ_CHECK(zero_mass);
    break;
  default:
    PLUME_FUZZ_CHECK(false && "create_body: an error it does not document");
  }
  PLUME_FUZZ_CHECK(bool(r) == (r.error == BodyError::none));
  if (!r) {
    PLUME_FUZZ_CHECK(!r.id.valid());
    PLUME_FUZZ_CHECK(Snapshot(w) == before);
    return;
  }
  BodyId const id = r.id;
  PLUME_FUZZ_CHECK(w.is_alive(id));
  // A reused slot: the next generation, and its old ids stay dead.
  for (MirrorBody const& b : m.bodies)
    if (b.id.index == id.index) PLUME_FUZZ_CHECK(!b.alive && id.generation > b.id.generation);
  for (MirrorCollider const& c : m.colliders)
    if (c.id.index == id.index) PLUME_FUZZ_CHECK(!c.alive && id.generation > c.id.generation);
  if (!m.free_slots.empty()) {
    PLUME_FUZZ_CHECK(id.index == m.free_slots.back());
    m.free_slots.pop_back();
  } else {
    PLUME_FUZZ_CHECK(id.index == before.slots && id.generation == 0);
  }
  PLUME_FUZZ_CHECK(w.type(id) == def.type);
  PLUME_FUZZ_CHECK(same(w.pose(id).translation, def.pose.translation));
  Quat const q = w.pose(id).rotation;
  PLUME_FUZZ_CHECK(finite(q) && std::abs(q.length() - 1.0f) < 1e-4f);
  bool const asleep =
      def.type == plume::BodyType::dynamic && !def.awake && def.enable_sleep && w.config().sleep;
  PLUME_FUZZ_CHECK(w.is_sleeping(id) == asleep);
  PLUME_FUZZ_CHECK(w.sleep_enabled(id) == def.enable_sleep);
  if (def.type == plume::BodyType::static_body || asleep) {
    PLUME_FUZZ_CHECK(same(w.linear_velocity(id), Vec3{}) && same(w.angular_velocity(id), Vec3{}));
  } else {
    PLUME_FUZZ_CHECK(same(w.linear_velocity(id), def.linear_velocity));
    PLUME_FUZZ_CHECK(same(w.angular_velocity(id), def.angular_velocity));
  }
  if (def.type == plume::BodyType::dynamic)
    PLUME_FUZZ_CHECK(w.mass(id) > 0.0f && std::isfinite(w.mass(id)));
  PLUME_FUZZ_CHECK(w.layers(id).memberships == def.layers.memberships);
  PLUME_FUZZ_CHECK(w.is_sensor(id) == def.sensor);
  PLUME_FUZZ_CHECK(w.is_bullet(id) == def.bullet);
  PLUME_FUZZ_CHECK(!w.is_frozen(id));
  PLUME_FUZZ_CHECK(w.body_joints(id).empty());
  m.bodies.push_back({id, true, def.type, triangles, massless});
}

void destroy_body(plume::World& w, Mirror& m, Input& in) {
  BodyId const id = m.pick(in);
  MirrorBody* b = m.find(id);
  Snapshot const before(w);
  BodyError const e = w.destroy_body(id);
  if (!b) {
    PLUME_FUZZ_CHECK(e == BodyError::bad_body);
    PLUME_FUZZ_CHECK(Snapshot(w) == before);
    return;
  }
  PLUME_FUZZ_CHECK(e == BodyError::none);
  PLUME_FUZZ_CHECK(!w.is_alive(id));
  b->alive = false;
  m.free_slots.push_back(id.index);
  for (MirrorJoint& j : m.joints) // its joints go with it
    if (j.alive && (j.a == id || j.b == id)) j.alive = false;
  PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)w.pose(id); }));
  PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)w.linear_velocity(id); }));
  PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)w.body_joints(id); }));
  PLUME_FUZZ_CHECK(w.destroy_body(id) == BodyError::bad_body);
}

void create_collider(plume::World& w, Mirror& m, Input& in) {
  if (m.alive_colliders() >= 8) return;
  plume::ColliderDef def;
  std::uint8_t const k = in.byte();
  def.shape = body_shape(in);
  bool bad_pose = false;
  def.pose = decode_pose(in, bad_pose);
  Faults f;
  def.friction = (k & 1) ? material(in, 0, 1, f) : 0.6f;
  def.restitution = (k & 2) ? material(in, 0, 1, f) : 0.0f;
  def.layers.memberships = (k & 4) ? 2u : 1u;
  def.sensor = (k & 8) != 0;
  bool const non_finite = bad_pose || f.non_finite;
  bool const bad_shape = std::visit(
      [](auto const& s) {
        if constexpr (plume::is_triangle_shape_v<std::decay_t<decltype(s)>>)
          return s.source() == nullptr || s.source()->empty();
        else
          return false;
      },
      def.shape);
  Snapshot const before(w);
  plume::CreateColliderResult const r = w.create_collider(def);
  switch (r.error) {
  case BodyError::none:
    PLUME_FUZZ_CHECK(!non_finite && !f.negative && !bad_shape);
    break;
  case BodyError::non_finite:
    PLUME_FUZZ_CHECK(non_finite);
    break;
  case BodyError::bad_material:
    PLUME_FUZZ_CHECK(f.negative);
    break;
  case BodyError::bad_shape:
    PLUME_FUZZ_CHECK(bad_shape);
    break;
  default:
    PLUME_FUZZ_CHECK(false && "create_collider: an error it does not document");
  }
  if (!r) {
    PLUME_FUZZ_CHECK(!r.id.valid());
    PLUME_FUZZ_CHECK(Snapshot(w) == before);
    return;
  }
  ColliderId const id = r.id;
  PLUME_FUZZ_CHECK(id.standalone && !id.body().valid() && w.is_alive(id));
  for (MirrorBody const& b : m.bodies)
    if (b.id.index == id.index) PLUME_FUZZ_CHECK(!b.alive && id.generation > b.id.generation);
  for (MirrorCollider const& c : m.colliders)
    if (c.id.index == id.index) PLUME_FUZZ_CHECK(!c.alive && id.generation > c.id.generation);
  if (!m.free_slots.empty()) {
    PLUME_FUZZ_CHECK(id.index == m.free_slots.back());
    m.free_slots.pop_back();
  } else {
    PLUME_FUZZ_CHECK(id.index == before.slots && id.generation == 0);
  }
  PLUME_FUZZ_CHECK(same(w.pose(id).translation, def.pose.translation));
  PLUME_FUZZ_CHECK(std::abs(w.pose(id).rotation.length() - 1.0f) < 1e-4f);
  PLUME_FUZZ_CHECK(w.is_sensor(id) == def.sensor);
  PLUME_FUZZ_CHECK(w.layers(id).memberships == def.layers.memberships);
  PLUME_FUZZ_CHECK(w.alive_count() == before.alive);
  m.colliders.push_back({id, true});
}

void destroy_collider(plume::World& w, Mirror& m, Input& in) {
  ColliderId const id = m.pick_collider(in);
  MirrorCollider* c = m.find_collider(id);
  Snapshot const before(w);
  BodyError const e = w.destroy_collider(id);
  if (!c) { // stale, never made, or a body's: refused
    PLUME_FUZZ_CHECK(e == BodyError::bad_body);
    PLUME_FUZZ_CHECK(Snapshot(w) == before);
    return;
  }
  PLUME_FUZZ_CHECK(e == BodyError::none);
  PLUME_FUZZ_CHECK(!w.is_alive(id));
  c->alive = false;
  m.free_slots.push_back(id.index);
  PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)w.pose(id); }));
  PLUME_FUZZ_CHECK(w.destroy_collider(id) == BodyError::bad_body);
}

/// A teleport (set(p) on id: World::set_pose or set_collider_pose) of a decoded pose: bad_body
/// unless the mirror has id live, non_finite for a bad pose (both leave the world alone), else
/// the pose with its rotation normalised.
template <class Id, class Set>
void teleport(plume::World& w, Id id, bool live, Input& in, Set&& set) {
  bool bad = false;
  Iso3 const p = decode_pose(in, bad);
  Snapshot const before(w);
  BodyError const e = set(p);
  if (!live) {
    PLUME_FUZZ_CHECK(e == BodyError::bad_body && Snapshot(w) == before);
    return;
  }
  if (bad) {
    PLUME_FUZZ_CHECK(e == BodyError::non_finite && Snapshot(w) == before);
    return;
  }
  PLUME_FUZZ_CHECK(e == BodyError::none);
  PLUME_FUZZ_CHECK(same(w.pose(id).translation, p.translation));
  PLUME_FUZZ_CHECK(std::abs(w.pose(id).rotation.length() - 1.0f) < 1e-4f);
}

void set_collider_layers(plume::World& w, Mirror& m, Input& in) {
  ColliderId const id = m.pick_collider(in);
  plume::CollisionLayers l;
  l.memberships = (in.byte() & 1) ? 2u : 1u;
  l.filters = (in.byte() & 3) == 0 ? 1u : 0xffffffffu;
  Snapshot const before(w);
  BodyError const e = w.set_collider_layers(id, l);
  if (!m.find_collider(id)) {
    PLUME_FUZZ_CHECK(e == BodyError::bad_body && Snapshot(w) == before);
    return;
  }
  PLUME_FUZZ_CHECK(e == BodyError::none);
  PLUME_FUZZ_CHECK(w.layers(id).memberships == l.memberships && w.layers(id).filters == l.filters);
}

void set_collider_pose(plume::World& w, Mirror& m, Input& in) {
  ColliderId const id = m.pick_collider(in);
  teleport(w, id, m.find_collider(id) != nullptr, in,
           [&](Iso3 const& p) { return w.set_collider_pose(id, p); });
}

void set_pose(plume::World& w, Mirror& m, Input& in) {
  BodyId const id = m.pick(in);
  teleport(w, id, m.find(id) != nullptr, in, [&](Iso3 const& p) { return w.set_pose(id, p); });
}

void set_velocity(plume::World& w, Mirror& m, Input& in) {
  BodyId const id = m.pick(in);
  bool bad_v = false, bad_w = false;
  Vec3 const v = decode_vec(in, -8, 8, bad_v), a = decode_vec(in, -4, 4, bad_w);
  Snapshot const before(w);
  BodyError const e = w.set_velocity(id, v, a);
  MirrorBody const* b = m.find(id);
  if (!b) {
    PLUME_FUZZ_CHECK(e == BodyError::bad_body && Snapshot(w) == before);
    return;
  }
  if (bad_v || bad_w) {
    PLUME_FUZZ_CHECK(e == BodyError::non_finite && Snapshot(w) == before);
    return;
  }
  PLUME_FUZZ_CHECK(e == BodyError::none);
  if (b->type == plume::BodyType::static_body) {
    PLUME_FUZZ_CHECK(same(w.linear_velocity(id), Vec3{}) && same(w.angular_velocity(id), Vec3{}));
  } else {
    PLUME_FUZZ_CHECK(same(w.linear_velocity(id), v) && same(w.angular_velocity(id), a));
  }
}

void apply_impulse(plume::World& w, Mirror& m, Input& in) {
  BodyId const id = m.pick(in);
  bool bad_j = false, bad_p = false;
  Vec3 const j = decode_vec(in, -50, 50, bad_j), p = decode_vec(in, -5, 5, bad_p);
  Snapshot const before(w);
  MirrorBody const* b = m.find(id);
  Vec3 const v0 = b ? w.linear_velocity(id) : Vec3{};
  BodyError const e = w.apply_impulse(id, j, p);
  if (!b) {
    PLUME_FUZZ_CHECK(e == BodyError::bad_body && Snapshot(w) == before);
    return;
  }
  if (bad_j || bad_p) {
    PLUME_FUZZ_CHECK(e == BodyError::non_finite && Snapshot(w) == before);
    return;
  }
  PLUME_FUZZ_CHECK(e == BodyError::none);
  if (b->type != plume::BodyType::dynamic || w.is_frozen(id)) {
    PLUME_FUZZ_CHECK(Snapshot(w) == before); // takes no impulse
    return;
  }
  Vec3 const dv = w.linear_velocity(id) - v0, want = j / w.mass(id);
  PLUME_FUZZ_CHECK((dv - want).length() <= 1e-4f * (want.length() + v0.length()) + 1e-6f);
  // (A body a huge dt sent far away can overflow (point - centre) x J: no promise there.)
  if ((p - w.center_of_mass(id)).length() < 1e6f)
    PLUME_FUZZ_CHECK(plume::fuzz::finite(w.angular_velocity(id)));
}

void set_type(plume::World& w, Mirror& m, Input& in) {
  BodyId const id = m.pick(in);
  auto const type = static_cast<plume::BodyType>(in.byte() % 3);
  MirrorBody* b = m.find(id);
  Snapshot const before(w);
  bool const was_frozen = b && w.is_frozen(id);
  BodyError const e = w.set_type(id, type);
  if (!b) {
    PLUME_FUZZ_CHECK(e == BodyError::bad_body && Snapshot(w) == before);
    return;
  }
  if (type == plume::BodyType::dynamic && b->type != plume::BodyType::dynamic) {
    if (b->triangles) {
      PLUME_FUZZ_CHECK(e == BodyError::bad_shape && Snapshot(w) == before);
      PLUME_FUZZ_CHECK(w.type(id) == b->type);
      return;
    }
    if (b->massless) {
      PLUME_FUZZ_CHECK(e == BodyError::zero_mass && Snapshot(w) == before);
      PLUME_FUZZ_CHECK(w.type(id) == b->type);
      return;
    }
  }
  PLUME_FUZZ_CHECK(e == BodyError::none);
  PLUME_FUZZ_CHECK(w.type(id) == type);
  PLUME_FUZZ_CHECK(!w.is_frozen(id));
  if (type == plume::BodyType::static_body || was_frozen)
    PLUME_FUZZ_CHECK(same(w.linear_velocity(id), Vec3{}) && same(w.angular_velocity(id), Vec3{}));
  if (type == plume::BodyType::dynamic) PLUME_FUZZ_CHECK(w.mass(id) > 0.0f);
  b->type = type;
}

void set_layers(plume::World& w, Mirror& m, Input& in) {
  BodyId const id = m.pick(in);
  plume::CollisionLayers l;
  l.memberships = (in.byte() & 1) ? 2u : 1u;
  l.filters = (in.byte() & 3) == 0 ? 1u : 0xffffffffu;
  Snapshot const before(w);
  BodyError const e = w.set_layers(id, l);
  if (!m.find(id)) {
    PLUME_FUZZ_CHECK(e == BodyError::bad_body && Snapshot(w) == before);
    return;
  }
  PLUME_FUZZ_CHECK(e == BodyError::none);
  PLUME_FUZZ_CHECK(w.layers(id).memberships == l.memberships && w.layers(id).filters == l.filters);
}

plume::JointFrame decode_frame(Input& in, bool& bad) {
  plume::JointFrame f;
  std::uint8_t const k = in.byte();
  f.anchor = in.vec3(-1, 1);
  f.axis = in.vec3(-1, 1);
  f.normal = in.vec3(-1, 1);
  if ((k & 7) == 0) f.axis = Vec3::X;
  switch (k >> 5) {
  case 0:
    f.axis = Vec3{};
    break;
  case 1:
    f.anchor.x = std::numeric_limits<float>::quiet_NaN();
    break;
  case 2:
    f.normal.z = std::numeric_limits<float>::infinity();
    break;
  default:
    break;
  }
  bad = !f.basis().has_value() || !plume::fuzz::finite(f.normal);
  return f;
}

void create_joint(plume::World& w, Mirror& m, Input& in) {
  if (m.alive_joints() >= 8) return;
  plume::JointDef def;
  def.body_a = m.pick(in);
  def.body_b = (in.byte() & 7) == 0 ? def.body_a : m.pick(in);
  bool bad_a = false, bad_b = false;
  def.frame_a = decode_frame(in, bad_a);
  def.frame_b = decode_frame(in, bad_b);
  def.type = decode_joint_type(in);
  def.collide_connected = in.flag();
  std::uint8_t const k = in.byte();
  if (k & 1) def.break_force = in.real(0, 1e4f);
  if (k & 2) def.break_torque = in.real(0, 1e4f);
  if ((k & 0x1c) == 0x1c) def.break_force = std::numeric_limits<float>::quiet_NaN();
  if ((k & 0xe0) == 0xe0) def.break_torque = -1.0f;

  bool const bad_body = !m.find(def.body_a) || !m.find(def.body_b);
  bool const same_body = def.body_a == def.body_b;
  bool const bad_axis = bad_a || bad_b;
  bool const bad_limits = std::visit(
      [](auto const& t) {
        if constexpr (std::is_same_v<std::decay_t<decltype(t)>, plume::FixedJoint>)
          return false;
        else
          return !t.limits_valid();
      },
      def.type);
  bool const bad_motor = std::visit(
      [](auto const& t) {
        if constexpr (requires { t.motor; })
          return !t.motor.valid();
        else
          return false;
      },
      def.type);
  bool const bad_value = std::isnan(def.break_force) || std::isnan(def.break_torque) ||
                         def.break_force < 0.0f || def.break_torque < 0.0f;
  Snapshot const before(w);
  plume::CreateJointResult const r = w.create_joint(def);
  switch (r.error) {
  case JointError::none:
    PLUME_FUZZ_CHECK(!bad_body && !same_body && !bad_axis && !bad_limits && !bad_motor &&
                     !bad_value);
    break;
  case JointError::bad_body:
    PLUME_FUZZ_CHECK(bad_body);
    break;
  case JointError::same_body:
    PLUME_FUZZ_CHECK(same_body);
    break;
  case JointError::bad_axis:
    PLUME_FUZZ_CHECK(bad_axis);
    break;
  case JointError::bad_limits:
    PLUME_FUZZ_CHECK(bad_limits);
    break;
  case JointError::bad_motor:
    PLUME_FUZZ_CHECK(bad_motor);
    break;
  case JointError::bad_value:
    PLUME_FUZZ_CHECK(bad_value);
    break;
  default:
    PLUME_FUZZ_CHECK(false && "create_joint: an error it does not document");
  }
  if (!r) {
    PLUME_FUZZ_CHECK(!r.id.valid() && Snapshot(w) == before);
    return;
  }
  PLUME_FUZZ_CHECK(w.is_alive(r.id));
  PLUME_FUZZ_CHECK(w.joint_def(r.id).body_a == def.body_a &&
                   w.joint_def(r.id).body_b == def.body_b);
  PLUME_FUZZ_CHECK(w.joint_def(r.id).type.index() == def.type.index());
  for (BodyId const b : {def.body_a, def.body_b}) {
    std::vector<JointId> const js = w.body_joints(b);
    PLUME_FUZZ_CHECK(std::find(js.begin(), js.end(), r.id) != js.end());
  }
  bool const motor = std::holds_alternative<plume::RevoluteJoint>(def.type) ||
                     std::holds_alternative<plume::PrismaticJoint>(def.type);
  m.joints.push_back({r.id, true, def.body_a, def.body_b, motor});
}

MirrorJoint* find_joint(Mirror& m, JointId id) { return find_alive(m.joints, id); }

void destroy_joint(plume::World& w, Mirror& m, Input& in) {
  JointId const id = m.pick_joint(in);
  MirrorJoint* j = find_joint(m, id);
  Snapshot const before(w);
  JointError const e = w.destroy_joint(id);
  if (!j) {
    PLUME_FUZZ_CHECK(e == JointError::bad_joint && Snapshot(w) == before);
    PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)w.joint_def(id); }));
    PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)w.joint_state(id); }));
    return;
  }
  PLUME_FUZZ_CHECK(e == JointError::none && !w.is_alive(id));
  j->alive = false;
}

void set_motor(plume::World& w, Mirror& m, Input& in) {
  JointId const id = m.pick_joint(in);
  MirrorJoint const* j = find_joint(m, id);
  std::uint8_t const k = in.byte();
  Snapshot const before(w);
  std::size_t const joints = w.joint_count();
  if (k & 1) {
    bool valid = false;
    plume::Motor const motor = decode_motor(in, valid);
    JointError const e = w.set_motor(id, motor);
    if (!j || !j->has_motor) {
      PLUME_FUZZ_CHECK(e == JointError::bad_joint);
    } else if (!valid) {
      PLUME_FUZZ_CHECK(e == JointError::bad_motor);
    } else {
      PLUME_FUZZ_CHECK(e == JointError::none);
      std::visit(
          [&](auto const& t) {
            if constexpr (requires { t.motor; })
              PLUME_FUZZ_CHECK(t.motor.enabled == motor.enabled &&
                               same(t.motor.target_velocity, motor.target_velocity) &&
                               same(t.motor.max_force, motor.max_force));
          },
          w.joint_def(id).type);
      return;
    }
  } else {
    float const v = in.maybe_bad(-5, 5), p = in.maybe_bad(-5, 5);
    JointError const e = w.set_motor_targets(id, v, p);
    if (!j || !j->has_motor) {
      PLUME_FUZZ_CHECK(e == JointError::bad_joint);
    } else {
      bool const ok = std::visit(
          [&](auto const& t) {
            if constexpr (requires { t.motor; }) {
              plume::Motor next = t.motor;
              next.target_velocity = v;
              next.target_position = p;
              return next.valid();
            } else {
              return false;
            }
          },
          w.joint_def(id).type);
      PLUME_FUZZ_CHECK(e == (ok ? JointError::none : JointError::bad_motor));
      if (ok) return;
    }
  }
  PLUME_FUZZ_CHECK(Snapshot(w) == before && w.joint_count() == joints);
}

void step(plume::World& w, Mirror& m, Input& in, int& steps) {
  if (steps >= 8) return;
  ++steps;
  std::uint8_t const k = in.byte();
  float dt;
  switch (k % 8) {
  case 0:
    dt = 0.0f;
    break;
  case 1:
    dt = (k & 8) ? -in.real(0, 1) : in.any_float();
    break;
  case 2:
    dt = (k & 8) ? std::numeric_limits<float>::infinity() : std::numeric_limits<float>::quiet_NaN();
    break;
  default:
    dt = in.real(1.0f / 480.0f, 1.0f / 20.0f);
    break;
  }
  Snapshot const before(w);
  std::vector<Iso3> static_poses;
  for (MirrorBody const& b : m.bodies)
    if (b.alive && b.type == plume::BodyType::static_body) static_poses.push_back(w.pose(b.id));
  for (MirrorCollider const& c : m.colliders)
    if (c.alive) static_poses.push_back(w.pose(c.id));
  bool const ignored = !(dt >= plume::World::min_dt && dt <= plume::World::max_dt);
  // step_with<T> gives the world step() gives, for every width the build has.
  // And so does a step whose parallel stages run as reversed one-item tasks.
  std::vector<std::uint64_t> widths;
  if constexpr (std::is_copy_constructible_v<plume::World>)
    if ((k & 0x30) == 0x30) {
      plume::fuzz::for_each_width([&]<class T>() {
        plume::World copy = w;
        copy.step_with<T>(dt);
        widths.push_back(copy.state_hash());
      });
      ReversedTasks tasks;
      plume::World copy = w;
      copy.set_task_system(&tasks);
      copy.step(dt);
      widths.push_back(copy.state_hash());
    }
  w.step(dt);
  if (ignored) {
    PLUME_FUZZ_CHECK(Snapshot(w) == before);
    return;
  }
  for (std::uint64_t const h : widths)
    PLUME_FUZZ_CHECK(h == w.state_hash());
  std::size_t s = 0;
  for (MirrorBody const& b : m.bodies) {
    if (!b.alive) continue;
    Iso3 const p = w.pose(b.id);
    PLUME_FUZZ_CHECK(plume::fuzz::finite(p.translation) && finite(p.rotation));
    PLUME_FUZZ_CHECK(plume::fuzz::finite(w.linear_velocity(b.id)) &&
                     plume::fuzz::finite(w.angular_velocity(b.id)));
    PLUME_FUZZ_CHECK(plume::fuzz::finite(w.center_of_mass(b.id)));
    if (b.type == plume::BodyType::static_body) PLUME_FUZZ_CHECK(same(p, static_poses[s++]));
  }
  for (MirrorCollider const& c : m.colliders)
    if (c.alive) PLUME_FUZZ_CHECK(same(w.pose(c.id), static_poses[s++]));
  // Every frozen body is in frozen_bodies() (which lists every freeze, ever).
  std::span<BodyId const> const frozen = w.frozen_bodies();
  for (MirrorBody const& b : m.bodies)
    if (b.alive && w.is_frozen(b.id))
      PLUME_FUZZ_CHECK(std::find(frozen.begin(), frozen.end(), b.id) != frozen.end());
  for (BodyId const f : frozen)
    PLUME_FUZZ_CHECK(std::any_of(m.bodies.begin(), m.bodies.end(),
                                 [&](MirrorBody const& b) { return b.id == f; }));
  plume::StepEvents const& ev = w.events();
  for (auto const* list : {&ev.contact_begin, &ev.contact_end, &ev.sensor_begin, &ev.sensor_end}) {
    for (std::size_t i = 0; i < list->size(); ++i) {
      plume::ColliderPair const& p = (*list)[i];
      PLUME_FUZZ_CHECK(p.a.index < p.b.index);
      if (i > 0) {
        plume::ColliderPair const& q = (*list)[i - 1];
        PLUME_FUZZ_CHECK(q.a.index < p.a.index ||
                         (q.a.index == p.a.index && q.b.index < p.b.index));
      }
    }
  }
  for (auto const* list : {&ev.contact_begin, &ev.sensor_begin})
    for (plume::ColliderPair const& p : *list)
      PLUME_FUZZ_CHECK(w.is_alive(p.a) && w.is_alive(p.b));
  // Swept bodies: live dynamic bodies, each once, by index.
  for (std::size_t i = 0; i < ev.continuous_stops.size(); ++i) {
    BodyId const b = ev.continuous_stops[i];
    PLUME_FUZZ_CHECK(w.is_alive(b) && w.type(b) == plume::BodyType::dynamic);
    if (i > 0) PLUME_FUZZ_CHECK(ev.continuous_stops[i - 1].index < b.index);
  }
  for (JointId const j : ev.joint_broken)
    PLUME_FUZZ_CHECK(w.is_alive(j));
  for (auto const* list : {&ev.woke_up, &ev.fell_asleep})
    for (std::size_t i = 1; i < list->size(); ++i)
      PLUME_FUZZ_CHECK((*list)[i - 1].index < (*list)[i].index ||
                       ((*list)[i - 1].index == (*list)[i].index &&
                        (*list)[i - 1].generation < (*list)[i].generation));
  for (BodyId const b : ev.fell_asleep)
    PLUME_FUZZ_CHECK(w.is_alive(b) && w.is_sleeping(b));
  if (!w.config().sleep) PLUME_FUZZ_CHECK(w.sleeping_count() == 0);
  for (MirrorJoint const& j : m.joints) {
    if (!j.alive) continue;
    plume::JointState const st = w.joint_state(j.id);
    PLUME_FUZZ_CHECK(std::isfinite(st.angle) && std::isfinite(st.swing) &&
                     std::isfinite(st.translation) && std::isfinite(st.angular_speed) &&
                     std::isfinite(st.linear_speed));
    PLUME_FUZZ_CHECK(plume::fuzz::finite(st.reaction_force) &&
                     plume::fuzz::finite(st.reaction_torque));
  }
  PLUME_FUZZ_CHECK(std::isfinite(w.kinetic_energy()));
}

void sleep_op(plume::World& w, Mirror& m, Input& in) {
  std::uint8_t const k = in.byte();
  BodyId const id = m.pick(in);
  MirrorBody const* b = m.find(id);
  Snapshot const before(w);
  BodyError e = BodyError::none;
  switch (k % 5) {
  case 0:
  case 1:
    e = w.set_awake(id, k % 5 == 1);
    if (b && e == BodyError::none) {
      if (k % 5 == 1)
        PLUME_FUZZ_CHECK(!w.is_sleeping(id));
      else {
        // Asleep exactly when it may: a dynamic, unfrozen body in a world that sleeps, unless
        // its island holds a body whose sleeping is disabled (any such body is a suspect).
        bool const may =
            w.config().sleep && w.type(id) == plume::BodyType::dynamic && !w.is_frozen(id);
        bool const vetoed = std::any_of(m.bodies.begin(), m.bodies.end(), [&](auto const& o) {
          return o.alive && !w.sleep_enabled(o.id);
        });
        PLUME_FUZZ_CHECK(!w.is_sleeping(id) || may);
        PLUME_FUZZ_CHECK(w.is_sleeping(id) || !may || vetoed);
      }
    }
    break;
  case 2:
    w.wake_all();
    PLUME_FUZZ_CHECK(w.sleeping_count() == 0);
    return;
  case 3:
    e = w.set_sleep_enabled(id, (k & 8) != 0);
    if (b && e == BodyError::none) {
      PLUME_FUZZ_CHECK(w.sleep_enabled(id) == ((k & 8) != 0));
      if (!(k & 8)) PLUME_FUZZ_CHECK(!w.is_sleeping(id));
    }
    break;
  default: {
    Faults f;
    float const t = material(in, 0, 2, f);
    e = w.set_sleep_threshold(id, t);
    if (b) {
      PLUME_FUZZ_CHECK(e == (f.non_finite ? BodyError::non_finite
                             : f.negative ? BodyError::bad_material
                                          : BodyError::none));
      if (e == BodyError::none)
        PLUME_FUZZ_CHECK(same(w.sleep_threshold(id), t) && !w.is_sleeping(id));
      else
        PLUME_FUZZ_CHECK(Snapshot(w) == before);
    }
    break;
  }
  }
  if (!b) PLUME_FUZZ_CHECK(e == BodyError::bad_body && Snapshot(w) == before);
}

void query(plume::World const& w, Mirror& m, Input& in) {
  std::uint8_t const k = in.byte();
  bool bad_o = false, bad_d = false;
  plume::Ray3 ray{decode_vec(in, -6, 6, bad_o), decode_vec(in, -1, 1, bad_d)};
  if ((k & 3) == 0) {
    ray.dir = Vec3{0.0f, -1.0f, 0.0f};
    bad_d = false;
  }
  float const max_toi = (k & 4) ? std::numeric_limits<float>::infinity() : in.real(0, 20);
  bool const usable = !bad_o && !bad_d && ray.dir.length_squared() > 0.0f;
  std::optional<plume::WorldRayHit> const hit = w.ray_cast(ray, max_toi);
  std::vector<plume::WorldRayHit> all;
  w.ray_cast_all(ray, max_toi, [&](plume::WorldRayHit const& h) {
    all.push_back(h);
    return true;
  });
  if (!usable) PLUME_FUZZ_CHECK(!hit && all.empty());
  for (std::size_t i = 0; i < all.size(); ++i) {
    PLUME_FUZZ_CHECK(w.is_alive(all[i].collider) && all[i].body == all[i].collider.body());
    PLUME_FUZZ_CHECK(all[i].toi >= 0.0f && all[i].toi <= max_toi);
    if (i > 0) PLUME_FUZZ_CHECK(all[i - 1].toi <= all[i].toi);
  }
  PLUME_FUZZ_CHECK(hit.has_value() == !all.empty());
  if (hit) {
    PLUME_FUZZ_CHECK(hit->collider == all.front().collider && same(hit->toi, all.front().toi));
    PLUME_FUZZ_CHECK(plume::fuzz::finite(hit->point) && plume::fuzz::finite(hit->normal));
  }
  // The batch form: each ray's answer is the single form's, bit for bit.
  std::vector<plume::Ray3> rays{ray};
  for (int i = 0; i < 4; ++i) {
    bool b1 = false, b2 = false;
    rays.push_back({decode_vec(in, -6, 6, b1), decode_vec(in, -1, 1, b2)});
  }
  std::vector<std::optional<plume::WorldRayHit>> out(rays.size());
  w.ray_cast(std::span<plume::Ray3 const>(rays), max_toi,
             std::span<std::optional<plume::WorldRayHit>>(out));
  for (std::size_t i = 0; i < rays.size(); ++i) {
    std::optional<plume::WorldRayHit> const one = w.ray_cast(rays[i], max_toi);
    PLUME_FUZZ_CHECK(one.has_value() == out[i].has_value());
    if (one)
      PLUME_FUZZ_CHECK(one->collider == out[i]->collider && one->body == out[i]->body &&
                       same(one->toi, out[i]->toi) && same(one->point, out[i]->point) &&
                       same(one->normal, out[i]->normal));
  }
  PLUME_FUZZ_CHECK(throws<std::invalid_argument>([&] {
    w.ray_cast(std::span<plume::Ray3 const>(rays), max_toi,
               std::span<std::optional<plume::WorldRayHit>>(out).first(1));
  }));
  // Box, point and shape queries see only live bodies.
  plume::Aabb3 const box{ray.origin - Vec3::splat(2.0f), ray.origin + Vec3::splat(2.0f)};
  auto const live = [&](ColliderId id) {
    PLUME_FUZZ_CHECK(w.is_alive(id));
    return true;
  };
  w.overlap_aabb(box, live);
  w.point_query(ray.origin, live);
  w.overlap_shape(plume::Sphere{1.0f}, Iso3{Quat::IDENTITY, ray.origin}, live);
  std::optional<plume::WorldPointHit> const near = w.project_point(ray.origin, 5.0f);
  if (bad_o) PLUME_FUZZ_CHECK(!near);
  if (near) {
    PLUME_FUZZ_CHECK(w.is_alive(near->collider) && near->body == near->collider.body());
    PLUME_FUZZ_CHECK(near->distance >= 0.0f && near->distance <= 5.0f);
  }
  int found = 0;
  w.contact_query(plume::Capsule{0.5f, 0.3f}, Iso3{Quat::IDENTITY, ray.origin},
                  (k & 8) ? -1.0f : 0.05f, [&](ColliderId id, plume::Manifold const& mf) {
                    PLUME_FUZZ_CHECK(w.is_alive(id));
                    for (auto const& c : mf)
                      PLUME_FUZZ_CHECK(c.separation <= 0.05f + 1e-4f);
                    ++found;
                    return true;
                  });
  if ((k & 8) || bad_o) PLUME_FUZZ_CHECK(found == 0);
  // Accessors of stale ids throw.
  for (MirrorBody const& b : m.bodies)
    if (!b.alive && !w.is_alive(b.id)) {
      PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)w.pose(b.id); }));
      PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)w.aabb(b.id); }));
      PLUME_FUZZ_CHECK(throws<std::out_of_range>([&] { (void)w.velocity_at(b.id, Vec3{}); }));
      break;
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  Input in(data, size);
  plume::WorldConfig cfg;
  std::uint8_t const c = in.byte();
  if (c & 1) cfg.broad_phase = plume::BroadPhaseKind::sort_and_sweep;
  if (c & 2) cfg.substeps = in.integer(1, 4);
  if (c & 4) {
    cfg.solve_iterations = in.integer(1, 3);
    cfg.relax_iterations = in.integer(0, 3);
  }
  if (c & 8) cfg.gravity = in.vec3(-20, 20);
  if (c & 16) cfg.sleep = false;
  if (c & 32) cfg.time_to_sleep = in.real(0, 0.1f); // islands fall asleep within the steps
  // Manifold reuse off, or as loose as it gets (half the speculative distance, a radian); no
  // bytes read, so the rest of an input decodes as before (only inputs with these bits set
  // now run with another reuse setting).
  if (c & 64) cfg.reuse_distance = 0.0f;
  if (c & 128) cfg.reuse_distance = 1.0f, cfg.reuse_angle = 1.0f;
  plume::World w(cfg);
  Mirror m;
  int steps = 0;
  int const ops = in.integer(1, 48);
  for (int op = 0; op < ops && !in.empty(); ++op) {
    std::uint8_t const k = in.byte();
    switch (k % 15) {
    case 0:
    case 1:
    case 2:
      create_body(w, m, in);
      break;
    case 3:
      destroy_body(w, m, in);
      break;
    case 4:
      set_pose(w, m, in);
      break;
    case 5:
      set_velocity(w, m, in);
      break;
    case 6:
      apply_impulse(w, m, in);
      break;
    case 7:
      set_type(w, m, in);
      break;
    case 8:
      set_layers(w, m, in);
      break;
    case 9:
      create_joint(w, m, in);
      break;
    case 10:
      if (k & 0x10)
        destroy_joint(w, m, in);
      else
        set_motor(w, m, in);
      break;
    case 11:
    case 12:
      step(w, m, in, steps);
      break;
    case 13:
      sleep_op(w, m, in);
      break;
    case 14:
      if ((k & 0x30) == 0)
        destroy_collider(w, m, in);
      else if ((k & 0x30) == 0x10)
        set_collider_pose(w, m, in);
      else if ((k & 0xf0) == 0x20)
        set_collider_layers(w, m, in);
      else
        create_collider(w, m, in);
      break;
    default:
      query(w, m, in);
      break;
    }
    check_mirror(w, m);
  }
  return 0;
}
