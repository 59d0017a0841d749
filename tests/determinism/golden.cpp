// plume_golden: the cross-build determinism check.
//
// Evaluates a fixed battery of plume functions on fixed inputs (its own generator, no
// library randomness) with float, double and every wide type of this build, hashes the bits
// of the results (FNV-1a; every NaN hashed as one pattern) and prints one line per battery.
//   plume_golden               print the hashes
//   plume_golden --check FILE  compare with FILE's hashes; exit 1 on any difference
// Every deterministic build (scalar, sse2, avx2, avx512) must print the same hashes, and
// every wide type must hash like the scalar one (lane-exactness); tests/determinism/golden.txt
// holds the expected lines. After an intended change of results, regenerate it with
// `plume_golden > tests/determinism/golden.txt` and say why in the commit.
#include <plume/numerics.hpp>
#include <plume/solver.hpp>

#include <cmath>

#include <bit>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

using namespace plume;

namespace plume {
/// a*b + a, so that the battery covers mul_add with two operands.
template <class T>
PLUME_INLINE T mul_add_self(T a, T b) noexcept {
  return plume::mul_add(a, b, a);
}
} // namespace plume

namespace {

struct fnv {
  std::uint64_t h = 1469598103934665603ull;
  template <class S>
  void add(S v) {
    std::uint64_t b;
    if (v != v)
      b = 0x7ff8dead; // any NaN
    else if constexpr (sizeof(S) == 4)
      b = std::bit_cast<std::uint32_t>(v);
    else
      b = std::bit_cast<std::uint64_t>(v);
    for (int i = 0; i < 8; ++i) {
      h ^= (b >> (8 * i)) & 0xff;
      h *= 1099511628211ull;
    }
  }
};

template <class S>
std::vector<S> inputs(double scale) {
  std::vector<S> v;
  std::uint64_t s = 0x9E3779B97F4A7C15ull;
  for (int i = 0; i < 4096; ++i) {
    s ^= s << 13;
    s ^= s >> 7;
    s ^= s << 17;
    double const u = double(s >> 11) * 0x1.0p-53; // [0, 1)
    double const x = (i % 3 == 0)
                         ? (u - 0.5) * 2 * scale
                         : std::ldexp(u + 0.5, int(s % 200) - 100) * ((s >> 40) & 1 ? 1 : -1);
    v.push_back(static_cast<S>(x));
  }
  for (double a : {0.0, -0.0, 1.0, -1.0, 0.5, 1e30, -1e30, 1e-40, 3.0e38, 1e300, 1e22, 8001.0, 2e8})
    v.push_back(static_cast<S>(a));
  v.push_back(std::numeric_limits<S>::infinity());
  v.push_back(-std::numeric_limits<S>::infinity());
  v.push_back(std::numeric_limits<S>::quiet_NaN());
  v.push_back(std::numeric_limits<S>::denorm_min());
  while (v.size() % 16)
    v.push_back(S(0.25));
  return v;
}

template <class T, class F>
void run_unary(fnv& h, std::vector<scalar_t<T>> const& in, F f) {
  for (std::size_t i = 0; i < in.size(); i += lanes_v<T>) {
    auto const out = to_array(f(load<T>(in.data() + i)));
    for (auto o : out)
      h.add(o);
  }
}
template <class T, class F>
void run_binary(fnv& h, std::vector<scalar_t<T>> const& a, std::vector<scalar_t<T>> const& b, F f) {
  for (std::size_t i = 0; i < a.size(); i += lanes_v<T>) {
    auto const out = to_array(f(load<T>(a.data() + i), load<T>(b.data() + i)));
    for (auto o : out)
      h.add(o);
  }
}

template <class T>
std::uint64_t numerics_battery() {
  using S = scalar_t<T>;
  fnv h;
  auto const x = inputs<S>(10), y = inputs<S>(3);
  std::vector<S> y2(y.rbegin(), y.rend());
#define U(fn)                                                                                      \
  run_unary<T>(h, x, [](auto v) { return plume::fn(v); });                                         \
  run_unary<T>(h, y, [](auto v) { return plume::fn(v); })
#define B(fn) run_binary<T>(h, x, y2, [](auto a, auto b) { return plume::fn(a, b); })
  U(sin);
  U(cos);
  U(tan);
  U(asin);
  U(acos);
  U(atan);
  U(exp);
  U(exp2);
  U(expm1);
  U(log);
  U(log2);
  U(log1p);
  U(sqrt);
  U(floor);
  U(ceil);
  U(round);
  U(round_ties_even);
  U(trunc);
  U(fract);
  U(abs);
  U(signum);
  U(recip);
  B(atan2);
  B(pow);
  B(min);
  B(max);
  B(hypot);
  B(copysign);
  B(mul_add_self);
#undef U
#undef B
  return h.h;
}

/// Velocity projection (3D with multipliers, 2D), brute force and depenetration on 256 fixed
/// problems with 0..15 planes each (lanes of a wide group have different counts).
template <class T>
std::uint64_t solver_battery() {
  using S = scalar_t<T>;
  constexpr std::size_t L = lanes_v<T>, P = 256, K = 15;
  fnv h;
  auto const r = inputs<double>(1); // 4096 + values; the first few hundred are ordinary
  std::size_t at = 0;
  auto next = [&] {
    double x;
    do
      x = r[at++ % 4000];
    while (!(std::abs(x) <= 1));
    return x;
  };
  auto unit3 = [&] {
    double x, y, z, n;
    do {
      x = next(), y = next(), z = next();
      n = std::sqrt(x * x + y * y + z * z);
    } while (n < 0.1 || n > 1);
    return GVec3<S>{S(x / n), S(y / n), S(z / n)};
  };
  std::vector<GVec3<S>> v(P), n(P * K);
  std::vector<S> depth(P * K);
  std::vector<std::size_t> count(P);
  for (std::size_t p = 0; p < P; ++p) {
    GVec3<S> const dir = unit3(); // two statements: operand order is unspecified
    v[p] = dir * S(1 + 4 * std::abs(next()));
    count[p] = p % (K + 1);
    for (std::size_t i = 0; i < count[p]; ++i) {
      n[p * K + i] = unit3();
      depth[p * K + i] = S(0.3 * next());
    }
  }
  for (std::size_t g = 0; g < P; g += L) {
    GVec3<T> wv;
    std::vector<GVec3<T>> wn(K);
    std::vector<GVec2<T>> wn2(K);
    std::vector<Penetration<GVec3<T>>> pen(K);
    for (std::size_t l = 0; l < L; ++l) {
      wv = with_lane(wv, l, v[g + l]);
      for (std::size_t i = 0; i < K; ++i) {
        GVec3<S> const ni = n[(g + l) * K + i]; // zero beyond the problem's count
        wn[i] = with_lane(wn[i], l, ni);
        wn2[i] = with_lane(wn2[i], l, GVec2<S>{ni.x, ni.y});
        pen[i].normal = wn[i];
        pen[i].depth = with_lane(pen[i].depth, l, depth[(g + l) * K + i]);
      }
    }
    std::vector<T> lambda(K);
    auto const r3 = project_velocity<T>(wv, wn, lambda);
    auto const bf = project_velocity_bruteforce<T>(wv, wn);
    auto const r2 = project_velocity<T>(GVec2<T>{wv.x, wv.y}, wn2);
    auto const dp = depenetrate(pen);
    // Problem by problem, so that every width hashes in the same order.
    for (std::size_t l = 0; l < L; ++l) {
      auto add3 = [&](GVec3<T> const& a) {
        auto const x = lane(a, l);
        h.add(x.x), h.add(x.y), h.add(x.z);
      };
      add3(r3.velocity);
      h.add(lane(r3.steps, l));
      for (auto const& x : lambda)
        h.add(lane(x, l));
      add3(bf.velocity);
      h.add(lane(r2.velocity.x, l)), h.add(lane(r2.velocity.y, l));
      add3(dp.correction);
      h.add(lane(dp.passes, l));
    }
  }
  return h.h;
}

} // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::uint64_t> got;
  bool lanes_ok = true;
  auto record = [&](char const* name, std::uint64_t scalar_hash,
                    std::initializer_list<std::uint64_t> wide) {
    got[name] = scalar_hash;
    for (auto w : wide)
      if (w != scalar_hash) {
        std::printf("LANE MISMATCH in %s: a wide type hashes %016" PRIx64 ", scalar %016" PRIx64
                    "\n",
                    name, w, scalar_hash);
        lanes_ok = false;
      }
  };
  record("numerics_f32", numerics_battery<float>(), {
#if PLUME_HAS_BATCHES
    numerics_battery<f32x4>(),
#endif
#if PLUME_HAS_AVX2
        numerics_battery<f32x8>(),
#endif
#if PLUME_HAS_AVX512
        numerics_battery<f32x16>(),
#endif
  });
  record("numerics_f64", numerics_battery<double>(), {
#if PLUME_HAS_BATCHES
    numerics_battery<f64x2>(),
#endif
#if PLUME_HAS_AVX2
        numerics_battery<f64x4>(),
#endif
#if PLUME_HAS_AVX512
        numerics_battery<f64x8>(),
#endif
  });
  record("solver_f32", solver_battery<float>(), {
#if PLUME_HAS_BATCHES
    solver_battery<f32x4>(),
#endif
#if PLUME_HAS_AVX2
        solver_battery<f32x8>(),
#endif
#if PLUME_HAS_AVX512
        solver_battery<f32x16>(),
#endif
  });
  record("solver_f64", solver_battery<double>(), {
#if PLUME_HAS_BATCHES
    solver_battery<f64x2>(),
#endif
#if PLUME_HAS_AVX2
        solver_battery<f64x4>(),
#endif
#if PLUME_HAS_AVX512
        solver_battery<f64x8>(),
#endif
  });
  if (argc == 3 && !std::strcmp(argv[1], "--check")) {
    std::ifstream f(argv[2]);
    std::string name, hex;
    int bad = lanes_ok ? 0 : 1, seen = 0;
    while (f >> name >> hex) {
      ++seen;
      auto const it = got.find(name);
      std::uint64_t const want = std::stoull(hex, nullptr, 16);
      if (it == got.end()) continue;
      std::printf("%-14s %016" PRIx64 " %s (golden %016" PRIx64 ", build %s)\n", name.c_str(),
                  it->second, it->second == want ? "OK" : "DIFFERS", want, plume::simd_name);
      if (it->second != want) bad = 1;
    }
    if (seen == 0) {
      std::printf("no golden hashes in %s\n", argv[2]);
      return 1;
    }
    return bad;
  }
  for (auto const& [name, hash] : got)
    std::printf("%s %016" PRIx64 "\n", name.c_str(), hash);
  return lanes_ok ? 0 : 1;
}
