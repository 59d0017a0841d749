// plume/numerics/detail/payne_hanek.hpp - exact reduction of huge arguments modulo pi/2.
// Internal to the trigonometric functions (plume/numerics/trig.hpp).
#pragma once

namespace plume::detail {

/// x - q*pi/2 for finite |x| >= 2^10, as hi + lo (|hi + lo| <= pi/4 + tiny, relative error
/// below 2^-100), and q mod 4 in `quadrant`. Payne-Hanek with a 1,408-bit table of 2/pi: the
/// result is that of an exact reduction, so sin(1e300) is right to the last bit of the
/// kernel. Scalar; the wide functions call it lane by lane for the lanes that need it.
struct huge_reduction {
  double hi;
  double lo;
  int quadrant;
};
huge_reduction reduce_half_pi_huge(double x) noexcept;

} // namespace plume::detail
