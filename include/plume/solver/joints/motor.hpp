// plume/solver/joints/motor.hpp - joint motors: a revolute joint's angular motor and a
// prismatic joint's linear motor, and the soft coefficients of their models.
//
// A motor drives the joint's coordinate x (angle in rad, or translation in m along the axis)
// and its speed v toward target_position and target_velocity, with the accumulated impulse of
// each substep clamped to [-max_force h, max_force h] (max torque in N m for an angular motor).
// With e = target_position - x (an angle wrapped to [-pi, pi): a target across +-pi is
// reached the short way) and e_v = target_velocity - v, the models are
//   spring_damper (frequency f Hz, damping ratio zeta; omega = 2 pi f): a = omega^2 e + 2 zeta
//   omega e_v acceleration  (stiffness k 1/s^2, damping d 1/s):                   a = k e + d e_v
//   force         (stiffness k N/m or N m/rad, damping d N s/m or N m s/rad): F = k e + d e_v
//   velocity      (rigid): v reaches target_velocity as fast as max_force allows; no position term
// The first two are mass-independent (a is an acceleration); force depends on the joint's
// effective mass m (a = F / m). Each is a velocity row solved once per substep h with
// Avian's update (symplectic in the spring, implicit in the damping):
//     dv = h (k e + d e_v) / (1 + h d + h^2 k)
// stable for any stiffness, with no numerical damping (the oscillation's frequency is
// omega / sqrt(1 + omega^2 h^2): 0.9% low at 5 Hz and h = 1/240 s). The implicit-Euler form
// of a soft constraint, h (k e + (d + h k) e_v) / (1 + h d + h^2 k), adds damping
// omega h / 2 to the ratio (a 5 Hz, zeta 0.2 spring overshoots 0.43 instead of 0.53).
// Velocity control: the velocity model, or acceleration / force with stiffness 0.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <string_view>

namespace plume {

enum class MotorModel : std::uint8_t {
  spring_damper, ///< frequency (Hz) and damping_ratio; mass-independent (the default, as Avian)
  acceleration,  ///< stiffness (1/s^2) and damping (1/s); mass-independent
  force,         ///< stiffness and damping in force units; depends on the effective mass
  velocity,      ///< rigid velocity control toward target_velocity (Box2D's motor)
};
std::string_view to_string(MotorModel m) noexcept;

struct Motor {
  bool enabled = false;
  float target_velocity = 0.0f; ///< rad/s or m/s
  float target_position = 0.0f; ///< rad (any value: the error wraps) or m
  /// N m (angular) or N (linear), >= 0; infinity: unlimited.
  float max_force = std::numeric_limits<float>::infinity();
  MotorModel model = MotorModel::spring_damper;
  float frequency = 5.0f;     ///< Hz, spring_damper
  float damping_ratio = 1.0f; ///< spring_damper
  float stiffness = 0.0f;     ///< acceleration, force
  float damping = 0.0f;       ///< acceleration, force

  /// A rigid velocity motor (the velocity model).
  static Motor velocity_control(float target_velocity, float max_force) noexcept {
    Motor m;
    m.enabled = true;
    m.model = MotorModel::velocity;
    m.target_velocity = target_velocity;
    m.max_force = max_force;
    return m;
  }
  /// A spring-damper motor toward target_position (frequency Hz, damping ratio).
  static Motor position_control(float target_position, float frequency = 5.0f,
                                float damping_ratio = 1.0f,
                                float max_force = std::numeric_limits<float>::infinity()) noexcept {
    Motor m;
    m.enabled = true;
    m.target_position = target_position;
    m.frequency = frequency;
    m.damping_ratio = damping_ratio;
    m.max_force = max_force;
    return m;
  }

  /// Finite targets and model parameters, none negative, max_force >= 0 (infinity allowed).
  bool valid() const noexcept {
    auto const ok = [](float x) { return std::isfinite(x) && x >= 0.0f; };
    return std::isfinite(target_velocity) && std::isfinite(target_position) &&
           !std::isnan(max_force) && max_force >= 0.0f && ok(frequency) && ok(damping_ratio) &&
           ok(stiffness) && ok(damping) && int(model) <= int(MotorModel::velocity);
  }
};

/// The coefficients of a motor row: with C the coordinate minus the target position and
/// Cdot its speed minus the target velocity, an iteration changes the row's accumulated
/// impulse by  -m_eff (mass_scale Cdot + bias_scale C) - impulse_scale impulse, which
/// converges in one iteration to dv = mass_scale e_v + bias_scale e (impulse_scale =
/// 1 - mass_scale keeps the two the same).
struct MotorCoefficients {
  float mass_scale = 0.0f;    ///< h d / D, D = 1 + h d + h^2 k (1: rigid velocity control)
  float bias_scale = 0.0f;    ///< h k / D (1/s)
  float impulse_scale = 1.0f; ///< 1 - mass_scale
};

/// Motor m's coefficients at substep h (s > 0), for a row whose inverse effective mass is
/// inv_mass (used by the force model only). Disabled, or no stiffness and no damping: {0, 0,
/// 1}, a row that holds no impulse.
inline MotorCoefficients motor_coefficients(Motor const& m, float inv_mass, float h) noexcept {
  if (!m.enabled) return {};
  float k = 0.0f, d = 0.0f;
  switch (m.model) {
  case MotorModel::velocity:
    return {1.0f, 0.0f, 0.0f};
  case MotorModel::spring_damper: {
    float const omega = 2.0f * 3.14159265358979f * m.frequency;
    k = omega * omega;
    d = 2.0f * m.damping_ratio * omega;
    break;
  }
  case MotorModel::acceleration:
    k = m.stiffness;
    d = m.damping;
    break;
  case MotorModel::force:
    k = m.stiffness * inv_mass;
    d = m.damping * inv_mass;
    break;
  }
  float const den = 1.0f + h * d + h * h * k;
  if (!std::isfinite(den)) return {1.0f, 0.0f, 0.0f}; // overflow: as rigid as it gets
  float const ms = h * d / den;
  return {ms, h * k / den, 1.0f - ms};
}

} // namespace plume
