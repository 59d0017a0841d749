// numerics/spans.cpp - the math functions over spans (include/plume/numerics/spans.hpp): the
// checks, then one call of the active set's kernel (span_kernels.cpp, isa.cpp).
#include "span_kernels.hpp"

#include <plume/numerics/spans.hpp>

#include <cstdint>
#include <type_traits>

namespace plume {

namespace {
detail::SpanKernels const& kernels() noexcept { return detail::span_kernels(); }
} // namespace

// ------------------------------------------------------------------------ the span calls
std::string_view to_string(SpanError e) noexcept {
  switch (e) {
  case SpanError::none:
    return "none";
  case SpanError::length_mismatch:
    return "span function: the spans differ in length";
  case SpanError::overlap:
    return "span function: an output overlaps an input or another output in part";
  }
  return "span function: unknown error";
}

namespace {

// True if the n-element ranges at p and q overlap without being the same range. Compared as
// addresses: ordering pointers into different arrays is not defined in C++.
template <class S>
bool overlaps_in_part(S const* p, S const* q, std::size_t n) noexcept {
  auto const a = reinterpret_cast<std::uintptr_t>(p), b = reinterpret_cast<std::uintptr_t>(q);
  std::uintptr_t const bytes = n * sizeof(S);
  return a != b && a < b + bytes && b < a + bytes;
}

template <class S>
SpanError check(std::span<S const> x, std::span<S> out) noexcept {
  if (x.size() != out.size()) return SpanError::length_mismatch;
  if (overlaps_in_part(x.data(), out.data(), x.size())) return SpanError::overlap;
  return SpanError::none;
}

template <class S>
SpanError check(std::span<S const> a, std::span<S const> b, std::span<S> out) noexcept {
  if (a.size() != b.size() || a.size() != out.size()) return SpanError::length_mismatch;
  if (overlaps_in_part(a.data(), out.data(), a.size()) ||
      overlaps_in_part(b.data(), out.data(), a.size()))
    return SpanError::overlap;
  return SpanError::none;
}

} // namespace

#define PLUME_DEFINE_SPAN_UNARY(name)                                                              \
  SpanError name(std::span<float const> x, std::span<float> out) noexcept {                        \
    SpanError const e = check(x, out);                                                             \
    if (e == SpanError::none && !x.empty()) kernels().name##_f32(x.data(), out.data(), x.size());  \
    return e;                                                                                      \
  }                                                                                                \
  SpanError name(std::span<double const> x, std::span<double> out) noexcept {                      \
    SpanError const e = check(x, out);                                                             \
    if (e == SpanError::none && !x.empty()) kernels().name##_f64(x.data(), out.data(), x.size());  \
    return e;                                                                                      \
  }
PLUME_SPAN_UNARY_LIST(PLUME_DEFINE_SPAN_UNARY)
#undef PLUME_DEFINE_SPAN_UNARY

#define PLUME_DEFINE_SPAN_BINARY(name)                                                             \
  SpanError name(std::span<float const> a, std::span<float const> b,                               \
                 std::span<float> out) noexcept {                                                  \
    SpanError const e = check(a, b, out);                                                          \
    if (e == SpanError::none && !a.empty())                                                        \
      kernels().name##_f32(a.data(), b.data(), out.data(), a.size());                              \
    return e;                                                                                      \
  }                                                                                                \
  SpanError name(std::span<double const> a, std::span<double const> b,                             \
                 std::span<double> out) noexcept {                                                 \
    SpanError const e = check(a, b, out);                                                          \
    if (e == SpanError::none && !a.empty())                                                        \
      kernels().name##_f64(a.data(), b.data(), out.data(), a.size());                              \
    return e;                                                                                      \
  }
PLUME_SPAN_BINARY_LIST(PLUME_DEFINE_SPAN_BINARY)
#undef PLUME_DEFINE_SPAN_BINARY

namespace {
template <class S>
SpanError sincos_impl(std::span<S const> x, std::span<S> s, std::span<S> c) noexcept {
  if (x.size() != s.size() || x.size() != c.size()) return SpanError::length_mismatch;
  if (overlaps_in_part(x.data(), s.data(), x.size()) ||
      overlaps_in_part(x.data(), c.data(), x.size()) ||
      (!x.empty() && (overlaps_in_part(s.data(), c.data(), x.size()) || s.data() == c.data())))
    return SpanError::overlap;
  if (x.empty()) return SpanError::none;
  if constexpr (std::is_same_v<S, float>)
    kernels().sincos_f32(x.data(), s.data(), c.data(), x.size());
  else
    kernels().sincos_f64(x.data(), s.data(), c.data(), x.size());
  return SpanError::none;
}
} // namespace

SpanError sincos(std::span<float const> x, std::span<float> s, std::span<float> c) noexcept {
  return sincos_impl(x, s, c);
}
SpanError sincos(std::span<double const> x, std::span<double> s, std::span<double> c) noexcept {
  return sincos_impl(x, s, c);
}

} // namespace plume
