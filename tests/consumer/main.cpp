// Uses plume as a user project would (and runs the README's tour example); exits 0 when the
// numbers are right.
#include <plume/plume.hpp>

#include <cmath>
#include <cstdio>

template <plume::Real T>
T bounce_height(T x, T height) {
  T const s = plume::sin(x) * height;
  return plume::select(s < T(0), -s, s);
}

int main() {
  float const s = plume::sin(plume::frac_pi_2<float>());
  double const l = plume::log2(1024.0);
  std::printf("consumer: sin(pi/2) = %g, log2(1024) = %g, build %s\n", s, l, plume::simd_name);
  float const one = bounce_height(4.0f, 2.0f);
  plume::f32xN const many = bounce_height(plume::f32xN(4.0f), plume::f32xN(2.0f));
  bool lanes_equal = true;
  for (std::size_t i = 0; i < plume::lanes_v<plume::f32xN>; ++i)
    lanes_equal = lanes_equal && plume::lane(many, i) == one;
  // The README's geometry example.
  using namespace plume;
  Vec3 const my_vec3_array[16] = {{1, 0, 0}, {0, 2, 0}, {0, 0, 3}};
  Vec3xN const dirs = pack<f32xN>(my_vec3_array);
  QuatxN const rot = QuatxN(Quat::from_axis_angle(Vec3::Y, 0.5f));
  Vec3xN const turned = rot * dirs.normalize_or_zero();
  auto [unit, ok] = turned.try_normalize();
  Vec3 const first = lane(turned, 0);
  bool const geometry_ok = plume::lane(ok, 0) && std::abs(first.length() - 1.0f) < 1e-6f &&
                           std::abs(lane(unit, 0).y) < 1e-6f;
  std::printf("consumer: first turned direction (%g, %g, %g)\n", first.x, first.y, first.z);
  return (s == 1.0f && l == 10.0 && lanes_equal && one > 1.5f && geometry_ok) ? 0 : 1;
}
