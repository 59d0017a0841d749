// Element-type lists of this build, for TEMPLATE_LIST_TEST_CASE: every test runs for the
// scalar types and every width the build enables.
#pragma once

#include <plume/numerics.hpp>

#include <tuple>
#include <utility>

namespace plume::test {

using wide_real_types = std::tuple<
#if PLUME_HAS_BATCHES
    f32x4, f64x2
#endif
#if PLUME_HAS_AVX2
    ,
    f32x8, f64x4
#endif
#if PLUME_HAS_AVX512
    ,
    f32x16, f64x8
#endif
    >;

/// The scalar types and then every wide type.
using real_types = decltype(std::tuple_cat(std::declval<std::tuple<float, double>>(),
                                           std::declval<wide_real_types>()));

/// float and every f32 width of the build (kernels that are float-only, like the solver's).
using f32_types = std::tuple<float
#if PLUME_HAS_BATCHES
                             ,
                             f32x4
#endif
#if PLUME_HAS_AVX2
                             ,
                             f32x8
#endif
#if PLUME_HAS_AVX512
                             ,
                             f32x16
#endif
                             >;

using int_types = std::tuple<std::int32_t, std::uint32_t
#if PLUME_HAS_BATCHES
                             ,
                             i32x4, u32x4
#endif
#if PLUME_HAS_AVX2
                             ,
                             i32x8, u32x8
#endif
#if PLUME_HAS_AVX512
                             ,
                             i32x16, u32x16
#endif
                             >;

} // namespace plume::test
