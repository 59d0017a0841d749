// plume/numerics/spans.hpp - the math functions over arrays, on the kernels of the chosen
// instruction set (<plume/numerics/isa.hpp>: in a PLUME_DISPATCH=ON build the widest this CPU
// runs, in any other the build's own).
//
//   SpanError e = plume::sin(x, out);          // out[i] = sin(x[i]),  float or double
//   e = plume::pow(base, exponent, out);       // out[i] = pow(base[i], exponent[i])
//   e = plume::sincos(x, sines, cosines);
//
// Each element gets exactly the bits of the scalar plume::<name>(x[i]) (the lane-exactness
// contract), whatever the instruction set, the length or the alignment: the functions, their
// accuracy and their special values are those of <plume/numerics.hpp>.
//
// Any length and alignment. Every span of one call has the same length, else length_mismatch
// and nothing is written. An output may be one of the inputs exactly (in place); an output
// that overlaps an input (or the other output) only in part is refused with `overlap`,
// nothing written. Empty spans: nothing to do, none.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace plume {

enum class SpanError : std::uint8_t {
  none,
  length_mismatch, ///< the spans of the call differ in length
  overlap,         ///< an output overlaps an input or another output, and is not the same span
};
std::string_view to_string(SpanError e) noexcept;

// out[i] = f(x[i]).
#define PLUME_DECLARE_SPAN_UNARY(name)                                                             \
  [[nodiscard]] SpanError name(std::span<float const> x, std::span<float> out) noexcept;           \
  [[nodiscard]] SpanError name(std::span<double const> x, std::span<double> out) noexcept;
PLUME_DECLARE_SPAN_UNARY(sin)
PLUME_DECLARE_SPAN_UNARY(cos)
PLUME_DECLARE_SPAN_UNARY(tan)
PLUME_DECLARE_SPAN_UNARY(asin)
PLUME_DECLARE_SPAN_UNARY(acos)
PLUME_DECLARE_SPAN_UNARY(atan)
PLUME_DECLARE_SPAN_UNARY(exp)
PLUME_DECLARE_SPAN_UNARY(exp2)
PLUME_DECLARE_SPAN_UNARY(expm1)
PLUME_DECLARE_SPAN_UNARY(log)
PLUME_DECLARE_SPAN_UNARY(log2)
PLUME_DECLARE_SPAN_UNARY(log1p)
PLUME_DECLARE_SPAN_UNARY(sqrt)
#undef PLUME_DECLARE_SPAN_UNARY

// out[i] = f(a[i], b[i]): atan2(y, x), pow(base, exponent), hypot(x, y).
#define PLUME_DECLARE_SPAN_BINARY(name)                                                            \
  [[nodiscard]] SpanError name(std::span<float const> a, std::span<float const> b,                 \
                               std::span<float> out) noexcept;                                     \
  [[nodiscard]] SpanError name(std::span<double const> a, std::span<double const> b,               \
                               std::span<double> out) noexcept;
PLUME_DECLARE_SPAN_BINARY(atan2)
PLUME_DECLARE_SPAN_BINARY(pow)
PLUME_DECLARE_SPAN_BINARY(hypot)
#undef PLUME_DECLARE_SPAN_BINARY

// sin_out[i] = sin(x[i]), cos_out[i] = cos(x[i]).
[[nodiscard]] SpanError sincos(std::span<float const> x, std::span<float> sin_out,
                               std::span<float> cos_out) noexcept;
[[nodiscard]] SpanError sincos(std::span<double const> x, std::span<double> sin_out,
                               std::span<double> cos_out) noexcept;

} // namespace plume
