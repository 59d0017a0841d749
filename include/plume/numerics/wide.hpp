// plume/numerics/wide.hpp - names of the wide element types.
//
//   f32x4 f64x2 i32x4 u32x4          with SSE2 (every build but scalar)
//   f32x8 f64x4 i32x8 u32x8          with AVX2
//   f32x16 f64x8 i32x16 u32x16       with AVX-512
//   f32xN f64xN i32xN                the widest the build enables (float/double/int32_t
//                                    in a scalar build), for code that just wants "wide"
//   f32xS                            the element type of stored structures (f32xN, or the
//                                    baseline's in a PLUME_DISPATCH=ON build)
//   stored_lanes, f32xR              the lanes of stored structures' nodes and blocks, and
//                                    the batch kernels read them with (below)
// A width the build does not enable is simply not declared.
//
// The one list of the widths a build has, for code that instantiates or registers something
// per width (tests, benchmarks, explicit instantiations):
//   f32_widths f64_widths i32_widths u32_widths   type_list<...> of the wide types, narrowest
//                                    first (empty in a scalar build)
//   f32_types f64_types              the scalar type, then every width of it
//   for_each_type<List>(f)           f.template operator()<T>() for each T, in list order
//   PLUME_FOR_EACH_F32_TYPE(X)       X(T, lanes) for float and every f32 width, for what
//                                    only a macro can repeat (explicit instantiations)
#pragma once

#include <plume/numerics/traits.hpp>

#include <cstddef>

namespace plume {
#if PLUME_HAS_BATCHES
using f32x4 = xsimd::batch<float, arch_128>;
using f64x2 = xsimd::batch<double, arch_128>;
using i32x4 = xsimd::batch<std::int32_t, arch_128>;
using u32x4 = xsimd::batch<std::uint32_t, arch_128>;
#endif
#if PLUME_HAS_AVX2
using f32x8 = xsimd::batch<float, arch_256>;
using f64x4 = xsimd::batch<double, arch_256>;
using i32x8 = xsimd::batch<std::int32_t, arch_256>;
using u32x8 = xsimd::batch<std::uint32_t, arch_256>;
#endif
#if PLUME_HAS_AVX512
using f32x16 = xsimd::batch<float, arch_512>;
using f64x8 = xsimd::batch<double, arch_512>;
using i32x16 = xsimd::batch<std::int32_t, arch_512>;
using u32x16 = xsimd::batch<std::uint32_t, arch_512>;
#endif

/// A list of types. Catch2's TEMPLATE_LIST_TEST_CASE takes it as it is.
template <class... Ts>
struct type_list {
  static constexpr std::size_t size = sizeof...(Ts);
};

#if PLUME_HAS_AVX512
using f32xN = f32x16;
using f64xN = f64x8;
using i32xN = i32x16;
using f32_widths = type_list<f32x4, f32x8, f32x16>;
using f64_widths = type_list<f64x2, f64x4, f64x8>;
using i32_widths = type_list<i32x4, i32x8, i32x16>;
using u32_widths = type_list<u32x4, u32x8, u32x16>;
#define PLUME_FOR_EACH_F32_TYPE(X) X(float, 1) X(f32x4, 4) X(f32x8, 8) X(f32x16, 16)
#elif PLUME_HAS_AVX2
using f32xN = f32x8;
using f64xN = f64x4;
using i32xN = i32x8;
using f32_widths = type_list<f32x4, f32x8>;
using f64_widths = type_list<f64x2, f64x4>;
using i32_widths = type_list<i32x4, i32x8>;
using u32_widths = type_list<u32x4, u32x8>;
#define PLUME_FOR_EACH_F32_TYPE(X) X(float, 1) X(f32x4, 4) X(f32x8, 8)
#elif PLUME_HAS_BATCHES
using f32xN = f32x4;
using f64xN = f64x2;
using i32xN = i32x4;
using f32_widths = type_list<f32x4>;
using f64_widths = type_list<f64x2>;
using i32_widths = type_list<i32x4>;
using u32_widths = type_list<u32x4>;
#define PLUME_FOR_EACH_F32_TYPE(X) X(float, 1) X(f32x4, 4)
#else
using f32xN = float;
using f64xN = double;
using i32xN = std::int32_t;
using f32_widths = type_list<>;
using f64_widths = type_list<>;
using i32_widths = type_list<>;
using u32_widths = type_list<>;
#define PLUME_FOR_EACH_F32_TYPE(X) X(float, 1)
#endif

/// The element type of the data structures that outlive a call and are read by kernels: a
/// mesh's trees and triangle blocks, the broad phase's wide copy of the static tree (the
/// WideBvh alias). f32xN in any build but PLUME_DISPATCH=ON; there, whatever the translation
/// unit's own flags, the sse2 baseline's batch, so that such a structure is one type in every
/// instruction set's code (its layout is stored_lanes', below).
#if defined(PLUME_DISPATCH) && PLUME_DISPATCH
using f32xS = xsimd::batch<float, xsimd::sse2>;
#else
using f32xS = f32xN;
#endif

/// The lanes of those structures' nodes and blocks (a WideBvh's children per node, a
/// multiple of a mesh's triangles per block): lanes_v<f32xN> in any build but
/// PLUME_DISPATCH=ON, there 8 in every instruction set's code. Their layout depends on these
/// counts only, not on the batch type (GWideBvh stores each child coordinate in an array of
/// its arity), so any batch whose lanes divide them reads them in whole batches.
/// f32xR is the one kernels read them with: f32xN, or in a PLUME_DISPATCH=ON build the
/// widest batch of the translation unit's own set whose lanes divide 8 (f32x4 in the sse2
/// baseline, f32x8 in the avx2 and avx512 kernels). So each set walks geometry built once at
/// its own width, as wide as the static build of that set but for avx512 (8 lanes, not 16).
#if defined(PLUME_DISPATCH) && PLUME_DISPATCH
inline constexpr std::size_t stored_lanes = 8;
#if PLUME_HAS_AVX2
using f32xR = f32x8;
#else
using f32xR = f32xN;
#endif
#else
inline constexpr std::size_t stored_lanes = lanes_v<f32xN>;
using f32xR = f32xN;
#endif
static_assert(stored_lanes % lanes_v<f32xR> == 0 && stored_lanes % lanes_v<f32xS> == 0);

namespace detail {
template <class... Ls>
struct type_list_cat;
template <class... As>
struct type_list_cat<type_list<As...>> {
  using type = type_list<As...>;
};
template <class... As, class... Bs, class... Rest>
struct type_list_cat<type_list<As...>, type_list<Bs...>, Rest...>
    : type_list_cat<type_list<As..., Bs...>, Rest...> {};
template <class... Ts, class F>
constexpr void for_each_type(type_list<Ts...>, F&& f) {
  (f.template operator()<Ts>(), ...);
}
} // namespace detail

/// The lists concatenated, in order.
template <class... Ls>
using type_list_cat_t = typename detail::type_list_cat<Ls...>::type;

/// float, then every f32 width of the build: what a float-only kernel instantiates for.
using f32_types = type_list_cat_t<type_list<float>, f32_widths>;
/// double, then every f64 width of the build.
using f64_types = type_list_cat_t<type_list<double>, f64_widths>;

/// Calls f.template operator()<T>() for each T of List, in the list's order.
template <class List, class F>
constexpr void for_each_type(F&& f) {
  detail::for_each_type(List{}, f);
}
} // namespace plume
