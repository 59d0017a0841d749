// plume/solver/joints/distance_joint.hpp - the distance joint: the anchors kept at a distance.
//
// Without a spring, a rigid rod: the distance stays rest_length (two limit rows at
// rest_length). With spring_enabled, a spring-damper toward rest_length (frequency Hz,
// damping ratio, at most max_force N: the motor row of solver/joints/motor.hpp with the
// spring_damper model) inside hard limits [min_length, max_length]; frequency 0 is a rope
// (slack between the limits). Rotations are free. Rows along the anchors' line (frame A's
// axis while the anchors coincide), in solve order: spring, lower and upper limits. A
// max_length past 1e9 m is taken as 1e9 m (no limit, and no overflow in the bias).
#pragma once

#include <plume/solver/joints/joint_constraint.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

PLUME_MASK_CODE_BEGIN

namespace plume {

struct DistanceJoint {
  float rest_length = 1.0f;                                  ///< m, >= 0
  float min_length = 0.0f;                                   ///< m, with the spring
  float max_length = std::numeric_limits<float>::infinity(); ///< m, >= min_length
  bool spring_enabled = false;
  float frequency = 5.0f;                                   ///< Hz, >= 0 (0: a rope)
  float damping_ratio = 1.0f;                               ///< >= 0
  float max_force = std::numeric_limits<float>::infinity(); ///< N, >= 0

  JointLaneParams lane_params() const noexcept {
    JointLaneParams p{.kind = JointKind::distance, .limit_enabled = true};
    if (!spring_enabled) {
      p.lower = p.upper = rest_length;
      return p;
    }
    p.lower = min_length;
    p.upper = std::min(max_length, 1.0e9f);
    p.motor.enabled = frequency > 0.0f;
    p.motor.model = MotorModel::spring_damper;
    p.motor.frequency = frequency;
    p.motor.damping_ratio = damping_ratio;
    p.motor.target_position = rest_length;
    p.motor.max_force = max_force;
    return p;
  }
  bool limits_valid() const noexcept {
    auto const ok = [](float v) { return std::isfinite(v) && v >= 0.0f; };
    return ok(rest_length) && ok(min_length) && !std::isnan(max_length) &&
           max_length >= min_length && ok(frequency) && ok(damping_ratio) &&
           !std::isnan(max_force) && max_force >= 0.0f;
  }
};

template <JointPass P, Real T>
void distance_joint_pass(GJointConstraint<T>& c, BodyState* states, T inv_h) noexcept {
  auto b = load_constraint_bodies(c, states);
  auto const g = joint_geometry(c, b);
  auto const soft = c.softness();
  T const len = g.d.length();
  GVec3<T> const n = g.d.normalize_or(g.x_axis());
  GRowJacobian<T> const j = distance_row(n, g.ra, g.rb);
  motor_row<P>(c.motor_impulse, b, j, len - c.motor_target_position.get(), zero<T>(),
               c.motor_max_impulse.get(), c.motor_terms());
  T const cap = c.limit_cap.get();
  limit_row<P>(c.lower_impulse, b, j, len - c.lower.get(), cap, soft, inv_h);
  limit_row<P>(c.upper_impulse, b, negated(j), c.upper.get() - len, cap, soft, inv_h);
  store_constraint_bodies(c, states, b);
}

} // namespace plume

PLUME_MASK_CODE_END
