// plume/numerics/detail/coefficients.hpp - polynomial coefficients and split constants of
// plume's transcendental functions. Internal: use plume/numerics/trig.hpp and exp_log.hpp.
//
// Polynomials are listed highest degree first (Horner order). Except the sin/cos sets
// (cephes' minimax sets, long public), each was fitted by tools/fit_coefficients.py
// (weighted Remez, relative error); split constants come from tools/gen_constants.py.
// The error noted beside a set is the relative error of the exact-coefficient fit; each
// was chosen so that its share of the function's final error stays under ~0.1 ulp.
#pragma once

#include <cstdint>

namespace plume::detail {

template <class S>
struct math_constants;

template <>
struct math_constants<float> {
  // sin(r) = r + r z S(z), cos(r) = 1 - z/2 + z^2 C(z), z = r^2, |r| <= pi/4 (cephes sinf/cosf)
  static constexpr float sin_poly[] = {-1.9515295891E-4f, 8.3321608736E-3f, -1.6666654611E-1f};
  static constexpr float cos_poly[] = {2.443315711809948E-5f, -1.388731625493765E-3f,
                                       4.166664568298827E-2f};
  // Cody-Waite pi/2 = sum of parts; q * part exact for |q| < 2^13; fast path |x| <= 8000
  static constexpr float pio2_parts[] = {1.57031250000f, 4.83751296997e-4f, 7.54953362048e-8f,
                                         2.56328291925e-12f, 6.12323426293e-17f};
  static constexpr float pio2_tail = 2.56334415e-12f; // parts[3] + parts[4], rounded
  static constexpr float trig_fast_limit = 8000.0f;
  static constexpr float round_magic =
      12582912.0f; // 1.5 * 2^23: (v + m) - m rounds |v| < 2^22 to even
  static constexpr std::uint64_t magic_bits = 0x4B400000u;
  static constexpr std::uint64_t two_p_bits = 0x4B000000u; // bits of 2^23
  static constexpr float two_p = 8388608.0f;
  static constexpr int mant_bits = 23;
  static constexpr int exp_bias = 127;
  static constexpr std::uint64_t hi_half_mask = 0xFFFFF000u; // keeps 12 significant bits
  static constexpr float split_factor = 4097.0f;             // 2^12 + 1 (Dekker)
  static constexpr float pio2_hi = 1.57079637051f, pio2_lo = -4.37113882867e-8f;
  static constexpr float pio4_hi = 7.85398185253e-1f, pio4_lo = -2.18556941434e-8f;
  static constexpr float pi_hi = 3.14159274101f, pi_lo = -8.74227765735e-8f;
  static constexpr float tan_3pi_8 = 2.41421356237f, tan_pi_8 = 0.414213562373f;
  // atan2's offsets k pi/2 +- atan(c), c in {0, 1/2, 1}, as hi + lo with hi's last bit at
  // 2^-22 or above, so that every sum k pi/2_hi +- atan(c)_hi (< 4) is exact
  static constexpr float atan2_pio2_hi = 0x1.921fb4p+0f, atan2_pio2_lo = 0x1.4442d2p-24f;
  static constexpr float atan2_pi_hi = 0x1.921fb4p+1f, atan2_pi_lo = 0x1.4442d2p-23f;
  static constexpr float atan2_pio4_hi = 0x1.921fb8p-1f, atan2_pio4_lo = -0x1.5dde98p-24f;
  static constexpr float atan2_half_hi = 0x1.dac67p-2f, atan2_half_lo = 0x1.586ed4p-28f;
  // atan2: beyond this max(|y|, |x|), 2 max + min could overflow (the general path scales)
  static constexpr float atan2_huge = 0x1p125f;
  static constexpr float ln2_hi = 6.93145751953e-1f,
                         ln2_lo = 1.42860676533e-6f; // n*hi exact, |n| < 2^8
  static constexpr float log2e = 1.44269502163f;
  static constexpr float ivln2_hi = 1.44287109375f, ivln2_lo = -1.76052853931e-4f; // 12-bit hi
  static constexpr float sqrt2 = 1.41421353816986083984375f;
  static constexpr float exp_clamp_lo = -110.0f, exp_clamp_hi = 100.0f; // beyond: 0 / inf
  static constexpr float exp2_clamp_lo = -160.0f, exp2_clamp_hi = 140.0f;
  static constexpr float expm1_clamp_lo = -30.0f; // below: -1
  // float pow's double core. log2(1 + f) = s Q(z), s = f / (2 + f), z = s^2 <= 0.1716^2;
  // fit (weighted for relative error): 2^-37.8. 2^r = 1 + r P(r), |r| <= 1/2: 2^-28.9.
  // t = y log2 x is clamped to +-powf_t_limit: 2^t is then a normal double, far beyond
  // float's range on either side.
  static constexpr double powf_log2_poly[] = {3.40734118902652094e-01, 4.11672052878205963e-01,
                                              5.77083608521757663e-01, 9.61796673076763087e-01,
                                              2.88539008179083067e+00};
  static constexpr double powf_exp2_poly[] = {1.53537713565860836e-04, 1.33984667609062251e-03,
                                              9.61843320172784365e-03, 5.55033344106826212e-02,
                                              2.40226479677588145e-01, 6.93147202448039512e-01};
  static constexpr double powf_t_limit = 200.0;
  // |x| below these: e^x and 2^x are normal numbers, n = round(x log2 e) in [-124, 127].
  static constexpr float exp_fast_limit = 86.0f, exp2_fast_limit = 124.0f;
  static constexpr float subnormal_scale = 16777216.0f; // 2^24
  static constexpr float subnormal_scale_log2 = 24.0f;
  // tan(r) = r + r z T(z), z = r^2 <= (pi/4)^2; fit: relative error 1.94e-8 (2^-25.62)
  static constexpr float tan_poly[] = {3.843601865e-03f, 1.184472096e-03f, 9.962731904e-03f,
                                       2.162094216e-02f, 5.399449117e-02f, 1.333323081e-01f,
                                       3.333333398e-01f};
  // asin(s) = s + s R, R = z P(z) = u Q(u), z = s^2 <= 1/4, u = 4z (Q's coefficients are P's
  // scaled by 4^-(k+1), exactly); fit: error of s + s R relative to s 2^-27.59
  static constexpr float asin_poly[] = {0x1.59dac2p-15f, 0x1.8ba26p-14f, 0x1.748c64p-11f,
                                        0x1.33014ep-8f, 0x1.5555cap-5f};
  // asin for |x| > 1/2 is asin_pio2_part + ((asin_one_up - 2s) + (pio2_lo - 2sR)):
  // asin_pio2_part + asin_one_up = pio2_hi exactly, 2s <= 1 is subtracted exactly from
  // asin_one_up (the float above 1) for 2s >= 1/2, and at s = 0 the sum is pio2_hi.
  static constexpr float asin_one_up = 0x1.000002p+0f, asin_pio2_part = 0x1.243f68p-1f;
  // atan2's atan(q) = q + q z P(z), z = q^2 <= 0.36^2; fit (weighted for relative error, then
  // rounded): relative error 2^-27.4
  static constexpr float atan2_poly[] = {8.682586253e-02f, -1.403630525e-01f, 1.998960972e-01f,
                                         -3.333319724e-01f};
  // atan(t) = t + t z P(z), z = t^2 <= tan(pi/8)^2; fit: relative error 1.59e-9 (2^-29.23)
  static constexpr float atan_poly[] = {5.051923183e-02f,  -8.626306881e-02f, 1.107161127e-01f,
                                        -1.428416640e-01f, 1.999997759e-01f,  -3.333333328e-01f};
  // exp(r) = 1 + r + r^2 P(r), |r| <= ln2/2; fit: relative error 1.24e-7 (2^-22.94), which
  // is at most 0.09 ulp of the result (r^2 P <= 0.06)
  static constexpr float exp_poly[] = {1.390128506e-03f, 8.363140380e-03f, 4.166685335e-02f,
                                       1.666657732e-01f, 4.999999955e-01f};
  // 2^r = 1 + r P(r), |r| <= 1/2; fit: relative error 2.32e-10 (2^-32.0)
  static constexpr float exp2_poly[] = {1.525271968e-05f, 1.546132989e-04f, 1.333366945e-03f,
                                        9.618057037e-03f, 5.550410728e-02f, 2.402265092e-01f,
                                        6.931471806e-01f};
  // log(1+f) = 2s + s z Q(z), s = f/(2+f), z = s^2 <= 0.0295; fit: relative error 2.76e-7
  // (2^-21.79)
  static constexpr float log_poly[] = {2.958051168e-01f, 3.998876405e-01f, 6.666668510e-01f};
};

template <>
struct math_constants<double> {
  // sin(r) = r + r z S(z), cos(r) = 1 - z/2 + z^2 C(z), z = r^2, |r| <= pi/4 (cephes sin/cos)
  static constexpr double sin_poly[] = {1.58962301576546568060E-10, -2.50507477628578072866E-8,
                                        2.75573136213857245213E-6,  -1.98412698295895385996E-4,
                                        8.33333333332211858878E-3,  -1.66666666666666307295E-1};
  static constexpr double cos_poly[] = {-1.13585365213876817300E-11, 2.08757008419747316778E-9,
                                        -2.75573141792967388112E-7,  2.48015872888517045348E-5,
                                        -1.38888888888730564116E-3,  4.16666666666665929218E-2};
  // Cody-Waite pi/2 = sum of parts; q * part exact for |q| < 2^27; fast path |x| <= 1e8
  static constexpr double pio2_parts[] = {0x1.921fb58000000p+0, -0x1.dde9740000000p-27,
                                          0x1.1a62630000000p-54, 0x1.8a2e038000000p-81,
                                          -0x1.f1976b7ed8fbcp-110};
  static constexpr double pio2_tail = pio2_parts[3] + pio2_parts[4];
  static constexpr double trig_fast_limit = 1e8;
  static constexpr double round_magic = 6755399441055744.0; // 1.5 * 2^52
  static constexpr std::uint64_t magic_bits = 0x4338000000000000ull;
  static constexpr std::uint64_t two_p_bits = 0x4330000000000000ull; // bits of 2^52
  static constexpr double two_p = 4503599627370496.0;
  static constexpr int mant_bits = 52;
  static constexpr int exp_bias = 1023;
  static constexpr std::uint64_t hi_half_mask = 0xFFFFFFFF00000000ull; // keeps 21 significant bits
  static constexpr double split_factor = 134217729.0;                  // 2^27 + 1 (Dekker)
  static constexpr double pio2_hi = 0x1.921fb54442d18p+0, pio2_lo = 0x1.1a62633145c07p-54;
  static constexpr double pio4_hi = 0x1.921fb54442d18p-1, pio4_lo = 0x1.1a62633145c07p-55;
  static constexpr double pi_hi = 0x1.921fb54442d18p+1, pi_lo = 0x1.1a62633145c07p-53;
  static constexpr double tan_3pi_8 = 2.41421356237309504880, tan_pi_8 = 0.41421356237309504880;
  // atan2's offsets, as for float: hi's last bit at 2^-51 or above (pi/2's already is)
  static constexpr double atan2_pio2_hi = pio2_hi, atan2_pio2_lo = pio2_lo;
  static constexpr double atan2_pi_hi = pi_hi, atan2_pi_lo = pi_lo;
  static constexpr double atan2_pio4_hi = pio4_hi, atan2_pio4_lo = pio4_lo;
  static constexpr double atan2_half_hi = 0x1.dac670561bb50p-2,
                          atan2_half_lo = -0x1.2ea406ee84d0fp-55;
  static constexpr double atan2_huge = 0x1p1021;
  static constexpr double ln2_hi = 0x1.62e42fefa3800p-1,
                          ln2_lo = 0x1.ef35793c76730p-45; // n*hi exact, |n| < 2^11
  static constexpr double log2e = 0x1.71547652b82fep+0;
  static constexpr double ivln2_hi = 0x1.7154700000000p+0,
                          ivln2_lo = 0x1.94ae0bf85ddf4p-22; // 21-bit hi
  static constexpr double sqrt2 = 1.4142135623730951454746218587388;
  static constexpr double exp_clamp_lo = -760.0, exp_clamp_hi = 720.0;
  static constexpr double exp2_clamp_lo = -1100.0, exp2_clamp_hi = 1040.0;
  static constexpr double expm1_clamp_lo = -50.0;
  static constexpr double exp_fast_limit = 708.0, exp2_fast_limit = 1020.0;
  static constexpr double subnormal_scale = 18014398509481984.0; // 2^54
  static constexpr double subnormal_scale_log2 = 54.0;
  // tan(r) = r + r z P(z) / Q(z), z = r^2 <= (pi/4)^2, Q monic (cephes tan's minimax set;
  // relative error of the ratio about 2^-56)
  static constexpr double tan_p[] = {-1.30936939181383777646E4, 1.15351664838587416140E6,
                                     -1.79565251976484877988E7};
  static constexpr double tan_q[] = {1.0, 1.36812963470692954678E4, -1.32089234440210967447E6,
                                     2.50083801823357915839E7, -5.38695755929454629881E7};
  // asin(s) = s + s R, R = z P(z) = u Q(u), z = s^2 <= 1/4, u = 4z; fit: error of s + s R
  // relative to s 2^-55.87
  static constexpr double asin_poly[] = {
      0x1.05cedae728263p-29, -0x1.0af6771943d37p-28, 0x1.40b30b6a5b7a1p-26, 0x1.aab1c0c97cfd2p-26,
      0x1.8ee4e73c3a658p-23, 0x1.c6f87267b4cbcp-21,  0x1.1c6c28693c2d9p-18, 0x1.6e89ef6c7c029p-16,
      0x1.f1c72c6dfa4dep-14, 0x1.6db6db41d1496p-11,  0x1.333333336f8dbp-8,  0x1.5555555555387p-5};
  static constexpr double asin_one_up = 0x1.0000000000001p+0,
                          asin_pio2_part = 0x1.243f6a8885a2ep-1; // as for float
  // atan2's atan(q) = q + q z P(z), z = q^2 <= 0.36^2; fit as for float: relative error 2^-58.7
  static constexpr double atan2_poly[] = {2.56698796815522760e-02, -4.67087228030193119e-02,
                                          5.78642229734334101e-02, -6.65679114378776582e-02,
                                          7.69164830990574644e-02, -9.09088074929651768e-02,
                                          1.11111103544682982e-01, -1.42857142740761722e-01,
                                          1.99999999999112055e-01, -3.33333333333330983e-01};
  // atan(t) = t + t z P(z), z = t^2 <= tan(pi/8)^2; fit: relative error 9.29e-17 (2^-53.26)
  static constexpr double atan_poly[] = {
      -1.91945036017889016e-02, 3.92468058220015736e-02,  -5.08600343638232061e-02,
      5.85826100363831329e-02,  -6.66452516534213335e-02, 7.69218423036370225e-02,
      -9.09090462610840783e-02, 1.11111110165294874e-01,  -1.42857142846837121e-01,
      1.99999999999956102e-01,  -3.33333333333333315e-01};
  // exp(r) = 1 + r + r^2 P(r), |r| <= ln2/2; fit: relative error 2.71e-18 (2^-58.35)
  static constexpr double exp_poly[] = {
      2.08893733412605747e-09, 2.51051735977179985e-08, 2.75573496208480485e-07,
      2.75572555143003458e-06, 2.48015872457415215e-05, 1.98412698747207499e-04,
      1.38888888889179569e-03, 8.33333333332616708e-03, 4.16666666666666158e-02,
      1.66666666666666713e-01, 5.00000000000000000e-01};
  // 2^r = 1 + r P(r), |r| <= 1/2; fit: relative error 2.35e-19 (2^-61.88)
  static constexpr double exp2_poly[] = {
      2.56784278807954536e-11, 4.45580485290219436e-10, 7.05493227225549875e-09,
      1.01780571692962057e-07, 1.32154867213575325e-06, 1.52527338413784526e-05,
      1.54035303934661684e-04, 1.33335581464066291e-03, 9.61812910762843698e-03,
      5.55041086648216248e-02, 2.40226506959100722e-01, 6.93147180559945286e-01};
  // log(1+f) = 2s + s z Q(z), s = f/(2+f), z = s^2 <= 0.0295; fit: relative error 4.55e-16
  // (2^-50.97)
  static constexpr double log_poly[] = {1.46168757273662353e-01, 1.53316840024377898e-01,
                                        1.81828903693279836e-01, 2.22222111158262681e-01,
                                        2.85714286261061767e-01, 3.99999999998991773e-01,
                                        6.66666666666666963e-01};
};

template <class S>
constexpr bool asin_split_exact =
    math_constants<S>::asin_pio2_part + math_constants<S>::asin_one_up ==
    math_constants<S>::pio2_hi&& math_constants<S>::pi_hi ==
    2 * math_constants<S>::pio2_hi&& math_constants<S>::pi_lo == 2 * math_constants<S>::pio2_lo;
static_assert(asin_split_exact<float> && asin_split_exact<double>);

} // namespace plume::detail
