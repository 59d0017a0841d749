// Meshes for the spatial and world tests: random triangle soups, grids and a terrain, built
// into TriangleMeshes (REQUIREd to build), and bitwise comparisons.
#pragma once

#include <plume/math/vec3.hpp>
#include <plume/spatial/triangle_mesh.hpp>

#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

namespace plume::test {

struct soup {
  std::vector<Vec3> v;
  std::vector<std::uint32_t> i;
};

/// n random triangles of size up to `size` in [-10, 10]^3, sharing vertices at random.
inline soup random_soup(std::uint32_t seed, std::size_t tris, float size) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  soup s;
  for (std::size_t t = 0; t < tris; ++t) {
    Vec3 const c{10 * u(g), 10 * u(g), 10 * u(g)};
    for (int k = 0; k < 3; ++k) {
      if (t > 0 && g() % 4 == 0) { // reuse a vertex
        s.i.push_back(std::uint32_t(g() % s.v.size()));
      } else {
        s.i.push_back(std::uint32_t(s.v.size()));
        s.v.push_back(c + Vec3{u(g), u(g), u(g)} * size);
      }
    }
  }
  return s;
}

/// An (n+1) x (n+1) vertex grid of spacing h over x, z in [0, n h], two triangles per cell,
/// wound so the front faces +y; heights from `height` (0 for a flat grid).
template <class H>
soup grid(std::uint32_t n, float h, H&& height) {
  soup s;
  for (std::uint32_t z = 0; z <= n; ++z)
    for (std::uint32_t x = 0; x <= n; ++x)
      s.v.push_back({float(x) * h, height(float(x) * h, float(z) * h), float(z) * h});
  auto const at = [&](std::uint32_t x, std::uint32_t z) { return z * (n + 1) + x; };
  for (std::uint32_t z = 0; z < n; ++z)
    for (std::uint32_t x = 0; x < n; ++x) {
      std::uint32_t const a = at(x, z), b = at(x + 1, z), c = at(x, z + 1), d = at(x + 1, z + 1);
      // (c - a) x (b - a) faces +y: a, c, b and b, c, d.
      s.i.insert(s.i.end(), {a, c, b, b, c, d});
    }
  return s;
}

inline float terrain_height(float x, float z) {
  return 0.7f * std::sin(0.9f * x) * std::cos(0.7f * z) + 0.2f * std::sin(2.3f * x + 1.1f * z);
}

inline TriangleMesh make(soup const& s) {
  auto r = TriangleMesh::build(s.v, s.i);
  REQUIRE(r.ok());
  return std::move(r.mesh);
}

inline bool same_bits(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}
inline bool same_bits(Vec3 const& a, Vec3 const& b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

} // namespace plume::test
