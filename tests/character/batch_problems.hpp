// tests/character/batch_problems.hpp - batches of velocity projection problems for
// project_velocities' tests (the character tests and the dispatch tests): 0 to 20 planes a
// problem, in runs of equal counts and mixed, with the inputs the single call treats specially
// (zero normals, non-unit and out-of-range normals, non-finite values, tiny and huge
// velocities, opposite and parallel planes), and the single call's answers to compare with.
#pragma once

#include <plume/character.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace plume::test {

template <class Vec>
struct ProjectionBatch {
  std::vector<Vec> velocities;
  std::vector<Vec> normals;
  std::vector<std::uint32_t> offsets{0};
  // The single call, problem by problem, without padding: the answers to match bit for bit.
  std::vector<GVelocityProjection<Vec>> expected;
  std::vector<float> expected_lambda;
};

template <class Vec>
Vec random_unit(std::mt19937& rng) {
  std::normal_distribution<float> g;
  for (;;) {
    Vec v;
    v.x = g(rng);
    v.y = g(rng);
    if constexpr (Vec::dim == 3) v.z = g(rng);
    float const l = std::sqrt(v.dot(v));
    if (l > 0.1f) return v * (1.0f / l);
  }
}

/// n problems from seed; cfg is what `expected` was computed with.
template <class Vec>
ProjectionBatch<Vec> make_projection_batch(std::size_t n, std::uint32_t seed,
                                           VelocityProjectionConfig const& cfg = {}) {
  ProjectionBatch<Vec> b;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  float const inf = std::numeric_limits<float>::infinity();
  float const nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t p = 0; p < n; ++p) {
    // Counts: runs of one count (the packets a sorted crowd makes), then mixed ones.
    std::size_t const count = p < n / 3 ? (p / 8) % 6 : rng() % 21;
    Vec v = random_unit<Vec>(rng) * (0.01f + 6.0f * u(rng));
    Vec const push = v * -1.0f; // planes facing v make the problems hard (many steps)
    std::size_t const special = rng() % 40;
    if (special == 0) v = v * 1e-4f; // below epsilon: unchanged
    if (special == 1) v.x = nan;     // invalid_input
    if (special == 2) v = v * 1e13f; // beyond 2^40: invalid_input
    if (special == 3) v.y = inf;     // invalid_input
    b.velocities.push_back(v);
    for (std::size_t i = 0; i < count; ++i) {
      Vec nrm = random_unit<Vec>(rng);
      if (nrm.dot(push) < 0.0f && rng() % 2) nrm = nrm * -1.0f;
      std::size_t const kind = rng() % 30;
      if (kind == 0) nrm = Vec{};                             // zero normals are ignored
      if (kind == 1) nrm = nrm * 3.0f;                        // a non-unit normal
      if (kind == 2 && i > 0) nrm = b.normals.back() * -1.0f; // opposite planes
      if (kind == 3 && i > 0) nrm = b.normals.back();         // a repeated plane
      if (kind == 4 && special == 5) nrm = nrm * 1e-4f;       // too short: invalid_input
      if (kind == 5 && special == 6) nrm.x = nan;             // invalid_input
      b.normals.push_back(nrm);
    }
    b.offsets.push_back(static_cast<std::uint32_t>(b.normals.size()));
  }
  b.expected_lambda.assign(b.normals.size(), -1.0f);
  for (std::size_t p = 0; p < n; ++p) {
    std::span<Vec const> const planes(b.normals.data() + b.offsets[p],
                                      b.offsets[p + 1] - b.offsets[p]);
    std::span<float> const lambda(b.expected_lambda.data() + b.offsets[p], planes.size());
    b.expected.push_back(project_velocity<float>(b.velocities[p], planes, lambda, cfg));
  }
  return b;
}

inline bool same_bits(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b) || (a != a && b != b);
}

/// The first problem whose answer (velocity, steps, flags) differs from the single call's in
/// any bit, or -1.
template <class Vec>
long first_projection_mismatch(ProjectionBatch<Vec> const& b,
                               std::vector<GVelocityProjection<Vec>> const& got) {
  for (std::size_t p = 0; p < b.expected.size(); ++p) {
    auto const& e = b.expected[p];
    auto const& g = got[p];
    bool ok = same_bits(e.velocity.x, g.velocity.x) && same_bits(e.velocity.y, g.velocity.y) &&
              same_bits(e.steps, g.steps) && e.converged == g.converged &&
              e.invalid_input == g.invalid_input;
    if constexpr (Vec::dim == 3) ok = ok && same_bits(e.velocity.z, g.velocity.z);
    if (!ok) return static_cast<long>(p);
  }
  return -1;
}

/// The first plane whose multiplier differs from the single call's, or -1.
inline long first_lambda_mismatch(std::vector<float> const& want, std::vector<float> const& got) {
  for (std::size_t i = 0; i < want.size(); ++i)
    if (!same_bits(want[i], got[i])) return static_cast<long>(i);
  return -1;
}

} // namespace plume::test
