// plume/numerics/wide.hpp - names of the wide element types.
//
//   f32x4 f64x2 i32x4 u32x4          with SSE2 (every build but scalar)
//   f32x8 f64x4 i32x8 u32x8          with AVX2
//   f32x16 f64x8 i32x16 u32x16       with AVX-512
//   f32xN f64xN i32xN                the widest the build enables (float/double/int32_t
//                                    in a scalar build), for code that just wants "wide"
// A width the build does not enable is simply not declared; PLUME_HAS_* in
// plume/config.hpp says which are.
#pragma once

#include <plume/numerics/traits.hpp>

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

#if PLUME_HAS_AVX512
using f32xN = f32x16;
using f64xN = f64x8;
using i32xN = i32x16;
#elif PLUME_HAS_AVX2
using f32xN = f32x8;
using f64xN = f64x4;
using i32xN = i32x8;
#elif PLUME_HAS_BATCHES
using f32xN = f32x4;
using f64xN = f64x2;
using i32xN = i32x4;
#else
using f32xN = float;
using f64xN = double;
using i32xN = std::int32_t;
#endif
} // namespace plume
