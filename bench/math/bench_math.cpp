// plume_bench_math: the geometry kernels, scalar against Eigen and glm, and wide against the
// scalar instantiation and a hand-written AVX2 version, on the same N = 4096 items.
//
// Names follow <case>/<f32|f64>/<implementation>/x<width>; items = operations (vectors
// rotated, matrices multiplied, ...). Scalar code works on arrays of structures (Vec3,
// Eigen::Vector3f, glm::vec3); wide code on structure-of-arrays streams (x[], y[], z[]),
// the layout wide code is meant for. Built without the auto-vectoriser (bench/CMakeLists),
// so x1 is one item at a time for every library.
#include <plume/math.hpp>

#include "../bench_support.hpp"
#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <benchmark/benchmark.h>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#if PLUME_HAS_AVX2
#include <immintrin.h>
#endif

#include <cstdint>
#include <cstdio>
#include <new>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr std::size_t N = 4096;

struct inputs {
  std::vector<plume::Vec3> v, w;
  std::vector<plume::Quat> q, r;
  std::vector<plume::Mat3> m, n;
  std::vector<float> t;
  inputs() {
    std::mt19937 g(7);
    std::uniform_real_distribution<float> u(-1, 1);
    for (std::size_t i = 0; i < N; ++i) {
      v.push_back({u(g), u(g), u(g)});
      w.push_back({u(g), u(g), u(g)});
      q.push_back(plume::Quat{u(g), u(g), u(g), u(g)}.normalize());
      r.push_back(plume::Quat{u(g), u(g), u(g), u(g)}.normalize());
      m.push_back(plume::Mat3::from_quat(q.back()) * plume::Mat3::from_diagonal({1.5f, 0.7f, 2.f}));
      n.push_back(plume::Mat3::from_quat(r.back()));
      t.push_back(0.5f * (u(g) + 1));
    }
  }
};
inputs const& data() {
  static inputs const d;
  return d;
}

template <class F>
void run(benchmark::State& st, F body) {
  for (auto _ : st) {
    body();
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * N));
}

// ------------------------------------------------------------------ scalar: plume/Eigen/glm
Eigen::Vector3f ev(plume::Vec3 const& v) { return {v.x, v.y, v.z}; }
Eigen::Quaternionf eq(plume::Quat const& q) { return {q.w, q.x, q.y, q.z}; }
Eigen::Matrix3f em(plume::Mat3 const& m) {
  Eigen::Matrix3f e;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      e(i, j) = m.at(std::size_t(i), std::size_t(j));
  return e;
}
glm::vec3 gv(plume::Vec3 const& v) { return {v.x, v.y, v.z}; }
glm::quat gq(plume::Quat const& q) { return glm::quat(q.w, q.x, q.y, q.z); } // glm 0.9.9: w first
glm::mat3 gm(plume::Mat3 const& m) { return glm::mat3(gv(m.x_axis), gv(m.y_axis), gv(m.z_axis)); }

template <class V, class Q, class M>
struct converted {
  std::vector<V> v, w;
  std::vector<Q> q, r;
  std::vector<M> m, n;
};

template <class V, class Q, class M, class CV, class CQ, class CM>
converted<V, Q, M> convert(CV cv, CQ cq, CM cm) {
  auto const& d = data();
  converted<V, Q, M> c;
  for (std::size_t i = 0; i < N; ++i) {
    c.v.push_back(cv(d.v[i]));
    c.w.push_back(cv(d.w[i]));
    c.q.push_back(cq(d.q[i]));
    c.r.push_back(cq(d.r[i]));
    c.m.push_back(cm(d.m[i]));
    c.n.push_back(cm(d.n[i]));
  }
  return c;
}

// One scalar case for the three libraries: OUT is the output element type, EXPR uses a, b, q,
// r, m, n, t at index i.
#define PLUME_SCALAR_CASE(name, OUT_P, EXPR_P, OUT_E, EXPR_E, OUT_G, EXPR_G)                       \
  benchmark::RegisterBenchmark(name "/f32/plume/x1", [](benchmark::State& st) {                    \
    auto const& c = data();                                                                        \
    std::vector<OUT_P> out(N);                                                                     \
    run(st, [&] {                                                                                  \
      for (std::size_t i = 0; i < N; ++i) {                                                        \
        [[maybe_unused]] auto const &a = c.v[i], &b = c.w[i];                                      \
        [[maybe_unused]] auto const &q = c.q[i], &r = c.r[i];                                      \
        [[maybe_unused]] auto const &m = c.m[i], &n = c.n[i];                                      \
        [[maybe_unused]] float const t = c.t[i];                                                   \
        out[i] = EXPR_P;                                                                           \
      }                                                                                            \
      benchmark::DoNotOptimize(out.data());                                                        \
    });                                                                                            \
  });                                                                                              \
  benchmark::RegisterBenchmark(name "/f32/eigen/x1", [](benchmark::State& st) {                    \
    static auto const c =                                                                          \
        convert<Eigen::Vector3f, Eigen::Quaternionf, Eigen::Matrix3f>(ev, eq, em);                 \
    auto const& tt = data().t;                                                                     \
    std::vector<OUT_E> out(N);                                                                     \
    run(st, [&] {                                                                                  \
      for (std::size_t i = 0; i < N; ++i) {                                                        \
        [[maybe_unused]] auto const &a = c.v[i], &b = c.w[i];                                      \
        [[maybe_unused]] auto const &q = c.q[i], &r = c.r[i];                                      \
        [[maybe_unused]] auto const &m = c.m[i], &n = c.n[i];                                      \
        [[maybe_unused]] float const t = tt[i];                                                    \
        out[i] = EXPR_E;                                                                           \
      }                                                                                            \
      benchmark::DoNotOptimize(out.data());                                                        \
    });                                                                                            \
  });                                                                                              \
  benchmark::RegisterBenchmark(name "/f32/glm/x1", [](benchmark::State& st) {                      \
    static auto const c = convert<glm::vec3, glm::quat, glm::mat3>(gv, gq, gm);                    \
    auto const& tt = data().t;                                                                     \
    std::vector<OUT_G> out(N);                                                                     \
    run(st, [&] {                                                                                  \
      for (std::size_t i = 0; i < N; ++i) {                                                        \
        [[maybe_unused]] auto const &a = c.v[i], &b = c.w[i];                                      \
        [[maybe_unused]] auto const &q = c.q[i], &r = c.r[i];                                      \
        [[maybe_unused]] auto const &m = c.m[i], &n = c.n[i];                                      \
        [[maybe_unused]] float const t = tt[i];                                                    \
        out[i] = EXPR_G;                                                                           \
      }                                                                                            \
      benchmark::DoNotOptimize(out.data());                                                        \
    });                                                                                            \
  })

void register_scalar() {
  using V = plume::Vec3;
  using Q = plume::Quat;
  using M = plume::Mat3;
  using EV = Eigen::Vector3f;
  using EQ = Eigen::Quaternionf;
  using EM = Eigen::Matrix3f;
  PLUME_SCALAR_CASE("dot", float, a.dot(b), float, a.dot(b), float, glm::dot(a, b));
  PLUME_SCALAR_CASE("cross", V, a.cross(b), EV, a.cross(b), glm::vec3, glm::cross(a, b));
  PLUME_SCALAR_CASE("normalize", V, a.normalize(), EV, a.normalized(), glm::vec3,
                    glm::normalize(a));
  PLUME_SCALAR_CASE("quat_rotate", V, q * a, EV, q * a, glm::vec3, q * a);
  PLUME_SCALAR_CASE("quat_mul", Q, q * r, EQ, q * r, glm::quat, q * r);
  PLUME_SCALAR_CASE("mat3_vec", V, m * a, EV, m * a, glm::vec3, m * a);
  PLUME_SCALAR_CASE("mat3_mul", M, m * n, EM, m * n, glm::mat3, m * n);
  PLUME_SCALAR_CASE("mat3_inverse", M, m.inverse(), EM, m.inverse(), glm::mat3, glm::inverse(m));
  PLUME_SCALAR_CASE("slerp", Q, q.slerp(r, t), EQ, q.slerp(t, r), glm::quat, glm::slerp(q, r, t));
}

// ------------------------------------------------------------------------- wide streams
struct soa {
  float *x, *y, *z, *w;
  explicit soa(std::size_t n)
      : x(new (std::align_val_t(64)) float[n]), y(new (std::align_val_t(64)) float[n]),
        z(new (std::align_val_t(64)) float[n]), w(new (std::align_val_t(64)) float[n]) {}
  ~soa() {
    for (float* p : {x, y, z, w})
      ::operator delete[](p, std::align_val_t(64));
  }
  soa(soa const&) = delete;
  soa& operator=(soa const&) = delete;
};
struct streams {
  soa v{N}, q{N}, r{N}, out{N}, outq{N};
  std::vector<float> t;
  std::vector<plume::Mat3> m;
  streams() {
    auto const& d = data();
    for (std::size_t i = 0; i < N; ++i) {
      v.x[i] = d.v[i].x, v.y[i] = d.v[i].y, v.z[i] = d.v[i].z;
      q.x[i] = d.q[i].x, q.y[i] = d.q[i].y, q.z[i] = d.q[i].z, q.w[i] = d.q[i].w;
      r.x[i] = d.r[i].x, r.y[i] = d.r[i].y, r.z[i] = d.r[i].z, r.w[i] = d.r[i].w;
    }
    t = d.t;
    m = d.m;
  }
};
streams& sdata() {
  static streams s;
  return s;
}

template <class T>
plume::GQuat<T> load_quat(soa const& s, std::size_t i) {
  return {plume::load_aligned<T>(s.x + i), plume::load_aligned<T>(s.y + i),
          plume::load_aligned<T>(s.z + i), plume::load_aligned<T>(s.w + i)};
}
template <class T>
void store_quat(soa& s, std::size_t i, plume::GQuat<T> const& q) {
  plume::store_aligned(s.x + i, q.x);
  plume::store_aligned(s.y + i, q.y);
  plume::store_aligned(s.z + i, q.z);
  plume::store_aligned(s.w + i, q.w);
}

/// A benchmark of op(v) over the vector stream, named <name>/f32/plume/x<width>.
template <class T, class Op>
void register_vec3_stream(std::string const& name, Op op) {
  constexpr std::size_t L = plume::lanes_v<T>;
  std::string const full = name + "/f32/plume/x" + std::to_string(L);
  benchmark::RegisterBenchmark(full.c_str(), [op](benchmark::State& st) {
    auto& s = sdata();
    run(st, [&] {
      for (std::size_t i = 0; i < N; i += L)
        plume::store_soa_aligned(op(plume::load_soa_aligned<T>(s.v.x + i, s.v.y + i, s.v.z + i)),
                                 s.out.x + i, s.out.y + i, s.out.z + i);
    });
  });
}

template <class T>
void register_width() {
  constexpr std::size_t L = plume::lanes_v<T>;
  std::string const w = "/f32/plume/x" + std::to_string(L);
  benchmark::RegisterBenchmark(("stream_quat_rotate" + w).c_str(), [](benchmark::State& st) {
    auto& s = sdata();
    run(st, [&] {
      for (std::size_t i = 0; i < N; i += L)
        plume::store_soa_aligned(load_quat<T>(s.q, i) *
                                     plume::load_soa_aligned<T>(s.v.x + i, s.v.y + i, s.v.z + i),
                                 s.out.x + i, s.out.y + i, s.out.z + i);
    });
  });
  register_vec3_stream<T>("stream_normalize", [](plume::GVec3<T> const& v)
                                                  PLUME_BENCH_INLINE { return v.normalize(); });
  benchmark::RegisterBenchmark(("stream_mat3_vec" + w).c_str(), [](benchmark::State& st) {
    auto& s = sdata();
    // One matrix applied to a stream of vectors (a body's rotation over its vertices).
    plume::GMat3<T> const m(s.m[0]);
    run(st, [&] {
      for (std::size_t i = 0; i < N; i += L)
        plume::store_soa_aligned(m * plume::load_soa_aligned<T>(s.v.x + i, s.v.y + i, s.v.z + i),
                                 s.out.x + i, s.out.y + i, s.out.z + i);
    });
  });
  benchmark::RegisterBenchmark(("stream_slerp" + w).c_str(), [](benchmark::State& st) {
    auto& s = sdata();
    run(st, [&] {
      for (std::size_t i = 0; i < N; i += L)
        store_quat(
            s.outq, i,
            load_quat<T>(s.q, i).slerp(load_quat<T>(s.r, i), plume::load<T>(s.t.data() + i)));
    });
  });
}

/// The clamp_length streams: lengths in [0, 1.7), about half of them longer than 0.8.
template <class T>
void register_clamp_width() {
  register_vec3_stream<T>("stream_clamp_length_max",
                          [](plume::GVec3<T> const& v) PLUME_BENCH_INLINE {
                            return v.clamp_length_max(plume::splat<T>(0.8f));
                          });
  register_vec3_stream<T>("stream_clamp_length", [](plume::GVec3<T> const& v) PLUME_BENCH_INLINE {
    return v.clamp_length(plume::splat<T>(0.4f), plume::splat<T>(0.8f));
  });
}

#if PLUME_HAS_AVX2
/// Hand-written AVX2 quaternion rotation on SoA streams, the same formula and operation order
/// as GQuat::mul_vec3 (t = 2 u x v; v + w t + u x t), unfused: the abstraction-cost reference.
void rotate_intrinsics(streams& s) {
  for (std::size_t i = 0; i < N; i += 8) {
    __m256 const qx = _mm256_load_ps(s.q.x + i), qy = _mm256_load_ps(s.q.y + i),
                 qz = _mm256_load_ps(s.q.z + i), qw = _mm256_load_ps(s.q.w + i);
    __m256 const vx = _mm256_load_ps(s.v.x + i), vy = _mm256_load_ps(s.v.y + i),
                 vz = _mm256_load_ps(s.v.z + i);
    __m256 const two = _mm256_set1_ps(2.f);
    // t = (u x v) * 2
    __m256 const tx =
        _mm256_mul_ps(_mm256_sub_ps(_mm256_mul_ps(qy, vz), _mm256_mul_ps(qz, vy)), two);
    __m256 const ty =
        _mm256_mul_ps(_mm256_sub_ps(_mm256_mul_ps(qz, vx), _mm256_mul_ps(qx, vz)), two);
    __m256 const tz =
        _mm256_mul_ps(_mm256_sub_ps(_mm256_mul_ps(qx, vy), _mm256_mul_ps(qy, vx)), two);
    // (v + t w) + u x t
    __m256 const cx = _mm256_sub_ps(_mm256_mul_ps(qy, tz), _mm256_mul_ps(qz, ty));
    __m256 const cy = _mm256_sub_ps(_mm256_mul_ps(qz, tx), _mm256_mul_ps(qx, tz));
    __m256 const cz = _mm256_sub_ps(_mm256_mul_ps(qx, ty), _mm256_mul_ps(qy, tx));
    _mm256_store_ps(s.out.x + i, _mm256_add_ps(_mm256_add_ps(vx, _mm256_mul_ps(tx, qw)), cx));
    _mm256_store_ps(s.out.y + i, _mm256_add_ps(_mm256_add_ps(vy, _mm256_mul_ps(ty, qw)), cy));
    _mm256_store_ps(s.out.z + i, _mm256_add_ps(_mm256_add_ps(vz, _mm256_mul_ps(tz, qw)), cz));
  }
}
void register_intrinsics() {
  benchmark::RegisterBenchmark("stream_quat_rotate/f32/intrinsics/x8", [](benchmark::State& st) {
    auto& s = sdata();
    run(st, [&] { rotate_intrinsics(s); });
  });
}

/// The intrinsics kernel must compute what plume computes, bit for bit, or the comparison
/// would not be of the same work.
bool intrinsics_agree() {
  auto& s = sdata();
  rotate_intrinsics(s);
  for (std::size_t i = 0; i < N; ++i) {
    plume::Quat const q{s.q.x[i], s.q.y[i], s.q.z[i], s.q.w[i]};
    plume::Vec3 const want = q * plume::Vec3{s.v.x[i], s.v.y[i], s.v.z[i]};
    if (want.x != s.out.x[i] || want.y != s.out.y[i] || want.z != s.out.z[i]) {
      std::fprintf(stderr, "intrinsics quat rotate differs from plume at item %zu\n", i);
      return false;
    }
  }
  return true;
}
#endif

} // namespace

int main(int argc, char** argv) {
  register_scalar();
  plume::bench::for_each_f32_width([]<class T>() {
    register_width<T>();
    register_clamp_width<T>();
  });
#if PLUME_HAS_AVX2
  register_intrinsics();
  if (!intrinsics_agree()) return 1;
#endif
  return plume::bench::run_benchmarks(argc, argv);
}
