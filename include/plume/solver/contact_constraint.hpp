// plume/solver/contact_constraint.hpp - the soft-step contact constraint: structure-of-arrays
// storage for W = lanes_v<T> manifolds (up to 4 points each) and the kernels that solve them,
// written once over T. The world solves W constraints that share no dynamic body per call
// (one graph colour, solver/constraint_graph.hpp); T = float solves one.
//
// Per step: prepare_contact_lane() fills a lane from a manifold (plain float, the same in
// every build); then per substep warm_start_contacts(), solve_contacts(use_bias = true), the
// position integration, solve_contacts(use_bias = false) (relax); after the substeps
// apply_restitution(). Impulses stay in the constraint; the caller reads them back to warm
// start the next step.
//
// Conventions: the normal is unit, world, from body A toward body B. Anchors are from each
// body's centre of mass to the contact point (the midpoint of the manifold's two surface
// points), world, at the start of the step. Separation of point i during the step (current
// positions from the body states' deltas):
//     s = base_separation + n . ((dp_B - dp_A) + (dq_B r_B - dq_A r_A))
// Normal impulse (soft step; Catto's Solver2D formulation, as Box2D v3 writes it):
//     s > 0 (speculative):  bias = s / h,                          mass_scale 1, impulse_scale 0
//     s <= 0, solve:        bias = max(bias_rate s, -max_push_speed), the constraint's softness
//     s <= 0, relax:        bias = 0,                               mass_scale 1, impulse_scale 0
//     dl = -m_n mass_scale (v_n + bias) - impulse_scale l;   l = max(l + dl, 0)
// Friction per manifold (a contact patch, as Box3D and Bepu do), not per point: two tangent
// rows at the centre of the manifold's points, clamped together to the circle of radius
// friction * (sum of the normal impulses), and a twist row about the normal, clamped to
// friction * sum * (mean distance of the points from the centre). Three rows instead of
// eight per manifold, and no per-point friction fighting the normal rows of the same patch.
// The tangents t1 (given by the caller: the world carries it from step to step projected
// onto the new contact plane, so warm-started friction keeps its meaning; any_orthonormal_pair()
// alone flips its basis when the normal's z crosses 0) and t2 = n x t1 are fixed for the step.
// Restitution, once after the substeps, for points that approached faster than the threshold
// and carried a normal impulse: dl = -m_n (v_n + e v_n0), l = max(l + dl, 0).
//
// Point counts: a constraint runs points 0 .. max_points-1, the most any lane prepared, so
// a block of one-point manifolds does a quarter of the normal rows of a block of four-point
// ones (the world packs each colour by point count: GConstraintBlocks::pack_grouped). When
// the lanes' counts differ (min_points < max_points), a point a lane lacks is masked out
// of that lane: its bodies and impulses keep their bits, as if the lane had stopped at its
// own count, which is what the same manifold solved alone (T = float) does. (Unmasked, the
// point's zero impulse would add signed zeros, which can turn a velocity of -0 into +0; no
// random trial has shown it, the mask makes it impossible.) Padding lanes
// (clear_contact_lane) take no part in the counts: their bodies are never written.
#pragma once

#include <plume/collision/manifold.hpp>
#include <plume/math/mat3.hpp>
#include <plume/math/quat.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>
#include <plume/solver/body_state.hpp>
#include <plume/solver/lane_storage.hpp>
#include <plume/solver/softness.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Real T>
struct GContactConstraintPoint {
  GLaneVec3<T> anchor_a;            ///< centre of mass of A -> contact point (world, m)
  GLaneVec3<T> anchor_b;            ///< centre of mass of B -> contact point
  GLaneArray<T> base_separation;    ///< separation - n . (anchor_b - anchor_a)
  GLaneArray<T> relative_velocity;  ///< normal relative velocity at prepare (restitution)
  GLaneArray<T> normal_mass;        ///< effective mass along the normal (0 = empty point)
  GLaneArray<T> normal_impulse;     ///< accumulated (N s)
  GLaneArray<T> max_normal_impulse; ///< largest normal impulse this step (restitution needs > 0)
};

template <Real T>
struct GContactConstraint : GConstraintBodyLanes<T> {
  using element_type = T;
  static constexpr std::size_t lanes = lanes_v<T>;
  GLaneVec3<T> normal, tangent1, tangent2;
  GLaneArray<T> friction, restitution;
  GLaneArray<T> bias_rate, mass_scale, impulse_scale; ///< softness (stiffer against static)
  std::array<GContactConstraintPoint<T>, 4> points;
  // Patch friction at the centre of the points.
  GLaneVec3<T> friction_anchor_a, friction_anchor_b;
  GLaneArray<T> tangent_mass1, tangent_mass2, twist_mass;
  GLaneArray<T> twist_radius; ///< mean distance of the points from the centre (m)
  GLaneArray<T> tangent_impulse1, tangent_impulse2, twist_impulse; ///< accumulated (N s, N m s)
  GLaneArray<T> point_count; ///< points of each lane's manifold (0-4, as T; 0 in padding)
  /// The most and the fewest points of the lanes prepare_contact_lane() filled since the
  /// constraint was made (padding lanes excluded); the kernels run max_points points and mask
  /// when min_points < max_points.
  std::uint8_t max_points = 0, min_points = 4;
};

/// The impulses of one manifold, kept from step to step for warm starting: per point along
/// the normal (N s), and the patch friction along t1, t2 (N s) and about the normal (N m s).
struct ContactImpulses {
  std::array<float, 4> normal{};
  float tangent1 = 0.0f, tangent2 = 0.0f, twist = 0.0f;
};

/// A unit tangent of the plane with normal n (unit): `previous` projected onto the plane and
/// normalised, which keeps a contact's friction axes continuous from step to step; when that
/// is degenerate (zero, non-finite, or nearly along n), the first of n.any_orthonormal_pair().
inline Vec3 contact_tangent(Vec3 const& n, Vec3 const& previous) noexcept {
  Vec3 const t = previous - n * n.dot(previous);
  float const len2 = t.dot(t);
  if (len2 > 0.01f && std::isfinite(len2)) return t * (1.0f / std::sqrt(len2));
  return n.any_orthonormal_pair()[0];
}

/// Fills lane `lane` of c from manifold m between bodies a and b (normal from A to B), with
/// the first friction axis `tangent` (unit, orthogonal to the normal: contact_tangent()) and
/// the previous step's impulses (zeros for a new manifold or new points).
template <Real T>
void prepare_contact_lane(GContactConstraint<T>& c, std::size_t lane, SolverBody const& a,
                          SolverBody const& b, Manifold const& m, Vec3 const& tangent,
                          ContactImpulses const& warm, float friction, float restitution,
                          Softness const& soft) noexcept {
  std::size_t const i = lane;
  std::uint8_t const count = std::uint8_t(std::clamp(m.count, 0, 4));
  c.point_count[i] = float(count);
  c.max_points = std::max(c.max_points, count);
  c.min_points = std::min(c.min_points, count);
  c.set_bodies(i, a, b);
  Vec3 const n = m.normal;
  std::array<Vec3, 2> const t = {tangent, n.cross(tangent)};
  c.normal.set_lane(i, n);
  c.tangent1.set_lane(i, t[0]);
  c.tangent2.set_lane(i, t[1]);
  c.friction[i] = friction;
  c.restitution[i] = restitution;
  c.bias_rate[i] = soft.bias_rate;
  c.mass_scale[i] = soft.mass_scale;
  c.impulse_scale[i] = soft.impulse_scale;
  auto const effective_mass = [&](Vec3 const& ra, Vec3 const& rb, Vec3 const& d) {
    Vec3 const ca = ra.cross(d), cb = rb.cross(d);
    float const k = (a.inv_mass + b.inv_mass) + ca.dot(a.inv_inertia.mul_vec3(ca)) +
                    cb.dot(b.inv_inertia.mul_vec3(cb));
    return k > 0.0f ? 1.0f / k : 0.0f;
  };
  Vec3 center{};
  for (std::size_t k = 0; k < std::size_t(m.count); ++k)
    center = center + (m.points[k].point_a + m.points[k].point_b) * 0.5f;
  center = m.count > 0 ? center * (1.0f / float(m.count)) : a.center;
  float radius = 0.0f;
  for (std::size_t k = 0; k < 4; ++k) {
    GContactConstraintPoint<T>& p = c.points[k];
    if (k >= std::size_t(m.count)) {
      p.anchor_a.set_lane(i, {});
      p.anchor_b.set_lane(i, {});
      p.base_separation[i] = 0.0f;
      p.relative_velocity[i] = 0.0f;
      p.normal_mass[i] = 0.0f;
      p.normal_impulse[i] = 0.0f;
      p.max_normal_impulse[i] = 0.0f;
      continue;
    }
    ContactPoint const& cp = m.points[k];
    Vec3 const mid = (cp.point_a + cp.point_b) * 0.5f;
    radius += (mid - center).length();
    Vec3 const ra = mid - a.center, rb = mid - b.center;
    p.anchor_a.set_lane(i, ra);
    p.anchor_b.set_lane(i, rb);
    p.base_separation[i] = cp.separation - (rb - ra).dot(n);
    Vec3 const dv = (b.linear_velocity + b.angular_velocity.cross(rb)) -
                    (a.linear_velocity + a.angular_velocity.cross(ra));
    p.relative_velocity[i] = dv.dot(n);
    p.normal_mass[i] = effective_mass(ra, rb, n);
    p.normal_impulse[i] = warm.normal[k];
    p.max_normal_impulse[i] = 0.0f;
  }
  bool const any = m.count > 0;
  Vec3 const fa = center - a.center, fb = center - b.center;
  c.friction_anchor_a.set_lane(i, fa);
  c.friction_anchor_b.set_lane(i, fb);
  c.tangent_mass1[i] = any ? effective_mass(fa, fb, t[0]) : 0.0f;
  c.tangent_mass2[i] = any ? effective_mass(fa, fb, t[1]) : 0.0f;
  float const kt = n.dot(a.inv_inertia.mul_vec3(n)) + n.dot(b.inv_inertia.mul_vec3(n));
  c.twist_mass[i] = any && kt > 0.0f ? 1.0f / kt : 0.0f;
  c.twist_radius[i] = any ? radius / float(m.count) : 0.0f;
  c.tangent_impulse1[i] = any ? warm.tangent1 : 0.0f;
  c.tangent_impulse2[i] = any ? warm.tangent2 : 0.0f;
  c.twist_impulse[i] = any ? warm.twist : 0.0f;
}

/// Makes lane `lane` empty: both bodies the identity record `identity_state`, nothing applied.
template <Real T>
void clear_contact_lane(GContactConstraint<T>& c, std::size_t lane,
                        std::int32_t identity_state) noexcept {
  SolverBody none;
  none.state = identity_state;
  Manifold empty;
  empty.normal = Vec3::Z;
  std::uint8_t const max_points = c.max_points, min_points = c.min_points;
  prepare_contact_lane(c, lane, none, none, empty, Vec3::X, {}, 0.0f, 0.0f, Softness{});
  c.max_points = max_points; // a padding lane takes no part in the counts
  c.min_points = min_points;
}

/// Reads back the accumulated impulses of lane `lane`.
template <Real T>
ContactImpulses contact_impulses(GContactConstraint<T> const& c, std::size_t lane) noexcept {
  ContactImpulses r;
  for (std::size_t k = 0; k < 4; ++k)
    r.normal[k] = c.points[k].normal_impulse[lane];
  r.tangent1 = c.tangent_impulse1[lane];
  r.tangent2 = c.tangent_impulse2[lane];
  r.twist = c.twist_impulse[lane];
  return r;
}

/// Applies the accumulated impulses (start of each substep).
template <Real T>
void warm_start_contacts(GContactConstraint<T> const& c, BodyState* states) noexcept {
  auto bodies = load_constraint_bodies(c, states);
  GVec3<T> const n = c.normal.get(), t1 = c.tangent1.get(), t2 = c.tangent2.get();
  std::size_t const np = c.max_points;
  if (c.min_points == c.max_points) {
    for (std::size_t k = 0; k < np; ++k) {
      auto const& p = c.points[k];
      bodies.apply(n * p.normal_impulse.get(), p.anchor_a.get(), p.anchor_b.get());
    }
  } else {
    T const count = c.point_count.get();
    for (std::size_t k = 0; k < np; ++k) {
      auto const& p = c.points[k];
      auto const before = bodies.velocities();
      bodies.apply(n * p.normal_impulse.get(), p.anchor_a.get(), p.anchor_b.get());
      bodies.keep_lanes(T(float(k)) < count, before);
    }
  }
  bodies.apply(t1 * c.tangent_impulse1.get() + t2 * c.tangent_impulse2.get(),
               c.friction_anchor_a.get(), c.friction_anchor_b.get());
  bodies.apply_angular(n * c.twist_impulse.get());
  store_constraint_bodies(c, states, bodies);
}

/// One Gauss–Seidel pass over W manifolds: the normal impulse of each point (with the soft
/// bias when use_bias, the relax pass without), then the patch friction. inv_h = 1 / substep (1/s);
/// max_push_speed caps the push-out velocity of penetrating points (m/s).
template <Real T>
void solve_contacts(GContactConstraint<T>& c, BodyState* states, float inv_h, float max_push_speed,
                    bool use_bias) noexcept {
  auto bodies = load_constraint_bodies(c, states);
  GVec3<T> const n = c.normal.get();
  GVec3<T> const dp = bodies.b.delta_position - bodies.a.delta_position;
  T const rate = c.bias_rate.get(), soft_mass = c.mass_scale.get(),
          soft_imp = c.impulse_scale.get();
  T const zero_t = zero<T>(), one_t = one<T>();
  auto const solve_point = [&](GContactConstraintPoint<T>& p) PLUME_INLINE_LAMBDA {
    GVec3<T> const ra = p.anchor_a.get(), rb = p.anchor_b.get();
    GVec3<T> const d =
        dp + (bodies.b.delta_rotation.mul_vec3(rb) - bodies.a.delta_rotation.mul_vec3(ra));
    T const s = d.dot(n) + p.base_separation.get();
    mask_t<T> const speculative = s > zero_t;
    T bias = s * T(inv_h);
    T mass_scale = one_t, impulse_scale = zero_t;
    if (use_bias) {
      bias = plume::select(speculative, bias, max_select(rate * s, T(-max_push_speed)));
      mass_scale = plume::select(speculative, one_t, soft_mass);
      impulse_scale = plume::select(speculative, zero_t, soft_imp);
    } else {
      bias = plume::select(speculative, bias, zero_t);
    }
    T const vn = bodies.relative_velocity(ra, rb).dot(n);
    T const old = p.normal_impulse.get();
    T const applied = max_select(
        old - p.normal_mass.get() * mass_scale * (vn + bias) - impulse_scale * old, zero_t);
    p.normal_impulse.set(applied);
    p.max_normal_impulse.set(max_select(p.max_normal_impulse.get(), applied));
    bodies.apply(n * (applied - old), ra, rb);
  };
  std::size_t const np = c.max_points;
  if (c.min_points == c.max_points) {
    for (std::size_t k = 0; k < np; ++k)
      solve_point(c.points[k]);
  } else {
    T const count = c.point_count.get();
    for (std::size_t k = 0; k < np; ++k) {
      GContactConstraintPoint<T>& p = c.points[k];
      auto const before = bodies.velocities();
      T const impulse = p.normal_impulse.get(), max_impulse = p.max_normal_impulse.get();
      solve_point(p);
      mask_t<T> const present = T(float(k)) < count;
      bodies.keep_lanes(present, before);
      p.normal_impulse.set(plume::select(present, p.normal_impulse.get(), impulse));
      p.max_normal_impulse.set(plume::select(present, p.max_normal_impulse.get(), max_impulse));
    }
  }
  // Patch friction: tangents at the centre, then twist, limited by the total normal impulse
  // (a point a lane lacks holds +0, which adds nothing: the sum is never -0).
  T total = zero_t;
  for (std::size_t k = 0; k < np; ++k)
    total = total + c.points[k].normal_impulse.get();
  T const limit = c.friction.get() * total;
  GVec3<T> const t1 = c.tangent1.get(), t2 = c.tangent2.get();
  GVec3<T> const fa = c.friction_anchor_a.get(), fb = c.friction_anchor_b.get();
  {
    GVec3<T> const dv = bodies.relative_velocity(fa, fb);
    T const old1 = c.tangent_impulse1.get(), old2 = c.tangent_impulse2.get();
    T l1 = old1 - c.tangent_mass1.get() * dv.dot(t1);
    T l2 = old2 - c.tangent_mass2.get() * dv.dot(t2);
    T const len2 = l1 * l1 + l2 * l2;
    mask_t<T> const over = len2 > limit * limit;
    T const scale = plume::select(over, limit / plume::sqrt(len2), one_t);
    l1 = l1 * scale;
    l2 = l2 * scale;
    c.tangent_impulse1.set(l1);
    c.tangent_impulse2.set(l2);
    bodies.apply(t1 * (l1 - old1) + t2 * (l2 - old2), fa, fb);
  }
  {
    T const wn = (bodies.b.angular_velocity - bodies.a.angular_velocity).dot(n);
    T const old = c.twist_impulse.get();
    T const max_twist = limit * c.twist_radius.get();
    T const next = clamp_select(old - c.twist_mass.get() * wn, -max_twist, max_twist);
    c.twist_impulse.set(next);
    bodies.apply_angular(n * (next - old));
  }
  store_constraint_bodies(c, states, bodies);
}

/// Restitution, once after the substeps: points whose normal velocity at prepare was below
/// -threshold (m/s) and that carried a normal impulse get v_n -> -e v_n0.
template <Real T>
void apply_restitution(GContactConstraint<T>& c, BodyState* states, float threshold) noexcept {
  auto bodies = load_constraint_bodies(c, states);
  GVec3<T> const n = c.normal.get();
  T const e = c.restitution.get();
  T const zero_t = zero<T>();
  T const count = c.point_count.get();
  for (std::size_t k = 0; k < c.max_points; ++k) {
    GContactConstraintPoint<T>& p = c.points[k];
    auto const before = bodies.velocities();
    T const v0 = p.relative_velocity.get();
    mask_t<T> const active = (v0 < T(-threshold)) & (p.max_normal_impulse.get() > zero_t) &
                             (e > zero_t) & (T(float(k)) < count);
    GVec3<T> const ra = p.anchor_a.get(), rb = p.anchor_b.get();
    T const vn = bodies.relative_velocity(ra, rb).dot(n);
    T const old = p.normal_impulse.get();
    T const next = max_select(old - p.normal_mass.get() * (vn + e * v0), zero_t);
    T const applied = plume::select(active, next, old);
    p.normal_impulse.set(applied);
    p.max_normal_impulse.set(max_select(p.max_normal_impulse.get(), applied));
    bodies.apply(n * (applied - old), ra, rb);
    bodies.keep_lanes(active, before); // lanes with nothing to restore stay bit for bit
  }
  store_constraint_bodies(c, states, bodies);
}

} // namespace plume

PLUME_MASK_CODE_END
