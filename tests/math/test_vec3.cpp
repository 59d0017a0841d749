// GVec3: identities, degenerate input and lane-exactness of every method, on every element
// type of the build.
#include "math_support.hpp"

#include <plume/math/bvec3.hpp>
#include <plume/math/mat3.hpp>
#include <plume/math/quat.hpp>
#include <plume/math/vec3.hpp>

using namespace plume;

TEMPLATE_LIST_TEST_CASE("vec3 identities", "[math][vec3]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  double const eps = test::eps_v<S>;
  test::rng r(1);
  for (int it = 0; it < 200; ++it) {
    auto const a = r.vec3<T>(), b = r.vec3<T>();
    auto const n = r.unit3<T>();
    auto const c = a.cross(b);
    auto const ab = a.dot(b), cc = c.length_squared(), aa = a.length_squared(),
               bb = b.length_squared(), ca = c.dot(a);
    auto const ref = a.reflect(n).reflect(n);
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      double const la = std::sqrt(double(lane(aa, i))), lb = std::sqrt(double(lane(bb, i)));
      // (a x b) is perpendicular to a: |(a x b) . a| <= 8 eps |a|^2 |b|.
      double const tol_perp = 8 * eps * la * la * lb;
      INFO("a = " << lane(a, i) << ", b = " << lane(b, i) << ", tolerance " << tol_perp);
      CHECK(std::abs(double(lane(ca, i))) <= tol_perp);
      // Lagrange: |a x b|^2 + (a . b)^2 = |a|^2 |b|^2, within 16 eps |a|^2 |b|^2.
      double const lhs = double(lane(cc, i)) + double(lane(ab, i)) * double(lane(ab, i));
      double const rhs = la * la * lb * lb;
      CHECK(std::abs(lhs - rhs) <= 16 * eps * rhs);
      // Reflecting twice across the same plane gives the vector back (8 eps |a|).
      auto const d = lane(ref, i) - lane(a, i);
      CHECK(double(d.length()) <= 8 * eps * la);
    }
    // Normalised vectors are unit within 2 eps, and angle_between matches the dot product.
    auto const u = a.normalize();
    auto const ang = a.angle_between(b);
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      CHECK(std::abs(double(lane(u, i).length()) - 1) <= 2 * eps);
      auto const la_ = lane(a, i), lb_ = lane(b, i);
      // Reference: the same atan2(|a x b|, a . b) in double. The float result's error is a few
      // eps in absolute radians (cross and dot each carry ~2 eps |a||b|).
      double const cx = double(la_.y) * lb_.z - double(la_.z) * lb_.y,
                   cy = double(la_.z) * lb_.x - double(la_.x) * lb_.z,
                   cz = double(la_.x) * lb_.y - double(la_.y) * lb_.x;
      double const dd = double(la_.x) * lb_.x + double(la_.y) * lb_.y + double(la_.z) * lb_.z;
      double const want = std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), dd);
      INFO("angle_between " << lane(ang, i) << ", atan2 in double " << want);
      CHECK(std::abs(double(lane(ang, i)) - want) <= 8 * eps);
    }
  }
}

TEMPLATE_LIST_TEST_CASE("vec3 methods against their definitions", "[math][vec3]",
                        test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  using V = GVec3<T>;
  double const eps = test::eps_v<S>;
  test::rng r(2);
  for (int it = 0; it < 100; ++it) {
    V const a = r.vec3<T>(), b = r.vec3<T>();
    V const n = r.unit3<T>();
    T const t = r.elem<T>(0, 1);
    // project + reject = a; reject is perpendicular to b.
    V const p = a.project_onto(b), q = a.reject_from(b);
    V const orth = n.any_orthonormal_vector();
    auto const pair = n.any_orthonormal_pair();
    V const ortho_any = a.any_orthogonal_vector();
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      auto const ai = lane(a, i), bi = lane(b, i), ni = lane(n, i);
      double const la = ai.length(), lb = bi.length();
      CHECK(double((lane(p, i) + lane(q, i) - ai).length()) <= 8 * eps * la);
      CHECK(std::abs(double(lane(q, i).dot(bi))) <= 16 * eps * la * lb);
      // Orthonormal basis: unit, perpendicular, right-handed.
      auto const o = lane(orth, i), p0 = lane(pair[0], i), p1 = lane(pair[1], i);
      CHECK(std::abs(double(o.length()) - 1) <= 8 * eps);
      CHECK(std::abs(double(o.dot(ni))) <= 8 * eps);
      CHECK(double((p0.cross(p1) - ni).length()) <= 16 * eps);
      CHECK(std::abs(double(lane(ortho_any, i).dot(ai))) <= 8 * eps * la * la);
      CHECK(double(lane(ortho_any, i).length()) >= 0.5 * la);
    }
    // clamp_length, move_towards, lerp and slerp endpoints.
    V const cl = a.clamp_length(splat<T>(S(1)), splat<T>(S(2)));
    V const mt = a.move_towards(b, splat<T>(S(0.5)));
    V const s0 = a.slerp(b, zero<T>()), s1 = a.slerp(b, one<T>()), sm = a.slerp(b, t);
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      auto const ai = lane(a, i), bi = lane(b, i);
      double const lc = lane(cl, i).length();
      CHECK(lc >= 1 - 4 * eps);
      CHECK(lc <= 2 + 4 * eps);
      double const dist = (bi - ai).length();
      double const moved = (lane(mt, i) - ai).length();
      CHECK(std::abs(moved - std::min(0.5, dist)) <= 16 * eps * (ai.length() + 1));
      CHECK(double((lane(s0, i) - ai).length()) <= 64 * eps * ai.length());
      CHECK(double((lane(s1, i) - bi).length()) <= 64 * eps * bi.length());
      // slerp's length is lerped.
      double const want_len = ai.length() + double(lane(t, i)) * (bi.length() - ai.length());
      CHECK(std::abs(double(lane(sm, i).length()) - want_len) <=
            64 * eps * (ai.length() + bi.length()));
    }
  }
}

TEMPLATE_LIST_TEST_CASE("vec3 degenerate input", "[math][vec3]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  using V = GVec3<T>;
  V const zero_v = V::ZERO;
  // normalize(0) is NaN; the _or forms and try_normalize are not.
  CHECK(plume::all(zero_v.normalize().is_nan()));
  CHECK(plume::all(zero_v.normalize_or_zero().cmpeq(V::ZERO).all()));
  CHECK(plume::all(zero_v.normalize_or(V::Y).cmpeq(V::Y).all()));
  auto const tn = zero_v.try_normalize();
  CHECK(plume::none(tn.valid));
  CHECK(plume::all(tn.value.cmpeq(V::ZERO).all()));
  auto const nl = zero_v.normalize_and_length();
  CHECK(plume::all(nl.value.cmpeq(V::X).all()));
  CHECK(plume::all(nl.length == zero<T>()));
  // Infinite and NaN vectors do not normalise either.
  CHECK(plume::none(V::INF.try_normalize().valid));
  CHECK(plume::none(V::QNAN.try_normalize().valid));
  // A tiny vector whose squared length underflows is reported invalid, not NaN.
  V const tiny = V::splat(splat<T>(std::numeric_limits<S>::denorm_min()));
  CHECK(plume::none(tiny.try_normalize().valid));
  CHECK(plume::none(tiny.normalize_or_zero().is_nan()));
  // angle_between with a zero vector is 0; clamp_length of zero stays zero.
  CHECK(plume::all(zero_v.angle_between(V::X) == zero<T>()));
  CHECK(plume::all(zero_v.clamp_length(one<T>(), two<T>()).cmpeq(V::ZERO).all()));
  // refract: total internal reflection gives zero.
  V const grazing = V{one<T>(), splat<T>(S(-0.01)), zero<T>()}.normalize();
  CHECK(plume::all(grazing.refract(V::Y, splat<T>(S(1.5))).cmpeq(V::ZERO).all()));
  // slerp of opposite vectors turns through a perpendicular direction at t = 1/2.
  V const mid = V::X.slerp(V::NEG_X, half<T>());
  for (std::size_t i = 0; i < lanes_v<T>; ++i) {
    CHECK(std::abs(double(lane(mid, i).x)) <= 8 * test::eps_v<S>);
    CHECK(std::abs(double(lane(mid, i).length()) - 1) <= 8 * test::eps_v<S>);
  }
  // any_orthonormal_vector at z = -1 and z = -0 (the seams of the formula) stays unit.
  for (S zz : {S(-1), S(1), S(-0.0), S(0.0)}) {
    V const n = V{zero<T>(), splat<T>(zz == 0 ? S(1) : S(0)), splat<T>(zz)};
    V const o = n.any_orthonormal_vector();
    CHECK(plume::all(plume::abs(o.length() - one<T>()) <= splat<T>(S(8 * test::eps_v<S>))));
    CHECK(plume::all(plume::abs(o.dot(n)) <= splat<T>(S(8 * test::eps_v<S>))));
  }
}

namespace {
/// Lane-exactness of a vec3 expression f(a, b, t) over adversarial lane mixes.
template <class T, class F>
void check_vec3_lanes(char const* name, F f) {
  test::lane_pool<T> const p(77);
  test::check_lanes<T>(
      name, p.size(),
      [&](std::size_t k) {
        return std::tuple{GVec3<T>{p.pick(k), p.pick(k + 1), p.pick(k + 2)},
                          GVec3<T>{p.pick(k + 3), p.pick(k + 5), p.pick(k + 8)}, p.pick(k + 11)};
      },
      f);
}
} // namespace

PLUME_WIDE_TEST_CASE("every vec3 method is lane-exact", "[math][vec3][lanes]",
                     test::wide_real_types) {
  using T = TestType;
#define V3(expr)                                                                                   \
  check_vec3_lanes<T>(#expr, []([[maybe_unused]] auto a, [[maybe_unused]] auto b,                  \
                                [[maybe_unused]] auto t) { return expr; })
  V3(a + b);
  V3(a - b);
  V3(a * b);
  V3(a / b);
  V3(a * t);
  V3(-a);
  V3(a.dot(b));
  V3(a.cross(b));
  V3(a.length());
  V3(a.length_squared());
  V3(a.length_recip());
  V3(a.distance(b));
  V3(a.distance_squared(b));
  V3(a.normalize());
  V3(a.normalize_or_zero());
  V3(a.normalize_or(b));
  V3(a.try_normalize().value);
  V3(a.try_normalize().valid);
  V3(a.normalize_and_length().value);
  V3(a.normalize_and_length().length);
  V3(a.is_normalized());
  V3(a.project_onto(b));
  V3(a.reject_from(b));
  V3(a.project_onto_normalized(b));
  V3(a.reject_from_normalized(b));
  V3(a.reflect(b));
  V3(a.refract(b, t));
  V3(a.angle_between(b));
  V3(a.any_orthogonal_vector());
  V3(a.any_orthonormal_vector());
  V3(a.any_orthonormal_pair());
  V3(a.clamp_length(plume::abs(t), plume::abs(t) * 2));
  V3(a.clamp_length_max(t));
  V3(a.clamp_length_min(t));
  V3(a.lerp(b, t));
  V3(a.midpoint(b));
  V3(a.move_towards(b, t));
  V3(a.slerp(b, t));
  V3(a.min(b));
  V3(a.max(b));
  V3(a.clamp(b, b + decltype(a)::splat(plume::abs(t))));
  V3(a.min_element());
  V3(a.max_element());
  V3(a.element_sum());
  V3(a.element_product());
  V3(a.abs());
  V3(a.signum());
  V3(a.copysign(b));
  V3(a.floor());
  V3(a.ceil());
  V3(a.round());
  V3(a.trunc());
  V3(a.fract());
  V3(a.recip());
  V3(a.mul_add(b, a));
  V3(a.cmpeq(b));
  V3(a.cmplt(b));
  V3(a.cmpge(b));
  V3(a.is_finite());
  V3(a.is_nan());
  V3(a.abs_diff_eq(b, t));
#undef V3
}

namespace {
template <class V>
std::string printed(V const& v) {
  std::ostringstream os;
  os << v;
  return os.str();
}
} // namespace

// Debug printing: scalars in a fixed form, wide values with every lane, in lane order, each
// printed as its scalar value is.
TEMPLATE_LIST_TEST_CASE("operator<< prints every lane", "[math][print]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  GVec3<T> v;
  GQuat<T> q;
  for (std::size_t i = 0; i < lanes_v<T>; ++i) {
    S const k = S(i);
    v = with_lane(v, i, GVec3<S>{k, S(2.5) * k, -k - S(1)});
    q = with_lane(q, i, GQuat<S>{k, S(0), S(-0.5), S(1)});
  }
  GMat3<T> const m = GMat3<T>::from_diagonal(v);
  if constexpr (!is_batch_v<T>) {
    CHECK(printed(v) == "(0, 0, -1)");
    CHECK(printed(q) == "quat(0, 0, -0.5, 1)");
    CHECK(printed(m) == "[x: (0, 0, 0), y: (0, 0, 0), z: (0, 0, -1)]");
  } else {
    std::string want_v = "[", want_q = "[";
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      want_v += (i ? ", " : "") + printed(lane(v, i));
      want_q += (i ? ", " : "") + printed(lane(q, i));
    }
    CHECK(printed(v) == want_v + "]");
    CHECK(printed(q) == want_q + "]");
    CHECK(printed(m) == "[x: " + printed(m.x_axis) + ", y: " + printed(m.y_axis) +
                            ", z: " + printed(m.z_axis) + "]");
    // The last lane is there: its x is lanes - 1.
    CHECK(printed(v).find("(" + printed(S(lanes_v<T> - 1)) + ", ") != std::string::npos);
  }
}

// ---------------------------------------------------------------- clamp_length at the range ends

namespace {
/// The formulas clamp_length* had before the overflow fix: the reference for the bits of every
/// vector whose squared length is finite.
template <class V, class T>
V plain_clamp_length(V const& v, T lo, T hi) {
  T const len = v.length();
  T const target = plume::clamp(len, lo, hi);
  return V::select((len != target) & (len > zero<T>()), v * (target / len), v);
}
template <class V, class T>
V plain_clamp_length_max(V const& v, T hi) {
  T const len = v.length();
  return V::select(len > hi, v * (hi / len), v);
}
template <class V, class T>
V plain_clamp_length_min(V const& v, T lo) {
  T const len = v.length();
  return V::select((len < lo) & (len > zero<T>()), v * (lo / len), v);
}

/// Every lane of a and b bitwise equal.
template <class V>
bool same_lanes(V const& a, V const& b) {
  for (std::size_t i = 0; i < lanes_v<typename V::element_type>; ++i)
    if (!test::same(test::lane_of(a, i), test::lane_of(b, i))) return false;
  return true;
}

/// v scaled to length `to` in long double (whose range holds any float or double squared).
template <class S>
std::array<long double, 3> scaled_to(GVec3<S> const& v, long double to) {
  long double const x = v.x, y = v.y, z = v.z;
  long double const len = std::sqrt(x * x + y * y + z * z);
  return {x * to / len, y * to / len, z * to / len};
}
template <class S>
long double length_ld(GVec3<S> const& v) {
  long double const x = v.x, y = v.y, z = v.z;
  return std::sqrt(x * x + y * y + z * z);
}

/// Checks r against v clamped to [lo, hi] in long double: v's bits where its length is within
/// the bounds, else the scaled vector within 8 eps of the bound per component.
template <class S>
void check_clamped(GVec3<S> const& v, GVec3<S> const& r, long double lo, long double hi) {
  long double const len = length_ld(v);
  INFO("v = " << v << ", |v| = " << double(len) << ", bounds [" << double(lo) << ", " << double(hi)
              << "], got " << r);
  if (len >= lo && len <= hi) {
    CHECK(test::same(r, v));
    return;
  }
  long double const to = len > hi ? hi : lo;
  auto const want = scaled_to(v, to);
  long double const tol = 8 * test::eps_v<S> * to;
  CHECK(std::abs(r.x - want[0]) <= tol);
  CHECK(std::abs(r.y - want[1]) <= tol);
  CHECK(std::abs(r.z - want[2]) <= tol);
  CHECK(std::abs(length_ld(r) - to) <= tol);
}
} // namespace

TEMPLATE_LIST_TEST_CASE("clamp_length keeps its bits where the squared length is finite",
                        "[math][vec3][clamp]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  test::rng r(31);
  // Lengths from 1e-15 to 1e15 (1e18 for float's largest exponents below the overflow).
  for (int it = 0; it < 400; ++it) {
    double const scale = std::pow(10.0, r.uniform(-15, sizeof(S) == 4 ? 18 : 150));
    GVec3<T> const a = r.vec3<T>(-scale, scale);
    GVec2<T> const a2{a.x, a.y};
    GVec4<T> const a4{a.x, a.y, a.z, r.elem<T>(-scale, scale)};
    T const lo = r.elem<T>(0, scale), hi = lo + r.elem<T>(0, scale);
    CHECK(same_lanes(a.clamp_length_max(hi), plain_clamp_length_max(a, hi)));
    CHECK(same_lanes(a.clamp_length_min(lo), plain_clamp_length_min(a, lo)));
    CHECK(same_lanes(a.clamp_length(lo, hi), plain_clamp_length(a, lo, hi)));
    CHECK(same_lanes(a2.clamp_length_max(hi), plain_clamp_length_max(a2, hi)));
    CHECK(same_lanes(a2.clamp_length_min(lo), plain_clamp_length_min(a2, lo)));
    CHECK(same_lanes(a2.clamp_length(lo, hi), plain_clamp_length(a2, lo, hi)));
    CHECK(same_lanes(a4.clamp_length(lo, hi), plain_clamp_length(a4, lo, hi)));
  }
}

TEMPLATE_TEST_CASE("clamp_length of huge, infinite and NaN vectors", "[math][vec3][clamp]", float,
                   double) {
  using S = TestType;
  using V = GVec3<S>;
  using L = std::numeric_limits<S>;
  S const big = L::max(), tiny = L::min(), sub = L::denorm_min(), inf = L::infinity();
  S const root = std::sqrt(big); // from here on a single component's square overflows
  // 1e38 is float's "near FLT_MAX"; for double the same fraction of DBL_MAX.
  S const e38 = sizeof(S) == 4 ? S(1e38) : S(0.3) * big;
  std::vector<V> const huge = {{big, 0, 0},        {big, big, big},     {-big, big, -big},
                               {e38, e38, e38},    {e38, -tiny, sub},   {sub, -big, tiny},
                               {4 * root, 0, 0},   {root, root, -root}, {-e38, 1, -1},
                               {2 * root, -sub, 0}};
  std::vector<S> const bounds = {S(0), S(1), S(2.5), root * 1000, e38, big, S(8) * root};
  for (V const& v : huge) {
    REQUIRE(v.length_squared() == inf); // every case overflows
    for (S const hi : bounds) {
      check_clamped(v, v.clamp_length_max(hi), 0, hi);
      check_clamped(v, v.clamp_length_min(hi), hi, inf);
      for (S const lo : bounds)
        if (lo <= hi) check_clamped(v, v.clamp_length(lo, hi), lo, hi);
      // GVec2 and GVec4 share the code; their x, y (z) are the 3D case's.
      GVec3<S> const r2 = GVec3<S>{GVec2<S>{v.x, v.y}.clamp_length_max(hi).x,
                                   GVec2<S>{v.x, v.y}.clamp_length_max(hi).y, S(0)};
      if (v.x != 0 || v.y != 0) check_clamped(V{v.x, v.y, 0}, r2, 0, hi);
      GVec4<S> const r4 = GVec4<S>{v.x, v.y, v.z, S(0)}.clamp_length(0, hi);
      check_clamped(v, V{r4.x, r4.y, r4.z}, 0, hi);
      CHECK(r4.w == 0);
    }
  }
  // A finite vector whose squared length overflows but whose length is within the bound comes
  // back unchanged; clamp_length_min scales one up to a bound beyond it.
  V const v{4 * root, 0, 0};
  CHECK(test::same(v.clamp_length_max(big), v));
  CHECK(test::same(v.clamp_length(root, big), v));
  check_clamped(v, v.clamp_length_min(S(16) * root), S(16) * root, inf);

  // Infinite components: the limit of huge ones, along the infinite components.
  CHECK(test::same(V{inf, 0, 0}.clamp_length_max(S(2)), V{2, 0, 0}));
  CHECK(test::same(V{-inf, S(3), -S(4)}.clamp_length_max(S(2)), V{-2, 0, -S(0)}));
  V const two_inf = V{-inf, inf, S(5)}.clamp_length_max(S(2));
  CHECK(two_inf.x == -two_inf.y);
  CHECK(std::abs(double(two_inf.y) - std::sqrt(2.0)) <= 4 * test::eps_v<S>);
  CHECK(test::same(two_inf.z, S(0)));
  CHECK(test::same(V{inf, 0, 0}.clamp_length(S(1), S(2)), V{2, 0, 0}));
  CHECK(test::same(V{inf, S(1), 0}.clamp_length_min(S(2)), V{inf, S(1), 0})); // already longer
  CHECK(test::same(V{inf, S(1), 0}.clamp_length_max(inf), V{inf, S(1), 0}));  // no bound
  // NaN: a NaN component makes the length NaN, which crosses no bound: v comes back.
  S const nan = L::quiet_NaN();
  for (V const& v_nan : {V{nan, 0, 0}, V{nan, big, big}, V{inf, nan, 1}}) {
    CHECK(test::same(v_nan.clamp_length_max(S(1)), v_nan));
    CHECK(test::same(v_nan.clamp_length_min(S(1)), v_nan));
    CHECK(test::same(v_nan.clamp_length(S(1), S(2)), v_nan));
  }
  // A NaN bound: clamp_length_max / _min return v; clamp_length follows plume::clamp (NaN).
  for (V const& w : {V{1, 2, 3}, V{big, big, 0}}) {
    CHECK(test::same(w.clamp_length_max(nan), w));
    CHECK(test::same(w.clamp_length_min(nan), w));
    CHECK(w.clamp_length(S(1), nan).is_nan());
  }
  // Zero stays zero.
  CHECK(test::same(V{}.clamp_length_min(S(1)), V{}));
  CHECK(test::same(V{}.clamp_length(S(1), S(2)), V{}));
}

PLUME_WIDE_TEST_CASE("clamp_length is lane-exact with huge, ordinary and non-finite lanes",
                     "[math][vec3][clamp][lanes]", test::wide_real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  using L = std::numeric_limits<S>;
  S const big = L::max(), inf = L::infinity(), nan = L::quiet_NaN();
  // One lane that needs the rescaled form among ordinary ones, and every other mix.
  std::vector<GVec3<S>> const cases = {{big, big, 0},      {S(0.3), -S(2), S(1)},
                                       {S(0), S(0), S(0)}, {inf, S(1), S(0)},
                                       {nan, S(1), S(1)},  {-big, S(1e-30), L::denorm_min()},
                                       {S(3), S(4), S(0)}, {S(1e-3), 0, 0}};
  std::vector<S> const bounds = {S(0.5), S(2.5), big, inf, nan};
  for (std::size_t k = 0; k < cases.size(); ++k) {
    GVec3<T> v;
    T hi{}, lo{};
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      v = with_lane(v, i, cases[(k + i * 3) % cases.size()]);
      hi = plume::with_lane(hi, i, bounds[(k + i) % bounds.size()]);
      lo = plume::with_lane(lo, i, bounds[(k + i + 2) % bounds.size()] / S(4));
    }
    GVec2<T> const v2{v.x, v.y};
    GVec4<T> const v4{v.x, v.y, v.z, v.x};
    auto const max3 = v.clamp_length_max(hi), min3 = v.clamp_length_min(lo);
    auto const cl3 = v.clamp_length(lo, hi);
    auto const max2 = v2.clamp_length_max(hi);
    auto const cl4 = v4.clamp_length(lo, hi);
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      auto const vi = lane(v, i);
      S const hi_i = plume::lane(hi, i), lo_i = plume::lane(lo, i);
      INFO("lane " << i << ": v = " << vi << ", lo = " << lo_i << ", hi = " << hi_i);
      CHECK(test::same(lane(max3, i), vi.clamp_length_max(hi_i)));
      CHECK(test::same(lane(min3, i), vi.clamp_length_min(lo_i)));
      CHECK(test::same(lane(cl3, i), vi.clamp_length(lo_i, hi_i)));
      CHECK(test::same(lane(max2, i), lane(v2, i).clamp_length_max(hi_i)));
      CHECK(test::same(lane(cl4, i), lane(v4, i).clamp_length(lo_i, hi_i)));
    }
  }
}
