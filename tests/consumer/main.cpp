// Uses plume as a user project would; exits 0 when the numbers are right.
#include <plume/plume.hpp>

#include <cstdio>

int main() {
  float const s = plume::sin(plume::frac_pi_2<float>());
  double const l = plume::log2(1024.0);
  std::printf("consumer: sin(pi/2) = %g, log2(1024) = %g, build %s\n", s, l, plume::simd_name);
  return (s == 1.0f && l == 10.0) ? 0 : 1;
}
