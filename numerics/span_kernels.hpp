// numerics/span_kernels.hpp - the table of the span kernels that one instruction set provides
// (private to the numerics floor).
//
// span_kernels.cpp fills one table per instruction set it is compiled for; isa.cpp hands out
// the active one and spans.cpp calls through it. The function lists are X-macros so that the table,
// its filling and the public span functions come from one list.
#pragma once

#include <plume/numerics/isa.hpp>

#include <cstddef>

// X(name): one-argument functions, out[i] = name(x[i]).
#define PLUME_SPAN_UNARY_LIST(X)                                                                   \
  X(sin)                                                                                           \
  X(cos) X(tan) X(asin) X(acos) X(atan) X(exp) X(exp2) X(expm1) X(log) X(log2) X(log1p) X(sqrt)
// X(name): two-argument functions, out[i] = name(a[i], b[i]).
#define PLUME_SPAN_BINARY_LIST(X) X(atan2) X(pow) X(hypot)

namespace plume::detail {

template <class S>
using unary_fn = void (*)(S const* x, S* out, std::size_t n) noexcept;
template <class S>
using binary_fn = void (*)(S const* a, S const* b, S* out, std::size_t n) noexcept;
template <class S>
using sincos_fn = void (*)(S const* x, S* sin_out, S* cos_out, std::size_t n) noexcept;

/// One instruction set's span kernels. Every kernel takes n >= 0 elements at any alignment; the
/// caller has checked the lengths and the overlaps (spans.cpp).
struct SpanKernels {
  Isa isa;            // the set the kernels were compiled for (the widest their flags enable)
  unsigned f32_lanes; // lanes of the float batch the kernels run on
#define PLUME_TABLE_UNARY(name)                                                                    \
  unary_fn<float> name##_f32;                                                                      \
  unary_fn<double> name##_f64;
  PLUME_SPAN_UNARY_LIST(PLUME_TABLE_UNARY)
#undef PLUME_TABLE_UNARY
#define PLUME_TABLE_BINARY(name)                                                                   \
  binary_fn<float> name##_f32;                                                                     \
  binary_fn<double> name##_f64;
  PLUME_SPAN_BINARY_LIST(PLUME_TABLE_BINARY)
#undef PLUME_TABLE_BINARY
  sincos_fn<float> sincos_f32;
  sincos_fn<double> sincos_f64;
};

/// The active set's table (isa.cpp).
SpanKernels const& span_kernels() noexcept;

} // namespace plume::detail

// Each span_kernels.cpp object defines its table's accessor
// `extern "C" SpanKernels const* plume_numerics_table_<suffix>() noexcept` (suffix: the set's
// name, or static_build): in a PLUME_DISPATCH=ON build the one global symbol of its isolated
// object (cmake/PlumeDispatch.cmake).
