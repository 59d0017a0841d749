// plume/math/detail/clamp_length.hpp - clamp_length, clamp_length_max and clamp_length_min of
// GVec2, GVec3 and GVec4, written once over the vector type V.
//
// Each clamp computes |v| = sqrt(v . v) (the same operations as v.length()) and scales v by (bound
// / |v|) where the bound is crossed: for a finite squared length these are the only operations, so
// the bits are those of that one formula. Where v . v overflows to +inf (a component beyond about
// 1e19 in float, 1e154 in double) the length is recomputed from u = v / m, m the largest
// |component|
// (|u| in [1, sqrt(dim)]): the true length is m |u| and the clamped vector u (bound / |u|).
// A vector with an infinite component is treated as the limit of huge ones: u is +-1 in the
// infinite components, +-0 in the others, and its length is +inf. NaN components make the
// squared length NaN: such a vector crosses no bound and is returned unchanged.
// Why: a velocity of 1e20 clamped to a maximum speed must come back at that speed, not zero.
//
// Cost: the overflow test is one compare and a branch that ordinary input never takes; the
// rescaled form runs (for every lane of a wide vector) only when some lane needs it, and
// select() keeps the other lanes' bits, so lane i is the scalar call on lane i.
#pragma once

#include <plume/numerics.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume::detail {

/// v = u m with |u| in [1, sqrt(dim)], for lanes whose squared length overflows: the rescaled
/// direction u, its length and the length of v (m |u|, +inf for an infinite component).
template <class V>
struct rescaled_length {
  V u;
  typename V::element_type u_length;
  typename V::element_type length;
};

template <class V>
PLUME_INLINE rescaled_length<V> rescale_by_max(V const& v) noexcept {
  using T = typename V::element_type;
  V const a = v.abs();
  T const m = a.max_element();
  V const inf = V::splat(infinity<T>());
  V const at_inf = V::select(a.cmpeq(inf), V::splat(one<T>()), V{}).copysign(v);
  V const u = V::select(m == infinity<T>(), at_inf, v / m);
  T const lu = u.length();
  return {u, lu, m * lu};
}

/// What a clamp asks of a length: the length to scale to, and whether to scale at all.
template <class T>
struct length_target {
  T target;
  mask_t<T> scale;
};

/// v scaled to aim(|v|).target where aim(|v|).scale, else v; aim is called on the length of
/// ordinary lanes and again on the true length of the lanes whose squared length overflows.
template <class V, class Aim>
PLUME_INLINE V clamp_length_to(V const& v, Aim aim) noexcept {
  using T = typename V::element_type;
  T const len2 = v.length_squared();
  mask_t<T> const huge = len2 == infinity<T>();
  T const len = plume::sqrt(len2);
  length_target<T> const a = aim(len);
  V r = V::select(a.scale, v * (a.target / len), v);
  if (plume::any(huge)) [[unlikely]] {
    rescaled_length<V> const s = rescale_by_max(v);
    length_target<T> const b = aim(s.length);
    r = V::select(huge, V::select(b.scale, s.u * (b.target / s.u_length), v), r);
  }
  return r;
}

/// Length clamped to [lo, hi] (plume::clamp's rule on the length: NaN bounds give NaN, lo > hi
/// gives hi); zero stays zero.
template <class T>
struct length_between {
  T lo, hi;
  PLUME_INLINE length_target<T> operator()(T len) const noexcept {
    T const target = plume::clamp(len, lo, hi);
    mask_t<T> const change = (len != target) & (len > zero<T>());
    return {target, change};
  }
};
/// Length at most hi; NaN hi gives v.
template <class T>
struct length_at_most {
  T hi;
  PLUME_INLINE length_target<T> operator()(T len) const noexcept {
    mask_t<T> const longer = len > hi;
    return {hi, longer};
  }
};
/// Length at least lo; zero stays zero; NaN lo gives v.
template <class T>
struct length_at_least {
  T lo;
  PLUME_INLINE length_target<T> operator()(T len) const noexcept {
    mask_t<T> const shorter = (len < lo) & (len > zero<T>());
    return {lo, shorter};
  }
};

template <class V, class T>
PLUME_INLINE V clamp_length(V const& v, T lo, T hi) noexcept {
  return clamp_length_to(v, length_between<T>{lo, hi});
}
template <class V, class T>
PLUME_INLINE V clamp_length_max(V const& v, T hi) noexcept {
  return clamp_length_to(v, length_at_most<T>{hi});
}
template <class V, class T>
PLUME_INLINE V clamp_length_min(V const& v, T lo) noexcept {
  return clamp_length_to(v, length_at_least<T>{lo});
}

} // namespace plume::detail

PLUME_MASK_CODE_END
