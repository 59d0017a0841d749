// plume/solver/joints/joint_rows.hpp - the rows every joint is made of, written once over T
// and shared by the joint types (solver/joints/*_joint.hpp): a point row (3-D, anchors
// coincide), 1-D rows along a linear or angular axis in three modes (lock: C = 0; limit:
// C >= 0, speculative; motor: solver/joints/motor.hpp), and the relative-rotation measures
// (twist angle about the joint axis, swing, full rotation error).
//
// A 1-D row has the Jacobian (linear n, angular_a j_a, angular_b j_b): its speed is
//     Cdot = n . (v_B - v_A) + j_b . w_B - j_a . w_A
// and an impulse l moves v_A -= m_A n l, w_A -= I_A^-1 j_a l, v_B += m_B n l, w_B += I_B^-1 j_b l.
// A linear row along n between anchors r_a, r_b (from each centre of mass) with d = anchor
// B - anchor A and n fixed in A (a slider axis) has j_a = (r_a + d) x n, j_b = r_b x n; an
// angular row along u has n = 0, j_a = j_b = u.
//
// Passes (JointPass): warm_start applies each row's accumulated impulse; solve runs each row
// with the soft bias (solver/softness.hpp: the joint's softness for locks and limits that are
// violated); relax runs locks and limits rigid without bias. Limits are speculative, as
// contacts: a limit C > 0 away lets the coordinate approach it at C / h in the substep, no
// faster. Motors (and a distance joint's spring) run in the solve pass only: a spring-damper
// is one implicit step per substep from the positions at its start; run again in relax, after
// the positions moved, it would be a second step in the same substep (twice the damping).
// Accumulated impulses are per substep (N s): a force is impulse / h.
//
// Effective masses are computed from the current Jacobian at every row solve (as Box2D),
// the point row's 3x3 inverse included (point_row says why). Rows with zero effective mass
// (empty lanes, two static bodies) do nothing.
#pragma once

#include <plume/math/quat.hpp>
#include <plume/math/sym_mat3.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>
#include <plume/solver/body_state.hpp>
#include <plume/solver/lane_storage.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume {

enum class JointPass : std::uint8_t { warm_start, solve, relax };

/// Soft coefficients per lane (solver/softness.hpp), loaded once per block.
template <Real T>
struct GRowSoftness {
  T bias_rate, mass_scale, impulse_scale;
};

/// A motor row's coefficients per lane (solver/joints/motor.hpp, MotorCoefficients).
template <Real T>
struct GMotorTerms {
  T mass_scale, bias_scale, impulse_scale;
};

/// A 1-D row's Jacobian: see the top of this header.
template <Real T>
struct GRowJacobian {
  GVec3<T> linear, angular_a, angular_b;
};

/// The Jacobian of a linear row along n (fixed in A) for anchors ra, rb and d = anchor B -
/// anchor A.
template <Real T>
PLUME_INLINE GRowJacobian<T> linear_row(GVec3<T> const& n, GVec3<T> const& ra, GVec3<T> const& rb,
                                        GVec3<T> const& d) noexcept {
  return {n, (ra + d).cross(n), rb.cross(n)};
}

/// The Jacobian of a linear row along n that turns with the line between the anchors (a
/// distance row): j_a = ra x n.
template <Real T>
PLUME_INLINE GRowJacobian<T> distance_row(GVec3<T> const& n, GVec3<T> const& ra,
                                          GVec3<T> const& rb) noexcept {
  return {n, ra.cross(n), rb.cross(n)};
}

/// An angular row along u (n = 0, j_a = j_b = u): its own type, so that the rows below skip
/// the linear terms' arithmetic for it.
template <Real T>
struct GAngularRow {
  GVec3<T> axis;
};

template <Real T>
PLUME_INLINE GAngularRow<T> angular_row(GVec3<T> const& u) noexcept {
  return {u};
}

/// The row with the opposite sign (the upper side of a limit).
template <Real T>
PLUME_INLINE GRowJacobian<T> negated(GRowJacobian<T> const& j) noexcept {
  return {-j.linear, -j.angular_a, -j.angular_b};
}
template <Real T>
PLUME_INLINE GAngularRow<T> negated(GAngularRow<T> const& j) noexcept {
  return {-j.axis};
}

namespace detail {

template <Real T>
PLUME_INLINE T row_speed(GConstraintBodies<T> const& b, GRowJacobian<T> const& j) noexcept {
  return (j.linear.dot(b.b.linear_velocity - b.a.linear_velocity) +
          j.angular_b.dot(b.b.angular_velocity)) -
         j.angular_a.dot(b.a.angular_velocity);
}
template <Real T>
PLUME_INLINE T row_mass(GConstraintBodies<T> const& b, GRowJacobian<T> const& j) noexcept {
  T const k = ((b.ma + b.mb) * j.linear.dot(j.linear) + j.angular_a.dot(b.ia * j.angular_a)) +
              j.angular_b.dot(b.ib * j.angular_b);
  return plume::select(k > zero<T>(), one<T>() / k, zero<T>());
}
template <Real T>
PLUME_INLINE void row_apply(GConstraintBodies<T>& b, GRowJacobian<T> const& j, T l) noexcept {
  b.a.linear_velocity = b.a.linear_velocity - j.linear * (b.ma * l);
  b.a.angular_velocity = b.a.angular_velocity - b.ia * (j.angular_a * l);
  b.b.linear_velocity = b.b.linear_velocity + j.linear * (b.mb * l);
  b.b.angular_velocity = b.b.angular_velocity + b.ib * (j.angular_b * l);
}
// Angular rows: the same arithmetic without the linear terms.
template <Real T>
PLUME_INLINE T row_speed(GConstraintBodies<T> const& b, GAngularRow<T> const& j) noexcept {
  return j.axis.dot(b.b.angular_velocity - b.a.angular_velocity);
}
template <Real T>
PLUME_INLINE T row_mass(GConstraintBodies<T> const& b, GAngularRow<T> const& j) noexcept {
  GVec3<T> const& u = j.axis;
  T const k = u.dot(b.ia * u) + u.dot(b.ib * u);
  return plume::select(k > zero<T>(), one<T>() / k, zero<T>());
}
template <Real T>
PLUME_INLINE void row_apply(GConstraintBodies<T>& b, GAngularRow<T> const& j, T l) noexcept {
  b.apply_angular(j.axis * l);
}

/// Bias, mass scale and impulse scale of a row with error c in pass P: locks and violated
/// limits soft with bias in solve, rigid without in relax; a limit not reached (speculative,
/// c > 0) lets it close at c / h.
template <JointPass P, bool Limit, Real T>
PLUME_INLINE GRowSoftness<T> row_terms(T c, GRowSoftness<T> const& soft, T inv_h) noexcept {
  T const zero_t = zero<T>(), one_t = one<T>();
  if constexpr (Limit) {
    mask_t<T> const speculative = c > zero_t;
    T const ahead = c * inv_h;
    if constexpr (P == JointPass::solve)
      return {plume::select(speculative, ahead, soft.bias_rate * c),
              plume::select(speculative, one_t, soft.mass_scale),
              plume::select(speculative, zero_t, soft.impulse_scale)};
    else
      return {plume::select(speculative, ahead, zero_t), one_t, zero_t};
  } else {
    if constexpr (P == JointPass::solve)
      return {soft.bias_rate * c, soft.mass_scale, soft.impulse_scale};
    else
      return {zero_t, one_t, zero_t};
  }
}

} // namespace detail

/// A 1-D lock row (C = 0) with error c along row j (a GRowJacobian or a GAngularRow).
template <JointPass P, Real T, class Row>
PLUME_INLINE void lock_row(GLaneArray<T>& impulse, GConstraintBodies<T>& b, Row const& j, T c,
                           GRowSoftness<T> const& soft, T inv_h) noexcept {
  T const old = impulse.get();
  if constexpr (P == JointPass::warm_start) {
    detail::row_apply(b, j, old);
  } else {
    auto const t = detail::row_terms<P, false>(c, soft, inv_h);
    T const m = detail::row_mass(b, j);
    T const next =
        old - m * t.mass_scale * (detail::row_speed(b, j) + t.bias_rate) - t.impulse_scale * old;
    impulse.set(next);
    detail::row_apply(b, j, next - old);
  }
}

/// A one-sided limit row: c >= 0 is allowed (c the distance to the limit along j), the
/// impulse is clamped to [0, cap] (cap 0: the limit is off).
template <JointPass P, Real T, class Row>
PLUME_INLINE void limit_row(GLaneArray<T>& impulse, GConstraintBodies<T>& b, Row const& j, T c,
                            T cap, GRowSoftness<T> const& soft, T inv_h) noexcept {
  T const old = impulse.get();
  if constexpr (P == JointPass::warm_start) {
    detail::row_apply(b, j, old);
  } else {
    auto const t = detail::row_terms<P, true>(c, soft, inv_h);
    T const m = detail::row_mass(b, j);
    T const next = clamp_select(old - m * t.mass_scale * (detail::row_speed(b, j) + t.bias_rate) -
                                    t.impulse_scale * old,
                                zero<T>(), cap);
    impulse.set(next);
    detail::row_apply(b, j, next - old);
  }
}

/// A motor row: drives the coordinate toward its targets with the motor's coefficients
/// (solver/joints/motor.hpp, MotorCoefficients); position_error = coordinate - target_position
/// (wrapped for an angle); the impulse is clamped to [-max_impulse, max_impulse]. Not run in relax.
template <JointPass P, Real T, class Row>
PLUME_INLINE void motor_row(GLaneArray<T>& impulse, GConstraintBodies<T>& b, Row const& j,
                            T position_error, T target_velocity, T max_impulse,
                            GMotorTerms<T> const& motor) noexcept {
  T const old = impulse.get();
  if constexpr (P == JointPass::warm_start) {
    detail::row_apply(b, j, old);
  } else if constexpr (P == JointPass::solve) {
    T const m = detail::row_mass(b, j);
    T const v = detail::row_speed(b, j) - target_velocity;
    T const next =
        clamp_select(old - m * (motor.mass_scale * v + motor.bias_scale * position_error) -
                         motor.impulse_scale * old,
                     -max_impulse, max_impulse);
    impulse.set(next);
    detail::row_apply(b, j, next - old);
  }
}

/// The inverse of the point row's 3x3 effective mass matrix for anchors ra, rb:
/// K = (m_a + m_b) 1 - [r_a] I_a [r_a] - [r_b] I_b [r_b], column j being
/// (m_a + m_b) e_j + (I_a (r_a x e_j)) x r_a + (I_b (r_b x e_j)) x r_b; zero where singular.
template <Real T>
PLUME_INLINE GSymMat3<T> point_mass(GConstraintBodies<T> const& b, GVec3<T> const& ra,
                                    GVec3<T> const& rb) noexcept {
  T const z = zero<T>(), o = one<T>();
  auto const col = [&](GVec3<T> const& e) {
    return (e * (b.ma + b.mb) + (b.ia * ra.cross(e)).cross(ra)) + (b.ib * rb.cross(e)).cross(rb);
  };
  GMat3<T> const k = GMat3<T>::from_cols(col({o, z, z}), col({z, o, z}), col({z, z, o}));
  return GSymMat3<T>::from_mat3(k.inverse_or_zero());
}

/// The point row: anchor B at anchor A (error d = anchor B - anchor A), solved as one 3x3
/// block whose mass matrix (point_mass) is rebuilt from the current anchors at every solve:
/// it is ill-conditioned (1 : 1 + m L^2 / I) for a small body far from its anchor, and one
/// from the step's start feeds energy in (docs/joints.md).
template <JointPass P, Real T>
PLUME_INLINE void point_row(GLaneVec3<T>& impulse, GConstraintBodies<T>& b, GVec3<T> const& ra,
                            GVec3<T> const& rb, GVec3<T> const& d,
                            GRowSoftness<T> const& soft) noexcept {
  GVec3<T> const old = impulse.get();
  if constexpr (P == JointPass::warm_start) {
    b.apply(old, ra, rb);
  } else {
    GSymMat3<T> const k_inv = point_mass(b, ra, rb);
    GVec3<T> const cdot = b.relative_velocity(ra, rb);
    GVec3<T> step;
    if constexpr (P == JointPass::solve)
      step = (k_inv * (cdot + d * soft.bias_rate)) * (-soft.mass_scale) - old * soft.impulse_scale;
    else
      step = -(k_inv * cdot);
    impulse.set(old + step);
    b.apply(step, ra, rb);
  }
}

/// The relative rotation of frame B to frame A, q = conj(frame_a) frame_b, on the
/// hemisphere w >= 0, split as q = swing twist with twist about frame A's x axis (the
/// joint axis).
template <Real T>
struct GSwingTwist {
  GQuat<T> relative;  ///< w >= 0
  T twist;            ///< rad in [-pi, pi]: the joint angle about the axis
  T swing_y, swing_z; ///< vector part of the swing (frame A's y, z): its rotation vector ~ 2x
  T swing_angle;      ///< rad in [0, pi]
};

template <Real T>
PLUME_INLINE GSwingTwist<T> swing_twist(GQuat<T> const& frame_a, GQuat<T> const& frame_b) noexcept {
  GQuat<T> q = frame_a.conjugate() * frame_b;
  T const s = plume::select(q.w < zero<T>(), T(-1.0f), one<T>());
  q = {q.x * s, q.y * s, q.z * s, q.w * s};
  T const n = plume::sqrt(q.x * q.x + q.w * q.w);
  T const inv_n = one<T>() / max_select(n, T(1e-12f));
  T const sy = (q.y * q.w - q.z * q.x) * inv_n;
  T const sz = (q.z * q.w + q.y * q.x) * inv_n;
  T const two = T(2.0f);
  return {q, two * plume::atan2(q.x, q.w), sy, sz,
          two * plume::atan2(plume::sqrt(sy * sy + sz * sz), n)};
}

/// The axis u whose u . (w_B - w_A) is the rate of swing_twist()'s twist angle:
/// (x_A + x_B) / (1 + x_A . x_B), x_A and x_B the two frames' x axes (frame A's x without
/// swing; longer as the swing grows: 1 / cos^2(swing / 2)). Near a half-turn swing the
/// denominator is held at 1e-3.
template <Real T>
PLUME_INLINE GVec3<T> twist_axis(GQuat<T> const& frame_a, GQuat<T> const& frame_b) noexcept {
  GVec3<T> const ex{one<T>(), zero<T>(), zero<T>()};
  GVec3<T> const xa = frame_a.mul_vec3(ex), xb = frame_b.mul_vec3(ex);
  return (xa + xb) * (one<T>() / max_select(one<T>() + xa.dot(xb), T(1e-3f)));
}

/// x - 2 pi round(x / (2 pi)): an angle error wrapped to [-pi, pi) (up to rounding at the ends).
template <Real T>
PLUME_INLINE T wrap_angle(T x) noexcept {
  T const two_pi = T(6.28318530717958647692f);
  return x - two_pi * plume::floor(x * T(0.159154943091895335769f) + T(0.5f));
}

} // namespace plume

PLUME_MASK_CODE_END
