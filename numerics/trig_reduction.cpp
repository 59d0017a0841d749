// Payne-Hanek reduction of huge trigonometric arguments (see detail/payne_hanek.hpp).
//
// x = m * 2^k with m a 53-bit integer. With 2/pi = sum_i b_i 2^-i, x * 2/pi mod 4 only
// needs the bits b_i with i >= k - 1 (the others contribute multiples of 4). We take 192
// of them from bit k - 1 on, multiply by m (245-bit product) and read the quadrant and
// a 128-bit fraction from it. 128 bits cover the worst cancellation of any double (about
// 61 bits, Kahan/McDonald) with 67 bits to spare.
#include <plume/numerics/detail/payne_hanek.hpp>

#include <bit>
#include <cmath>
#include <cstdint>

namespace plume::detail {
namespace {

__extension__ typedef unsigned __int128 u128;
__extension__ typedef __int128 i128;

// 2/pi after the binary point, preceded by 64 zero bits so that windows starting before
// bit 1 (k - 1 < 1, i.e. |x| < 2^53) read zeros. tools/gen_constants.py prints it.
constexpr std::uint64_t two_over_pi_bits[] = {
    0x0000000000000000ULL, 0xa2f9836e4e441529ULL, 0xfc2757d1f534ddc0ULL, 0xdb6295993c439041ULL,
    0xfe5163abdebbc561ULL, 0xb7246e3a424dd2e0ULL, 0x06492eea09d1921cULL, 0xfe1deb1cb129a73eULL,
    0xe88235f52ebb4484ULL, 0xe99c7026b45f7e41ULL, 0x3991d639835339f4ULL, 0x9c845f8bbdf9283bULL,
    0x1ff897ffde05980fULL, 0xef2f118b5a0a6d1fULL, 0x6d367ecf27cb09b7ULL, 0x4f463f669e5fea2dULL,
    0x7527bac7ebe5f17bULL, 0x3d0739f78a5292eaULL, 0x6bfb5fb11f8d5d08ULL, 0x56033046fc7b6babULL,
    0xf0cfbc209af4361dULL, 0xa9e391615ee61000ULL,
};
constexpr int table_bits =
    64 * static_cast<int>(sizeof(two_over_pi_bits) / sizeof(two_over_pi_bits[0]));

// 64 bits of the table starting at global bit g (bit 0 = most significant of word 0).
std::uint64_t window64(int g) noexcept {
  int const w = g >> 6, off = g & 63;
  std::uint64_t const a = two_over_pi_bits[w];
  std::uint64_t const b = (w + 1) * 64 < table_bits ? two_over_pi_bits[w + 1] : 0;
  return off == 0 ? a : (a << off) | (b >> (64 - off));
}

} // namespace

huge_reduction reduce_half_pi_huge(double x) noexcept {
  std::uint64_t const bits = std::bit_cast<std::uint64_t>(x);
  bool const negative = (bits >> 63) != 0;
  int const biased = static_cast<int>((bits >> 52) & 0x7ff);
  if (biased == 0x7ff) return {x - x, 0.0, 0}; // inf/NaN: NaN, never reached from plume
  std::uint64_t const m = (bits & ((std::uint64_t(1) << 52) - 1)) | (std::uint64_t(1) << 52);
  int const k = biased - 1075; // x = m * 2^k
  // First needed bit b_(k-1); b_i sits at global position i + 63 (b_1 right after the
  // 64 leading zero bits).
  int g = (k - 1) + 63;
  if (g < 0) g = 0; // |x| < 2^-10: never called so (documented precondition)
  std::uint64_t const w0 = window64(g), w1 = window64(g + 64), w2 = window64(g + 128);
  // P = m * (w0:w1:w2); y = P * 2^-190 (mod 4).
  u128 acc = static_cast<u128>(m) * w2;
  std::uint64_t const p0 = static_cast<std::uint64_t>(acc);
  acc >>= 64;
  acc += static_cast<u128>(m) * w1;
  std::uint64_t const p1 = static_cast<std::uint64_t>(acc);
  acc >>= 64;
  acc += static_cast<u128>(m) * w0;
  std::uint64_t const p2 = static_cast<std::uint64_t>(acc);
  int q = static_cast<int>(p2 >> 62);
  // 128 fraction bits below bit 190, as a fixed-point number in [0, 1).
  std::uint64_t const f1 = (p2 << 2) | (p1 >> 62);
  std::uint64_t const f0 = (p1 << 2) | (p0 >> 62);
  i128 f = static_cast<i128>((static_cast<u128>(f1) << 64) | f0);
  // f as a signed fraction in [-1/2, 1/2): a fraction >= 1/2 belongs to the next quadrant.
  // (The unsigned value reinterpreted as signed is exactly f - 1 when its top bit is set.)
  if ((f1 >> 63) != 0) q += 1;
  // f * 2^-128 as a double-double.
  std::int64_t const top = static_cast<std::int64_t>(f >> 64);
  std::uint64_t const low = static_cast<std::uint64_t>(f);
  double const top_d = static_cast<double>(top);                    // 53 leading bits
  std::int64_t const rest = top - static_cast<std::int64_t>(top_d); // |rest| <= 2^10, exact
  double const lo_part =
      std::ldexp(static_cast<double>(rest), -64) + std::ldexp(static_cast<double>(low), -128);
  double const fh = std::ldexp(top_d, -64);
  double const s = fh + lo_part;
  double const sl = lo_part - (s - fh);
  // r = (s + sl) * pi/2, double-double; std::fma is correctly rounded in every build.
  constexpr double pio2_hi = 0x1.921fb54442d18p+0, pio2_lo = 0x1.1a62633145c07p-54;
  double const p = s * pio2_hi;
  double const pe = std::fma(s, pio2_hi, -p) + (s * pio2_lo + sl * pio2_hi);
  double hi = p + pe;
  double lo = pe - (hi - p);
  if (negative) {
    hi = -hi;
    lo = -lo;
    q = -q;
  }
  return {hi, lo, q & 3};
}

} // namespace plume::detail
