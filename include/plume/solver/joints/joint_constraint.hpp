// plume/solver/joints/joint_constraint.hpp - the soft-step joint constraint: structure-of-
// arrays storage for W = lanes_v<T> joints of one kind, prepared lane by lane in plain float
// and solved W at a time by the kind's kernel (solver/joints/<kind>_joint.hpp), written once
// over T like the contact kernels (solver/contact_constraint.hpp). The world packs joints by
// kind and graph colour (solver/constraint_blocks.hpp), so no dynamic body appears twice in a
// block; T = float solves one.
//
// A joint holds two frames, one on each body (JointFrame: anchor point, axis and normal in the
// body's shape frame). Per step, prepare_joint_lane() stores the anchors as offsets from each
// centre of mass and the frames' rotations, in world axes at the step's start; in each
// substep a kernel measures the joint from the bodies' accumulated deltas (BodyState), so
// errors are current: d = anchor B - anchor A, the relative rotation of the frames, and from
// them the joint's coordinate (angle about the axis, translation along it, or distance).
// Rows and passes are those of solver/joints/joint_rows.hpp; accumulated impulses persist in
// the joint between steps (JointImpulses) for warm starting.
#pragma once

#include <plume/math/iso3.hpp>
#include <plume/math/mat3.hpp>
#include <plume/math/quat.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>
#include <plume/solver/body_state.hpp>
#include <plume/solver/contact_constraint.hpp>
#include <plume/solver/joints/joint_rows.hpp>
#include <plume/solver/joints/motor.hpp>
#include <plume/solver/lane_storage.hpp>
#include <plume/solver/softness.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>

PLUME_MASK_CODE_BEGIN

namespace plume {

enum class JointKind : std::uint8_t { fixed, revolute, prismatic, spherical, distance };
inline constexpr int joint_kind_count = 5;
/// The kind's name ("fixed", "revolute", ...); "unknown" for a value outside the enum.
std::string_view to_string(JointKind k) noexcept;

/// A joint's frame on one body, in the body's shape frame (the frame of World::pose()).
struct JointFrame {
  Vec3 anchor{};         ///< the joint's point (m)
  Vec3 axis = Vec3::X;   ///< hinge, slider or twist axis (any length > 0; normalised)
  Vec3 normal = Vec3::Y; ///< angle 0: where the two frames' normals agree about the axis

  /// The frame's rotation in the body frame: x along axis, y along normal made orthogonal
  /// to it (any orthogonal direction when normal is zero or along the axis), z = x cross y.
  /// nullopt when the axis is zero, or the anchor, axis or normal not finite.
  std::optional<Quat> basis() const noexcept {
    if (!anchor.is_finite() || !axis.is_finite() || !normal.is_finite()) return std::nullopt;
    // Scaled by the largest component first, so 1e-30 and 1e30 long axes normalise too.
    auto const unit = [](Vec3 v) {
      float const big = std::max(std::max(std::abs(v.x), std::abs(v.y)), std::abs(v.z));
      if (!(big > 0.0f)) return Vec3{};
      v = v * (1.0f / big);
      return v * (1.0f / v.length());
    };
    Vec3 const x = unit(axis);
    if (!(x.length_squared() > 0.0f)) return std::nullopt;
    Vec3 const n = unit(normal);
    Vec3 y = n - x * x.dot(n);
    float const ly = y.length();
    if (!(ly > 1e-4f))
      y = x.any_orthonormal_vector();
    else
      y = y * (1.0f / ly);
    Vec3 const z = x.cross(y);
    return Quat::from_mat3(Mat3::from_cols(x, y, z)).normalize();
  }
};

/// The parameters a joint type gives its lane besides the frames (each type's to_lane()).
struct JointLaneParams {
  JointKind kind = JointKind::fixed;
  /// On the joint's coordinate: angle (revolute, spherical twist; rad), translation
  /// (prismatic; m) or distance (m).
  bool limit_enabled = false;
  float lower = 0.0f, upper = 0.0f;
  bool cone_enabled = false; ///< spherical: swing within cone_angle (rad)
  float cone_angle = 0.0f;
  Motor motor{}; ///< revolute, prismatic; a distance joint's spring (target = rest length)
};

/// The accumulated impulses of one joint (per substep, N s and N m s), kept from step to
/// step for warm starting. Rows a kind does not have stay zero.
struct JointImpulses {
  Vec3 point{};                   ///< point row (world)
  std::array<float, 3> angular{}; ///< angular locks along frame A's x, y, z
  std::array<float, 2> linear{};  ///< prismatic locks along frame A's y, z
  float lower = 0.0f, upper = 0.0f, motor = 0.0f, cone = 0.0f;
};

template <Real T>
struct GJointConstraint : GConstraintBodyLanes<T> {
  using element_type = T;
  static constexpr std::size_t lanes = lanes_v<T>;
  GLaneVec3<T> anchor_a, anchor_b; ///< centre of mass -> anchor, world, at prepare
  GLaneVec3<T> base_delta;         ///< anchor B - anchor A at prepare (world)
  GLaneQuat<T> frame_a, frame_b;   ///< the frames' rotations at prepare (world)
  GLaneArray<T> bias_rate, mass_scale, impulse_scale; ///< the joint's softness
  GLaneArray<T> lower, upper, limit_cap;              ///< limit_cap: 0 off, max float on
  GLaneArray<T> cone_angle, cone_cap;
  GLaneArray<T> motor_target_velocity, motor_target_position, motor_max_impulse;
  GLaneArray<T> motor_mass_scale, motor_bias_scale, motor_impulse_scale; ///< MotorCoefficients
  // Accumulated impulses.
  GLaneVec3<T> point_impulse;
  std::array<GLaneArray<T>, 3> angular_impulse;
  std::array<GLaneArray<T>, 2> linear_impulse;
  GLaneArray<T> lower_impulse, upper_impulse, motor_impulse, cone_impulse;

  GRowSoftness<T> softness() const noexcept {
    return {bias_rate.get(), mass_scale.get(), impulse_scale.get()};
  }
  GMotorTerms<T> motor_terms() const noexcept {
    return {motor_mass_scale.get(), motor_bias_scale.get(), motor_impulse_scale.get()};
  }
};

/// A joint's two bodies as prepare_joint_lane() needs them: the solver's view (SolverBody:
/// state index, write index, mass, world inverse inertia, centre of mass) and the pose.
struct JointBody {
  SolverBody solver;
  Iso3 pose{};
};

/// Fills lane `lane` of c for a joint between a and b with frames (anchor and basis()
/// rotation, body frame) fa, fb, the type's parameters p, the previous step's impulses, the
/// joint softness and substep h (s).
template <Real T>
void prepare_joint_lane(GJointConstraint<T>& c, std::size_t lane, JointBody const& a,
                        Vec3 const& anchor_a, Quat const& basis_a, JointBody const& b,
                        Vec3 const& anchor_b, Quat const& basis_b, JointLaneParams const& p,
                        JointImpulses const& warm, Softness const& soft, float h) noexcept {
  std::size_t const i = lane;
  SolverBody const& sa = a.solver;
  SolverBody const& sb = b.solver;
  c.set_bodies(i, sa, sb);
  Vec3 const pa = a.pose.transform_point(anchor_a), pb = b.pose.transform_point(anchor_b);
  Vec3 const ra = pa - sa.center, rb = pb - sb.center;
  c.anchor_a.set_lane(i, ra);
  c.anchor_b.set_lane(i, rb);
  c.base_delta.set_lane(i, pb - pa);
  Quat const qa = a.pose.rotation * basis_a, qb = b.pose.rotation * basis_b;
  c.frame_a.set_lane(i, qa);
  c.frame_b.set_lane(i, qb);
  c.bias_rate[i] = soft.bias_rate;
  c.mass_scale[i] = soft.mass_scale;
  c.impulse_scale[i] = soft.impulse_scale;
  float const big = std::numeric_limits<float>::max();
  c.lower[i] = p.lower;
  c.upper[i] = p.upper;
  c.limit_cap[i] = p.limit_enabled ? big : 0.0f;
  c.cone_angle[i] = p.cone_angle;
  c.cone_cap[i] = p.cone_enabled ? big : 0.0f;
  // The motor's row: angular about frame A's x (revolute), linear along it (prismatic), or
  // along the anchors' line (distance spring).
  Vec3 const x = qa * Vec3::X;
  float w = 0.0f; // inverse effective mass, for the force model
  if (p.kind == JointKind::revolute) {
    w = x.dot(sa.inv_inertia.mul_vec3(x)) + x.dot(sb.inv_inertia.mul_vec3(x));
  } else if (p.kind == JointKind::prismatic || p.kind == JointKind::distance) {
    Vec3 n = x;
    if (p.kind == JointKind::distance) n = (pb - pa).normalize_or(x);
    Vec3 const ja = (p.kind == JointKind::prismatic ? ra + (pb - pa) : ra).cross(n);
    Vec3 const jb = rb.cross(n);
    w = (sa.inv_mass + sb.inv_mass) + ja.dot(sa.inv_inertia.mul_vec3(ja)) +
        jb.dot(sb.inv_inertia.mul_vec3(jb));
  }
  Motor const& m = p.motor;
  MotorCoefficients const mc = motor_coefficients(m, w, h);
  c.motor_target_velocity[i] = m.enabled ? m.target_velocity : 0.0f;
  // An angle target reduced to [-pi, pi] in double, so that a target of 1e8 rad (exact in
  // float) keeps its meaning through wrap_angle()'s float arithmetic.
  float const target =
      p.kind == JointKind::revolute
          ? float(std::remainder(double(m.target_position), 2.0 * 3.14159265358979323846))
          : m.target_position;
  c.motor_target_position[i] = m.enabled ? target : 0.0f;
  c.motor_max_impulse[i] = m.enabled ? m.max_force * h : 0.0f;
  c.motor_mass_scale[i] = mc.mass_scale;
  c.motor_bias_scale[i] = mc.bias_scale;
  c.motor_impulse_scale[i] = mc.impulse_scale;
  c.point_impulse.set_lane(i, warm.point);
  for (std::size_t r = 0; r < 3; ++r)
    c.angular_impulse[r][i] = warm.angular[r];
  for (std::size_t r = 0; r < 2; ++r)
    c.linear_impulse[r][i] = warm.linear[r];
  c.lower_impulse[i] = p.limit_enabled ? warm.lower : 0.0f;
  c.upper_impulse[i] = p.limit_enabled ? warm.upper : 0.0f;
  c.motor_impulse[i] = m.enabled ? warm.motor : 0.0f;
  c.cone_impulse[i] = p.cone_enabled ? warm.cone : 0.0f;
}

/// Makes lane `lane` empty: both bodies the identity record `identity_state`, nothing applied.
template <Real T>
void clear_joint_lane(GJointConstraint<T>& c, std::size_t lane,
                      std::int32_t identity_state) noexcept {
  JointBody none;
  none.solver.state = identity_state;
  prepare_joint_lane(c, lane, none, Vec3{}, Quat::IDENTITY, none, Vec3{}, Quat::IDENTITY,
                     JointLaneParams{}, JointImpulses{}, Softness{}, 0.0f);
}

/// Reads back the accumulated impulses of lane `lane`.
template <Real T>
JointImpulses joint_impulses(GJointConstraint<T> const& c, std::size_t lane) noexcept {
  JointImpulses r;
  r.point = {c.point_impulse.x[lane], c.point_impulse.y[lane], c.point_impulse.z[lane]};
  for (std::size_t k = 0; k < 3; ++k)
    r.angular[k] = c.angular_impulse[k][lane];
  for (std::size_t k = 0; k < 2; ++k)
    r.linear[k] = c.linear_impulse[k][lane];
  r.lower = c.lower_impulse[lane];
  r.upper = c.upper_impulse[lane];
  r.motor = c.motor_impulse[lane];
  r.cone = c.cone_impulse[lane];
  return r;
}

/// The joint measured from the bodies' current deltas (every kernel starts here).
template <Real T>
struct GJointGeometry {
  GVec3<T> ra, rb; ///< centre of mass -> anchor, world, now
  GVec3<T> d;      ///< anchor B - anchor A, now
  GQuat<T> qa, qb; ///< the frames' rotations, now
  GVec3<T> x_axis() const noexcept { return qa.mul_vec3({one<T>(), zero<T>(), zero<T>()}); }
  GVec3<T> y_axis() const noexcept { return qa.mul_vec3({zero<T>(), one<T>(), zero<T>()}); }
  GVec3<T> z_axis() const noexcept { return qa.mul_vec3({zero<T>(), zero<T>(), one<T>()}); }
};

template <Real T>
PLUME_INLINE GJointGeometry<T> joint_geometry(GJointConstraint<T> const& c,
                                              GConstraintBodies<T> const& b) noexcept {
  GVec3<T> const ra0 = c.anchor_a.get(), rb0 = c.anchor_b.get();
  GVec3<T> const ra = b.a.delta_rotation.mul_vec3(ra0), rb = b.b.delta_rotation.mul_vec3(rb0);
  GVec3<T> const d =
      (c.base_delta.get() + (b.b.delta_position - b.a.delta_position)) + ((rb - rb0) - (ra - ra0));
  return {ra, rb, d, b.a.delta_rotation * c.frame_a.get(), b.b.delta_rotation * c.frame_b.get()};
}

/// The rotation error of a joint that locks every rotation (fixed, prismatic): twice the
/// vector part of the relative rotation on w >= 0, in frame A's axes (rad, small angles).
template <Real T>
PLUME_INLINE GVec3<T> rotation_error(GQuat<T> const& qa, GQuat<T> const& qb) noexcept {
  GQuat<T> const q = qa.conjugate() * qb;
  T const s = plume::select(q.w < zero<T>(), T(-2.0f), T(2.0f));
  return {q.x * s, q.y * s, q.z * s};
}

} // namespace plume

PLUME_MASK_CODE_END
