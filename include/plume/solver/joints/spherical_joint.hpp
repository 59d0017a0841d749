// plume/solver/joints/spherical_joint.hpp - the spherical joint (ball and socket): anchor B
// held at anchor A, rotation free, with an optional swing cone and twist limits.
//
// The relative rotation of frame B to frame A splits into a twist about frame A's x axis
// (JointFrame::axis: the twist axis, a bone's length) and a swing of that axis
// (solver/joints/joint_rows.hpp, swing_twist): the cone limit keeps the swing angle within
// cone_angle (rad, in [0, pi]), the twist limits keep the twist angle in [lower, upper]
// (within [-pi, pi]). The twist rows' axis is twist_axis(): the twist's exact rate at any
// swing. Rows, in solve order: cone, lower and upper twist limits, the point row.
#pragma once

#include <plume/solver/joints/joint_constraint.hpp>

#include <numbers>

PLUME_MASK_CODE_BEGIN

namespace plume {

struct SphericalJoint {
  bool cone_enabled = false;
  float cone_angle = 0.5f * std::numbers::pi_v<float>; ///< rad, in [0, pi]
  bool twist_limit_enabled = false;
  float lower_twist = -std::numbers::pi_v<float>; ///< rad, >= -pi
  float upper_twist = std::numbers::pi_v<float>;  ///< rad, <= pi, >= lower_twist

  JointLaneParams lane_params() const noexcept {
    return {.kind = JointKind::spherical,
            .limit_enabled = twist_limit_enabled,
            .lower = lower_twist,
            .upper = upper_twist,
            .cone_enabled = cone_enabled,
            .cone_angle = cone_angle};
  }
  bool limits_valid() const noexcept {
    float const pi = std::numbers::pi_v<float>;
    return cone_angle >= 0.0f && cone_angle <= pi && lower_twist >= -pi && upper_twist <= pi &&
           lower_twist <= upper_twist;
  }
};

template <JointPass P, Real T>
void spherical_joint_pass(GJointConstraint<T>& c, BodyState* states, T inv_h) noexcept {
  auto b = load_constraint_bodies(c, states);
  auto const g = joint_geometry(c, b);
  auto const soft = c.softness();
  GSwingTwist<T> const st = swing_twist(g.qa, g.qb);
  // The swing's axis in world (d swing_angle / dt = axis . (w_B - w_A)); frame A's y when
  // there is no swing (the row is then far from its limit).
  GVec3<T> const swing_axis =
      g.qa.mul_vec3(GVec3<T>{zero<T>(), st.swing_y, st.swing_z}).normalize_or(g.y_axis());
  limit_row<P>(c.cone_impulse, b, angular_row(-swing_axis), c.cone_angle.get() - st.swing_angle,
               c.cone_cap.get(), soft, inv_h);
  GVec3<T> const u = twist_axis(g.qa, g.qb);
  T const cap = c.limit_cap.get();
  limit_row<P>(c.lower_impulse, b, angular_row(u), st.twist - c.lower.get(), cap, soft, inv_h);
  limit_row<P>(c.upper_impulse, b, angular_row(-u), c.upper.get() - st.twist, cap, soft, inv_h);
  point_row<P>(c.point_impulse, b, g.ra, g.rb, g.d, soft);
  store_constraint_bodies(c, states, b);
}

} // namespace plume

PLUME_MASK_CODE_END
