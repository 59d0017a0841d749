// plume/solver/character/depenetration.hpp - the translation that pushes a shape out of the planes
// it penetrates (Gauss–Seidel over (normal, depth) pairs), the first and last step of
// move-and-slide.
//
//   depenetrate(span<GPenetration<GVec3<T>> const>, cfg) -> GDepenetration<GVec3<T>>
//   (and the same for GVec2<T>; Penetration3/2 and Depenetration3/2 for float)
//
// Each pair asks for fix . n_i >= d_i: n_i the push-out direction (unit, out of the
// obstacle), d_i the depth plus skin (length units). One pass visits the pairs in order:
//     e = max(0, d_i - fix . n_i);   fix += e n_i;   total += e.
// The lane has converged after the first pass with total < cfg.max_error; at most
// cfg.iterations passes (default 16). The result is the best-effort fix either way, a
// translation in the normals' frame. Why Gauss–Seidel: a pass is O(k) with no system to
// solve, and a pass cut short still leaves a usable (partial) fix.
//
// Bad input, per lane (other lanes unaffected):
//  - Pairs with d_i > cfg.rejection_threshold (default 0.5 length units) are ignored: such a
//    deep contact is more likely a bad manifold than something to push out of in one step.
//  - Pairs with a non-finite normal or depth, or a zero normal, are ignored (zero pairs are
//    the padding of wide inputs). Normals are used as given: make them unit length.
//  - Exactly opposing planes cannot both be satisfied: fix stays bounded (it alternates) and
//    converged is false.
#pragma once

#include <plume/math/vec2.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

#include <ranges>
#include <span>
#include <type_traits>

PLUME_MASK_CODE_BEGIN

namespace plume {

/// Iterations and tolerances of depenetrate().
template <ScalarReal S>
struct GDepenetrationConfig {
  int iterations = 16;            ///< Gauss–Seidel passes at most
  S max_error = S(1e-4);          ///< converged when one pass moves less than this in total
  S rejection_threshold = S(0.5); ///< deeper pairs are ignored (length units)

  /// This configuration with every length-valued field (max_error, rejection_threshold)
  /// multiplied by length_unit, e.g. `DepenetrationConfig{}.scaled(100)` for centimetres.
  constexpr GDepenetrationConfig scaled(S length_unit) const noexcept {
    GDepenetrationConfig c = *this;
    c.max_error = c.max_error * length_unit;
    c.rejection_threshold = c.rejection_threshold * length_unit;
    return c;
  }
};
using DepenetrationConfig = GDepenetrationConfig<float>;
using DDepenetrationConfig = GDepenetrationConfig<double>;

/// One penetrated plane: push-out direction and depth (+ skin).
template <class Vec>
struct GPenetration {
  using vec_type = Vec;
  Vec normal;
  typename Vec::element_type depth;
};
using Penetration3 = GPenetration<GVec3<float>>;
using Penetration2 = GPenetration<GVec2<float>>;

/// Result of depenetrate().
template <class Vec>
struct GDepenetration {
  using T = typename Vec::element_type;
  Vec correction;      ///< the translation to apply
  mask_t<T> converged; ///< total push of the last pass below max_error
  T passes;            ///< passes run, the converging one included (a small whole number)
};
using Depenetration3 = GDepenetration<GVec3<float>>;
using Depenetration2 = GDepenetration<GVec2<float>>;

/// Gauss–Seidel push-out over `pairs` (see the file comment).
template <class Vec>
GDepenetration<Vec>
depenetrate(std::span<GPenetration<Vec> const> pairs,
            GDepenetrationConfig<scalar_t<typename Vec::element_type>> const& cfg = {}) {
  using T = typename Vec::element_type;
  using M = mask_t<T>;
  T const zero = plume::zero<T>();
  T const max_error = splat<T>(cfg.max_error);
  T const reject = splat<T>(cfg.rejection_threshold);
  Vec fix{};
  T passes = zero;
  M running = all_lanes<T>();
  M converged = no_lanes<T>();
  for (int it = 0; it < cfg.iterations && plume::any(running); ++it) {
    T total = zero;
    for (auto const& p : pairs) {
      // Usable: finite depth within the threshold, finite nonzero normal.
      T const nn = p.normal.dot(p.normal);
      M const usable = (p.depth <= reject) & (nn > zero) & (nn < infinity<T>());
      T const need = p.depth - fix.dot(p.normal);
      M const push = running & usable & (need > zero);
      fix = Vec::select(push, fix + p.normal * need, fix);
      total = total + plume::select(push, need, zero);
    }
    passes = plume::select(running, passes + one<T>(), passes);
    M const done = running & (total < max_error);
    converged = converged | done;
    running = running & !done;
  }
  return {fix, converged, passes};
}

/// depenetrate for any contiguous range of pairs (std::vector, std::array, C array).
template <std::ranges::contiguous_range R>
requires requires { typename std::ranges::range_value_t<R>::vec_type; }
auto depenetrate(
    R const& pairs,
    GDepenetrationConfig<
        scalar_t<typename std::ranges::range_value_t<R>::vec_type::element_type>> const& cfg = {}) {
  using Vec = typename std::ranges::range_value_t<R>::vec_type;
  return plume::depenetrate<Vec>(
      std::span<GPenetration<Vec> const>(std::ranges::data(pairs), std::ranges::size(pairs)), cfg);
}

} // namespace plume

PLUME_MASK_CODE_END
