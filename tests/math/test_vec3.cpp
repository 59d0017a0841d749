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
