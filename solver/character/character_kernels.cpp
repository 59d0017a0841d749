// solver/character/character_kernels.cpp - the character floor's array kernels of one
// instruction set (a PLUME_DISPATCH=ON build compiles it once per carried set): batches of
// velocity projections, lanes_v<f32xN> problems at a time.
#include "character_kernels.hpp"

#include <algorithm>
#include <array>
#include <vector>

#ifndef PLUME_DISPATCH_ISA
#error "compile character_kernels.cpp with PLUME_DISPATCH_ISA set to the instruction set's name"
#endif
#define PLUME_CAT2(a, b) a##b
#define PLUME_CAT(a, b) PLUME_CAT2(a, b)

namespace plume::detail {
namespace {

template <class Vec>
using wide_vec_t = std::conditional_t<Vec::dim == 3, GVec3<f32xN>, GVec2<f32xN>>;

/// Copies lane values into a wide vector, component by component (lanes beyond `lanes` zero).
template <class Vec, std::size_t L>
wide_vec_t<Vec> gather(std::array<Vec, L> const& v) noexcept {
  alignas(64) std::array<float, L> x{}, y{}, z{};
  for (std::size_t l = 0; l < L; ++l) {
    x[l] = v[l].x;
    y[l] = v[l].y;
    if constexpr (Vec::dim == 3) z[l] = v[l].z;
  }
  if constexpr (Vec::dim == 3)
    return {load_aligned<f32xN>(x.data()), load_aligned<f32xN>(y.data()),
            load_aligned<f32xN>(z.data())};
  else
    return {load_aligned<f32xN>(x.data()), load_aligned<f32xN>(y.data())};
}

/// The order in which the problems fill packets: by plane count (a counting sort, counts of 63
/// and more sharing the last bucket), so that a packet's lanes have similar counts and pad
/// little. Only speed depends on it: a lane's answer does not depend on its neighbours.
std::vector<std::size_t> packet_order(std::uint32_t const* offsets, std::size_t n) {
  constexpr std::size_t buckets = 64;
  std::array<std::size_t, buckets + 1> start{};
  auto const bucket = [&](std::size_t p) {
    return std::min<std::size_t>(offsets[p + 1] - offsets[p], buckets - 1);
  };
  for (std::size_t p = 0; p < n; ++p)
    ++start[bucket(p) + 1];
  for (std::size_t b = 0; b < buckets; ++b)
    start[b + 1] += start[b];
  std::vector<std::size_t> order(n);
  for (std::size_t p = 0; p < n; ++p)
    order[start[bucket(p)]++] = p;
  return order;
}

template <class Vec>
void project_batch(Vec const* velocities, std::size_t n, Vec const* normals,
                   std::uint32_t const* offsets, VelocityProjectionConfig const& cfg,
                   GVelocityProjection<Vec>* out, float* lambda) noexcept {
  using W = wide_vec_t<Vec>;
  constexpr std::size_t L = lanes_v<f32xN>;
  std::vector<std::size_t> const order =
      L > 1 ? packet_order(offsets, n) : std::vector<std::size_t>{};
  auto const problem = [&](std::size_t k) { return L > 1 ? order[k] : k; };
  // Scratch reused across packets: the padded normals and multipliers of one packet.
  std::vector<W> wn;
  std::vector<f32xN> wl;
  for (std::size_t g = 0; g < n; g += L) {
    std::size_t const lanes = std::min(L, n - g);
    std::array<std::size_t, L> p{};
    std::size_t kmax = 0;
    std::array<Vec, L> v{};
    for (std::size_t l = 0; l < lanes; ++l) {
      p[l] = problem(g + l);
      v[l] = velocities[p[l]];
      kmax = std::max<std::size_t>(kmax, offsets[p[l] + 1] - offsets[p[l]]);
    }
    wn.resize(kmax);
    for (std::size_t i = 0; i < kmax; ++i) {
      std::array<Vec, L> ni{}; // zero normals pad the shorter problems (and the empty lanes)
      for (std::size_t l = 0; l < lanes; ++l)
        if (offsets[p[l]] + i < offsets[p[l] + 1]) ni[l] = normals[offsets[p[l]] + i];
      wn[i] = gather(ni);
    }
    std::span<W const> const planes(wn.data(), kmax);
    GVelocityProjection<W> r;
    if (lambda) {
      wl.assign(kmax, zero<f32xN>());
      r = project_velocity<f32xN>(gather(v), planes, std::span<f32xN>(wl), cfg);
    } else {
      r = project_velocity<f32xN>(gather(v), planes, cfg);
    }
    std::uint64_t const converged = bitmask(r.converged), invalid = bitmask(r.invalid_input);
    for (std::size_t l = 0; l < lanes; ++l) {
      GVelocityProjection<Vec>& o = out[p[l]];
      o.velocity = lane(r.velocity, l);
      o.steps = lane(r.steps, l);
      o.converged = (converged >> l & 1u) != 0;
      o.invalid_input = (invalid >> l & 1u) != 0;
      if (lambda)
        for (std::uint32_t i = offsets[p[l]]; i < offsets[p[l] + 1]; ++i)
          lambda[i] = lane(wl[i - offsets[p[l]]], l);
    }
  }
}

constexpr CharacterKernels table = {
    PLUME_HAS_AVX512 ? Isa::avx512
    : PLUME_HAS_AVX2 ? Isa::avx2
    : PLUME_HAS_SSE2 ? Isa::sse2
                     : Isa::scalar,
    unsigned(lanes_v<f32xN>),
    &project_batch<Vec3>,
    &project_batch<Vec2>,
};

} // namespace
} // namespace plume::detail

extern "C" plume::detail::CharacterKernels const* PLUME_CAT(plume_character_table_,
                                                            PLUME_DISPATCH_ISA)() noexcept {
  return &plume::detail::table;
}
