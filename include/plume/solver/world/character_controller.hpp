// plume/solver/world/character_controller.hpp - a kinematic character controller over the
// world: move_and_slide (solver/character/move_and_slide.hpp) with what a game's character
// needs around it. The features and defaults of Jolt's CharacterVirtual:
//  - an up direction and a ground state (on ground, on steep ground, not supported, in air)
//    with the ground's point, normal, body and velocity;
//  - a maximum walkable slope: steeper surfaces are walls to a character walking into them
//    (it slides down them under gravity, never climbs them), and standing still on a
//    walkable slope does not slide;
//  - stick to floor: walking off a step or over the top of a slope snaps down onto walkable
//    ground within a distance (not when moving up, as in a jump);
//  - stair stepping: blocked by a ledge up to a height with room and walkable ground beyond
//    it, the character steps up onto it (never higher: no launching up steps too high);
//  - moving platforms: carried by the kinematic or dynamic body it stands on, its rotation
//    included, exactly (by the body's change of pose, not its velocity, so a rotating
//    platform does not fling the character outward);
//  - pushing: dynamic bodies walked into get the character's push, at most max_strength
//    newtons; what it stands on is pushed down by its weight;
//  - shape changes (crouch, stand) refused when the new shape would overlap something;
//  - character-vs-character: each controller keeps a kinematic proxy body in the world that
//    the others' queries (and the game's ray casts) see, and that the step ignores (a falling
//    crate passes through a character; a character pushes crates only by max_strength).
// docs/character.md has the design, where it departs from Jolt and why, and the tests.
//
//   CharacterController hero(world, {.shape = Capsule{0.5f, 0.3f}, .position = {0, 1, 0}});
//   every frame, after world.step(dt):
//     Vec3 v = hero.velocity();               // relative to the ground it stands on
//     Vec3 walk = input * 4.0f;                // horizontal, m/s
//     if (hero.on_ground()) v = walk + (jump ? up * 5.0f : Vec3{});
//     else v = walk + up * v.dot(up) + world.config().gravity * dt;
//     hero.set_velocity(v);
//     hero.update(world, dt);
//
// update(world, dt), in order:
//  1. carried: standing on a moving body, the character moves by that body's change of pose
//     since the last update (a move_and_slide, so a platform does not carry it into a wall);
//  2. on the ground and not rising (the velocity goes no more up than walking along the
//     ground does), the velocity follows the ground: its horizontal part is bent along the
//     ground plane, and its downward part goes straight into it (the floor cancels it: no
//     slide down a walkable slope, and no hover above it);
//  3. move_and_slide by velocity * dt; a touched slope steeper than max_slope (facing up)
//     adds a vertical wall facing the character;
//  4. stairs: on the ground, blocked by a wall or too-steep slope facing the motion, try
//     up by step_height, forward by the rest of the motion (at least min_step_forward), and
//     down onto walkable ground no higher than step_height above the feet; kept when it went
//     higher and at least half of min_step_forward forward;
//  5. stick to floor: on the ground before and not now, not rising: a cast down by
//     stick_to_floor, kept when it lands on walkable ground;
//  6. the ground state from the contacts within skin + ground_tolerance (the nearest
//     walkable one; a tilted contact, as on a ledge's rounded-over edge, takes the normal of
//     the face a short ray finds beside it); the proxy body moved; pushes applied
//     (world.apply_impulse).
// Lengths in metres (scaled() for other units), velocities m/s, mass kg, force N, angles rad.
//
// Bad input: update() with a non-finite or negative dt, or a velocity or position that is not
// finite, does nothing and says so (CharacterUpdate::invalid_input); dt = 0 makes no move of
// its own (a platform that moved still carries it; no stick; pushes are zero). set_shape() with a
// shape that is not convex (a half-space, mesh or height field), a bad size, or a negative
// max_penetration is refused (bad_shape). The constructor throws std::invalid_argument for a
// non-convex or degenerate shape, a zero or non-finite up, a non-finite position, a negative
// or non-finite length, angle, mass or strength, or max_slope of 90 degrees or more.
#pragma once

#include <plume/solver/character/move_and_slide.hpp>
#include <plume/solver/world/move_query.hpp>
#include <plume/solver/world/world.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace plume {

/// Where a character stands (Jolt's EGroundState).
enum class GroundState : std::uint8_t {
  on_ground,       ///< on walkable ground: it can walk
  on_steep_ground, ///< on a slope too steep to walk: it slides down under gravity
  not_supported,   ///< touching something (a wall, a ceiling) that does not hold it up
  in_air,          ///< touching nothing
};
/// A short English name of the state ("on ground", ...); "?" for a value out of range.
std::string_view to_string(GroundState s) noexcept;

/// What a controller call refused.
enum class CharacterError : std::uint8_t {
  none,
  bad_shape, ///< not a convex shape, or a size that is not finite and positive
  overlap,   ///< set_shape: the new shape would overlap something deeper than allowed
  non_finite ///< a non-finite position, velocity or rotation
};
/// A short English description of the error; "?" for a value out of range.
std::string_view to_string(CharacterError e) noexcept;

/// A controller's parameters: Jolt CharacterVirtual's defaults, in metres.
struct CharacterConfig {
  BodyShape shape = Capsule{0.5f, 0.3f}; ///< convex; its frame is the character's position
  Vec3 position{};                       ///< of the shape's frame, world
  Vec3 up{0.0f, 1.0f, 0.0f};             ///< unit (normalised by the constructor)
  /// Steepest walkable slope (rad, 50 degrees): steeper ground is a wall to walk into.
  float max_slope = 0.87266463f;
  /// Contacts within skin + ground_tolerance are the ground the state is made from.
  float ground_tolerance = 0.01f;
  float step_height = 0.4f;        ///< highest ledge stepped up onto; 0 disables stairs
  float min_step_forward = 0.02f;  ///< a step moves at least this far forward onto the ledge
  float step_forward_test = 0.15f; ///< a step's landing is also probed this much further on
  /// A wall blocks the motion (so stairs are tried) when its horizontal normal is within
  /// this angle of the motion reversed (rad, 75 degrees).
  float step_contact_angle = 1.3089969f;
  float stick_to_floor = 0.5f; ///< snap-down distance when leaving the ground; 0 disables
  float mass = 70.0f;          ///< kg: its weight pushes down on dynamic ground
  float max_strength = 100.0f; ///< N: the largest push on a dynamic body walked into
  /// The layers the character collides with (QueryFilter::mask of its queries).
  std::uint32_t collides_with = 0xffffffffu;
  /// Whether the character has a proxy body in the world (a kinematic body of its shape that
  /// the step ignores, filters = 0): other characters and the game's queries see it.
  bool proxy = true;
  std::uint32_t proxy_layers = 1u; ///< the proxy's memberships
  /// Whether sensor bodies block the character (false: it walks through trigger volumes; the
  /// proxy never raises sensor events, its filters being 0).
  bool sensors_block = false;
  MoveAndSlideConfig move{}; ///< the loop's (skin 0.01, 4 sweeps, ...)

  /// This configuration with every length multiplied by length_unit (the shape excepted:
  /// give it in the new unit).
  CharacterConfig scaled(float length_unit) const noexcept {
    CharacterConfig c = *this;
    c.position = c.position * length_unit;
    c.ground_tolerance *= length_unit;
    c.step_height *= length_unit;
    c.min_step_forward *= length_unit;
    c.step_forward_test *= length_unit;
    c.stick_to_floor *= length_unit;
    c.max_strength *= length_unit; // N = kg m / s^2
    c.move = c.move.scaled(length_unit);
    return c;
  }
};

/// What the ground under a character is (the contact the state came from).
struct CharacterGround {
  GroundState state = GroundState::in_air;
  BodyId body{};         ///< invalid in the air and on a standalone collider
  ColliderId collider{}; ///< what it stands on (invalid in the air)
  Vec3 point{};          ///< on the surface stood on, world
  Vec3 normal{};         ///< unit, out of the surface (for a V of steep slopes: their mean)
  Vec3 velocity{};       ///< the surface's velocity at point (m/s; zero on a standalone collider)
  float separation = 0.0f;
};

/// A push the last update gave a dynamic body (already applied).
struct CharacterPush {
  BodyId body;
  Vec3 impulse{}; ///< N s, world
  Vec3 point{};   ///< where, world
};

/// What one update() did.
struct CharacterUpdate {
  bool invalid_input = false; ///< nothing was done
  bool carried = false;       ///< moved by the platform it stood on
  bool stepped = false;       ///< climbed a step
  bool stuck_to_floor = false;
  Vec3 displacement{};                   ///< position after - before, world
  MoveAndSlideResult<ColliderId> move{}; ///< the main move's result (hits, flags)
};

/// A kinematic character in a World. Not copyable (it owns its proxy body); destroy() (or the
/// destructor of the world first) removes the proxy. The world must outlive the controller's
/// calls; the controller keeps no pointer to it.
class CharacterController {
public:
  CharacterController(World& world, CharacterConfig const& cfg);
  CharacterController(CharacterController const&) = delete;
  CharacterController& operator=(CharacterController const&) = delete;
  /// The moved-from controller has no proxy. No assignment: it would have to remove the
  /// assigned-to controller's proxy from a world it keeps no pointer to (destroy() it first,
  /// then construct anew, or keep controllers in a container that only moves-constructs).
  CharacterController(CharacterController&& o) noexcept;
  CharacterController& operator=(CharacterController&&) = delete;

  /// Moves the character by its velocity over dt seconds (the file comment says how).
  CharacterUpdate const& update(World& world, float dt);

  Vec3 position() const noexcept { return position_; }
  /// The velocity (what the last update left: the requested one, projected on what it hit),
  /// relative to the ground while on_ground(), in the world otherwise: leaving the ground
  /// adds the ground's velocity (a jump off a moving platform keeps its momentum), landing
  /// subtracts the new ground's.
  Vec3 velocity() const noexcept { return velocity_; }
  /// The velocity in the world: velocity() plus the ground's when on it.
  Vec3 world_velocity() const noexcept;
  Quat rotation() const noexcept { return rotation_; }
  BodyShape const& shape() const noexcept { return cfg_.shape; }
  Vec3 up() const noexcept { return cfg_.up; }
  CharacterConfig const& config() const noexcept { return cfg_; }

  CharacterGround const& ground() const noexcept { return ground_; }
  GroundState ground_state() const noexcept { return ground_.state; }
  bool on_ground() const noexcept { return ground_.state == GroundState::on_ground; }
  /// Whether a unit normal is walkable ground: normal . up >= cos(max_slope).
  bool walkable(Vec3 const& normal) const noexcept { return normal.dot(cfg_.up) >= cos_slope_; }
  /// The rotation about up the platform under it turned the character by in the last update
  /// (identity when it did not turn; CharacterUpdate::carried is set when it did or moved):
  /// a game turns the character's facing by it.
  Quat platform_rotation() const noexcept { return platform_rotation_; }
  std::span<CharacterPush const> pushes() const noexcept { return pushes_; }
  CharacterUpdate const& last_update() const noexcept { return last_; }
  /// The proxy body (invalid without one).
  BodyId proxy() const noexcept { return proxy_; }

  /// The velocity for the next update, relative to the ground (m/s). non_finite: unchanged.
  CharacterError set_velocity(Vec3 const& v) noexcept;
  /// Teleports the character (the ground state is found again at the next update).
  CharacterError set_position(World& world, Vec3 const& p);
  /// The shape's rotation (the default maps +y to up).
  CharacterError set_rotation(World& world, Quat const& q);
  /// Changes the shape (crouch, stand), keeping the lowest point along -up where it is (the
  /// feet stay on the floor); the proxy is made anew (proxy() changes). Refused (overlap, nothing
  /// changed) when the new shape would be closer than -max_penetration to anything (0: any overlap
  /// refuses; touching is allowed).
  CharacterError set_shape(World& world, BodyShape const& shape, float max_penetration = 0.0f);
  /// Whether `shape` at `position` (this character's rotation) would overlap something by more
  /// than max_penetration.
  bool overlaps(World const& world, BodyShape const& shape, Vec3 const& position,
                float max_penetration = 0.0f) const;
  /// Removes the proxy body from the world (the controller is then inert for queries).
  void destroy(World& world);

private:
  QueryFilter filter(std::span<BodyId const> exclude) const;
  /// The character's layers, its proxy excluded, sensors skipped unless sensors_block.
  QueryFilter own_filter() const;
  bool make_proxy(World& world); ///< a kinematic body of the shape at the position
  Iso3 pose_at(Vec3 const& p) const { return Iso3{rotation_, p}; }
  CharacterGround find_ground(World const& world, Vec3 const& p) const;
  /// The walkable face under an edge contact at `point` of `body` (character at p), if any.
  std::optional<Vec3> surface_normal(World const& world, ColliderId collider, Vec3 const& point,
                                     Vec3 const& p) const;
  void carry(World& world, WorldMoveQuery const& scene);
  bool walk_stairs(WorldMoveQuery const& scene, Vec3 const& forward);
  bool stick(World const& world, WorldMoveQuery const& scene);
  void push(World& world, float dt, Vec3 const& frame_velocity);

  CharacterConfig cfg_;
  float cos_slope_ = 0.0f;
  Vec3 position_{}, velocity_{};
  Quat rotation_{Quat::IDENTITY};
  Quat platform_rotation_{Quat::IDENTITY};
  CharacterGround ground_{};
  Iso3 ground_pose_{}; ///< the ground body's pose at the end of the last update
  BodyId proxy_{};
  std::vector<MoveHit<ColliderId>> touched_; ///< the last move's accepted hits on dynamic bodies
  std::vector<CharacterPush> pushes_;
  CharacterUpdate last_{};
};

} // namespace plume
