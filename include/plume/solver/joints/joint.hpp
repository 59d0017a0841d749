// plume/solver/joints/joint.hpp - the joint types a JointDef (solver/world/world.hpp) can hold,
// the errors a definition can have, and what the world reports about a joint (JointState).
// The joint types and their rows: solver/joints/{fixed,revolute,prismatic,spherical,
// distance}_joint.hpp over solver/joints/joint_rows.hpp; motors: solver/joints/motor.hpp.
//
//   JointDef def{.body_a = door_frame, .body_b = door,
//                .frame_a = {.anchor = {0.5f, 0, 0}, .axis = Vec3::Y},
//                .frame_b = {.anchor = {-0.5f, 0, 0}, .axis = Vec3::Y},
//                .type = RevoluteJoint{.limit_enabled = true, .lower_angle = 0,
//                                      .upper_angle = 1.5708f}};
//   JointId hinge = world.create_joint(def).id;
#pragma once

#include <plume/solver/joints/distance_joint.hpp>
#include <plume/solver/joints/fixed_joint.hpp>
#include <plume/solver/joints/joint_constraint.hpp>
#include <plume/solver/joints/motor.hpp>
#include <plume/solver/joints/prismatic_joint.hpp>
#include <plume/solver/joints/revolute_joint.hpp>
#include <plume/solver/joints/spherical_joint.hpp>

#include <cstdint>
#include <limits>
#include <string_view>
#include <variant>

PLUME_MASK_CODE_BEGIN

namespace plume {

/// The joint types, in JointKind order.
using JointType =
    std::variant<FixedJoint, RevoluteJoint, PrismaticJoint, SphericalJoint, DistanceJoint>;

enum class JointError : std::uint8_t {
  none,
  bad_body,   ///< a body id names no live body
  same_body,  ///< body_a == body_b
  bad_axis,   ///< a frame's axis is zero or not finite, or its anchor or normal not finite
  bad_limits, ///< lower > upper, angles outside [-pi, pi], a negative or non-finite length
  bad_motor,  ///< a NaN target, a negative max force or model parameter (Motor::valid)
  bad_value,  ///< a NaN or negative break threshold
  bad_joint,  ///< the id names no live joint, or the joint type has no motor
};
/// The error's name and what it means; "unknown" for a value outside the enum.
std::string_view to_string(JointError e) noexcept;

/// A joint: its slot and the slot's generation (as BodyId).
struct JointId {
  std::uint32_t index = ~std::uint32_t(0);
  std::uint32_t generation = 0;
  bool valid() const noexcept { return index != ~std::uint32_t(0); }
  friend bool operator==(JointId, JointId) = default;
};

struct CreateJointResult {
  JointId id; ///< invalid when error != none
  JointError error = JointError::none;
  explicit operator bool() const noexcept { return error == JointError::none; }
};

/// A joint as of the last step (poses and velocities now).
struct JointState {
  JointKind kind = JointKind::fixed;
  /// Revolute and spherical: the twist of frame B about the axis (rad, [-pi, pi]); others 0.
  float angle = 0.0f;
  /// Spherical: the swing angle (rad, [0, pi]); others 0.
  float swing = 0.0f;
  /// Prismatic: (anchor B - anchor A) . axis (m); distance: |anchor B - anchor A|; others 0.
  float translation = 0.0f;
  /// The angle's rate (rad/s): (w_B - w_A) . axis; spherical: . twist_axis() (the twist's)
  float angular_speed = 0.0f;
  float linear_speed = 0.0f; ///< the translation's rate (m/s): prismatic and distance
  Vec3 reaction_force{};     ///< on body B, world (N), over the last substep of the last step
  Vec3 reaction_torque{};    ///< on body B, world (N m), the angular rows only
  bool broken = false;
};

/// Runs pass P of kind `kind`'s kernel on block c.
template <JointPass P, Real T>
PLUME_INLINE void joint_pass(JointKind kind, GJointConstraint<T>& c, BodyState* states,
                             T inv_h) noexcept {
  switch (kind) {
  case JointKind::fixed:
    fixed_joint_pass<P>(c, states, inv_h);
    break;
  case JointKind::revolute:
    revolute_joint_pass<P>(c, states, inv_h);
    break;
  case JointKind::prismatic:
    prismatic_joint_pass<P>(c, states, inv_h);
    break;
  case JointKind::spherical:
    spherical_joint_pass<P>(c, states, inv_h);
    break;
  case JointKind::distance:
    distance_joint_pass<P>(c, states, inv_h);
    break;
  }
}

} // namespace plume

PLUME_MASK_CODE_END
