// tests/fuzz/velocity_projection.cpp - fuzzes project_velocity (the n-step algorithm, with and
// without multipliers) and project_velocity_bruteforce
// (solver/character/velocity_projection.hpp), in 3D and 2D, on normal sets given directly
// (unit, scaled, zero, duplicated, opposite, nearly parallel, hostile) or collected by a plane
// set (solver/character/plane_set.hpp), with default and other tolerances. Properties:
//  - bad input (a non-finite v or normal, a nonzero normal of length outside [2^-20, 2^20]):
//    zero velocity, invalid_input, not converged, multipliers 0;
//  - steps a whole number <= max_steps; a lane that did not converge returns zero velocity
//    and multipliers 0;
//  - converged: every plane satisfied within epsilon (n . u >= -epsilon), |u| <= |v| +
//    epsilon; where |v| <= 1e18 (its square does not overflow) and the normals are unit (or
//    zero): |u - v| <= |u* - v| + epsilon for the exact projection u* (a double-precision
//    enumeration of faces, creases and the apex), a v shorter than epsilon comes back
//    unchanged in no steps, and the multipliers are >= 0, zero for planes not touching u
//    (n . u = 0 where > 0) and u = v + sum lambda_i n_i;
//  - the brute force: converged for finite input, feasible within epsilon, |u| <= |v| +
//    epsilon, and (unit normals, |v| <= 1e18) no farther than |u* - v| + epsilon;
//  - plane sets: unit normals, at most max_planes of them, a zero or non-finite normal
//    rejected with the set unchanged;
//  - wide lanes (f32x8): lane l equals the scalar call on lane l's inputs bit for bit;
//  - the batch (project_velocities, solver/character/project_velocities.hpp): each problem the
//    single call's bits, multipliers included; broken lengths or offsets refused with the
//    documented error and nothing written.
#include "fuzz_input.hpp"

#include <plume/math/pack.hpp>
#include <plume/math/vec2.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>
#include <plume/solver/character/plane_set.hpp>
#include <plume/solver/character/project_velocities.hpp>
#include <plume/solver/character/velocity_projection.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace {

using namespace plume;
using plume::fuzz::Input;

using W = f32x8;
constexpr std::size_t lanes = lanes_v<W>;
constexpr std::size_t max_normals = 12;

// --------------------------------------------------------------- dimension-generic helpers

template <class V>
constexpr int dim = V::dim;

template <class V>
std::array<double, 3> dbl(V const& v) {
  if constexpr (dim<V> == 3)
    return {double(v.x), double(v.y), double(v.z)};
  else
    return {double(v.x), double(v.y), 0.0};
}
double ddot(std::array<double, 3> a, std::array<double, 3> b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
std::array<double, 3> dsub(std::array<double, 3> a, std::array<double, 3> b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
std::array<double, 3> dscale(std::array<double, 3> a, double s) {
  return {a[0] * s, a[1] * s, a[2] * s};
}
double dlen(std::array<double, 3> a) { return std::sqrt(ddot(a, a)); }

template <class V>
bool finite_vec(V const& v) {
  if constexpr (dim<V> == 3)
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  else
    return std::isfinite(v.x) && std::isfinite(v.y);
}
template <class V>
bool is_zero(V const& v) {
  if constexpr (dim<V> == 3)
    return v.x == 0 && v.y == 0 && v.z == 0;
  else
    return v.x == 0 && v.y == 0;
}
/// A normal project_velocity takes: zero, or finite with a length in [2^-20, 2^20] (in
/// double, so the test does not share the header's float rounding).
template <class V>
bool usable_normal(V const& n) {
  if (is_zero(n)) return true;
  if (!finite_vec(n)) return false;
  double l2 = double(n.x) * n.x + double(n.y) * n.y;
  if constexpr (dim<V> == 3) l2 += double(n.z) * n.z;
  return l2 >= 0x1p-40 && l2 <= 0x1p40;
}
/// Every component at most 2^40 in magnitude (the header's bound on v; NaN fails).
template <class V>
bool usable_velocity(V const& v) {
  bool ok = std::abs(v.x) <= 0x1p40f && std::abs(v.y) <= 0x1p40f;
  if constexpr (dim<V> == 3) ok = ok && std::abs(v.z) <= 0x1p40f;
  return ok;
}
template <class V>
bool same_bits(V const& a, V const& b) {
  bool same = std::bit_cast<std::uint32_t>(a.x) == std::bit_cast<std::uint32_t>(b.x) &&
              std::bit_cast<std::uint32_t>(a.y) == std::bit_cast<std::uint32_t>(b.y);
  if constexpr (dim<V> == 3)
    same = same && std::bit_cast<std::uint32_t>(a.z) == std::bit_cast<std::uint32_t>(b.z);
  return same;
}

/// |u* - v| for the exact projection u* of v on {u : n_i . u >= 0}, in double: the nearest
/// feasible of v, its projections on each plane, on each crease (3D) and 0.
template <class V>
double exact_distance(V const& v, std::vector<V> const& normals) {
  std::array<double, 3> const dv = dbl(v);
  double const vl = dlen(dv);
  std::vector<std::array<double, 3>> ns;
  for (auto const& n : normals)
    if (!is_zero(n)) ns.push_back(dbl(n));
  auto const feasible = [&](std::array<double, 3> const& p) {
    for (auto const& n : ns)
      if (ddot(n, p) < -1e-9 * (vl + 1e-30) * dlen(n)) return false;
    return true;
  };
  double best = vl; // the apex
  auto const consider = [&](std::array<double, 3> const& p) {
    if (feasible(p)) best = std::min(best, dlen(dsub(p, dv)));
  };
  consider(dv);
  for (auto const& n : ns)
    consider(dsub(dv, dscale(n, ddot(n, dv) / ddot(n, n))));
  if constexpr (dim<V> == 3) {
    for (std::size_t i = 0; i < ns.size(); ++i)
      for (std::size_t j = i + 1; j < ns.size(); ++j) {
        auto const &a = ns[i], &b = ns[j];
        std::array<double, 3> const e{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                      a[0] * b[1] - a[1] * b[0]};
        double const ee = ddot(e, e);
        if (ee > 1e-20 * ddot(a, a) * ddot(b, b)) consider(dscale(e, ddot(dv, e) / ee));
      }
  }
  return best;
}

// ------------------------------------------------------------------------------ the input

template <class V>
V read_vec(Input& in, float lo, float hi, bool hostile) {
  if constexpr (dim<V> == 3) {
    if (hostile) return {in.maybe_bad(lo, hi), in.maybe_bad(lo, hi), in.maybe_bad(lo, hi)};
    return {in.real(lo, hi), in.real(lo, hi), in.real(lo, hi)};
  } else {
    if (hostile) return {in.maybe_bad(lo, hi), in.maybe_bad(lo, hi)};
    return {in.real(lo, hi), in.real(lo, hi)};
  }
}

template <class V>
V unit(V const& v) {
  double const l = dlen(dbl(v));
  if (!(l > 1e-3)) {
    V e{};
    e.x = 1;
    return e;
  }
  return v * float(1.0 / l);
}

/// A normal set: unit normals mostly, then zero, scaled, repeated, opposite, nearly parallel
/// or (hostile) raw ones.
template <class V>
std::vector<V> read_normals(Input& in, bool hostile, bool& unit_set) {
  std::vector<V> ns;
  unit_set = true;
  int const k = in.integer(0, int(max_normals));
  for (int i = 0; i < k; ++i) {
    int const how = in.byte() & 15;
    V n = unit(read_vec<V>(in, -1, 1, false));
    if (how == 0) n = V{};
    if (how == 1) {
      n = n * in.real(0.1f, 3);
      unit_set = false;
    }
    if (how == 2 && i > 0) n = ns[std::size_t(in.integer(0, i - 1))];
    if (how == 3 && i > 0) n = ns[std::size_t(in.integer(0, i - 1))] * -1.0f;
    if (how == 4 && i > 0) {
      V const d = read_vec<V>(in, -1e-3f, 1e-3f, false);
      n = unit(ns[std::size_t(in.integer(0, i - 1))] + d);
    }
    if (how == 5 && hostile) {
      n = read_vec<V>(in, -1, 1, true);
      unit_set = false;
    }
    ns.push_back(n);
  }
  return ns;
}

// ------------------------------------------------------------------------------ the checks

template <class V>
void check_projection(V const& v, std::vector<V> const& ns, bool unit_set,
                      GVelocityProjectionConfig<float> const& cfg) {
  std::vector<float> lambda(ns.size(), -1.0f);
  auto const r = project_velocity(v, std::span<V const>(ns), std::span<float>(lambda), cfg);
  auto const plain = project_velocity(v, std::span<V const>(ns), cfg);
  // Multipliers are bookkeeping only: the same answer without them.
  PLUME_FUZZ_CHECK(same_bits(r.velocity, plain.velocity) && r.steps == plain.steps &&
                   bool(r.converged) == bool(plain.converged) &&
                   bool(r.invalid_input) == bool(plain.invalid_input));

  bool const finite_input =
      finite_vec(v) && std::all_of(ns.begin(), ns.end(), [](V const& n) { return finite_vec(n); });
  bool const usable = usable_velocity(v) && std::all_of(ns.begin(), ns.end(), [](V const& n) {
                        return usable_normal(n);
                      });
  // (Lengths within a float rounding of the range ends may go either way.)
  bool const near_end = std::any_of(ns.begin(), ns.end(), [](V const& n) {
    if (is_zero(n) || !finite_vec(n)) return false;
    double l2 = double(n.x) * n.x + double(n.y) * n.y;
    if constexpr (dim<V> == 3) l2 += double(n.z) * n.z;
    return std::abs(l2 / 0x1p40 - 1) < 1e-6 || std::abs(l2 / 0x1p-40 - 1) < 1e-6;
  });
  if (!near_end) PLUME_FUZZ_CHECK(bool(r.invalid_input) == !usable);
  PLUME_FUZZ_CHECK(r.steps >= 0 && r.steps <= float(cfg.max_steps) &&
                   r.steps == std::floor(r.steps));
  bool const lambdas_zero =
      std::all_of(lambda.begin(), lambda.end(), [](float l) { return l == 0; });
  if (r.invalid_input || !r.converged) {
    PLUME_FUZZ_CHECK(is_zero(r.velocity));
    PLUME_FUZZ_CHECK(lambdas_zero);
    if (r.invalid_input) PLUME_FUZZ_CHECK(!r.converged);
    return;
  }
  PLUME_FUZZ_CHECK(finite_input);

  V const u = r.velocity;
  PLUME_FUZZ_CHECK(finite_vec(u));
  float const eps = cfg.epsilon;
  for (auto const& n : ns)
    PLUME_FUZZ_CHECK(!(n.dot(u) < -eps));
  double const vl = dlen(dbl(v)), ul = dlen(dbl(u));
  double const round = 1e-5 * vl + 1e-30;
  PLUME_FUZZ_CHECK(ul <= vl + double(eps) + round);
  // Optimality where squares of the velocity do not overflow float (|v| below about 1e19).
  bool const moderate = vl <= 1e18;
  if (unit_set && moderate) {
    double const star = exact_distance(v, ns);
    PLUME_FUZZ_CHECK(dlen(dsub(dbl(u), dbl(v))) <= star + double(eps) + round);
    if (vl < 0.999 * double(eps)) PLUME_FUZZ_CHECK(same_bits(u, v) && r.steps == 0);
  }

  // The brute force reference.
  auto const brute = project_velocity_bruteforce(v, std::span<V const>(ns), cfg);
  PLUME_FUZZ_CHECK(brute.converged && !brute.invalid_input);
  for (auto const& n : ns)
    PLUME_FUZZ_CHECK(!(n.dot(brute.velocity) < -eps));
  PLUME_FUZZ_CHECK(dlen(dbl(brute.velocity)) <= vl + double(eps) + round);
  if (unit_set && moderate)
    PLUME_FUZZ_CHECK(dlen(dsub(dbl(brute.velocity), dbl(v))) <=
                     exact_distance(v, ns) + double(eps) + round);

  // Multipliers (where they cannot overflow): >= 0, zero off the planes through u, and
  // u = v + sum lambda_i n_i.
  if (!moderate) return;
  std::array<double, 3> sum = dbl(v);
  double mass = vl;
  for (std::size_t i = 0; i < ns.size(); ++i) {
    float const l = lambda[i];
    PLUME_FUZZ_CHECK(std::isfinite(l) && l >= 0);
    std::array<double, 3> const n = dbl(ns[i]);
    sum = {sum[0] + double(l) * n[0], sum[1] + double(l) * n[1], sum[2] + double(l) * n[2]};
    mass += double(l) * dlen(n);
  }
  // Up to rounding, which grows as 1 / sin^2 of the angle between two planes that both push
  // (the multipliers of a crease come from its Gram determinant).
  double min_sin2 = 1;
  for (std::size_t i = 0; i < ns.size(); ++i)
    for (std::size_t j = i + 1; j < ns.size(); ++j) {
      if (!(lambda[i] > 0 && lambda[j] > 0)) continue;
      std::array<double, 3> const a = dbl(ns[i]), b = dbl(ns[j]);
      std::array<double, 3> const c{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                    a[0] * b[1] - a[1] * b[0]};
      min_sin2 = std::min(min_sin2, ddot(c, c) / (ddot(a, a) * ddot(b, b)));
    }
  double const tol = mass * (1e-4 + 1e-6 / std::max(min_sin2, 1e-30)) + 1e-6;
  PLUME_FUZZ_CHECK(dlen(dsub(sum, dbl(u))) <= tol);
  for (std::size_t i = 0; i < ns.size(); ++i)
    if (lambda[i] > 0) // on the plane: n . u = 0 (relative to |n|: normals may be scaled)
      PLUME_FUZZ_CHECK(std::abs(ddot(dbl(ns[i]), dbl(u))) <= tol * dlen(dbl(ns[i])));
}

/// Plane sets: the kept normals are unit, at most max_planes; a zero or non-finite normal is
/// rejected and leaves the set as it was. Returns the kept normals.
template <class V>
std::vector<V> collect(V const& v, std::vector<V> const& raw, std::size_t max_planes) {
  GPlaneSetConfig<float> pcfg;
  pcfg.max_planes = max_planes;
  GPlaneSet<V> set(v, pcfg);
  for (auto const& n : raw) {
    std::vector<V> const before(set.normals().begin(), set.normals().end());
    bool const kept = set.add(n);
    if (!finite_vec(n) || is_zero(n)) {
      PLUME_FUZZ_CHECK(!kept);
      std::vector<V> const after(set.normals().begin(), set.normals().end());
      PLUME_FUZZ_CHECK(after.size() == before.size());
      for (std::size_t i = 0; i < after.size(); ++i)
        PLUME_FUZZ_CHECK(same_bits(after[i], before[i]));
    }
  }
  PLUME_FUZZ_CHECK(set.normals().size() <= max_planes);
  PLUME_FUZZ_CHECK(set.count() == float(set.normals().size()));
  for (auto const& n : set.normals())
    PLUME_FUZZ_CHECK(std::abs(dlen(dbl(n)) - 1.0) <= 1e-5);
  return {set.normals().begin(), set.normals().end()};
}

/// Wide lanes equal scalar calls: lane l projects v scaled by factor[l] against the normals
/// with those of bit i of skip[l] set to zero (padding).
template <class V>
void check_lanes(Input& in, V const& v, std::vector<V> const& ns,
                 GVelocityProjectionConfig<float> const& cfg) {
  using WV = std::conditional_t<dim<V> == 3, GVec3<W>, GVec2<W>>;
  std::array<float, lanes> factor{};
  std::array<std::uint16_t, lanes> skip{};
  for (std::size_t l = 0; l < lanes; ++l) {
    factor[l] = l == 0 ? 1.0f : in.real(-2, 2);
    skip[l] = l == 0 ? 0 : in.bits<std::uint16_t>();
  }
  auto const lane_v = [&](std::size_t l) { return v * factor[l]; };
  auto const lane_n = [&](std::size_t l, std::size_t i) {
    return ((skip[l] >> i) & 1) ? V{} : ns[i];
  };
  auto const widen = [&](auto const& get) {
    std::array<float, lanes> xs{}, ys{}, zs{};
    for (std::size_t l = 0; l < lanes; ++l) {
      V const s = get(l);
      xs[l] = s.x;
      ys[l] = s.y;
      if constexpr (dim<V> == 3) zs[l] = s.z;
    }
    WV w;
    w.x = W::load_unaligned(xs.data());
    w.y = W::load_unaligned(ys.data());
    if constexpr (dim<V> == 3) w.z = W::load_unaligned(zs.data());
    return w;
  };
  WV const wv = widen(lane_v);
  std::vector<WV> wn;
  for (std::size_t i = 0; i < ns.size(); ++i)
    wn.push_back(widen([&](std::size_t l) { return lane_n(l, i); }));
  std::vector<W> wl(ns.size());
  auto const wide = project_velocity(wv, std::span<WV const>(wn), std::span<W>(wl), cfg);
  auto const as_float = [](mask_t<W> m) { return plume::select(m, W(1.0f), W(0.0f)); };
  for (std::size_t l = 0; l < lanes; ++l) {
    std::vector<V> sn;
    for (std::size_t i = 0; i < ns.size(); ++i)
      sn.push_back(lane_n(l, i));
    std::vector<float> sl(ns.size());
    auto const s = project_velocity(lane_v(l), std::span<V const>(sn), std::span<float>(sl), cfg);
    V got;
    got.x = plume::lane(wide.velocity.x, l);
    got.y = plume::lane(wide.velocity.y, l);
    if constexpr (dim<V> == 3) got.z = plume::lane(wide.velocity.z, l);
    PLUME_FUZZ_CHECK(same_bits(got, s.velocity));
    PLUME_FUZZ_CHECK(plume::lane(wide.steps, l) == s.steps);
    PLUME_FUZZ_CHECK((plume::lane(as_float(wide.converged), l) != 0) == bool(s.converged));
    PLUME_FUZZ_CHECK((plume::lane(as_float(wide.invalid_input), l) != 0) == bool(s.invalid_input));
    for (std::size_t i = 0; i < ns.size(); ++i)
      PLUME_FUZZ_CHECK(std::bit_cast<std::uint32_t>(plume::lane(wl[i], l)) ==
                       std::bit_cast<std::uint32_t>(sl[i]));
  }
}

/// project_velocities (the batch): problems made of v scaled and windows of ns, in offsets the
/// input may break; a well-formed batch gives each problem the single call's bits, a broken
/// one its documented error with nothing written.
template <class V>
void check_batch(Input& in, V const& v, std::vector<V> const& ns,
                 GVelocityProjectionConfig<float> const& cfg) {
  std::size_t const problems = std::size_t(in.integer(1, 20));
  std::vector<V> vs, normals;
  std::vector<std::uint32_t> offsets{0};
  for (std::size_t p = 0; p < problems; ++p) {
    vs.push_back(v * in.real(-2.0f, 2.0f));
    std::size_t const from = ns.empty() ? 0 : std::size_t(in.integer(0, int(ns.size())));
    std::size_t const count = std::size_t(in.integer(0, int(ns.size() - from)));
    normals.insert(normals.end(), ns.begin() + long(from), ns.begin() + long(from + count));
    offsets.push_back(std::uint32_t(normals.size()));
  }
  std::uint8_t const damage = in.byte();
  using E = ProjectVelocitiesError;
  std::size_t out_size = problems, lambda_size = normals.size();
  if ((damage & 7) == 1) out_size = problems - 1;                              // short output
  if ((damage & 7) == 2 && !normals.empty()) lambda_size = normals.size() - 1; // short lambda
  if ((damage & 7) == 3) // a raised offset: past the end, or decreasing after it, or harmless
    offsets[std::size_t(in.integer(0, int(problems)))] += std::uint32_t(in.integer(1, 3));
  if ((damage & 7) == 4) offsets.pop_back();
  // The documented rule, lengths first (an empty lambda_out asks for no multipliers).
  E want = E::none;
  if (out_size != problems || (lambda_size != 0 && lambda_size != normals.size()) ||
      offsets.size() != problems + 1)
    want = E::length_mismatch;
  else if (offsets.front() != 0 || offsets.back() != normals.size() ||
           !std::is_sorted(offsets.begin(), offsets.end()))
    want = E::bad_offsets;
  GVelocityProjection<V> sentinel;
  sentinel.steps = -1.0f;
  std::vector<GVelocityProjection<V>> out(out_size, sentinel);
  std::vector<float> lambda(lambda_size, -1.0f);
  E const got = project_velocities(std::span<V const>(vs), std::span<V const>(normals), offsets,
                                   std::span<GVelocityProjection<V>>(out), lambda, cfg);
  PLUME_FUZZ_CHECK(got == want);
  if (got != E::none) {
    for (auto const& o : out)
      PLUME_FUZZ_CHECK(o.steps == -1.0f);
    for (float l : lambda)
      PLUME_FUZZ_CHECK(l == -1.0f);
    return;
  }
  for (std::size_t p = 0; p < problems; ++p) {
    std::size_t const a = offsets[p], k = offsets[p + 1] - a;
    std::vector<float> sl(k);
    auto const s = project_velocity(vs[p], std::span<V const>(normals.data() + a, k),
                                    std::span<float>(sl), cfg);
    PLUME_FUZZ_CHECK(same_bits(out[p].velocity, s.velocity));
    PLUME_FUZZ_CHECK(out[p].steps == s.steps);
    PLUME_FUZZ_CHECK(bool(out[p].converged) == bool(s.converged));
    PLUME_FUZZ_CHECK(bool(out[p].invalid_input) == bool(s.invalid_input));
    for (std::size_t i = 0; i < k && !lambda.empty(); ++i)
      PLUME_FUZZ_CHECK(std::bit_cast<std::uint32_t>(lambda[a + i]) ==
                       std::bit_cast<std::uint32_t>(sl[i]));
  }
}

template <class V>
void run(Input& in) {
  bool const hostile = (in.byte() & 7) == 0;
  GVelocityProjectionConfig<float> cfg;
  std::uint8_t const opts = in.byte();
  if (opts & 1) cfg.epsilon = in.real(1e-4f, 0.1f);
  if (opts & 2) cfg.max_steps = in.integer(1, 12);
  V v = read_vec<V>(in, -10, 10, hostile);
  if (opts & 4) v = v * 1e-3f; // short: |v| < epsilon now and then
  bool unit_set = true;
  std::vector<V> ns = read_normals<V>(in, hostile, unit_set);
  if (opts & 8) {
    // Through a plane set: unit normals, merged, at most max_planes.
    ns = collect(v, ns, std::size_t(in.integer(1, int(max_normals))));
    unit_set = true;
  }
  check_projection(v, ns, unit_set, cfg);
  if (opts & 16) check_lanes(in, v, ns, cfg);
  if (opts & 32) check_batch(in, v, ns, cfg);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  Input in(data, size);
  if (in.flag())
    run<Vec3>(in);
  else
    run<Vec2>(in);
  return 0;
}
