// Traits, concepts, masks, constants, lane access, loads and stores.
#include "../common/harness.hpp"
#include "../common/types.hpp"

#include <plume/numerics/concepts.hpp>
#include <plume/numerics/constants.hpp>
#include <plume/numerics/mask.hpp>
#include <plume/numerics/memory.hpp>
#include <plume/numerics/reduce.hpp>
#include <plume/numerics/simd.hpp>
#include <plume/numerics/traits.hpp>

#include <random>

using namespace plume;

// Which types satisfy which concept (the table of DESIGN.md).
static_assert(Num<float> && Signed<float> && Real<float> && Float<float> && ScalarReal<float>);
static_assert(Float<double> && ScalarReal<double> && !WideReal<double>);
static_assert(Num<std::int32_t> && Signed<std::int32_t> && Int<std::int32_t> &&
              !Real<std::int32_t>);
static_assert(Num<std::uint32_t> && Int<std::uint32_t> && !Signed<std::uint32_t>);
static_assert(Mask<bool> && !Num<bool> && !Real<bool>);
static_assert(lanes_v<float> == 1 && std::is_same_v<mask_t<float>, bool>);
static_assert(std::is_same_v<bits_t<double>, std::uint64_t> &&
              std::is_same_v<scalar_t<double>, double>);
#if PLUME_HAS_BATCHES
static_assert(Float<f32x4> && WideReal<f32x4> && !ScalarReal<f32x4>);
static_assert(Float<f64x2> && lanes_v<f64x2> == 2 && lanes_v<f32x4> == 4);
static_assert(Int<i32x4> && Signed<i32x4> && !Real<i32x4>);
static_assert(Int<u32x4> && !Signed<u32x4>);
static_assert(Mask<mask_t<f32x4>> && !Num<mask_t<f32x4>>);
static_assert(std::is_same_v<scalar_t<f32x4>, float> &&
              std::is_same_v<bits_t<f32x4>, xsimd::batch<std::uint32_t, arch_128>>);
#endif
#if PLUME_HAS_AVX2
static_assert(lanes_v<f32x8> == 8 && lanes_v<f64x4> == 4 && WideReal<f64x4>);
#endif
#if PLUME_HAS_AVX512
static_assert(lanes_v<f32x16> == 16 && lanes_v<f64x8> == 8 && Int<i32x16>);
#endif
static_assert(lanes_v<f32xN> >= 1 && Float<f32xN> && Float<f64xN>);

TEMPLATE_LIST_TEST_CASE("splat, lane, with_lane, arrays", "[numerics][traits]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  T x = splat<T>(2.5);
  for (std::size_t i = 0; i < lanes_v<T>; ++i)
    CHECK(lane(x, i) == S(2.5));
  for (std::size_t i = 0; i < lanes_v<T>; ++i)
    x = with_lane(x, i, S(i) * 3);
  auto const a = to_array(x);
  for (std::size_t i = 0; i < lanes_v<T>; ++i)
    CHECK(a[i] == S(i) * 3);
  CHECK(test::same_bits(lane(from_array<T>(a), lanes_v<T> - 1), S(lanes_v<T> - 1) * 3));
}

TEMPLATE_LIST_TEST_CASE("loads and stores, full and partial", "[numerics][memory]",
                        test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  alignas(64) S src[lanes_v<T> + 1];
  for (std::size_t i = 0; i <= lanes_v<T>; ++i)
    src[i] = S(i + 1);
  CHECK(lane(load_aligned<T>(src), 0) == S(1));
  CHECK(lane(load<T>(src + 1), lanes_v<T> - 1) == S(lanes_v<T> + 1));
  for (std::size_t n = 0; n <= lanes_v<T>; ++n) {
    T const p = load_partial<T>(src, n);
    for (std::size_t i = 0; i < lanes_v<T>; ++i)
      CHECK(lane(p, i) == (i < n ? S(i + 1) : S(0)));
    S dst[lanes_v<T> + 1];
    for (auto& d : dst)
      d = S(-7);
    store_partial(dst, splat<T>(9), n);
    for (std::size_t i = 0; i <= lanes_v<T>; ++i)
      CHECK(dst[i] == (i < n ? S(9) : S(-7)));
  }
  alignas(64) S out[lanes_v<T>];
  store_aligned(out, splat<T>(4));
  store(out, splat<T>(5));
  CHECK(out[lanes_v<T> - 1] == S(5));
}

TEMPLATE_LIST_TEST_CASE("masks: operators, scalar-left comparisons, any/all/none, bitmask, select",
                        "[numerics][mask]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  T x = zero<T>();
  for (std::size_t i = 0; i < lanes_v<T>; ++i)
    x = with_lane(x, i, S(i));
  mask_t<T> const lt = S(0.5) < x; // scalar on the left
  mask_t<T> const gt = x > S(0.5);
  std::uint64_t const want = lanes_v<T> == 1 ? 0 : ((std::uint64_t(1) << lanes_v<T>)-2);
  CHECK(plume::bitmask(lt) == want);
  CHECK(plume::bitmask(gt) == want);
  CHECK(plume::bitmask(S(0) == x) == 1u);
  CHECK(plume::bitmask(x == S(0)) == 1u);
  CHECK(plume::bitmask(S(0) != x) == want);
  CHECK(plume::bitmask(!(x == S(0))) == want);
  CHECK(plume::bitmask((x >= S(0)) & (x <= S(0))) == 1u);
  CHECK(plume::bitmask((x < S(0)) | (x == S(0))) == 1u);
  CHECK(plume::bitmask((x >= S(0)) ^ (x > S(0))) == 1u);
  CHECK(plume::any(x >= S(0)));
  CHECK(plume::all(x >= S(0)));
  CHECK(plume::none(x < S(0)));
  CHECK(plume::any(x == S(0)));
  CHECK(plume::all(x == S(0)) == (lanes_v<T> == 1));
  T const s = plume::select(x > S(0.5), x, splat<T>(-1));
  CHECK(lane(s, 0) == S(-1));
  CHECK(lane(plume::select(x > S(0.5), S(7), x), 0) == S(0));
  CHECK(lane(plume::select(x < S(0.5), x, S(7)), 0) == S(0));
  CHECK(lane(s, lanes_v<T> - 1) == (lanes_v<T> == 1 ? S(-1) : S(lanes_v<T> - 1)));
}

TEMPLATE_LIST_TEST_CASE("select picks per lane, also with one mask feeding two selects",
                        "[numerics][mask]", test::real_types) {
  // g++ builds of AVX code take select's own vblendvps path (numerics/mask.hpp); a swapped
  // operand or a wrong mask register shows in some lane here.
  using T = TestType;
  using S = scalar_t<T>;
  T x = zero<T>(), y = zero<T>();
  for (std::size_t i = 0; i < lanes_v<T>; ++i) {
    x = with_lane(x, i, S(i) + S(1));
    y = with_lane(y, i, -S(i) - S(100));
  }
  for (std::uint64_t pattern : {0x5555ull, 0xAAAAull, 0x0F0Full, 0x1ull, 0xFFFFull}) {
    T bits = zero<T>();
    for (std::size_t i = 0; i < lanes_v<T>; ++i)
      bits = with_lane(bits, i, S((pattern >> i) & 1u));
    mask_t<T> const m = bits > S(0.5);
    T const a = plume::select(m, x, y), b = plume::select(m, y, x);
    T const c = plume::select(m, S(7), y), d = plume::select(m, x, S(-7));
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      bool const on = (pattern >> i) & 1u;
      INFO("pattern " << pattern << " lane " << i);
      CHECK(lane(a, i) == (on ? lane(x, i) : lane(y, i)));
      CHECK(lane(b, i) == (on ? lane(y, i) : lane(x, i)));
      CHECK(lane(c, i) == (on ? S(7) : lane(y, i)));
      CHECK(lane(d, i) == (on ? lane(x, i) : S(-7)));
    }
  }
}

TEMPLATE_LIST_TEST_CASE("and_not is m & !n on every lane", "[numerics][mask]", test::real_types) {
  // One ANDN of the mask bits (a k-register on AVX-512): an operand order swapped in either
  // form gives !m & n, which differs from m & !n in the lanes where exactly one is set.
  using T = TestType;
  using S = scalar_t<T>;
  constexpr std::size_t L = lanes_v<T>;
  for (std::uint64_t pm : {0x0ull, 0x5555ull, 0x3333ull, 0xFFFFull, 0x1ull, 0x8000ull}) {
    for (std::uint64_t pn : {0x0ull, 0x0F0Full, 0x3333ull, 0xFFFFull, 0x2ull}) {
      T bm = zero<T>(), bn = zero<T>();
      for (std::size_t i = 0; i < L; ++i) {
        bm = with_lane(bm, i, S((pm >> i) & 1u));
        bn = with_lane(bn, i, S((pn >> i) & 1u));
      }
      mask_t<T> const m = bm > S(0.5), n = bn > S(0.5);
      std::uint64_t const lanes = L == 64 ? ~0ull : (1ull << L) - 1;
      INFO("m " << pm << " n " << pn);
      CHECK(plume::bitmask(plume::and_not(m, n)) == ((pm & ~pn) & lanes));
      CHECK(plume::bitmask(plume::and_not(m, n)) == plume::bitmask(m & !n));
    }
  }
}

TEMPLATE_LIST_TEST_CASE("keep_if and select_sign pick per lane", "[numerics][mask]",
                        test::real_types) {
  // keep_if is an AND with the mask on SSE/AVX, select_sign a blend on the sign bit under
  // g++: checked against select on every lane, signed zeros, infinities and NaNs of either
  // sign included (the bits must be select's, so -0 in a stays -0).
  using T = TestType;
  using S = scalar_t<T>;
  S const inf = std::numeric_limits<S>::infinity(), nan = std::numeric_limits<S>::quiet_NaN();
  S const signs[] = {S(1), S(-1), S(0), -S(0), inf, -inf, nan, -nan, S(1e-40), S(-1e-40)};
  for (std::size_t shift = 0; shift < std::size(signs); ++shift) {
    T s = zero<T>(), a = zero<T>(), b = zero<T>();
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      s = with_lane(s, i, signs[(i + shift) % std::size(signs)]);
      a = with_lane(a, i, i % 3 == 0 ? -S(0) : S(i) + S(0.5));
      b = with_lane(b, i, -S(i) - S(100));
    }
    mask_t<T> const m = is_sign_negative(s);
    T const picked = plume::select_sign(s, a, b), kept = plume::keep_if(m, a);
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      bool const neg = std::signbit(lane(s, i));
      INFO("shift " << shift << " lane " << i << " s " << lane(s, i));
      CHECK(std::bit_cast<bits_t<S>>(lane(picked, i)) ==
            std::bit_cast<bits_t<S>>(neg ? lane(a, i) : lane(b, i)));
      CHECK(std::bit_cast<bits_t<S>>(lane(kept, i)) ==
            std::bit_cast<bits_t<S>>(neg ? lane(a, i) : S(0)));
    }
  }
}

TEMPLATE_LIST_TEST_CASE("constants have one spelling for every type", "[numerics][constants]",
                        test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  CHECK(lane(pi<T>(), 0) == std::numbers::pi_v<S>);
  CHECK(lane(tau<T>(), 0) == S(2) * std::numbers::pi_v<S>);
  CHECK(lane(e<T>(), 0) == std::numbers::e_v<S>);
  CHECK(lane(frac_pi_2<T>(), 0) == std::numbers::pi_v<S> / 2);
  CHECK(lane(ln2<T>(), 0) == std::numbers::ln2_v<S>);
  CHECK(lane(sqrt2<T>(), 0) == std::numbers::sqrt2_v<S>);
  CHECK(lane(epsilon<T>(), 0) == std::numeric_limits<S>::epsilon());
  CHECK(lane(max_value<T>(), 0) == std::numeric_limits<S>::max());
  CHECK(lane(min_value<T>(), 0) == std::numeric_limits<S>::lowest());
  CHECK(lane(min_positive<T>(), 0) == std::numeric_limits<S>::min());
  CHECK(std::isinf(lane(infinity<T>(), 0)));
  CHECK(lane(neg_infinity<T>(), 0) < 0);
  CHECK(std::isnan(lane(nan<T>(), 0)));
  CHECK(lane(zero<T>() + one<T>() + neg_one<T>() + two<T>() * half<T>(), 0) == S(1));
  CHECK(lane(log2_10<T>(), 0) == Approx(std::log2(10.0)).epsilon(1e-7));
  CHECK(lane(log10_2<T>(), 0) == Approx(std::log10(2.0)).epsilon(1e-7));
  CHECK(lane(frac_1_sqrt2<T>(), 0) == Approx(std::sqrt(0.5)).epsilon(1e-7));
  CHECK(lane(frac_2_sqrt_pi<T>(), 0) == Approx(2 / std::sqrt(std::numbers::pi)).epsilon(1e-7));
}

TEMPLATE_LIST_TEST_CASE("integer element types", "[numerics][int]", test::int_types) {
  using T = TestType;
  using S = scalar_t<T>;
  T const a = splat<T>(7), b = splat<T>(3);
  CHECK(lane(plume::min(a, b), 0) == S(3));
  CHECK(lane(plume::max(a, b), 0) == S(7));
  CHECK(lane(plume::clamp(splat<T>(9), b, a), 0) == S(7));
  CHECK(lane(a * b + a - b, 0) == S(25));
  CHECK(plume::reduce_add(a) == S(7 * lanes_v<T>));
  // Distinct lanes, so that a reduction pairing the wrong lanes (a wrong shift or block
  // order in registers, numerics/reduce.hpp) counts some twice and others not at all; the
  // extremes sit in every lane in turn. The unsigned largest value has the sign bit set, so
  // a signed compare would take it for the smallest. (Unsigned sums wrap, as they may.)
  S const small = std::is_signed_v<S> ? S(-1000) : S(0);
  S const large = std::is_signed_v<S> ? S(1) << 30 : std::numeric_limits<S>::max();
  for (std::size_t at = 0; at < lanes_v<T>; ++at) {
    T x = zero<T>();
    S sum = 0;
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      S const v = i == at ? small : i == (at + 1) % lanes_v<T> ? large : S(3 * i + 1);
      x = with_lane(x, i, v);
      sum = S(sum + v);
    }
    INFO("extremes at lane " << at);
    CHECK(plume::reduce_add(x) == sum);
    CHECK(plume::reduce_min(x) == small);
    CHECK(plume::reduce_max(x) == (lanes_v<T> == 1 ? small : large));
  }
  if constexpr (std::is_signed_v<S>) {
    CHECK(lane(plume::abs(splat<T>(-4)), 0) == S(4));
    CHECK(lane(plume::signum(splat<T>(-4)), 0) == S(-1));
    CHECK(lane(plume::signum(zero<T>()), 0) == S(0));
  }
}

TEMPLATE_LIST_TEST_CASE("reductions in registers give the scalar tree's bits", "[numerics][reduce]",
                        test::real_types) {
  // The wide reductions shift the upper half of the lanes onto the lower half in registers
  // (numerics/reduce.hpp); a wrong shift count or block order pairs other lanes, which shows
  // in the sum's bits and, with signed zeros and infinities placed per lane, in min and max.
  using T = TestType;
  using S = scalar_t<T>;
  S const inf = std::numeric_limits<S>::infinity();
  S const specials[] = {S(0), -S(0), inf, -inf, S(1e-40), S(-3), S(2.5), S(1e30)};
  std::mt19937 g(17);
  std::uniform_real_distribution<S> u(S(-1e6), S(1e6));
  for (int k = 0; k < 400; ++k) {
    T x = zero<T>();
    for (std::size_t i = 0; i < lanes_v<T>; ++i)
      x = with_lane(x, i, (k + int(i)) % 3 == 0 ? specials[(std::size_t(k) * 7 + i) % 8] : u(g));
    auto v = to_array(x);
    auto tree = [&](auto op) {
      auto a = v;
      for (std::size_t n = a.size() / 2; n >= 1; n /= 2)
        for (std::size_t i = 0; i < n; ++i)
          a[i] = op(a[i], a[i + n]);
      return a[0];
    };
    S const sum = tree([](S a, S b) { return S(a + b); });
    S const lo = tree([](S a, S b) { return plume::min(a, b); });
    S const hi = tree([](S a, S b) { return plume::max(a, b); });
    INFO("case " << k << " x " << x);
    CHECK(test::same_bits(plume::reduce_add(x), sum));
    CHECK(test::same_bits(plume::reduce_min(x), lo));
    CHECK(test::same_bits(plume::reduce_max(x), hi));
  }
  // A NaN in any lane makes min and max NaN.
  for (std::size_t i = 0; i < lanes_v<T>; ++i) {
    T const x = with_lane(splat<T>(S(2)), i, std::numeric_limits<S>::quiet_NaN());
    CHECK(std::isnan(plume::reduce_min(x)));
    CHECK(std::isnan(plume::reduce_max(x)));
    CHECK(std::isnan(plume::reduce_add(x)));
  }
}

TEMPLATE_LIST_TEST_CASE("reductions have a fixed order", "[numerics][reduce]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  T x = zero<T>();
  // Values whose sum depends on the order: big, tiny, -big, ...
  for (std::size_t i = 0; i < lanes_v<T>; ++i)
    x = with_lane(x, i, S((i % 2) ? 1e-3 : 1e7) * S(i % 4 < 2 ? 1 : -1) + S(i));
  auto const a = to_array(x);
  // The documented order: upper half onto lower half, repeatedly.
  std::vector<S> v(a.begin(), a.end());
  for (std::size_t n = v.size() / 2; n >= 1; n /= 2)
    for (std::size_t i = 0; i < n; ++i)
      v[i] = v[i] + v[i + n];
  CHECK(test::same_bits(plume::reduce_add(x), v[0]));
  CHECK(plume::reduce_min(x) == *std::min_element(a.begin(), a.end()));
  CHECK(plume::reduce_max(x) == *std::max_element(a.begin(), a.end()));
  CHECK(std::isnan(
      plume::reduce_min(with_lane(x, lanes_v<T> - 1, std::numeric_limits<S>::quiet_NaN()))));
  CHECK(std::isnan(plume::reduce_max(with_lane(x, 0, std::numeric_limits<S>::quiet_NaN()))));
}
