// plume/solver/world/world.hpp - a minimal rigid-body world around the wide contact solver: bodies
// with shapes from the collision module, a BVH broad phase, manifolds from
// collision/manifold.hpp matched across steps by feature id, a persistent graph colouring
// and the soft-step solver (solver/contact_constraint.hpp) run W constraints at a time.
//
//   World world;                                   // gravity -9.81 m/s^2 along y
//   world.create_body({.type = BodyType::static_body, .shape = HalfSpace{Vec3::Y}});
//   BodyId box = world.create_body({.pose = Iso3::from_translation({0, 2, 0}),
//                                   .shape = Cuboid{Vec3::splat(0.5f)}}).id;
//   for (int i = 0; i < 60; ++i) world.step(1.0f / 60.0f);
//   Iso3 p = world.pose(box);
//
// Units are SI (m, kg, s, rad); the world is float. step(dt) solves with the widest batch
// the build enables (f32xN; in a PLUME_DISPATCH=ON build that of the instruction set chosen
// at run time, plume/numerics/isa.hpp); step_with<T>(dt) with the one named (float, f32x4, f32x8,
// f32x16: those the build has). Every width gives bitwise the same world (the colouring does
// not depend on the width, no body appears twice in a colour, and every kernel is
// lane-exact), and so does every deterministic build (scalar, sse2, avx2, avx512).
//
// Step, in named stages (solver/world/step.cpp): find_pairs (broad phase, AABBs grown by the
// speculative distance; bounding volume hierarchies by default, WorldConfig::broad_phase) ->
// collide_pairs (manifolds) -> the contact cache (warm starts, colouring) -> prepare_bodies -> pack
// the constraints (solver/constraint_blocks.hpp) -> per substep: integrate velocities (gravity,
// damping), warm start, solve, integrate positions, relax -> restitution -> store impulses ->
// finalize_bodies (poses). Overflow constraints (no free colour) are solved first in each pass, one
// at a time, then the colours in order.
//
// Meshes: a static or kinematic body may have a MeshShape (a shared TriangleMesh: level
// geometry) or a HeightFieldShape (a shared HeightField: terrain). Dynamic bodies collide with
// it triangle by triangle, with internal edges corrected so that a body sliding across two
// coplanar triangles meets no ghost bump, and one contact per group of triangles with one
// normal (spatial/mesh_queries.hpp): a pair with a mesh may hold up to max_mesh_manifolds
// contacts. Every query sees meshes. Bodies change type with set_type().
//
// Bad input: create_body() rejects a non-finite pose, velocity or material, a dynamic body
// whose shape and density give no positive finite mass, and a mesh or height field that is
// empty or on a dynamic body (BodyError; the world is unchanged). Setters reject non-finite
// values the same way. A dynamic body whose state turns non-finite during a step (absurd
// velocities) is put back where the step began, stopped and frozen: it then acts as a static
// body, and frozen_bodies() reports it. step() ignores dt outside [min_dt, max_dt] = [1e-6 s, 60
// s]. Accessors taking a BodyId throw std::out_of_range for an id that names no live body (never
// created, or destroyed: ids carry a generation); setters and destroy_body() return
// BodyError::bad_body instead.
//
// Continuous collision: a dynamic body that moved far for its size in a step (WorldConfig::
// ccd_fraction) is swept along its path against static bodies, and a bullet (BodyDef::bullet)
// also against kinematic and dynamic ones, and put back at the first time of impact
// (solver/world/continuous.cpp); a 0.1 m ball at 400 m/s stops at a 1 cm wall. The sweep is a
// translation at the step's final orientation: a body that tunnels only by spinning (a long,
// thin rod turning fast) is not caught.
//
// Standalone colliders (create_collider): a shape with no body, as Avian's colliders without a
// rigid body, for level geometry and triggers. It collides as a static body (never moves in a
// step, infinite mass; a sensor collider reports overlaps), lives in a broad-phase tree of its
// own, so that creating, moving or destroying one never rebuilds the static bodies' tree, and
// may be teleported at any time (set_collider_pose). Queries and events name what they meet by
// ColliderId: a body's (its BodyId converts) or a standalone collider's (no body).
//
// Sleeping (WorldConfig::sleep, on by default): dynamic bodies touching each other (contacts
// with manifold points) or jointed form islands; an island falls asleep at the end of a step
// when each of its bodies has stayed below its sleep threshold (BodyDef::sleep_threshold,
// 0.05 m/s, on the speed of its farthest point |v| + |w| max_extent, Box2D v3's measure) for
// WorldConfig::time_to_sleep (0.5 s). A sleeping body stops (velocities zero), keeps its
// contacts, sensor overlaps and joints (no events), and costs the step nothing (the broad
// phase files it in a tree of its own; only its joints are still looked at, once each). Its
// island wakes when an awake dynamic body, or a kinematic body with a velocity, touches one of
// its bodies (at the start of a step: the wake is in that step), on every setter of one of its
// bodies or joints, when a body, collider or joint it touches is destroyed, teleported or
// re-layered, when a static body or collider is created over it, and on demand (set_awake,
// wake_all). A body that touches a kinematic body with a
// velocity, or whose sleeping is disabled (BodyDef::enable_sleep), keeps its island awake.
// Islands are found anew each step from the awake contacts and joints, in body index order,
// so sleeping is as deterministic as the rest of the step (every width and build).
// StepEvents::fell_asleep and woke_up report the changes. No callback runs during a step, so
// nothing can wake a body mid-step.
//
// Threads (WorldConfig::tasks, set_task_system; solver/world/tasks.hpp): with a task system
// of more than one worker, the bodies' AABBs, the broad phase's queries for moved bodies
// (chunks of 32), the narrow phase (chunks of 16 pairs), the bodies' preparation, integration
// and finalisation, the packing of contacts and joints, and each colour's blocks in every
// solver pass run as range tasks; the rest of the step (the trees' edits, the contact cache,
// colouring, events, continuous collision, sleeping) runs on the calling thread. Each task
// writes only its own items' results, so the world is bitwise the same for any task system
// and thread count; a stage with little work (no more items than its minimum range) runs
// inline. The step's calling thread must be the only one using the world during the step.
//
// Out of scope for this version (named, not stubbed): compound bodies (one shape per body).
#pragma once

#include <plume/collision/convex_hull.hpp>
#include <plume/collision/gjk.hpp>
#include <plume/collision/manifold.hpp>
#include <plume/collision/mass_properties.hpp>
#include <plume/collision/ray_cast.hpp>
#include <plume/collision/shapes.hpp>
#include <plume/math/aabb3.hpp>
#include <plume/math/iso3.hpp>
#include <plume/math/mat3.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics/isa.hpp>
#include <plume/solver/body_state.hpp>
#include <plume/solver/constraint_blocks.hpp>
#include <plume/solver/constraint_graph.hpp>
#include <plume/solver/contact_constraint.hpp>
#include <plume/solver/joints/joint.hpp>
#include <plume/solver/world/broad_phase.hpp>
#include <plume/solver/world/contact_cache.hpp>
#include <plume/solver/world/tasks.hpp>
#include <plume/spatial/height_field.hpp>
#include <plume/spatial/mesh_queries.hpp>
#include <plume/spatial/triangle_mesh.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

namespace plume {

enum class BroadPhaseKind : std::uint8_t {
  bvh,            ///< bounding volume hierarchies: static bodies cost nothing per step
  sort_and_sweep, ///< every body sorted on x every step
};

enum class BodyType : std::uint8_t {
  static_body, ///< never moves, infinite mass
  kinematic,   ///< moves with its velocity, infinite mass, not pushed by contacts
  dynamic,     ///< moved by gravity and contacts
};

/// Collision filtering, as Avian's CollisionLayers: bodies a and b can touch when
/// (a.memberships & b.filters) != 0 and (b.memberships & a.filters) != 0. A query sees a body
/// when (body.memberships & QueryFilter::mask) != 0.
struct CollisionLayers {
  std::uint32_t memberships = 1;       ///< the layers the body is in
  std::uint32_t filters = 0xffffffffu; ///< the layers it interacts with
  bool interacts(CollisionLayers const& o) const noexcept {
    return (memberships & o.filters) != 0 && (o.memberships & filters) != 0;
  }
};

/// A triangle mesh as a body's shape (level geometry): the mesh is shared, not copied (the
/// shape keeps it alive). Static and kinematic bodies only: a mesh has no
/// inside, so no mass. Contacts with convex bodies follow spatial/mesh_queries.hpp (internal
/// edges corrected, up to max_mesh_manifolds manifolds per pair); two meshes, or a mesh and a
/// half-space, never collide.
struct MeshShape {
  std::shared_ptr<TriangleMesh const> mesh;
  /// The mesh's bounds at pose (EMPTY without a mesh).
  Aabb3 aabb(Iso3 const& pose) const noexcept {
    return mesh && !mesh->empty() ? mesh->local_aabb().transformed(pose) : Aabb3::EMPTY;
  }
  /// The mesh (null without one): what the world's queries and contacts run on.
  TriangleMesh const* source() const noexcept { return mesh.get(); }
};

/// A height field as a body's shape (terrain): shared as MeshShape's mesh, with the same rules
/// (static and kinematic bodies only; contacts, events and queries as a mesh's).
struct HeightFieldShape {
  std::shared_ptr<HeightField const> field;
  /// The field's bounds at pose (EMPTY without a field).
  Aabb3 aabb(Iso3 const& pose) const noexcept {
    return field && !field->empty() ? field->local_aabb().transformed(pose) : Aabb3::EMPTY;
  }
  /// The field (null without one): what the world's queries and contacts run on.
  HeightField const* source() const noexcept { return field.get(); }
};

/// The shapes a body can have (one per body).
using BodyShape = std::variant<Sphere, Capsule, Cuboid, Cylinder, ConvexHull, HalfSpace, MeshShape,
                               HeightFieldShape>;

/// Whether a body shape is made of triangles (MeshShape, HeightFieldShape).
template <class S>
inline constexpr bool is_triangle_shape_v =
    std::is_same_v<S, MeshShape> || std::is_same_v<S, HeightFieldShape>;
/// Whether a body shape can be the query shape of a cast, overlap or contact query (not a
/// half-space, mesh or height field).
inline bool is_convex_shape(BodyShape const& s) noexcept {
  return std::visit(
      [](auto const& x) {
        using S = std::decay_t<decltype(x)>;
        return !std::is_same_v<S, HalfSpace> && !is_triangle_shape_v<S>;
      },
      s);
}

struct BodyDef {
  BodyType type = BodyType::dynamic;
  Iso3 pose{};             ///< the shape's frame in the world
  Vec3 linear_velocity{};  ///< of the centre of mass, m/s
  Vec3 angular_velocity{}; ///< rad/s, world axes
  BodyShape shape = Sphere{0.5f};
  float density = 1000.0f;      ///< kg/m^3 (dynamic bodies)
  float friction = 0.6f;        ///< Coulomb coefficient; a pair uses sqrt(f_a f_b)
  float restitution = 0.0f;     ///< 0..1; a pair uses max(e_a, e_b)
  float linear_damping = 0.0f;  ///< 1/s: v /= 1 + h c each substep
  float angular_damping = 0.0f; ///< 1/s
  float gravity_scale = 1.0f;
  CollisionLayers layers{};
  /// A sensor reports the bodies it overlaps (sensor events) and takes no contact response;
  /// it pairs, like every body, only where at least one of the two is dynamic.
  bool sensor = false;
  /// A bullet is swept (continuous collision, WorldConfig::continuous) against kinematic and
  /// dynamic bodies at their poses at the end of the step too, not only against static ones:
  /// for projectiles, at the cost of a sweep through every tree. Two bullets are not swept
  /// against each other.
  bool bullet = false;
  /// false: the body never sleeps and keeps every body it touches awake (a player's body).
  bool enable_sleep = true;
  /// m/s: the body may sleep while |v| + |w| x max extent (the speed of its farthest point
  /// from its centre of mass) stays at most this (Box2D v3's default). Finite and >= 0, else
  /// bad_material.
  float sleep_threshold = 0.05f;
  /// false: a dynamic body created asleep, in an island of its own (a stack placed at rest
  /// sleeps until something touches it). Other types, and bodies with enable_sleep false,
  /// ignore it.
  bool awake = true;
};

enum class BodyError : std::uint8_t {
  none,
  non_finite,   ///< pose, velocity or a material value is NaN or infinite
  zero_mass,    ///< a dynamic body whose shape and density give no positive finite mass
  bad_material, ///< negative density, friction, restitution, damping or sleep threshold
  bad_body,     ///< the id names no live body (collider calls: no live standalone collider)
  bad_shape,    ///< a MeshShape or HeightFieldShape that is empty or on a dynamic body
};
std::string_view to_string(BodyError e) noexcept;

/// A body: its slot and the slot's generation. destroy_body() frees the slot for reuse by a
/// later create_body() or create_collider() with the next generation, so an id kept past its body's
/// destruction names no body (accessors throw, setters return bad_body), never the slot's new body.
struct BodyId {
  std::uint32_t index = ~std::uint32_t(0);
  std::uint32_t generation = 0;
  bool valid() const noexcept { return index != ~std::uint32_t(0); }
  friend bool operator==(BodyId, BodyId) = default;
};

/// What a query or event met: a body's shape (one per body) or a standalone collider. Bodies and
/// standalone colliders share the world's slots, so `index` is unique among live colliders;
/// a slot reused after a destroy gets the next generation. A BodyId converts to its body's
/// collider; body() goes back (an invalid BodyId for a standalone collider).
struct ColliderId {
  std::uint32_t index = ~std::uint32_t(0);
  std::uint32_t generation = 0;
  bool standalone = false; ///< a collider without a body (World::create_collider)
  constexpr ColliderId() noexcept = default;
  constexpr ColliderId(std::uint32_t i, std::uint32_t g, bool alone) noexcept
      : index(i), generation(g), standalone(alone) {}
  /// The collider of body b.
  constexpr ColliderId(BodyId b) noexcept : index(b.index), generation(b.generation) {}
  /// The body whose shape this is (invalid for a standalone collider).
  constexpr BodyId body() const noexcept {
    return standalone ? BodyId{} : BodyId{index, generation};
  }
  bool valid() const noexcept { return index != ~std::uint32_t(0); }
  friend bool operator==(ColliderId, ColliderId) = default;
};

/// A standalone collider: a shape with no body (level geometry, a trigger). It collides as a
/// static body with the dynamic bodies whose layers it interacts with.
struct ColliderDef {
  Iso3 pose{}; ///< the shape's frame in the world
  BodyShape shape = Sphere{0.5f};
  float friction = 0.6f;    ///< as BodyDef::friction
  float restitution = 0.0f; ///< as BodyDef::restitution
  CollisionLayers layers{};
  /// A sensor (a trigger) reports the dynamic bodies it overlaps and takes no contact response.
  bool sensor = false;
};

struct CreateColliderResult {
  ColliderId id; ///< invalid when error != none
  BodyError error = BodyError::none;
  explicit operator bool() const noexcept { return error == BodyError::none; }
};

/// A joint between two bodies (solver/joints/joint.hpp has the types, rows and errors).
struct JointDef {
  BodyId body_a, body_b;
  JointFrame frame_a, frame_b; ///< each in its body's shape frame
  JointType type = FixedJoint{};
  /// false: the two bodies do not collide with each other while the joint exists and is
  /// not broken.
  bool collide_connected = false;
  /// The joint breaks (stops acting, reported in StepEvents::joint_broken) in the first step
  /// whose reaction force (N) or torque (N m) exceeds these.
  float break_force = std::numeric_limits<float>::infinity();
  float break_torque = std::numeric_limits<float>::infinity();
};

/// Which colliders a world query sees: those in a layer of `mask`, not of a body in `exclude`,
/// sensors only with `sensors`, and for which `predicate` (when set) returns true. `exclude`
/// names bodies only (a BodyId made from a standalone collider's slot excludes nothing): leave
/// out a standalone collider with the predicate.
struct QueryFilter {
  std::uint32_t mask = 0xffffffffu;
  std::span<BodyId const> exclude{};
  std::function<bool(ColliderId)> predicate{};
  bool sensors = true; ///< false: sensors are not seen (a character walks through them)
};

/// A ray's hit on a collider: toi in units of the ray's direction, the world point and the
/// outward unit normal of the surface there (zero when the ray starts inside). `body` is the
/// body hit (invalid for a standalone collider); `collider` names the shape either way.
struct WorldRayHit {
  BodyId body;
  float toi = 0.0f;
  Vec3 point{};
  Vec3 normal{};
  ColliderId collider{};
};

/// A shape cast's first contact with a body: toi in units of the motion; point on the body;
/// normal out of the body toward the cast shape; penetrating when it started in contact.
/// (body and collider as WorldRayHit's.)
struct WorldShapeHit {
  BodyId body;
  float toi = 0.0f;
  Vec3 point{};
  Vec3 normal{};
  bool penetrating = false;
  ColliderId collider{};
};

/// The nearest point on a collider's surface to a query point (distance 0 and the point itself
/// when the point is inside; body and collider as WorldRayHit's).
struct WorldPointHit {
  BodyId body;
  float distance = 0.0f;
  Vec3 point{};
  ColliderId collider{};
};

namespace detail {
/// The contact manifolds of two body shapes (A toward B), as the step computes them: one for
/// two convex shapes or a half-space, up to max_mesh_manifolds for a convex shape and a mesh
/// (spatial/mesh_queries.hpp), none for two meshes or a mesh and a half-space. Returns how
/// many of `out` it wrote (empty manifolds are not written; a failed one is, with count 0).
int collide(BodyShape const& a, Iso3 const& pa, BodyShape const& b, Iso3 const& pb,
            ManifoldConfig const& cfg, std::array<Manifold, max_mesh_manifolds>& out);
/// The shape cast World::shape_cast runs on each candidate: the convex `shape` (is_convex_shape)
/// at `pose` moving by t * motion against one body's shape at body_pose (the hit's body is left
/// unset). None for a miss, a query shape that is not convex, or non-finite input.
std::optional<WorldShapeHit> cast_against(BodyShape const& body, Iso3 const& body_pose,
                                          BodyShape const& shape, Iso3 const& pose,
                                          Vec3 const& motion, ShapeCastConfig const& cfg);
} // namespace detail

/// Two colliders in an event, the lower slot first (ids as they were when the event
/// happened): two bodies, or a body and a standalone collider (a.body() or b.body() invalid).
struct ColliderPair {
  ColliderId a, b;
  friend bool operator==(ColliderPair const&, ColliderPair const&) = default;
};

/// What changed in the last step, each list in increasing pair order. A contact begins in the
/// step its pair first has manifold points (within the speculative distance) and ends in the
/// step it has none, or when a body is destroyed (destroy_body's ends are reported by the next
/// step); a body frozen in a step keeps a contact it still touches, as a static body. A sensor
/// overlap begins when the shapes first intersect (touching counts) and ends when they no longer
/// do. Both are found at the poses the step starts from.
struct StepEvents {
  std::vector<ColliderPair> contact_begin, contact_end;
  std::vector<ColliderPair> sensor_begin, sensor_end;
  /// Joints whose reaction passed their break force or torque in this step, by joint index.
  std::vector<JointId> joint_broken;
  /// Bodies the continuous pass put back to their first time of impact in this step (their
  /// velocities unchanged: the next step's contact stops them), by body index.
  std::vector<BodyId> continuous_stops;
  /// Dynamic bodies that woke since the last step began (by a setter, a destroy, set_awake,
  /// or a touch found at this step's start) and are alive, and those asleep at this step's
  /// end that fell asleep since it began (the step's islands, set_awake(false), created
  /// asleep), each by body index, each body once. A body woken and put to sleep again in
  /// between is in both.
  std::vector<BodyId> woke_up, fell_asleep;
};

struct CreateBodyResult {
  BodyId id; ///< invalid when error != none
  BodyError error = BodyError::none;
  explicit operator bool() const noexcept { return error == BodyError::none; }
};

struct WorldConfig {
  Vec3 gravity{0.0f, -9.81f, 0.0f}; ///< m/s^2
  int substeps = 4;
  /// Gauss–Seidel passes per substep: with the soft bias (solve) and without (relax).
  /// Box2D's 2D solver runs 1 + 1; 3D boxes with 4-point manifolds couple more and converge
  /// slower: 2 + 3 is the fewest that hold the 15- and 20-layer pyramids still for 10 s
  /// (docs/performance.md, "World step", has the measurements).
  int solve_iterations = 2;
  int relax_iterations = 3;
  /// Contact stiffness (Hz), capped at a quarter of the substep rate (Box2D's cap: 60 Hz at
  /// 60 steps/s and 4 substeps); contacts against static and kinematic bodies use
  /// static_hertz_scale times it (stiffer: nothing gives). A soft contact acts as a spring of
  /// stiffness m_eff (2 pi hertz)^2 per point, so a column of n boxes of edge L and mass m
  /// buckles (Greenhill) unless that spring beats the load: at 30 Hz the 20-box stack of 1 m
  /// cubes leans over and falls, at 60 Hz it stands.
  float contact_hertz = 60.0f;
  float static_hertz_scale = 2.0f;
  float contact_damping_ratio = 10.0f;
  float max_push_speed = 3.0f;        ///< m/s: fastest push out of penetration
  float restitution_threshold = 1.0f; ///< m/s: slower impacts do not bounce
  float max_linear_speed = 400.0f;    ///< m/s: velocities are clamped to it
  /// Largest rotation of a body in one substep (rad): keeps the quaternion update accurate.
  float max_rotation = 0.25f * 3.14159265f;
  /// Speculative distance: manifolds keep points up to this separation, and AABBs grow by it.
  float speculative_distance = 0.02f;
  /// A manifold point without a feature-id match inherits the impulses of the nearest point of
  /// the previous step within this distance (m).
  float contact_match_distance = 0.01f;
  ManifoldConfig manifold{};
  /// Manifold reuse (m): a pair keeps the manifolds it had when they were last computed, moved
  /// with its bodies (the normal with A, B's points with B, each separation measured again
  /// from A's point, A's point put back opposite B's), while nothing within the speculative
  /// distance of the smaller of its two shapes has moved more than reuse_distance relative
  /// to the other body since then and their relative rotation has not changed by more than
  /// reuse_angle (rad); a pair that was apart stays apart. The motion is bounded by |change
  /// of that shape's origin seen from the other body| + 2 sin(angle/2) x (the shape's reach,
  /// its farthest point from its origin, + the speculative distance or the manifold's
  /// deepest overlap): a long body turning a little is not reused where a small one is (the
  /// rule and its error: docs/performance.md, "Manifold reuse"). Each reused separation is
  /// then within reuse_distance of the same point's when it was computed (so the smallest
  /// within twice reuse_distance of the shapes' distance), and a pair reused as apart is
  /// still more than speculative_distance - reuse_distance apart: it cannot pass into
  /// another. The normal is the old one turned with A: B's frame turned at most reuse_angle
  /// against it. reuse_distance above half the speculative distance acts as half of it,
  /// reuse_angle above 1 rad as 1; either 0, negative or NaN: every pair is computed every
  /// step (StepProfile::reused_pairs counts the others). Slot reuse (a body destroyed and
  /// another created in its place) is never mistaken for the old pair. Every width and thread
  /// count reuses the same pairs.
  float reuse_distance = 0.0001f;
  float reuse_angle = 0.01f;
  /// Which broad phase finds the pairs (solver/world/broad_phase.hpp). Both give the same
  /// pairs, so the same world; sort_and_sweep is the baseline the BVH is measured against.
  BroadPhaseKind broad_phase = BroadPhaseKind::bvh;
  /// Continuous collision: after the solver, a dynamic body (not a sensor) whose centre of
  /// mass moved at least ccd_fraction x its min extent (the distance from its centre of mass
  /// to the nearest point of its surface) is swept from where the step began to where it
  /// ended, at its final orientation, against static bodies (bullets: every body but other
  /// bullets) that it interacts with (layers, sensors and jointed pairs as contacts), and put
  /// back at the first time of impact, ccd_distance() short of the surface. A sweep that
  /// starts touching a body (a box sliding on a floor) casts the body's core instead, a sphere
  /// of a quarter of its min extent at its centre of mass, against that body, as Box2D v3 does:
  /// the body may then stop in some penetration, which the next step's contact removes, but
  /// its centre never passes through. Velocities are kept: the speculative contact of the next
  /// step stops the body. false: no sweeps (a fast body can tunnel through thin geometry).
  /// ccd_fraction <= 0 sweeps every body that moved; NaN sweeps none.
  bool continuous = true;
  float ccd_fraction = 0.5f;
  /// Sleeping (the top of this header): islands of dynamic bodies whose bodies all stayed
  /// below their sleep thresholds for time_to_sleep seconds fall asleep. false: no body
  /// sleeps (bodies asleep when it is turned off wake at the next step).
  bool sleep = true;
  /// s (Box2D v3's b2_timeToSleep). 0 or less: an island sleeps in the first step all its
  /// bodies are below their thresholds; NaN: never.
  float time_to_sleep = 0.5f;
  /// The gap a sweep stops at (m): a quarter of the speculative distance, so that the next
  /// step finds the contact.
  float ccd_distance() const noexcept { return 0.25f * speculative_distance; }
  /// The task system the step runs its parallel stages on (not owned; it must outlive its
  /// use by the world). nullptr (the default): every stage on the calling thread.
  TaskSystem* tasks = nullptr;
  /// Joint stiffness (Hz) and damping ratio of every joint row that holds an error at zero
  /// (points, locks, limits), capped at a quarter of the substep rate as contact_hertz
  /// (Box2D's defaults: 60 Hz, 2).
  float joint_hertz = 60.0f;
  float joint_damping_ratio = 2.0f;
};

/// Seconds spent in each part of the last step (std::chrono::steady_clock).
/// joints: the part of solve spent in the joint passes (warm start, solve, relax).
/// continuous: the sweeps of fast bodies (after finalize, not part of it).
/// sleep: finding islands and putting them to sleep (after continuous, not part of finalize);
/// the waking of touched islands at the step's start is part of broad_phase.
/// manifolds: the part of narrow_phase spent making the pairs' manifolds (before the contact
/// cache matches them). pairs: the pairs the narrow phase tested; box_pairs: those of two cuboids,
/// which it ran through the manifold kernel in lanes (collision/box_manifold.hpp);
/// general_box_pairs: those of them the kernel left to the general path. reused_pairs: the
/// pairs that kept their manifolds (WorldConfig::reuse_distance), not counted in box_pairs.
struct StepProfile {
  double broad_phase = 0, narrow_phase = 0, prepare = 0, solve = 0, finalize = 0, total = 0;
  double joints = 0;
  double continuous = 0;
  double sleep = 0;
  double manifolds = 0;
  std::size_t pairs = 0, box_pairs = 0, general_box_pairs = 0, reused_pairs = 0;
};

class World {
public:
  explicit World(WorldConfig const& cfg = {});

  CreateBodyResult create_body(BodyDef const& def);

  /// Removes the body and its contacts now; its slot is reused by a later create_body() or
  /// create_collider().
  /// bad_body for an id that names no live body (the world is unchanged).
  BodyError destroy_body(BodyId id);
  /// True when the id names a live body (its slot's current generation).
  bool is_alive(BodyId id) const noexcept {
    return id.index < bodies_.size() && bodies_[id.index].alive && !bodies_[id.index].standalone &&
           bodies_[id.index].generation == id.generation;
  }
  /// The id of the live body in slot `index` (std::out_of_range if the slot holds no body).
  BodyId body_id(std::uint32_t index) const;

  /// Slots: one more than the largest index ever used, destroyed bodies and standalone
  /// colliders included (Contact::body_a and body_b are slots: collider_id() names them).
  std::size_t body_count() const noexcept { return bodies_.size(); }
  /// Live bodies.
  std::size_t alive_count() const noexcept {
    return bodies_.size() - free_slots_.size() - standalone_count_;
  }

  // -------------------------------------------------------------- standalone colliders
  // Shapes without a body (see the top of this file). Errors as create_body's: non_finite,
  // bad_material (negative friction or restitution), bad_shape (an empty mesh or height
  // field); a stale id gets bad_body from setters and std::out_of_range from accessors.

  CreateColliderResult create_collider(ColliderDef const& def);
  /// Removes the collider and its contacts and overlaps now (their ends are reported by the
  /// next step); its slot is reused by a later create_body() or create_collider().
  BodyError destroy_collider(ColliderId id);
  /// True when the id names a live collider: a live body's, or a live standalone one.
  bool is_alive(ColliderId id) const noexcept {
    return id.index < bodies_.size() && bodies_[id.index].alive &&
           bodies_[id.index].standalone == id.standalone &&
           bodies_[id.index].generation == id.generation;
  }
  /// The collider in slot `index`: a body's or a standalone one (std::out_of_range if free).
  ColliderId collider_id(std::uint32_t index) const;
  /// Live standalone colliders.
  std::size_t collider_count() const noexcept { return standalone_count_; }
  /// The collider's pose, shape, box, layers, material and sensor flag (any live collider,
  /// a body's included).
  Iso3 pose(ColliderId id) const { return slot(id).pose; }
  BodyShape const& shape(ColliderId id) const { return slot(id).shape; }
  Aabb3 aabb(ColliderId id) const;
  CollisionLayers layers(ColliderId id) const { return slot(id).layers; }
  float friction(ColliderId id) const { return slot(id).friction; }
  float restitution(ColliderId id) const { return slot(id).restitution; }
  bool is_sensor(ColliderId id) const { return slot(id).sensor; }
  /// Teleports a standalone collider (non_finite, and bad_body for a stale id or a body's
  /// collider (use set_pose), leave it unchanged). It carries no velocity: a dynamic body it
  /// moves into is pushed out as from a static body that appeared there.
  BodyError set_collider_pose(ColliderId id, Iso3 const& pose);
  /// New layers for a standalone collider: queries see them at once, contacts from the next
  /// step (bad_body as above).
  BodyError set_collider_layers(ColliderId id, CollisionLayers const& layers);
  BodyType type(BodyId id) const { return body(id).type; }
  /// The shape's frame in the world.
  Iso3 pose(BodyId id) const { return body(id).pose; }
  /// World centre of mass.
  Vec3 center_of_mass(BodyId id) const { return body(id).center; }
  Vec3 linear_velocity(BodyId id) const {
    return (void)body(id), states_[id.index].linear_velocity;
  }
  Vec3 angular_velocity(BodyId id) const {
    return (void)body(id), states_[id.index].angular_velocity;
  }
  float mass(BodyId id) const { return body(id).mass; }
  BodyShape const& shape(BodyId id) const { return body(id).shape; }
  /// The body's AABB at its pose (infinite for a half-space).
  Aabb3 aabb(BodyId id) const;

  /// Teleports a body (resets nothing else). non_finite / bad_body leave it unchanged.
  BodyError set_pose(BodyId id, Iso3 const& pose);
  BodyError set_velocity(BodyId id, Vec3 const& linear, Vec3 const& angular);
  /// The velocity (m/s) of the body's material point at world `point`: v + w x (point - centre
  /// of mass); zero for a static body. std::out_of_range for a stale id.
  Vec3 velocity_at(BodyId id, Vec3 const& point) const;
  /// Adds an impulse (N s, world axes) at a world point to a dynamic body: v += J / m,
  /// w += I^-1 ((point - centre of mass) x J), effective in the next step. Static, kinematic
  /// and frozen bodies take no impulses (none is returned: nothing to do). non_finite /
  /// bad_body leave the world unchanged.
  BodyError apply_impulse(BodyId id, Vec3 const& impulse, Vec3 const& point);

  /// Changes the body's type, keeping its pose, shape, material, layers and (unless it becomes
  /// static) its velocities. Becoming dynamic computes the mass from the shape and the
  /// density it was created with (zero_mass, or bad_shape for a mesh or height field, as
  /// create_body; the world is then unchanged); becoming static stops it. A frozen body
  /// (frozen_bodies()) set to any type, its own included, is unfrozen and at rest. Its contacts
  /// are found again by the next step under the new type's rules (no warm start that step);
  /// pairs the new type no longer simulates (a static body on static ground) end in that
  /// step's events, and new ones begin. bad_body for a stale id.
  BodyError set_type(BodyId id, BodyType type);

  CollisionLayers layers(BodyId id) const { return body(id).layers; }
  /// New layers, effective from the next step (contacts that the layers now forbid end then).
  BodyError set_layers(BodyId id, CollisionLayers const& layers);

  bool is_bullet(BodyId id) const { return body(id).bullet; }
  /// Makes the body a bullet or not (BodyDef::bullet), effective from the next step. bad_body
  /// for a stale id.
  BodyError set_bullet(BodyId id, bool bullet);

  // -------------------------------------------------------------- sleeping
  // (the rules are at the top of this header). Every setter above wakes the body's island.

  /// True for a dynamic body that is asleep (every other body: false).
  bool is_sleeping(BodyId id) const { return body(id).sleeping; }
  /// awake: wakes the body's island. !awake: puts the body's island to sleep now, the awake
  /// dynamic bodies that touch it (contacts of the last step) or are jointed to it, directly
  /// or through others, included, each stopped; an island with a body whose sleeping is
  /// disabled stays awake. Static, kinematic and frozen bodies have no island (none: nothing
  /// to do). bad_body for a stale id.
  BodyError set_awake(BodyId id, bool awake);
  /// Wakes every sleeping body.
  void wake_all();
  /// false: the body never sleeps (it wakes now) and keeps its island awake (BodyDef::
  /// enable_sleep). bad_body for a stale id.
  BodyError set_sleep_enabled(BodyId id, bool enabled);
  bool sleep_enabled(BodyId id) const { return body(id).sleep_enabled; }
  /// BodyDef::sleep_threshold (m/s; bad_material when negative, non_finite for NaN or
  /// infinity; the body is unchanged then). Wakes the body.
  BodyError set_sleep_threshold(BodyId id, float threshold);
  float sleep_threshold(BodyId id) const { return body(id).sleep_threshold; }
  /// How long (s) the body has stayed below its sleep threshold while awake (0 when asleep
  /// and after a wake).
  float sleep_time(BodyId id) const { return body(id).sleep_time; }
  /// Dynamic bodies asleep now.
  std::size_t sleeping_count() const noexcept { return sleeping_count_; }

  // -------------------------------------------------------------- spatial queries
  // Exact queries on the bodies' shapes at their current poses, through the broad phase's
  // trees. Every query takes a QueryFilter; non-finite input (and a zero ray direction) finds
  // nothing. Reported in a deterministic order: by distance (toi) for the closest forms, by
  // body index for the others. Threads: a step leaves the trees synced, so queries after
  // step() only read; after create_body, set_pose, set_type (or with sort and sweep) the first
  // query updates the trees, so do not run that one concurrently (destroy_body updates them at
  // once). Until the next step, queries after static edits walk the static tree instead of
  // its faster wide copy. A callback or predicate must not change the world.

  /// The closest body the ray hits within max_toi (ties: the lower body index).
  std::optional<WorldRayHit> ray_cast(Ray3 const& ray, float max_toi,
                                      QueryFilter const& filter = {}) const;
  /// Every body the ray hits within max_toi, in increasing toi (ties by body index);
  /// f returns false to stop.
  void ray_cast_all(Ray3 const& ray, float max_toi,
                    std::function<bool(WorldRayHit const&)> const& f,
                    QueryFilter const& filter = {}) const;
  /// One ray_cast per ray, out[i] for rays[i] (each out[i] bitwise the single form's), with
  /// the widest batch the build has: ray_cast_with<f32xN> (dispatched as step is).
  /// std::invalid_argument when out is not as long as rays (nothing written).
  void ray_cast(std::span<Ray3 const> rays, float max_toi,
                std::span<std::optional<WorldRayHit>> out, QueryFilter const& filter = {}) const;
  /// The batch form, lanes_v<T> consecutive rays at a time (T one of float, f32x4, f32x8,
  /// f32x16 that the build enables). Rays that start within batch_ray_spread of each other
  /// (a fan, a grid of probes) walk the trees as one packet (AabbTree::ray_query_lanes) and
  /// are cast against a convex shape or half-space they share in one call of the single
  /// form's template (meshes, hulls and a body one ray reaches: one ray at a time); rays that
  /// start farther apart run the single form one by one, whose walk of the static bodies'
  /// wide tree beats a packet's union of paths (docs/performance.md).
  /// How far apart (m, on every axis) the origins of a batch's packet may be for its rays to
  /// walk the trees together.
  static constexpr float batch_ray_spread = 2.0f;
  template <class T>
  void ray_cast_with(std::span<Ray3 const> rays, float max_toi,
                     std::span<std::optional<WorldRayHit>> out,
                     QueryFilter const& filter = {}) const;
  /// The first body a convex shape (is_convex_shape) at `pose` hits moving by
  /// t * motion, t in [0, cfg.max_toi], with cfg's target distance and penetration rule.
  std::optional<WorldShapeHit> shape_cast(BodyShape const& shape, Iso3 const& pose,
                                          Vec3 const& motion, ShapeCastConfig const& cfg = {},
                                          QueryFilter const& filter = {}) const;
  /// One shape_cast per query: out[i] for shapes[i] at poses[i] moving by motions[i], each
  /// bitwise the single form's, with the widest batch the build has (shape_cast_with<f32xN>,
  /// dispatched as step is).
  /// std::invalid_argument when the four spans differ in length (nothing written).
  void shape_cast(std::span<BodyShape const> shapes, std::span<Iso3 const> poses,
                  std::span<Vec3 const> motions, ShapeCastConfig const& cfg,
                  std::span<std::optional<WorldShapeHit>> out,
                  QueryFilter const& filter = {}) const;
  /// The batch form, lanes_v<T> queries at a time: in a packet of consecutive queries whose
  /// shapes are all spheres, all capsules, all cuboids or all cylinders (of any sizes: W
  /// characters' capsules), each lane finds its own candidates, and a sphere, capsule, cuboid
  /// or cylinder body that two or more lanes share is cast against all of them in one call of
  /// the single form's template; a body only one lane has, a half-space, a hull or a mesh,
  /// lane by lane. Other packets run one query at a time. Queries near each other (a crowd)
  /// share the most (docs/performance.md).
  template <class T>
  void shape_cast_with(std::span<BodyShape const> shapes, std::span<Iso3 const> poses,
                       std::span<Vec3 const> motions, ShapeCastConfig const& cfg,
                       std::span<std::optional<WorldShapeHit>> out,
                       QueryFilter const& filter = {}) const;
  /// Colliders whose (grown) bounding boxes overlap `box`, by slot index; f returns false to
  /// stop. (Every query reports colliders: a body's, whose id.body() is the body, or a
  /// standalone one.)
  void overlap_aabb(Aabb3 const& box, std::function<bool(ColliderId)> const& f,
                    QueryFilter const& filter = {}) const;
  /// Colliders whose shapes intersect (touch or overlap) the convex shape at `pose`, exactly
  /// (GJK), by slot index.
  void overlap_shape(BodyShape const& shape, Iso3 const& pose,
                     std::function<bool(ColliderId)> const& f,
                     QueryFilter const& filter = {}) const;
  /// The contact manifold of every collider within `distance` (>= 0, length units) of the
  /// convex shape (is_convex_shape) at `pose`, by slot index: A is the collider, B the shape
  /// (normal out of the body toward the shape, separation negative when they overlap, only
  /// points with separation <= distance); a mesh body may give up to max_mesh_manifolds
  /// manifolds, one call each. f returns false to stop. Non-finite input or a
  /// negative distance finds nothing.
  void contact_query(BodyShape const& shape, Iso3 const& pose, float distance,
                     std::function<bool(ColliderId, Manifold const&)> const& f,
                     QueryFilter const& filter = {}) const;
  /// Colliders whose shapes contain the point (surface included), by slot index.
  void point_query(Vec3 const& point, std::function<bool(ColliderId)> const& f,
                   QueryFilter const& filter = {}) const;
  /// The collider whose surface is nearest the point within max_distance (inside: distance
  /// 0).
  std::optional<WorldPointHit> project_point(Vec3 const& point, float max_distance,
                                             QueryFilter const& filter = {}) const;

  // -------------------------------------------------------------- joints
  // Joints (solver/joints/) between two bodies, solved in the step before the contacts, W at
  // a time (graph-coloured with the contacts). Bad definitions are refused with a JointError
  // and leave the world unchanged; destroying a body destroys its joints.

  /// A new joint. bad_body (an id names no live body), same_body, bad_axis (JointFrame::basis
  /// fails), bad_limits, bad_motor (Motor::valid), bad_value (a NaN or negative break
  /// threshold).
  CreateJointResult create_joint(JointDef const& def);
  /// Removes the joint now (bad_joint for a stale id; the world is unchanged).
  JointError destroy_joint(JointId id);
  bool is_alive(JointId id) const noexcept {
    return id.index < joints_.size() && joints_[id.index].alive &&
           joints_[id.index].generation == id.generation;
  }
  /// Live joints.
  std::size_t joint_count() const noexcept { return joints_.size() - free_joint_slots_.size(); }
  /// The joint's definition as created (motor as last set). std::out_of_range for a stale id.
  JointDef const& joint_def(JointId id) const { return joint(id).def; }
  /// Angle, translation, speeds and reaction (JointState) now. std::out_of_range for a stale id.
  JointState joint_state(JointId id) const;
  /// Replaces the motor of a revolute or prismatic joint (bad_joint for another type or a
  /// stale id; bad_motor when !motor.valid()). Effective from the next step.
  JointError set_motor(JointId id, Motor const& motor);
  /// Changes only the motor's targets (as set_motor).
  JointError set_motor_targets(JointId id, float target_velocity, float target_position);
  /// Joints of the body, by joint index. std::out_of_range for a stale body id.
  std::vector<JointId> body_joints(BodyId id) const;
  /// A frame on `body` from world-space data: its anchor at world_anchor, its axis along
  /// world_axis, its normal along world_normal, all at the body's current pose (give two
  /// bodies frames from the same world data and the joint starts at rest: angle 0,
  /// translation 0). std::out_of_range for a stale id; non-finite input gives a frame that
  /// create_joint refuses (bad_axis).
  JointFrame joint_frame(BodyId body, Vec3 const& world_anchor, Vec3 const& world_axis,
                         Vec3 const& world_normal = Vec3::Y) const;

  bool is_sensor(BodyId id) const { return body(id).sensor; }
  /// The last step's contact and sensor events.
  StepEvents const& events() const noexcept { return events_; }
  /// The sensor overlaps as of the last step, as body_pair_key()s in increasing order.
  std::span<std::uint64_t const> sensor_overlaps() const noexcept { return sensor_now_; }

  /// Bodies frozen because their state turned non-finite (ever, in freezing order).
  std::span<BodyId const> frozen_bodies() const noexcept { return frozen_; }
  bool is_frozen(BodyId id) const { return body(id).frozen; }

  /// The shortest step taken (s): the solver divides by the substep, and below this its
  /// rates (impulse / h, error / h) leave any meaningful range; step() ignores a shorter dt.
  static constexpr float min_dt = 1e-6f;
  /// The longest step taken (s): a longer dt is a caller's bug (milliseconds passed as
  /// seconds, a paused clock), and one of 1e30 s carries bodies where distances overflow.
  static constexpr float max_dt = 60.0f;

  /// Advances dt seconds with the widest batch the build has (in a PLUME_DISPATCH=ON build,
  /// the widest of the instruction set chosen at run time: plume/numerics/isa.hpp). Ignores dt
  /// outside [min_dt, max_dt] (zero, negative, NaN and infinite included): the world is
  /// unchanged.
  void step(float dt);
  /// Advances dt seconds solving lanes_v<T> constraints at a time; T one of float, f32x4,
  /// f32x8, f32x16 that the build enables. Bitwise the same result for every T.
  template <class T>
  void step_with(float dt);

  WorldConfig const& config() const noexcept { return config_; }
  /// Sets WorldConfig::tasks: the task system of the following steps (nullptr: one thread).
  /// May change between any two steps (another thread count, another system); the world's
  /// results do not depend on it.
  void set_task_system(TaskSystem* tasks) noexcept { config_.tasks = tasks; }
  /// The task system of the following steps (WorldConfig::tasks; nullptr: one thread).
  TaskSystem* task_system() const noexcept { return config_.tasks; }
  /// The contacts of the last step that the solver worked on (those of awake bodies).
  std::span<Contact const> contacts() const noexcept { return cache_.contacts(); }
  /// The contacts of sleeping bodies, kept as they were when their island fell asleep (those
  /// of bodies woken since the last step stay here until the next one).
  std::span<Contact const> sleeping_contacts() const noexcept { return cache_.sleeping_contacts(); }
  /// Constraints per colour in the last step; index color_count is the overflow.
  std::array<std::size_t, ConstraintGraph::color_count + 1> const& color_sizes() const noexcept {
    return color_sizes_;
  }
  StepProfile const& last_profile() const noexcept { return profile_; }
  /// The BVH broad phase (diagnostics: its trees' sizes, what their last optimisation ran, whether
  /// the static tree's wide copy is fresh), as of the last step or query: edits since then are
  /// filed by the next one.
  BvhBroadPhase const& broad_phase() const noexcept { return bvh_; }

  /// Sum of 1/2 m v^2 + 1/2 w . I w over dynamic bodies (J).
  double kinetic_energy() const;
  /// FNV-1a over the bits of every body's pose and velocities: equal hashes, equal worlds.
  std::uint64_t state_hash() const;

private:
  struct Body {
    BodyType type = BodyType::dynamic;
    bool frozen = false;
    Iso3 pose{};
    Vec3 local_center{};
    Vec3 center{};
    float mass = 0.0f, inv_mass = 0.0f;
    float density = 0.0f; ///< as created: set_type() makes a dynamic body's mass from it
    Mat3 inertia_local = Mat3::ZERO, inv_inertia_local = Mat3::ZERO;
    Mat3 inv_inertia_world = Mat3::ZERO;
    BodyShape shape;
    float friction = 0.6f, restitution = 0.0f;
    float linear_damping = 0.0f, angular_damping = 0.0f, gravity_scale = 1.0f;
    CollisionLayers layers{};
    bool alive = true;
    bool sensor = false;
    bool bullet = false;
    /// A standalone collider: a static slot no BodyId names (ColliderId::standalone).
    bool standalone = false;
    /// Distance from the centre of mass to the nearest point of the surface (dynamic bodies;
    /// continuous collision's measure of "fast").
    float min_extent = 0.0f;
    /// Distance from the centre of mass to the farthest point of the surface (dynamic
    /// bodies; sleeping's measure of speed).
    float max_extent = 0.0f;
    /// Distance from the body's origin to the farthest point of its shape (infinite for a
    /// half-space): manifold reuse's lever arm.
    float reach = 0.0f;
    bool sleeping = false; ///< a dynamic body asleep (not in moving_bodies_)
    bool sleep_enabled = true;
    float sleep_threshold = 0.05f;
    float sleep_time = 0.0f;                  ///< s below the threshold while awake
    std::uint32_t island = ~std::uint32_t(0); ///< its sleeping island (islands_) when asleep
    std::uint32_t generation = 0;
    bool moves() const noexcept { return alive && !frozen && type != BodyType::static_body; }
    bool is_dynamic() const noexcept { return alive && !frozen && type == BodyType::dynamic; }
    /// Simulated this step: a dynamic body that is not asleep.
    bool active() const noexcept { return is_dynamic() && !sleeping; }
  };

  /// The live body `id` names; std::out_of_range otherwise.
  Body const& body(BodyId id) const;
  /// The live collider's slot; std::out_of_range otherwise.
  Body const& slot(ColliderId id) const;
  /// The collider in live slot i.
  ColliderId collider_at(std::uint32_t i) const noexcept {
    return {i, bodies_[i].generation, bodies_[i].standalone};
  }
  /// A ray's hit on the collider in slot i.
  WorldRayHit ray_hit(std::uint32_t i, float toi, Vec3 const& point,
                      Vec3 const& normal) const noexcept {
    ColliderId const c = collider_at(i);
    return {c.body(), toi, point, normal, c};
  }
  /// Files slot i (a static body or a standalone collider) for the next tree sync. The list is
  /// compacted when it outgrows the slots (a collider teleported every frame in a world that
  /// syncs only for queries, as sort and sweep's does).
  void mark_stale_static(std::uint32_t i) {
    stale_statics_.push_back(i);
    if (stale_statics_.size() > 2 * bodies_.size() + 16) {
      std::sort(stale_statics_.begin(), stale_statics_.end());
      stale_statics_.erase(std::unique(stale_statics_.begin(), stale_statics_.end()),
                           stale_statics_.end());
    }
  }
  /// Takes slot i (a body or a standalone collider) out of the world: its contacts and
  /// overlaps end (reported by the next step), the broad phase forgets it, the slot is freed.
  void release_slot(std::uint32_t i);
  /// A new slot for b (the last freed one, at its next generation); returns its index.
  std::uint32_t take_slot(Body&& b, BodyState const& s);

  struct Joint {
    JointDef def;
    JointLaneParams params;
    Quat basis_a = Quat::IDENTITY, basis_b = Quat::IDENTITY; ///< JointFrame::basis()
    JointImpulses impulses{};
    Vec3 force{}, torque{}; ///< the last step's reaction on body B (N, N m)
    int color = ConstraintGraph::overflow;
    bool colored = false;                      ///< color holds graph bits (or is overflow)
    bool dynamic_a = false, dynamic_b = false; ///< as the colouring saw them
    bool alive = true;
    bool broken = false;
    bool filters = false; ///< its pair is in no_collide_pairs_ (!collide_connected, not broken)
    std::uint32_t generation = 0;
  };
  Joint const& joint(JointId id) const;
  /// Takes the joint's pair out of no_collide_pairs_ (when it is there).
  void stop_filtering(Joint& j);
  /// Zeroes the warm-start impulses of the joints of these bodies (sorted or not): a body
  /// that froze or changed type starts its joints afresh.
  void reset_joint_impulses(std::span<std::uint32_t const> bodies);
  /// The pair keys of live joints whose bodies do not collide, sorted (repeats allowed).
  std::vector<std::uint64_t> no_collide_pairs_;
  bool jointed_no_collide(std::uint32_t a, std::uint32_t b) const;
  void release_joint_color(Joint& j);
  /// Sets b's mass, centre of mass and inertia from its shape and density; false (b
  /// unchanged) when they give no positive finite mass.
  static bool give_mass(Body& b);

  // The stages of a step, in order (solver/world/step.cpp).
  void find_pairs();
  Aabb3 grown_aabb(std::uint32_t i) const;
  /// Files the edits since the last sync in the broad phase's trees. With `tasks` (the step's),
  /// the boxes of a full refit are computed on its threads.
  void sync_trees(TaskSystem* tasks = nullptr) const;
  /// The broad-phase kind of a kinematic or dynamic body (asleep: the sleeping tree).
  ProxyKind moving_kind(std::uint32_t i) const noexcept {
    Body const& b = bodies_[i];
    return b.type != BodyType::dynamic ? ProxyKind::kinematic
           : b.sleeping                ? ProxyKind::sleeping
                                       : ProxyKind::dynamic;
  }
  void split_sensor_pairs();
  void update_events();
  bool shapes_touch(std::uint32_t a, std::uint32_t b) const;
  ColliderPair pair_ids(std::uint64_t key) const;
  bool passes(std::uint32_t i, QueryFilter const& filter) const;
  /// Bodies whose grown boxes overlap `box` and pass the filter, by index (candidates).
  void candidates(Aabb3 const& box, QueryFilter const& filter,
                  std::vector<std::uint32_t>& out) const;
  template <class T>
  void collide_pairs();
  void prepare_bodies();
  template <class T>
  void pack_contacts(GConstraintBlocks<GContactConstraint, T>& blocks, float h) const;
  /// The joints packed by kind, then by colour; items[k][i]: the joint of kind k's i-th.
  template <class T>
  struct JointBlocks {
    std::array<GConstraintBlocks<GJointConstraint, T>, joint_kind_count> by_kind;
    std::array<std::vector<std::uint32_t>, joint_kind_count> items;
    bool empty = true;
  };
  void color_joints();
  template <class T>
  void pack_joints(JointBlocks<T>& blocks, float h) const;
  template <JointPass P, class T>
  void run_joints(JointBlocks<T>& blocks, float inv_h);
  template <class T>
  void solve_substeps(GConstraintBlocks<GContactConstraint, T>& blocks, JointBlocks<T>& joints,
                      int substeps, float h);
  template <class T>
  void store_joint_impulses(JointBlocks<T> const& blocks);
  /// Reaction forces from the stored impulses and the poses now; joints past their
  /// thresholds break (events_.joint_broken).
  void update_joint_reactions(float h);
  JointBody joint_body(std::uint32_t i) const;
  void integrate_velocities(float h);
  void integrate_positions(float h);
  template <class T>
  void store_impulses(GConstraintBlocks<GContactConstraint, T> const& blocks);
  void finalize_bodies();
  /// Sweeps the bodies finalize_bodies() found fast (solver/world/continuous.cpp); true when
  /// it left the trees synced to the step's final poses (it syncs them for bullets).
  bool solve_continuous();

  // Sleeping (solver/world/sleep.cpp).
  /// A kinematic body with a non-zero velocity: it keeps what it touches awake.
  bool moving_kinematic(std::uint32_t i) const noexcept;
  /// Wakes the sleeping islands that this step's pairs show touched by an awake dynamic body
  /// or a moving kinematic one, finding the pairs again after each wake; then drops the pairs
  /// that have a sleeping body.
  void wake_touched();
  /// Sleep timers, islands, and the islands that fall asleep (end of the step).
  void update_sleep(float dt);
  /// Puts each group of awake dynamic bodies (each sorted) to sleep as one island, in one
  /// pass over the contacts however many groups there are.
  void sleep_islands(std::vector<std::vector<std::uint32_t>> const& groups);
  /// Wakes the island of body i (nothing if i is not asleep).
  void wake(std::uint32_t i);
  /// Wakes these sleeping islands (indices into islands_, repeats allowed) in one pass over
  /// the sleeping contacts, however many there are.
  void wake_islands(std::vector<std::uint32_t>& islands);
  /// Wakes i's island and those of the bodies i touches (contacts, asleep or not) or is
  /// jointed to: what an edit of i (a teleport, a new type, its destruction) disturbs.
  void wake_around(std::uint32_t i);
  /// Wakes the islands of the sleeping bodies whose grown boxes overlap body i's and that
  /// could touch it (layers, jointed pairs).
  void wake_in(std::uint32_t i);
  /// Moves the contacts of the bodies woken since the last call back among the awake ones, and
  /// their touching pairs back into touching_now_ (wake_islands defers this part).
  void flush_woken();
  std::vector<std::uint32_t> woken_; ///< woken bodies whose contacts are still set aside
  /// Joins, in the union-find `parent` (parent[i] == i for each awake dynamic body i), the
  /// awake dynamic bodies that the awake contacts and live joints connect.
  void join_islands(std::vector<std::uint32_t>& parent) const;
  /// The awake dynamic bodies connected to i through the last step's contacts and the
  /// joints, i included (sorted).
  std::vector<std::uint32_t> island_of(std::uint32_t i) const;
  struct Island {
    std::vector<std::uint32_t> bodies; ///< sorted; empty: a free slot
  };
  std::vector<Island> islands_;             ///< sleeping islands
  std::vector<std::uint32_t> free_islands_; ///< free slots of islands_, reused last-freed first
  std::size_t sleeping_count_ = 0;
  // update_sleep's scratch, by body index (only awake dynamic bodies' entries are used).
  std::vector<std::uint32_t> parent_;
  std::vector<float> island_time_;
  std::vector<std::uint32_t> island_slot_;
  struct FastBody {
    std::uint32_t index;
    Vec3 start; ///< centre of mass where the step began
  };
  std::vector<FastBody> fast_;                ///< this step's fast bodies, by index
  std::vector<std::uint8_t> finalize_status_; ///< finalize_bodies(): per moving body, its outcome
  std::vector<Vec3> finalize_start_;          ///< and a fast body's centre at the step's start
  SolverBody contact_body(std::uint32_t i) const;

  WorldConfig config_;
  std::vector<Body> bodies_;
  std::vector<BodyState> states_; ///< one per body, then the shared identity record
  SortAndSweep sort_and_sweep_;
  // The trees also answer queries between steps, so a const query may sync them first.
  mutable BvhBroadPhase bvh_;
  mutable bool trees_synced_ = false;
  std::vector<Aabb3> boxes_;                 ///< sort and sweep: this step's grown AABBs, by body
  mutable std::vector<Aabb3> moving_boxes_;  ///< sync_trees(): a full refit's boxes, by moving body
  std::vector<std::uint32_t> moving_bodies_; ///< every kinematic and dynamic body, by index
  mutable std::vector<std::uint32_t>
      stale_statics_; ///< statics created or moved since the last sync
  /// Kinematic and dynamic bodies created, teleported or retyped since the last sync (a
  /// query after one set_pose refits one box, not every moving body's).
  mutable std::vector<std::uint32_t> stale_moving_;
  mutable bool all_moving_stale_ = false; ///< a step moved them all
  void mark_stale_moving(std::uint32_t i) {
    if (!all_moving_stale_) stale_moving_.push_back(i);
  }
  std::vector<std::uint64_t> pairs_; ///< this step's overlapping pairs (body_pair_key)
  std::vector<PairManifold> found_;  ///< this step's manifolds, by pair
  /// The narrow phase's output per chunk of collide_chunk pairs (kept for their capacity).
  std::vector<std::vector<PairManifold>> found_chunks_;
  /// Per chunk: its cuboid pairs, how many of them took the general path and how many pairs
  /// kept their manifolds (StepProfile).
  std::vector<std::array<std::uint32_t, 3>> chunk_counts_;
  /// A pair's manifolds as last computed, for reuse (WorldConfig::reuse_distance): the slots'
  /// generations, B's rotation and origin seen from A and A's origin seen from B at the time,
  /// and `count` manifolds from `first` in reuse_pool_ (normal and point_a in A's frame,
  /// point_b in B's; count 0: apart). fresh: computed this step, `first` then counts in its
  /// chunk's list until the pool takes them.
  struct ReuseEntry {
    std::uint64_t pair = 0;
    std::uint32_t generation_a = 0, generation_b = 0;
    Quat rotation{};
    Vec3 b_from_a{}, a_from_b{};
    float depth = 0.0f; ///< the largest |separation| of its points
    std::uint32_t first = 0, count = 0;
    bool fresh = false;
  };
  std::vector<ReuseEntry> reuse_;      ///< sorted by pair; the last narrow phase's pairs
  std::vector<ReuseEntry> reuse_next_; ///< being built by this step's narrow phase
  /// The kept manifolds: appended to as pairs are computed, compacted when most of it is no
  /// longer named (a settled scene appends nothing and copies nothing).
  std::vector<Manifold> reuse_pool_, reuse_pool_spare_;
  std::vector<std::vector<ReuseEntry>> reuse_chunks_;        ///< per chunk
  std::vector<std::vector<Manifold>> reuse_manifold_chunks_; ///< a chunk's fresh manifolds
  ContactCache cache_;
  std::vector<BodyId> frozen_;
  StepEvents events_, pending_; ///< pending_: destroy_body's ends, for the next step
  std::vector<std::uint64_t> touching_before_, touching_now_; ///< contact pair keys
  std::vector<std::uint64_t> sensor_pairs_, sensor_now_;      ///< candidates, overlaps
  std::vector<std::uint32_t> free_slots_; ///< destroyed bodies' slots, reused last-freed first
  std::size_t standalone_count_ = 0;      ///< live standalone colliders
  std::vector<Joint> joints_;
  std::vector<std::uint32_t>
      free_joint_slots_; ///< destroyed joints' slots, reused last-freed first
  StepProfile profile_;
  std::array<std::size_t, ConstraintGraph::color_count + 1> color_sizes_{};
};

namespace detail {
/// The instruction set whose kernels World::step, ray_cast and shape_cast run now: the active
/// one in a PLUME_DISPATCH=ON build, the build's own in any other (what tests check to see
/// that a switch changed the code that runs).
Isa world_kernels_isa() noexcept;
} // namespace detail

} // namespace plume
