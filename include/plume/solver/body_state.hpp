// plume/solver/body_state.hpp - the compact per-body record the contact solver reads and
// writes during a step, and its wide form.
//
// BodyState (64 bytes, one per body that moves) holds what changes inside a step: linear and
// angular velocity (world, m/s and rad/s about the centre of mass) and the translation and
// rotation of the centre of mass since the step began. Bodies that never move (static) all
// share one identity record, so a constraint reads them like any other body.
//
// GBodyState<T> is W = lanes_v<T> records side by side. gather_states() builds one from W
// record indices (a transpose); scatter_velocities() writes the velocities back, only for the
// lanes whose write index is >= 0 (dynamic bodies: static and kinematic bodies and empty
// lanes are never written). For T = float both are plain copies.
#pragma once

#include <plume/math/mat3.hpp>
#include <plume/math/quat.hpp>
#include <plume/math/sym_mat3.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>
#include <plume/numerics/transpose.hpp>
#include <plume/solver/lane_storage.hpp>

#include <array>
#include <cstddef> // offsetof
#include <cstdint>

namespace plume {

/// Field order and padding are part of the contract: gather_states() and
/// scatter_velocities() move the record as 16 floats (v, pad, w, pad, dp, pad, dq).
struct alignas(64) BodyState {
  Vec3 linear_velocity{};
  float pad0 = 0.0f;
  Vec3 angular_velocity{};
  float pad1 = 0.0f;
  Vec3 delta_position{};
  float pad2 = 0.0f;
  Quat delta_rotation = Quat::IDENTITY;
};
static_assert(sizeof(BodyState) == 64, "BodyState is one cache line");
static_assert(offsetof(BodyState, angular_velocity) == 16 &&
                  offsetof(BodyState, delta_position) == 32 &&
                  offsetof(BodyState, delta_rotation) == 48 && sizeof(Vec3) == 12,
              "gather_states() reads a BodyState as 16 floats");

template <Real T>
struct GBodyState {
  GVec3<T> linear_velocity;
  GVec3<T> angular_velocity;
  GVec3<T> delta_position;
  GQuat<T> delta_rotation;
};

/// Lane i of the result is states[index[i]] (every index must name a record: no checks).
template <Real T>
PLUME_INLINE GBodyState<T> gather_states(BodyState const* states,
                                         std::int32_t const* index) noexcept {
  // One record is 16 floats: v, pad, w, pad, dp, pad, dq. Register transposes (a plain copy
  // for T = float) turn W records into 16 columns.
  constexpr std::size_t W = lanes_v<T>;
  float const* rows[W];
  for (std::size_t i = 0; i < W; ++i)
    rows[i] = &states[index[i]].linear_velocity.x;
  T c[16];
  load_transposed<T, 16>(rows, c);
  return {
      {c[0], c[1], c[2]}, {c[4], c[5], c[6]}, {c[8], c[9], c[10]}, {c[12], c[13], c[14], c[15]}};
}

/// states[write[i]] gets lane i's velocities, for every lane with write[i] >= 0 (its padding
/// floats become 0; lanes with write[i] < 0 write nothing).
template <Real T>
PLUME_INLINE void scatter_velocities(BodyState* states, std::int32_t const* write,
                                     GBodyState<T> const& b) noexcept {
  // The record's first 8 floats (v, pad, w, pad) are written whole, one row per lane.
  constexpr std::size_t W = lanes_v<T>;
  float* rows[W];
  for (std::size_t i = 0; i < W; ++i)
    rows[i] = write[i] >= 0 ? &states[write[i]].linear_velocity.x : nullptr;
  T const pad = zero<T>();
  T const c[8] = {b.linear_velocity.x,  b.linear_velocity.y,  b.linear_velocity.z,  pad,
                  b.angular_velocity.x, b.angular_velocity.y, b.angular_velocity.z, pad};
  store_transposed<T, 8>(c, rows);
}

/// One body of a constraint as the prepare functions need it (prepare_contact_lane,
/// prepare_joint_lane): where its state is, whether it is written back, its inverse mass and
/// world inverse inertia, its centre of mass and velocities, all in world axes, SI units.
struct SolverBody {
  std::int32_t state = 0;  ///< BodyState index (the shared identity record for static bodies)
  std::int32_t write = -1; ///< BodyState index to write back, or -1 (not dynamic)
  float inv_mass = 0.0f;
  Mat3 inv_inertia = Mat3::ZERO; ///< world
  Vec3 center{};                 ///< world centre of mass
  Vec3 linear_velocity{};
  Vec3 angular_velocity{};
};

/// The two bodies' fields of W constraints (contacts, joints derive from it), written a lane
/// at a time by set_bodies() and read by load_constraint_bodies() / store_constraint_bodies().
template <Real T>
struct GConstraintBodyLanes {
  static constexpr std::size_t body_lanes = lanes_v<T>;
  std::array<std::int32_t, body_lanes> state_a{}, state_b{}; ///< BodyState indices
  std::array<std::int32_t, body_lanes> write_a{}, write_b{}; ///< written back when >= 0
  GLaneArray<T> inv_mass_a, inv_mass_b;
  GLaneSymMat3<T> inv_inertia_a, inv_inertia_b; ///< world, at prepare

  /// Lane `lane` gets bodies a and b.
  void set_bodies(std::size_t lane, SolverBody const& a, SolverBody const& b) noexcept {
    state_a[lane] = a.state;
    state_b[lane] = b.state;
    write_a[lane] = a.write;
    write_b[lane] = b.write;
    inv_mass_a[lane] = a.inv_mass;
    inv_mass_b[lane] = b.inv_mass;
    inv_inertia_a.set_lane(lane, a.inv_inertia);
    inv_inertia_b.set_lane(lane, b.inv_inertia);
  }
};

/// The two bodies of W constraints as the solver kernels (contacts, joints) work on them:
/// their states gathered, inverse masses and world inverse inertias, and the impulse
/// application. load_constraint_bodies() / store_constraint_bodies() read and write them for
/// any constraint block with the fields state_a, state_b, write_a, write_b, inv_mass_a,
/// inv_mass_b, inv_inertia_a and inv_inertia_b.
template <Real T>
struct GConstraintBodies {
  GBodyState<T> a, b;
  T ma, mb;
  GSymMat3<T> ia, ib;

  /// Applies impulse p at anchors ra (on A, negated) and rb (on B).
  PLUME_INLINE void apply(GVec3<T> const& p, GVec3<T> const& ra, GVec3<T> const& rb) noexcept {
    a.linear_velocity = a.linear_velocity - p * ma;
    a.angular_velocity = a.angular_velocity - ia * ra.cross(p);
    b.linear_velocity = b.linear_velocity + p * mb;
    b.angular_velocity = b.angular_velocity + ib * rb.cross(p);
  }
  /// Applies angular impulse j (-j on A, +j on B).
  PLUME_INLINE void apply_angular(GVec3<T> const& j) noexcept {
    a.angular_velocity = a.angular_velocity - ia * j;
    b.angular_velocity = b.angular_velocity + ib * j;
  }
  PLUME_INLINE GVec3<T> relative_velocity(GVec3<T> const& ra, GVec3<T> const& rb) const noexcept {
    return (b.linear_velocity + b.angular_velocity.cross(rb)) -
           (a.linear_velocity + a.angular_velocity.cross(ra));
  }

  /// The four velocities the impulses change, to restore lanes with keep_lanes().
  struct Velocities {
    GVec3<T> va, wa, vb, wb;
  };
  PLUME_INLINE Velocities velocities() const noexcept {
    return {a.linear_velocity, a.angular_velocity, b.linear_velocity, b.angular_velocity};
  }
  /// Lanes where `kept` is false get their velocities back from `before`, bit for bit.
  PLUME_INLINE void keep_lanes(mask_t<T> const& kept, Velocities const& before) noexcept {
    a.linear_velocity = GVec3<T>::select(kept, a.linear_velocity, before.va);
    a.angular_velocity = GVec3<T>::select(kept, a.angular_velocity, before.wa);
    b.linear_velocity = GVec3<T>::select(kept, b.linear_velocity, before.vb);
    b.angular_velocity = GVec3<T>::select(kept, b.angular_velocity, before.wb);
  }
};

template <class Block, Real T = typename Block::element_type>
PLUME_INLINE GConstraintBodies<T> load_constraint_bodies(Block const& c,
                                                         BodyState const* states) noexcept {
  return {gather_states<T>(states, c.state_a.data()),
          gather_states<T>(states, c.state_b.data()),
          c.inv_mass_a.get(),
          c.inv_mass_b.get(),
          c.inv_inertia_a.get(),
          c.inv_inertia_b.get()};
}

template <class Block, Real T = typename Block::element_type>
PLUME_INLINE void store_constraint_bodies(Block const& c, BodyState* states,
                                          GConstraintBodies<T> const& bodies) noexcept {
  scatter_velocities<T>(states, c.write_a.data(), bodies.a);
  scatter_velocities<T>(states, c.write_b.data(), bodies.b);
}

} // namespace plume
