// tests/fuzz/fuzz_input.hpp - what every fuzz target shares: a reader that turns the
// fuzzer's bytes into values, and a check that aborts (so libFuzzer and the regression
// runner report the input) with a message naming the broken property.
//
// The reader never fails: past the end of the data it yields zeros, so every byte string is
// a valid input. Floats come in two flavours: `real(lo, hi)` maps bytes to a finite value in
// [lo, hi] (the "reasonable input" a property holds for), `any_float()` takes the raw bits
// (NaN, infinities, subnormals, huge values: the bad input an entry point must refuse or
// survive).
#pragma once

#include <plume/math.hpp>

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace plume::fuzz {

class Input {
public:
  Input(std::uint8_t const* data, std::size_t size) noexcept : data_(data), size_(size) {}

  [[nodiscard]] std::size_t remaining() const noexcept { return size_ - pos_; }
  [[nodiscard]] bool empty() const noexcept { return pos_ >= size_; }

  template <class U>
  U bits() noexcept {
    U v{};
    std::size_t const n = remaining() < sizeof(U) ? remaining() : sizeof(U);
    if (n > 0) std::memcpy(&v, data_ + pos_, n);
    pos_ += n;
    return v;
  }
  std::uint8_t byte() noexcept { return bits<std::uint8_t>(); }
  bool flag() noexcept { return (byte() & 1) != 0; }
  /// An integer in [lo, hi].
  int integer(int lo, int hi) noexcept {
    auto const span = static_cast<std::uint32_t>(hi - lo) + 1u;
    return lo + static_cast<int>(bits<std::uint16_t>() % span);
  }
  /// A finite float in [lo, hi], from 16 bits (65,536 evenly spaced values).
  float real(float lo, float hi) noexcept {
    float const u = static_cast<float>(bits<std::uint16_t>()) / 65535.0f;
    return lo + (hi - lo) * u;
  }
  /// Any float: the raw bits (NaN, inf, subnormals, 1e38 ...).
  float any_float() noexcept { return std::bit_cast<float>(bits<std::uint32_t>()); }
  /// Mostly reasonable, sometimes hostile: with one chance in 8 the raw bits.
  float maybe_bad(float lo, float hi) noexcept {
    return (byte() & 7) == 0 ? any_float() : real(lo, hi);
  }
  Vec3 vec3(float lo, float hi) noexcept { return {real(lo, hi), real(lo, hi), real(lo, hi)}; }
  Vec3 maybe_bad_vec3(float lo, float hi) noexcept {
    return {maybe_bad(lo, hi), maybe_bad(lo, hi), maybe_bad(lo, hi)};
  }
  /// A unit quaternion from four reals (identity when they are all zero).
  Quat rotation() noexcept {
    Quat const q{real(-1, 1), real(-1, 1), real(-1, 1), real(-1, 1)};
    float const n = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    return n > 1e-3f ? Quat{q.x / n, q.y / n, q.z / n, q.w / n} : Quat::IDENTITY;
  }

private:
  std::uint8_t const* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

[[noreturn]] inline void fail(char const* what, char const* file, int line) {
  std::fprintf(stderr, "%s:%d: fuzz property broken: %s\n", file, line, what);
  std::abort();
}

inline bool finite(float v) noexcept { return std::isfinite(v); }
inline bool finite(Vec3 const& v) noexcept {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

} // namespace plume::fuzz

/// Checks a property of the result; on failure prints it and aborts.
#define PLUME_FUZZ_CHECK(cond)                                                                     \
  do {                                                                                             \
    if (!(cond)) ::plume::fuzz::fail(#cond, __FILE__, __LINE__);                                   \
  } while (false)
