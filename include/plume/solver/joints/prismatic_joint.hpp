// plume/solver/joints/prismatic_joint.hpp - the prismatic joint (slider): frame B keeps
// frame A's rotation, and anchor B moves only along frame A's x axis (JointFrame::axis).
//
// Translation: (anchor B - anchor A) . axis (m), 0 where the anchors coincide. Limits
// [lower, upper]; the motor (solver/joints/motor.hpp) drives the translation and its speed,
// with max_force in N. Rows, in solve order: motor, lower and upper limits, two linear locks
// (along frame A's y and z), three angular locks, all linear rows with the slider's
// Jacobian (the axis turns with body A).
#pragma once

#include <plume/solver/joints/joint_constraint.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume {

struct PrismaticJoint {
  bool limit_enabled = false;
  float lower_translation = 0.0f; ///< m
  float upper_translation = 0.0f; ///< m, >= lower_translation
  Motor motor{};                  ///< max_force in N

  JointLaneParams lane_params() const noexcept {
    return {.kind = JointKind::prismatic,
            .limit_enabled = limit_enabled,
            .lower = lower_translation,
            .upper = upper_translation,
            .motor = motor};
  }
  bool limits_valid() const noexcept {
    return std::isfinite(lower_translation) && std::isfinite(upper_translation) &&
           lower_translation <= upper_translation;
  }
};

template <JointPass P, Real T>
void prismatic_joint_pass(GJointConstraint<T>& c, BodyState* states, T inv_h) noexcept {
  auto b = load_constraint_bodies(c, states);
  auto const g = joint_geometry(c, b);
  auto const soft = c.softness();
  GVec3<T> const x = g.x_axis(), y = g.y_axis(), z = g.z_axis();
  T const s = g.d.dot(x);
  GRowJacobian<T> const jx = linear_row(x, g.ra, g.rb, g.d);
  motor_row<P>(c.motor_impulse, b, jx, s - c.motor_target_position.get(),
               c.motor_target_velocity.get(), c.motor_max_impulse.get(), c.motor_terms());
  T const cap = c.limit_cap.get();
  limit_row<P>(c.lower_impulse, b, jx, s - c.lower.get(), cap, soft, inv_h);
  limit_row<P>(c.upper_impulse, b, negated(jx), c.upper.get() - s, cap, soft, inv_h);
  lock_row<P>(c.linear_impulse[0], b, linear_row(y, g.ra, g.rb, g.d), g.d.dot(y), soft, inv_h);
  lock_row<P>(c.linear_impulse[1], b, linear_row(z, g.ra, g.rb, g.d), g.d.dot(z), soft, inv_h);
  GVec3<T> const e = rotation_error(g.qa, g.qb);
  lock_row<P>(c.angular_impulse[0], b, angular_row(x), e.x, soft, inv_h);
  lock_row<P>(c.angular_impulse[1], b, angular_row(y), e.y, soft, inv_h);
  lock_row<P>(c.angular_impulse[2], b, angular_row(z), e.z, soft, inv_h);
  store_constraint_bodies(c, states, b);
}

} // namespace plume

PLUME_MASK_CODE_END
