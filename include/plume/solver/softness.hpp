// plume/solver/softness.hpp - soft constraint coefficients (the "soft step" of Box2D v3,
// Bepu and Avian): a constraint that behaves like a damped spring of stiffness `hertz` and
// damping ratio `zeta`, solved implicitly at substep h.
//
//   w = 2 pi hertz,  a1 = 2 zeta + h w,  a2 = h w a1,  a3 = 1 / (1 + a2)
//   bias_rate = w / a1 (1/s),  mass_scale = a2 a3,  impulse_scale = a3
//
// A constraint error C (length, negative = penetration) becomes the velocity bias
// bias_rate * C; an impulse update reads  dl = -m (mass_scale * v + bias) - impulse_scale * l.
// hertz = 0 (or h = 0) gives all three 0: the constraint does nothing (a rigid constraint is
// hertz -> infinity: bias_rate -> 1/h, mass_scale -> 1, impulse_scale -> 0). Worked example,
// 30 Hz, zeta 10, h = 1/240 s: bias_rate 9.07/s, mass_scale 0.942, impulse_scale 0.058.
#pragma once

#include <numbers>

namespace plume {

/// The three coefficients of a soft constraint; see the top of this header.
struct Softness {
  float bias_rate = 0.0f;     ///< 1/s: velocity bias per unit of position error
  float mass_scale = 0.0f;    ///< multiplies the effective mass term (0..1)
  float impulse_scale = 0.0f; ///< leaks the accumulated impulse (0..1)

  /// Coefficients for stiffness `hertz` (>= 0), damping ratio `zeta` (>= 0) at substep `h`
  /// (seconds, > 0). hertz == 0 or h <= 0 gives {0, 0, 0}.
  static Softness make(float hertz, float zeta, float h) noexcept {
    if (!(hertz > 0.0f) || !(h > 0.0f)) return {};
    float const omega = 2.0f * std::numbers::pi_v<float> * hertz;
    float const a1 = 2.0f * zeta + h * omega;
    float const a2 = h * omega * a1;
    float const a3 = 1.0f / (1.0f + a2);
    return {omega / a1, a2 * a3, a3};
  }
};

} // namespace plume
