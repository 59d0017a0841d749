// Helpers for the character tests: quasi-random unit directions (plastic- and golden-ratio
// sequences), the plane sets of Avian's agreement test (+z and 16 tilted normals), an
// independent QP oracle (Eigen, enumerating active sets in double), and packing per-lane
// scalar plane sets into wide ones padded with zero normals.
#pragma once

#include "../math/math_support.hpp"

#include <plume/character.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <numbers>
#include <vector>

namespace plume::test {

/// Unit directions on the sphere from the plastic-number (R2) sequence: z and the azimuth step
/// by 1/p and 1/p^2 (p = 1.3247...) mod 1, evenly spread without randomness.
struct plastic_directions {
  double i = 0, j = 0;
  static constexpr double plastic = 1.32471795724475;
  DVec3 next() {
    double const phi = 2 * std::numbers::pi * j;
    double const zc = 2 * i - 1;
    double const rho = std::sqrt(1 - zc * zc);
    i = std::fmod(i + 1 / plastic, 1.0);
    j = std::fmod(j + 1 / (plastic * plastic), 1.0);
    return {rho * std::cos(phi), rho * std::sin(phi), zc};
  }
};

/// Unit directions on the circle from the golden-ratio sequence.
struct golden_directions {
  double j = 0;
  static constexpr double golden = 1.61803398875;
  DVec2 next() {
    double const phi = 2 * std::numbers::pi * j;
    j = std::fmod(j + 1 / golden, 1.0);
    return {std::cos(phi), std::sin(phi)};
  }
};

/// +Z and 16 normals around it ((+-2, 0, 1), (0, +-2, 1), (+-1.5, +-1.5, 1), (+-1, +-1.75, 1),
/// (+-1.75, +-1, 1)), normalised in double: floors, slopes and walls meeting at one point.
inline std::vector<DVec3> avian_normals_3d() {
  std::vector<DVec3> n = {
      {0, 0, 1},      {2, 0, 1},      {-2, 0, 1},      {0, 2, 1},     {0, -2, 1},    {1.5, 1.5, 1},
      {1.5, -1.5, 1}, {-1.5, 1.5, 1}, {-1.5, -1.5, 1}, {1, 1.75, 1},  {1, -1.75, 1}, {-1, 1.75, 1},
      {-1, -1.75, 1}, {1.75, 1, 1},   {1.75, -1, 1},   {-1.75, 1, 1}, {-1.75, -1, 1}};
  for (auto& v : n)
    v = v.normalize();
  return n;
}

/// +Y, (+-2, 1), (+-1, 1), normalised.
inline std::vector<DVec2> avian_normals_2d() {
  std::vector<DVec2> n = {{0, 1}, {2, 1}, {-2, 1}, {1, 1}, {-1, 1}};
  for (auto& v : n)
    v = v.normalize();
  return n;
}

/// A scalar vector converted to another lane type (rounded to nearest).
template <class S, class U>
GVec3<S> to(GVec3<U> const& v) {
  return {S(v.x), S(v.y), S(v.z)};
}
template <class S, class U>
GVec2<S> to(GVec2<U> const& v) {
  return {S(v.x), S(v.y)};
}

/// The exact projection of v onto {u : n_i . u >= 0} in double, by enumerating active sets
/// of up to dim planes: the candidate that satisfies every optimality condition (lambda >= 0
/// by an Eigen solve, every plane allowed) nearest to v. Independent of plume's code.
template <int Dim>
Eigen::Matrix<double, Dim, 1> qp_oracle(Eigen::Matrix<double, Dim, 1> const& v,
                                        std::vector<Eigen::Matrix<double, Dim, 1>> const& n) {
  using Vec = Eigen::Matrix<double, Dim, 1>;
  Vec best = Vec::Zero();
  double best_d = v.squaredNorm(); // the apex is always allowed
  auto allowed = [&](Vec const& u) {
    for (auto const& ni : n)
      if (ni.dot(u) < -1e-12 * (1 + u.norm())) return false;
    return true;
  };
  if (allowed(v)) return v;
  std::size_t const k = n.size();
  std::vector<std::size_t> set;
  auto try_set = [&] {
    Eigen::MatrixXd N(Dim, set.size());
    for (std::size_t c = 0; c < set.size(); ++c)
      N.col(Eigen::Index(c)) = n[set[c]];
    Eigen::MatrixXd G = N.transpose() * N;
    Eigen::FullPivLU<Eigen::MatrixXd> lu(G);
    if (lu.rank() < Eigen::Index(set.size())) return;
    Eigen::VectorXd lambda = lu.solve(-(N.transpose() * v));
    if ((lambda.array() < -1e-12).any()) return;
    Vec const u = v + N * lambda;
    double const d = (u - v).squaredNorm();
    if (allowed(u) && d < best_d) best = u, best_d = d;
  };
  for (std::size_t i = 0; i < k; ++i) {
    set = {i};
    try_set();
    for (std::size_t j = i + 1; j < k && Dim >= 2; ++j) {
      set = {i, j};
      try_set();
      for (std::size_t l = j + 1; l < k && Dim >= 3; ++l) {
        set = {i, j, l};
        try_set();
      }
    }
  }
  return best;
}

/// Wide plane sets from per-lane scalar ones: slot i of lane l is lane l's normal i, or zero.
template <class T>
std::vector<GVec3<T>> pack_planes3(std::vector<std::vector<GVec3<scalar_t<T>>>> const& per_lane) {
  std::size_t k = 0;
  for (auto const& l : per_lane)
    k = std::max(k, l.size());
  std::vector<GVec3<T>> out(k);
  for (std::size_t l = 0; l < per_lane.size(); ++l)
    for (std::size_t i = 0; i < per_lane[l].size(); ++i)
      out[i] = with_lane(out[i], l, per_lane[l][i]);
  return out;
}
template <class T>
std::vector<GVec2<T>> pack_planes2(std::vector<std::vector<GVec2<scalar_t<T>>>> const& per_lane) {
  std::size_t k = 0;
  for (auto const& l : per_lane)
    k = std::max(k, l.size());
  std::vector<GVec2<T>> out(k);
  for (std::size_t l = 0; l < per_lane.size(); ++l)
    for (std::size_t i = 0; i < per_lane[l].size(); ++i)
      out[i] = with_lane(out[i], l, per_lane[l][i]);
  return out;
}

/// Bitwise equality of two math values of any element type, lane by lane.
template <class A>
bool same_lanes(A const& a, A const& b) {
  using E = typename A::element_type;
  for (std::size_t i = 0; i < lanes_v<E>; ++i)
    if (!same(lane_of(a, i), lane_of(b, i))) return false;
  return true;
}

/// Lane l of each slot of a wide plane set.
template <class Vec>
auto lane_planes(std::vector<Vec> const& wide, std::size_t l) {
  std::vector<decltype(lane(wide[0], l))> out;
  for (auto const& n : wide)
    out.push_back(lane(n, l));
  return out;
}

} // namespace plume::test
