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

#include <plume/math/quat.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

#include <array>
#include <cstddef>
#include <cstdint>

namespace plume {

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

template <Real T>
struct GBodyState {
  GVec3<T> linear_velocity;
  GVec3<T> angular_velocity;
  GVec3<T> delta_position;
  GQuat<T> delta_rotation;
};

/// Lane i of the result is states[index[i]].
template <Real T>
PLUME_INLINE GBodyState<T> gather_states(BodyState const* states,
                                         std::int32_t const* index) noexcept {
  constexpr std::size_t W = lanes_v<T>;
  if constexpr (W == 1) {
    BodyState const& r = states[index[0]];
    return {r.linear_velocity, r.angular_velocity, r.delta_position, r.delta_rotation};
  } else {
    alignas(64) float f[13][W];
    for (std::size_t i = 0; i < W; ++i) {
      BodyState const& r = states[index[i]];
      f[0][i] = r.linear_velocity.x;
      f[1][i] = r.linear_velocity.y;
      f[2][i] = r.linear_velocity.z;
      f[3][i] = r.angular_velocity.x;
      f[4][i] = r.angular_velocity.y;
      f[5][i] = r.angular_velocity.z;
      f[6][i] = r.delta_position.x;
      f[7][i] = r.delta_position.y;
      f[8][i] = r.delta_position.z;
      f[9][i] = r.delta_rotation.x;
      f[10][i] = r.delta_rotation.y;
      f[11][i] = r.delta_rotation.z;
      f[12][i] = r.delta_rotation.w;
    }
    auto const l = [&](int k) { return load_aligned<T>(f[k]); };
    return {
        {l(0), l(1), l(2)}, {l(3), l(4), l(5)}, {l(6), l(7), l(8)}, {l(9), l(10), l(11), l(12)}};
  }
}

/// states[write[i]] gets lane i's velocities, for every lane with write[i] >= 0.
template <Real T>
PLUME_INLINE void scatter_velocities(BodyState* states, std::int32_t const* write,
                                     GBodyState<T> const& b) noexcept {
  constexpr std::size_t W = lanes_v<T>;
  if constexpr (W == 1) {
    if (write[0] < 0) return;
    BodyState& r = states[write[0]];
    r.linear_velocity = b.linear_velocity;
    r.angular_velocity = b.angular_velocity;
  } else {
    alignas(64) float f[6][W];
    store_aligned(f[0], b.linear_velocity.x);
    store_aligned(f[1], b.linear_velocity.y);
    store_aligned(f[2], b.linear_velocity.z);
    store_aligned(f[3], b.angular_velocity.x);
    store_aligned(f[4], b.angular_velocity.y);
    store_aligned(f[5], b.angular_velocity.z);
    for (std::size_t i = 0; i < W; ++i) {
      if (write[i] < 0) continue;
      BodyState& r = states[write[i]];
      r.linear_velocity = {f[0][i], f[1][i], f[2][i]};
      r.angular_velocity = {f[3][i], f[4][i], f[5][i]};
    }
  }
}

} // namespace plume
