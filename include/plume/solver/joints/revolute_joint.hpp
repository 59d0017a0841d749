// plume/solver/joints/revolute_joint.hpp - the revolute joint (hinge): anchor B held at
// anchor A, frame B free to turn about frame A's x axis (JointFrame::axis) only.
//
// Angle: the twist of frame B relative to frame A about the axis, in [-pi, pi], 0 where the
// frames' normals agree, positive counter-clockwise about the axis (right hand). Limits
// [lower, upper] within [-pi, pi]; the motor (solver/joints/motor.hpp) drives the angle and
// the angular speed about the axis, its position error wrapped to [-pi, pi).
// Rows, in solve order (motors first, the point last, as Box2D): motor, lower and upper
// limits, two angular locks (the swing, along frame A's y and z), the point row.
#pragma once

#include <plume/solver/joints/joint_constraint.hpp>

#include <numbers>

PLUME_MASK_CODE_BEGIN

namespace plume {

struct RevoluteJoint {
  bool limit_enabled = false;
  float lower_angle = -std::numbers::pi_v<float>; ///< rad, >= -pi
  float upper_angle = std::numbers::pi_v<float>;  ///< rad, <= pi, >= lower_angle
  Motor motor{};                                  ///< max_force is a torque (N m)

  JointLaneParams lane_params() const noexcept {
    return {.kind = JointKind::revolute,
            .limit_enabled = limit_enabled,
            .lower = lower_angle,
            .upper = upper_angle,
            .motor = motor};
  }
  bool limits_valid() const noexcept {
    float const pi = std::numbers::pi_v<float>;
    return lower_angle >= -pi && upper_angle <= pi && lower_angle <= upper_angle;
  }
};

template <JointPass P, Real T>
void revolute_joint_pass(GJointConstraint<T>& c, BodyState* states, T inv_h) noexcept {
  auto b = load_constraint_bodies(c, states);
  auto const g = joint_geometry(c, b);
  auto const soft = c.softness();
  GSwingTwist<T> const st = swing_twist(g.qa, g.qb);
  GVec3<T> const x = g.x_axis();
  motor_row<P>(c.motor_impulse, b, angular_row(x),
               wrap_angle(st.twist - c.motor_target_position.get()), c.motor_target_velocity.get(),
               c.motor_max_impulse.get(), c.motor_terms());
  T const cap = c.limit_cap.get();
  limit_row<P>(c.lower_impulse, b, angular_row(x), st.twist - c.lower.get(), cap, soft, inv_h);
  limit_row<P>(c.upper_impulse, b, angular_row(-x), c.upper.get() - st.twist, cap, soft, inv_h);
  T const two = T(2.0f);
  lock_row<P>(c.angular_impulse[1], b, angular_row(g.y_axis()), two * st.swing_y, soft, inv_h);
  lock_row<P>(c.angular_impulse[2], b, angular_row(g.z_axis()), two * st.swing_z, soft, inv_h);
  point_row<P>(c.point_impulse, b, g.ra, g.rb, g.d, soft);
  store_constraint_bodies(c, states, b);
}

} // namespace plume

PLUME_MASK_CODE_END
