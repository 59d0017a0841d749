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
//     dv = h (k e + (d + theta h k) e_v) / (1 + h d + h^2 k),   theta = min(1, omega h / 2)
// (omega = sqrt(k)): Avian's update (theta = 0: symplectic spring, implicit damping) with
// (omega h)^2 / 4 of damping added, which cancels its leading error, becoming the implicit
// Euler step of a soft constraint (theta = 1) from omega h = 2 on, so a stiff motor does not
// ring. docs/joints.md compares the three on the closed-form step responses.
// Velocity control: the velocity model, or acceleration / force with stiffness 0.
#pragma once

#include <algorithm>
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
/// The model's name ("spring_damper", ...); "unknown" for a value outside the enum.
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
  float mass_scale = 0.0f;    ///< h (d + theta h k) / D, D = 1 + h d + h^2 k (1: rigid)
  float bias_scale = 0.0f;    ///< h k / D (1/s)
  float impulse_scale = 1.0f; ///< 1 - mass_scale
};

/// Motor m's coefficients at substep h (s > 0), for a row whose inverse effective mass is
/// inv_mass (used by the force model only). Disabled, or no stiffness and no damping: {0, 0,
/// 1}, a row that holds no impulse.
inline MotorCoefficients motor_coefficients(Motor const& m, float inv_mass, float h) noexcept {
  if (!m.enabled) return {};
  double k = 0.0, d = 0.0; // double: omega^2 of a 1e19 Hz spring is 4e39
  switch (m.model) {
  case MotorModel::velocity:
    return {1.0f, 0.0f, 0.0f};
  case MotorModel::spring_damper: {
    double const omega = 2.0 * 3.14159265358979323846 * double(m.frequency);
    k = omega * omega;
    d = 2.0 * double(m.damping_ratio) * omega;
    break;
  }
  case MotorModel::acceleration:
    k = m.stiffness;
    d = m.damping;
    break;
  case MotorModel::force:
    k = double(m.stiffness) * inv_mass;
    d = double(m.damping) * inv_mass;
    break;
  }
  double const hd = double(h) * d, hk = double(h) * k;
  double const den = (1.0 + hd) + double(h) * hk;
  double const theta = std::min(1.0, 0.5 * std::sqrt(k) * h);
  double const ms = (hd + theta * (double(h) * hk)) / den;
  if (!std::isfinite(den) || !std::isfinite(ms)) // beyond double: the stiff limit
    return {1.0f, 1.0f / h, 0.0f};
  return {float(ms), float(hk / den), float(1.0 - ms)};
}

} // namespace plume
