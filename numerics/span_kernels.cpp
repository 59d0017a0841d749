// solver/dispatch/kernels.cpp - the array kernels, compiled once per instruction set.
//
// A PLUME_DISPATCH=ON build compiles this file once for each instruction set of the list in
// cmake/PlumeDispatch.cmake, with that set's flags and PLUME_DISPATCH_ISA defined to its name;
// a static build compiles it once, with the build's flags. Each loop runs the widest batch the
// flags enable (plume's f32xN / f64xN) and finishes with one batch loaded from a copy of the
// tail padded with ones, so no scalar code path exists here: every element goes through the same
// template, and the lane-exactness contract makes that the scalar function's bits.
#include "span_kernels.hpp"

#include <plume/numerics.hpp>

#include <algorithm>
#include <cstring>

#ifndef PLUME_DISPATCH_ISA
#error "compile span_kernels.cpp with PLUME_DISPATCH_ISA set to the instruction set's name"
#endif
#define PLUME_CAT2(a, b) a##b
#define PLUME_CAT(a, b) PLUME_CAT2(a, b)

namespace plume::detail {
namespace {

template <class S>
using wide_t = std::conditional_t<std::is_same_v<S, float>, f32xN, f64xN>;

template <class W, class S>
PLUME_INLINE W load(S const* p) noexcept {
  if constexpr (is_batch_v<W>)
    return W::load_unaligned(p);
  else
    return *p;
}

template <class W, class S>
PLUME_INLINE void store(W const& w, S* p) noexcept {
  if constexpr (is_batch_v<W>)
    w.store_unaligned(p);
  else
    *p = w;
}

// out[i] = f(x[i]) over whole batches, then one padded batch for the tail. Loads come before
// the store of the same batch, so out == x (in place) is fine.
template <class S, class F>
void map1(S const* x, S* out, std::size_t n, F f) noexcept {
  using W = wide_t<S>;
  constexpr std::size_t L = lanes_v<W>;
  std::size_t i = 0;
  for (; i + L <= n; i += L)
    store(f(load<W>(x + i)), out + i);
  if (std::size_t const rest = n - i; rest != 0) {
    alignas(64) S in[L], res[L];
    std::fill(in, in + L, S(1)); // a harmless argument for every function (no FP flag raised)
    std::memcpy(in, x + i, rest * sizeof(S));
    store(f(load<W>(in)), res);
    std::memcpy(out + i, res, rest * sizeof(S));
  }
}

template <class S, class F>
void map2(S const* a, S const* b, S* out, std::size_t n, F f) noexcept {
  using W = wide_t<S>;
  constexpr std::size_t L = lanes_v<W>;
  std::size_t i = 0;
  for (; i + L <= n; i += L)
    store(f(load<W>(a + i), load<W>(b + i)), out + i);
  if (std::size_t const rest = n - i; rest != 0) {
    alignas(64) S in_a[L], in_b[L], res[L];
    std::fill(in_a, in_a + L, S(1));
    std::fill(in_b, in_b + L, S(1));
    std::memcpy(in_a, a + i, rest * sizeof(S));
    std::memcpy(in_b, b + i, rest * sizeof(S));
    store(f(load<W>(in_a), load<W>(in_b)), res);
    std::memcpy(out + i, res, rest * sizeof(S));
  }
}

template <class S>
void sincos_kernel(S const* x, S* sin_out, S* cos_out, std::size_t n) noexcept {
  using W = wide_t<S>;
  constexpr std::size_t L = lanes_v<W>;
  std::size_t i = 0;
  for (; i + L <= n; i += L) {
    auto const r = plume::sincos(load<W>(x + i));
    store(r.sin, sin_out + i);
    store(r.cos, cos_out + i);
  }
  if (std::size_t const rest = n - i; rest != 0) {
    alignas(64) S in[L], s[L], c[L];
    std::fill(in, in + L, S(1));
    std::memcpy(in, x + i, rest * sizeof(S));
    auto const r = plume::sincos(load<W>(in));
    store(r.sin, s);
    store(r.cos, c);
    std::memcpy(sin_out + i, s, rest * sizeof(S));
    std::memcpy(cos_out + i, c, rest * sizeof(S));
  }
}

#define PLUME_KERNEL_UNARY(name)                                                                   \
  template <class S>                                                                               \
  void name##_kernel(S const* x, S* out, std::size_t n) noexcept {                                 \
    map1(x, out, n, [](auto v) PLUME_INLINE_LAMBDA { return plume::name(v); });                    \
  }
PLUME_SPAN_UNARY_LIST(PLUME_KERNEL_UNARY)
#undef PLUME_KERNEL_UNARY
#define PLUME_KERNEL_BINARY(name)                                                                  \
  template <class S>                                                                               \
  void name##_kernel(S const* a, S const* b, S* out, std::size_t n) noexcept {                     \
    map2(a, b, out, n, [](auto u, auto v) PLUME_INLINE_LAMBDA { return plume::name(u, v); });      \
  }
PLUME_SPAN_BINARY_LIST(PLUME_KERNEL_BINARY)
#undef PLUME_KERNEL_BINARY

constexpr SpanKernels table = {
    PLUME_HAS_AVX512 ? Isa::avx512
    : PLUME_HAS_AVX2 ? Isa::avx2
    : PLUME_HAS_SSE2 ? Isa::sse2
                     : Isa::scalar,
    static_cast<unsigned>(lanes_v<f32xN>),
#define PLUME_FILL_UNARY(name) &name##_kernel<float>, &name##_kernel<double>,
    PLUME_SPAN_UNARY_LIST(PLUME_FILL_UNARY)
#undef PLUME_FILL_UNARY
#define PLUME_FILL_BINARY(name) &name##_kernel<float>, &name##_kernel<double>,
            PLUME_SPAN_BINARY_LIST(PLUME_FILL_BINARY)
#undef PLUME_FILL_BINARY
        & sincos_kernel<float>,
    &sincos_kernel<double>,
};

} // namespace
} // namespace plume::detail

extern "C" plume::detail::SpanKernels const* PLUME_CAT(plume_numerics_table_,
                                                       PLUME_DISPATCH_ISA)() noexcept {
  return &plume::detail::table;
}
