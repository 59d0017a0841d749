// GQuat and GMat3: identities with derived tolerances, Eigen as an independent oracle,
// degenerate input and lane-exactness, on every element type of the build.
#include "math_support.hpp"

#include <plume/math/mat3.hpp>
#include <plume/math/quat.hpp>

#include <Eigen/Dense>
#include <Eigen/Geometry>

using namespace plume;

namespace {
template <class S>
Eigen::Matrix3d to_eigen(GMat3<S> const& m) {
  Eigen::Matrix3d e;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      e(i, j) = double(m.at(std::size_t(i), std::size_t(j)));
  return e;
}
template <class S>
Eigen::Quaterniond to_eigen(GQuat<S> const& q) {
  return Eigen::Quaterniond(double(q.w), double(q.x), double(q.y), double(q.z));
}
/// Distance between rotations given as quaternions, q ~ -q.
template <class S>
double quat_dist(GQuat<S> const& a, Eigen::Quaterniond const& b) {
  Eigen::Vector4d const av(double(a.x), double(a.y), double(a.z), double(a.w));
  Eigen::Vector4d const bv(b.x(), b.y(), b.z(), b.w());
  return std::min((av - bv).norm(), (av + bv).norm());
}
/// Product of the column lengths: bounds |det| (Hadamard) and scales its rounding error.
template <class S>
double hadamard(GMat3<S> const& m) {
  return double(m.x_axis.length()) * double(m.y_axis.length()) * double(m.z_axis.length());
}
} // namespace

TEMPLATE_LIST_TEST_CASE("quaternion identities", "[math][quat]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  double const eps = test::eps_v<S>;
  test::rng r(3);
  for (int it = 0; it < 200; ++it) {
    auto const q1 = r.quat<T>(), q2 = r.quat<T>();
    auto const v = r.vec3<T>();
    auto const rv = q1 * v;
    auto const qq = q1 * q1.inverse();
    auto const lhs = (q1 * q2) * v, rhs = q1 * (q2 * v);
    auto const back = GQuat<T>::from_mat3(GMat3<T>::from_quat(q1));
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      double const lv = lane(v, i).length();
      INFO("q1 = " << lane(q1, i) << ", q2 = " << lane(q2, i) << ", v = " << lane(v, i));
      // |q v| = |v| within 8 eps |v|.
      CHECK(std::abs(double(lane(rv, i).length()) - lv) <= 8 * eps * lv);
      // q q^-1 = identity within 4 eps per component.
      auto const e = lane(qq, i);
      CHECK(std::abs(double(e.x)) + std::abs(double(e.y)) + std::abs(double(e.z)) +
                std::abs(double(e.w) - 1) <=
            8 * eps);
      // (q1 q2) v = q1 (q2 v) within 16 eps |v|.
      CHECK(double((lane(lhs, i) - lane(rhs, i)).length()) <= 16 * eps * lv);
      // from_mat3(from_quat(q)) = +-q within 8 eps.
      CHECK(quat_dist(lane(back, i), to_eigen(lane(q1, i))) <= 8 * eps);
    }
    // slerp: endpoints and constant angular speed.
    T const t = r.elem<T>(0, 1);
    auto const s0 = q1.slerp(q2, zero<T>()), s1 = q1.slerp(q2, one<T>()), st = q1.slerp(q2, t);
    auto const total = q1.angle_between(q2), part = q1.angle_between(st);
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      CHECK(quat_dist(lane(s0, i), to_eigen(lane(q1, i))) <= 16 * eps);
      CHECK(quat_dist(lane(s1, i), to_eigen(lane(q2, i))) <= 16 * eps);
      double const want = double(lane(t, i)) * double(lane(total, i));
      INFO("slerp at t = " << lane(t, i) << ": angle " << lane(part, i) << ", expected " << want);
      CHECK(std::abs(double(lane(part, i)) - want) <= 128 * eps);
    }
  }
}

// The float product has its own SSE code; it must give the bits of the documented formula,
// which the generic (double and wide) code spells out. Every x, y, z, w of both factors from
// {0, -0, 1, -1, 0.5}: 390625 products, many with pairs that cancel to an exact zero, where
// rewriting -(p + q) as (-p) - q would flip the sign of a zero result.
TEST_CASE("float quaternion product: the formula's bits, signed zeros included", "[math][quat]") {
  float const vals[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f};
  std::size_t failures = 0;
  for (std::size_t k = 0; k < 390625; ++k) {
    std::size_t c = k;
    float e[8];
    for (float& f : e) {
      f = vals[c % 5];
      c /= 5;
    }
    Quat const a{e[0], e[1], e[2], e[3]}, b{e[4], e[5], e[6], e[7]};
    float const x = a.x, y = a.y, z = a.z, w = a.w;
    Quat const want{
        (w * b.x + y * b.z) + (x * b.w - z * b.y), (w * b.y + y * b.w) - (x * b.z - z * b.x),
        (w * b.z - y * b.x) + (x * b.y + z * b.w), (w * b.w - y * b.y) - (x * b.x + z * b.z)};
    Quat const got = a * b;
    if (!test::same(got, want) && failures++ < 3)
      FAIL_CHECK(a << " * " << b << " = " << got << ", the formula gives " << want);
  }
  CHECK(failures == 0);
}

TEMPLATE_LIST_TEST_CASE("euler angles round trip in every order", "[math][quat]",
                        test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  double const eps = test::eps_v<S>;
  test::rng r(4);
  for (auto order :
       {EulerRot::XYZ, EulerRot::XZY, EulerRot::YXZ, EulerRot::YZX, EulerRot::ZXY, EulerRot::ZYX}) {
    for (int it = 0; it < 50; ++it) {
      T const a = r.elem<T>(-3.1, 3.1), b = r.elem<T>(-1.4, 1.4), c = r.elem<T>(-3.1, 3.1);
      auto const q = GQuat<T>::from_euler(order, a, b, c);
      auto const e = q.to_euler(order);
      for (std::size_t i = 0; i < lanes_v<T>; ++i) {
        INFO("order " << int(order) << ": (" << lane(a, i) << ", " << lane(b, i) << ", "
                      << lane(c, i) << ") -> (" << lane(e[0], i) << ", " << lane(e[1], i) << ", "
                      << lane(e[2], i) << ")");
        // asin near |b| = 1.4 amplifies the matrix entry's error by 1/cos(1.4) ~ 6.
        CHECK(std::abs(double(lane(e[0], i)) - double(lane(a, i))) <= 256 * eps);
        CHECK(std::abs(double(lane(e[1], i)) - double(lane(b, i))) <= 256 * eps);
        CHECK(std::abs(double(lane(e[2], i)) - double(lane(c, i))) <= 256 * eps);
      }
      // Any rotation, gimbal lock included, comes back as the same rotation.
      auto const q2 = r.quat<T>();
      auto const e2 = q2.to_euler(order);
      auto const back = GQuat<T>::from_euler(order, e2[0], e2[1], e2[2]);
      for (std::size_t i = 0; i < lanes_v<T>; ++i)
        CHECK(quat_dist(lane(back, i), to_eigen(lane(q2, i))) <= 64 * eps);
    }
    // Gimbal lock: b = +-pi/2 exactly.
    for (S sb : {S(1), S(-1)}) {
      auto const q = GQuat<T>::from_euler(order, splat<T>(S(0.3)), splat<T>(sb * pi<S>() / 2),
                                          splat<T>(S(0.2)));
      auto const e = q.to_euler(order);
      auto const back = GQuat<T>::from_euler(order, e[0], e[1], e[2]);
      for (std::size_t i = 0; i < lanes_v<T>; ++i)
        CHECK(quat_dist(lane(back, i), to_eigen(lane(q, i))) <= 1e3 * eps);
    }
  }
}

TEMPLATE_LIST_TEST_CASE("mat3 identities", "[math][mat3]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  double const eps = test::eps_v<S>;
  test::rng r(5);
  for (int it = 0; it < 200; ++it) {
    // Well conditioned: a rotation times a diagonal in [0.5, 2] (condition number <= 4).
    auto const rot = GMat3<T>::from_quat(r.quat<T>());
    auto const m = rot * GMat3<T>::from_diagonal(r.vec3<T>(0.5, 2));
    auto const mi = m * m.inverse();
    auto const a = r.mat3<T>(), b = r.mat3<T>();
    auto const dab = (a * b).determinant(), da = a.determinant(), db = b.determinant();
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      auto const e = lane(mi, i);
      double err = 0;
      for (std::size_t p = 0; p < 3; ++p)
        for (std::size_t q = 0; q < 3; ++q)
          err = std::max(err, std::abs(double(e.at(p, q)) - (p == q ? 1.0 : 0.0)));
      INFO("M = " << lane(m, i) << ", M M^-1 = " << e);
      CHECK(err <= 64 * eps);
      // det(AB) = det A det B within 32 eps times the Hadamard bounds.
      double const tol = 32 * eps * hadamard(lane(a, i)) * hadamard(lane(b, i));
      INFO("det(AB) = " << lane(dab, i)
                        << ", det A det B = " << double(lane(da, i)) * double(lane(db, i)));
      CHECK(std::abs(double(lane(dab, i)) - double(lane(da, i)) * double(lane(db, i))) <= tol);
    }
  }
}

TEMPLATE_LIST_TEST_CASE("Eigen agrees with plume's matrices and quaternions", "[math][eigen]",
                        test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  double const eps = test::eps_v<S>;
  test::rng r(6);
  for (int it = 0; it < 200; ++it) {
    auto const a = r.mat3<T>(), b = r.mat3<T>();
    auto const q1 = r.quat<T>(), q2 = r.quat<T>();
    auto const v = r.vec3<T>();
    T const t = r.elem<T>(0, 1);
    auto const ab = a * b, ai = a.inverse();
    auto const det = a.determinant();
    auto const rq = GMat3<T>::from_quat(q1);
    auto const qm = GQuat<T>::from_mat3(rq);
    auto const sl = q1.slerp(q2, t);
    auto const av = a * v;
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      Eigen::Matrix3d const ea = to_eigen(lane(a, i)), eb = to_eigen(lane(b, i));
      double const na = ea.norm(), nb = eb.norm();
      CHECK((to_eigen(lane(ab, i)) - ea * eb).norm() <= 8 * eps * na * nb);
      CHECK(std::abs(double(lane(det, i)) - ea.determinant()) <= 16 * eps * hadamard(lane(a, i)));
      // Inverse: relative to the condition number Eigen computes.
      Eigen::Matrix3d const einv = ea.inverse();
      double const cond = na * einv.norm();
      if (cond < 1e3) CHECK((to_eigen(lane(ai, i)) - einv).norm() <= 16 * eps * cond * einv.norm());
      Eigen::Vector3d const ev(lane(v, i).x, lane(v, i).y, lane(v, i).z);
      Eigen::Vector3d const eav = ea * ev;
      auto const pav = lane(av, i);
      CHECK((Eigen::Vector3d(pav.x, pav.y, pav.z) - eav).norm() <= 8 * eps * na * ev.norm());
      // Quaternion <-> matrix and slerp.
      Eigen::Quaterniond const e1 = to_eigen(lane(q1, i)), e2 = to_eigen(lane(q2, i));
      CHECK((to_eigen(lane(rq, i)) - e1.toRotationMatrix()).norm() <= 8 * eps);
      CHECK(quat_dist(lane(qm, i), e1) <= 8 * eps);
      CHECK(quat_dist(lane(sl, i), e1.slerp(double(lane(t, i)), e2)) <= 64 * eps);
    }
  }
}

TEMPLATE_LIST_TEST_CASE("slerp against long double, across angles and t", "[math][quat][slerp]",
                        test::real_types) {
  // The f32 series weights (t in [-1/2, 3/2]) and the acos/sincos path (f64, and f32 beyond),
  // on the given inputs' exact slerp: random pairs, pairs 2^-k apart (k < 24) and exactly
  // perpendicular ones (half angle pi/4, the edge of the series' domain).
  using T = TestType;
  using S = scalar_t<T>;
  double const eps = test::eps_v<S>;
  test::rng r(11);
  double worst = 0, worst_far = 0;
  for (int it = 0; it < 4000; ++it) {
    GQuat<T> q1 = r.quat<T>(), q2 = r.quat<T>();
    if (it % 4 == 1) {
      T const step = splat<T>(S(std::ldexp(1.0, -(it / 4) % 24)));
      q2 = GQuat<T>{q1.x + step * q2.x, q1.y + step * q2.y, q1.z + step * q2.z, q1.w + step * q2.w}
               .normalize();
    } else if (it % 4 == 2) {
      q2 = GQuat<T>{-q1.y, q1.x, -q1.w, q1.z}; // dot = 0 exactly
    }
    bool const far = it % 8 == 7;
    T const t = far ? r.elem<T>(-3, 4) : r.elem<T>(-0.5, 1.5);
    GQuat<T> const got = q1.slerp(q2, t);
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      auto const a = lane(q1, i), b = lane(q2, i), g = lane(got, i);
      long double const ti = lane(t, i);
      long double d = (long double)a.x * b.x + (long double)a.y * b.y + (long double)a.z * b.z +
                      (long double)a.w * b.w;
      long double const sign = d < 0 ? -1 : 1;
      d = std::min(std::abs(d), 1.0L);
      long double const ang = std::acos(d);
      long double const w0 = ang < 1e-30L ? 1 - ti : std::sin((1 - ti) * ang) / std::sin(ang);
      long double const w1 = ang < 1e-30L ? ti : sign * std::sin(ti * ang) / std::sin(ang);
      long double const ex[4] = {w0 * a.x + w1 * b.x, w0 * a.y + w1 * b.y, w0 * a.z + w1 * b.z,
                                 w0 * a.w + w1 * b.w};
      S const gv[4] = {g.x, g.y, g.z, g.w};
      double err = 0;
      for (int c = 0; c < 4; ++c)
        err = std::max(err, double(std::abs(gv[c] - ex[c])));
      // Rounding grows with the weights, which grow with |t - 1/2|.
      double const rel = err / (eps * (1 + std::abs(double(ti) - 0.5)));
      (far ? worst_far : worst) = std::max(far ? worst_far : worst, rel);
      INFO("t = " << double(ti) << ", angle " << double(ang) << ": error " << err / eps << " eps");
      CHECK(err <= (far ? 4 : 2.5) * eps * (1 + std::abs(double(ti) - 0.5)));
    }
  }
  WARN("slerp error / (eps (1 + |t - 1/2|)): " << worst << " for t in [-1/2, 3/2], " << worst_far
                                               << " for t in [-3, 4]");
}

TEMPLATE_LIST_TEST_CASE("quat and mat3 degenerate input", "[math][quat][mat3]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  using V = GVec3<T>;
  using Q = GQuat<T>;
  using M = GMat3<T>;
  double const eps = test::eps_v<S>;
  // Singular matrices: try_inverse says so and gives zero; inverse_or_zero is zero.
  M const singular{V::X, V::X * two<T>(), V::Z};
  auto const ti = singular.try_inverse();
  CHECK(plume::none(ti.valid));
  CHECK(plume::all(ti.value.abs_diff_eq(M::ZERO, zero<T>())));
  CHECK(plume::all(singular.inverse_or_zero().abs_diff_eq(M::ZERO, zero<T>())));
  CHECK(plume::all(M::IDENTITY.try_inverse().valid));
  CHECK(plume::none(M::QNAN.try_inverse().valid));
  // from_rotation_arc of opposite vectors: a half turn taking a to -a.
  test::rng r(7);
  for (int it = 0; it < 20; ++it) {
    V const a = r.unit3<T>();
    Q const q = Q::from_rotation_arc(a, -a);
    V const back = q * a;
    Q const same_q = Q::from_rotation_arc(a, a);
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      CHECK(double((lane(back, i) + lane(a, i)).length()) <= 16 * eps);
      CHECK(!lane(q, i).is_nan());
      CHECK(quat_dist(lane(same_q, i), Eigen::Quaterniond::Identity()) <= 4 * eps);
    }
    // General arcs rotate a onto b.
    V const b = r.unit3<T>();
    V const ab = Q::from_rotation_arc(a, b) * a;
    for (std::size_t i = 0; i < lanes_v<T>; ++i)
      CHECK(double((lane(ab, i) - lane(b, i)).length()) <= 64 * eps);
  }
  // slerp of identical quaternions is the same rotation; of q and -q, q.
  Q const q = Q::from_axis_angle(V::Y, splat<T>(S(0.7)));
  for (S tt : {S(0), S(0.3), S(1)}) {
    Q const s1 = q.slerp(q, splat<T>(tt)), s2 = q.slerp(-q, splat<T>(tt));
    CHECK(plume::none(s1.is_nan()));
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      CHECK(quat_dist(lane(s1, i), to_eigen(lane(q, i))) <= 4 * eps);
      CHECK(quat_dist(lane(s2, i), to_eigen(lane(q, i))) <= 4 * eps);
    }
  }
  // slerp of inputs a few ulp longer than unit (|dot| > 1): q to rounding, no NaN; a NaN t or
  // an infinite component: NaN.
  Q const longer = q * splat<T>(S(1) + S(8) * std::numeric_limits<S>::epsilon());
  for (S tt : {S(-0.4), S(0.3), S(0.9), S(1.4), S(3)}) {
    Q const s = q.slerp(longer, splat<T>(tt));
    for (std::size_t i = 0; i < lanes_v<T>; ++i)
      CHECK(quat_dist(lane(s, i), to_eigen(lane(q, i))) <= 32 * eps * (1 + std::abs(double(tt))));
  }
  Q const turned = Q::from_axis_angle(V::X, splat<T>(S(1)));
  CHECK(plume::all(q.slerp(turned, nan<T>()).is_nan()));
  Q inf_q = turned;
  inf_q.z = infinity<T>();
  for (S tt : {S(0.3), S(2.5)})
    CHECK(plume::all(q.slerp(inf_q, splat<T>(tt)).is_nan()));
  // from_scaled_axis(0) = identity; to_axis_angle(identity) = (X, 0).
  CHECK(plume::all(Q::from_scaled_axis(V::ZERO).abs_diff_eq(Q::IDENTITY, zero<T>())));
  auto const aa = Q::IDENTITY.to_axis_angle();
  CHECK(plume::all(aa.axis.cmpeq(V::X).all()));
  CHECK(plume::all(aa.angle == zero<T>()));
  // ... and so is any vector part below 1e-8 (documented), whatever its direction.
  auto const tiny = Q{zero<T>(), splat<T>(S(1e-9)), zero<T>(), one<T>()}.to_axis_angle();
  CHECK(plume::all(tiny.axis.cmpeq(V::X).all()));
  CHECK(plume::all(tiny.angle == zero<T>()));
  CHECK(plume::all(Q::IDENTITY.is_near_identity()));
  CHECK(plume::none(Q::from_rotation_x(splat<T>(S(0.01))).is_near_identity()));
  // q and -q are the same rotation: -identity, and a small turn negated, are near identity.
  Q const small_turn = Q::from_rotation_y(splat<T>(S(0.001)));
  CHECK(plume::all((-Q::IDENTITY).is_near_identity()));
  CHECK(plume::all((-small_turn).is_near_identity()));
  // rotate_towards stops at the target and never overshoots.
  Q const target = Q::from_rotation_z(splat<T>(S(1)));
  Q const step = Q::IDENTITY.rotate_towards(target, splat<T>(S(0.25)));
  CHECK(plume::all(plume::abs(Q::IDENTITY.angle_between(step) - splat<T>(S(0.25))) <=
                   splat<T>(S(16 * eps))));
  CHECK(plume::all(Q::IDENTITY.rotate_towards(target, splat<T>(S(5)))
                       .abs_diff_eq(target, splat<T>(S(16 * eps)))));
  // A negative max_angle turns away from the target by that much (glam's convention).
  Q const away = Q::IDENTITY.rotate_towards(target, splat<T>(S(-0.25)));
  CHECK(plume::all(plume::abs(away.angle_between(target) - splat<T>(S(1.25))) <=
                   splat<T>(S(16 * eps))));
  CHECK(plume::all(plume::abs(Q::IDENTITY.angle_between(away) - splat<T>(S(0.25))) <=
                   splat<T>(S(16 * eps))));
}

namespace {
/// Lane-exactness of a quaternion/matrix expression f(q1, q2, v, t): random unit rotations
/// with one lane poisoned by an adversarial value per case (the other lanes must not change),
/// and sometimes q2 = q1 in a lane (the identical-input branches).
template <class T, class F>
void check_quat_lanes(char const* name, F f) {
  using S = scalar_t<T>;
  test::rng r(8);
  auto const adv = test::adversarial<S>();
  test::check_lanes<T>(
      name, 300,
      [&](std::size_t k) {
        auto q1 = r.quat<T>(), q2 = r.quat<T>();
        auto v = r.vec3<T>();
        T t = r.elem<T>(-1, 2);
        std::size_t const bad = k % lanes_v<T>;
        S const poison = adv[k % adv.size()];
        if (k % 3 == 0) q1.y = plume::with_lane(q1.y, bad, poison);
        if (k % 3 == 1) v.z = plume::with_lane(v.z, bad, poison);
        if (k % 3 == 2) t = plume::with_lane(t, bad, poison);
        if (k % 7 == 0)
          q2 = plume::with_lane(q2, (bad + 1) % lanes_v<T>, lane(q1, (bad + 1) % lanes_v<T>));
        return std::tuple{q1, q2, v, t};
      },
      f);
}
} // namespace

PLUME_WIDE_TEST_CASE("every quat and mat3 method is lane-exact", "[math][lanes]",
                        test::wide_real_types) {
  using T = TestType;
#define QL(expr)                                                                                   \
  check_quat_lanes<T>(#expr,                                                                       \
                      []([[maybe_unused]] auto q1, [[maybe_unused]] auto q2,                       \
                         [[maybe_unused]] auto v, [[maybe_unused]] auto t) { return expr; })
  QL(q1 * q2);
  QL(q1 * v);
  QL(q1.inverse());
  QL(q1.normalize());
  QL(q1.length());
  QL(q1.dot(q2));
  QL(q1.is_normalized());
  QL(q1.is_near_identity());
  QL(q1.angle_between(q2));
  QL(q1.lerp(q2, t));
  QL(q1.slerp(q2, t));
  QL(q1.rotate_towards(q2, t));
  QL(q1.to_axis_angle().axis);
  QL(q1.to_axis_angle().angle);
  QL(q1.to_scaled_axis());
  QL(decltype(q1)::from_axis_angle(v.normalize(), t));
  QL(decltype(q1)::from_scaled_axis(v));
  QL(decltype(q1)::from_rotation_x(t));
  QL(decltype(q1)::from_euler(EulerRot::YXZ, t, t * 0.5f, t * 2.0f));
  QL(q1.to_euler(EulerRot::XYZ));
  QL(q1.to_euler(EulerRot::ZYX));
  QL(decltype(q1)::from_rotation_arc(v.normalize(), q2 * v.normalize()));
  QL(decltype(q1)::from_mat3(GMat3<decltype(t)>::from_quat(q1)));
  QL(GMat3<decltype(t)>::from_quat(q1));
  QL(GMat3<decltype(t)>::from_quat(q1) * v);
  QL(GMat3<decltype(t)>::from_axis_angle(v.normalize(), t));
  QL((GMat3<decltype(t)>::from_quat(q1) * GMat3<decltype(t)>::from_diagonal(v)).inverse());
  QL((GMat3<decltype(t)>::from_quat(q1) * GMat3<decltype(t)>::from_diagonal(v))
         .try_inverse()
         .valid);
  QL((GMat3<decltype(t)>::from_quat(q1) * GMat3<decltype(t)>::from_diagonal(v)).determinant());
  QL(GMat3<decltype(t)>::from_quat(q1).mul_transpose_vec3(v));
  QL(GMat3<decltype(t)>::from_diagonal(v).rotate_inertia(GMat3<decltype(t)>::from_quat(q2)));
  QL(GMat3<decltype(t)>::skew(v) * GMat3<decltype(t)>::from_quat(q1).transpose());
#undef QL
}
