// Element-type lists of this build, for TEMPLATE_LIST_TEST_CASE: every test runs for the
// scalar types and every width the build enables (the lists come from plume/numerics/wide.hpp).
#pragma once

#include <plume/numerics.hpp>

namespace plume::test {

#if PLUME_TEST_WIDEST_ONLY
// The sanitizer build (tests/CMakeLists.txt) looks for memory errors and undefined
// behaviour, not for lane-exactness: the widest type of each element is enough there, and the
// narrower widths are built and tested, optimised, by the sse2 and avx2 variants.
using wide_real_types = type_list_cat_t<type_list<f32xN>, type_list<f64xN>>;
using f32_types = type_list<float, f32xN>;
#else
/// Every wide real type of the build: the f32 widths, then the f64 widths.
using wide_real_types = type_list_cat_t<f32_widths, f64_widths>;

/// float and every f32 width of the build (kernels that are float-only, like the solver's).
using f32_types = plume::f32_types;
#endif

/// The scalar types and then every wide type.
using real_types = type_list_cat_t<type_list<float, double>, wide_real_types>;

using int_types = type_list_cat_t<type_list<std::int32_t, std::uint32_t>, i32_widths, u32_widths>;

} // namespace plume::test

/// TEMPLATE_LIST_TEST_CASE over a list of wide types only (test::wide_real_types, f32_widths):
/// a scalar build has none, and Catch2 expands an empty list into a zero-size array (an error
/// under -Wpedantic), so there the test body compiles as a template that is never
/// instantiated and nothing is registered.
#if PLUME_HAS_BATCHES
#define PLUME_WIDE_TEST_CASE(name, tags, list) TEMPLATE_LIST_TEST_CASE(name, tags, list)
#else
#define PLUME_WIDE_TEST_CASE_NAME2(line) plume_no_wide_types_##line
#define PLUME_WIDE_TEST_CASE_NAME(line) PLUME_WIDE_TEST_CASE_NAME2(line)
#define PLUME_WIDE_TEST_CASE(name, tags, list)                                                     \
  template <class TestType>                                                                        \
  [[maybe_unused]] static void PLUME_WIDE_TEST_CASE_NAME(__LINE__)()
#endif
