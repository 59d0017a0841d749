// Element-type lists of this build, for TEMPLATE_LIST_TEST_CASE (the widths come from
// plume/numerics/wide.hpp):
//   real_types       the scalar types, then the wide ones
//   wide_real_types  the wide f32 types, then the wide f64 types
//   f32_types, f64_types   float-only (the solver's) or double-only kernels: scalar, then wide
//   f32_wide_types   the f32 widths that whole-world tests step against the float world
//   int_types        the integer types
#pragma once

#include <plume/numerics.hpp>

namespace plume::test {

// Which element types the tests instantiate, set by PLUME_TEST_TYPES (tests/CMakeLists.txt):
//   all      float, double and every width of the build (the default);
//   widest   float, double and the widest width of each element (the sanitizer build: it
//            looks for memory errors, not for widths);
//   native   only the build's own widest width (the CI's sse2, avx2, avx512 and clang builds: each
//            width is tested, optimised, in the build whose width it is, the scalar types in
//            the scalar build; the golden battery still runs every width of every build, and
//            each wide test compares its lanes with the scalar path of the same build).
// A scalar build tests float and double whichever is set.
#define PLUME_TEST_TYPES_ALL 0
#define PLUME_TEST_TYPES_WIDEST 1
#define PLUME_TEST_TYPES_NATIVE 2
#ifndef PLUME_TEST_TYPES
#define PLUME_TEST_TYPES PLUME_TEST_TYPES_ALL
#endif

/// 1 in unoptimised builds (the -O0 sanitizer build): long random sequences and big scenes
/// shrink there, as they would take most of the CI's time.
#ifdef __OPTIMIZE__
#define PLUME_TEST_UNOPTIMISED 0
#else
#define PLUME_TEST_UNOPTIMISED 1
#endif

#if PLUME_TEST_TYPES == PLUME_TEST_TYPES_ALL || !PLUME_HAS_BATCHES
using wide_real_types = type_list_cat_t<f32_widths, f64_widths>;
#else
using wide_real_types = type_list<f32xN, f64xN>;
#endif

#if PLUME_TEST_TYPES == PLUME_TEST_TYPES_ALL || !PLUME_HAS_BATCHES
using f32_wide_types = f32_widths;
#else
using f32_wide_types = type_list<f32xN>;
#endif

#if PLUME_TEST_TYPES == PLUME_TEST_TYPES_NATIVE && PLUME_HAS_BATCHES
using real_types = wide_real_types;
using f32_types = type_list<f32xN>;
using f64_types = type_list<f64xN>;
using int_types = type_list<i32xN, rebind_t<f32xN, std::uint32_t>>;
#elif PLUME_TEST_TYPES == PLUME_TEST_TYPES_WIDEST && PLUME_HAS_BATCHES
using real_types = type_list_cat_t<type_list<float, double>, wide_real_types>;
using f32_types = type_list<float, f32xN>;
using f64_types = type_list<double, f64xN>;
using int_types = type_list<std::int32_t, std::uint32_t, i32xN, rebind_t<f32xN, std::uint32_t>>;
#else
using real_types = type_list_cat_t<type_list<float, double>, wide_real_types>;
using f32_types = plume::f32_types;
using f64_types = plume::f64_types;
using int_types = type_list_cat_t<type_list<std::int32_t, std::uint32_t>, i32_widths, u32_widths>;
#endif

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
