// plume/solver/joints/fixed_joint.hpp - the fixed joint (weld): anchor B held at anchor A and
// frame B at frame A (all six degrees of freedom locked, soft as every joint row).
//
// Rows, in solve order: three angular locks along frame A's axes (error: twice the vector
// part of the relative rotation), then the point row.
#pragma once

#include <plume/solver/joints/joint_constraint.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume {

struct FixedJoint {
  JointLaneParams lane_params() const noexcept { return {.kind = JointKind::fixed}; }
};

template <JointPass P, Real T>
void fixed_joint_pass(GJointConstraint<T>& c, BodyState* states, T inv_h) noexcept {
  auto b = load_constraint_bodies(c, states);
  auto const g = joint_geometry(c, b);
  auto const soft = c.softness();
  GVec3<T> const e = rotation_error(g.qa, g.qb);
  lock_row<P>(c.angular_impulse[0], b, angular_row(g.x_axis()), e.x, soft, inv_h);
  lock_row<P>(c.angular_impulse[1], b, angular_row(g.y_axis()), e.y, soft, inv_h);
  lock_row<P>(c.angular_impulse[2], b, angular_row(g.z_axis()), e.z, soft, inv_h);
  point_row<P>(c.point_impulse, b, g.ra, g.rb, g.d, soft);
  store_constraint_bodies(c, states, b);
}

} // namespace plume

PLUME_MASK_CODE_END
