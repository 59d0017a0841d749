// plume/math/detail/clamp_length.hpp - clamp_length, clamp_length_max and clamp_length_min of
// GVec2, GVec3 and GVec4, written once over the vector type V.
//
// Each clamp computes |v| = sqrt(v . v) (the operations of v.length()) and scales v by
// (bound / |v|) where the bound is crossed: for a finite squared length these are the only
// operations, so the bits are those of that one formula. Where v . v overflows to +inf (a
// component beyond about 1e19 in float, 1e154 in double) the length is recomputed from
// u = v / m, m the largest |component| (|u| in [1, sqrt(dim)]): the true length is m |u| and
// the clamped vector u (bound / |u|). A vector with an infinite component is treated as the
// limit of huge ones: u is +-1 in the infinite components, +-0 in the others, its length +inf.
// NaN components make the squared length NaN: such a vector crosses no bound and comes back
// unchanged. Squared lengths below the smallest normal (|v| below about 1e-19 in float) are
// not rescaled: their length loses precision, and below about 2.6e-23 it reads as 0 (the
// clamps then return v unchanged, as they return zero).
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

/// v scaled to aim.target(|v|) where aim.scale(|v|, target), else v; aim is asked about the
/// length of ordinary lanes and again about the true length of the lanes whose squared length
/// overflows.
template <class V, class Aim>
PLUME_INLINE V clamp_length_to(V const& v, Aim const& aim) noexcept {
  using T = typename V::element_type;
  T const len2 = v.length_squared();
  mask_t<T> const huge = len2 >= infinity<T>(); // == inf, as one branch for scalars
  T const len = plume::sqrt(len2);
  T const target = aim.target(len);
  V r = V::select(aim.scale(len, target), v * (target / len), v);
  if (plume::any(huge)) [[unlikely]] {
    rescaled_length<V> const s = rescale_by_max(v);
    T const t = aim.target(s.length);
    r = V::select(huge, V::select(aim.scale(s.length, t), s.u * (t / s.u_length), v), r);
  }
  return r;
}

/// Length clamped to [lo, hi] (plume::clamp's rule on the length: NaN bounds give NaN, lo > hi
/// gives hi); zero stays zero.
template <class T>
struct length_between {
  T lo, hi;
  PLUME_INLINE T target(T len) const noexcept { return plume::clamp(len, lo, hi); }
  PLUME_INLINE mask_t<T> scale(T len, T to) const noexcept {
    return (len != to) & (len > zero<T>());
  }
};
/// Length at most hi; NaN hi gives v.
template <class T>
struct length_at_most {
  T hi;
  PLUME_INLINE T target(T) const noexcept { return hi; }
  PLUME_INLINE mask_t<T> scale(T len, T) const noexcept { return len > hi; }
};
/// Length at least lo; zero stays zero; NaN lo gives v.
template <class T>
struct length_at_least {
  T lo;
  PLUME_INLINE T target(T) const noexcept { return lo; }
  PLUME_INLINE mask_t<T> scale(T len, T) const noexcept { return (len < lo) & (len > zero<T>()); }
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
