// The 2D types: GVec2, GRot2, GIso2, GMat2, GAabb2 — identities against their 3D or closed
// forms, degenerate input and lane-exactness.
#include "math_support.hpp"

#include <plume/math/aabb2.hpp>
#include <plume/math/bvec2.hpp>
#include <plume/math/iso2.hpp>
#include <plume/math/mat2.hpp>
#include <plume/math/mat4.hpp>
#include <plume/math/rot2.hpp>
#include <plume/math/vec2.hpp>
#include <plume/math/vec4.hpp>

#include <Eigen/Dense>

using namespace plume;

namespace {
template <class T>
GVec2<T> rand_vec2(test::rng& r, double lo = -10, double hi = 10) {
  return {r.elem<T>(lo, hi), r.elem<T>(lo, hi)};
}
} // namespace

TEMPLATE_LIST_TEST_CASE("vec2 and rot2 identities", "[math][2d]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  double const eps = test::eps_v<S>;
  test::rng r(21);
  for (int it = 0; it < 200; ++it) {
    auto const a = rand_vec2<T>(r), b = rand_vec2<T>(r);
    T const ang1 = r.elem<T>(-3, 3), ang2 = r.elem<T>(-3, 3);
    // perp_dot is the z of the 3D cross product; perp is perpendicular and of equal length.
    auto const pd = a.perp_dot(b);
    auto const c3 = GVec3<T>{a.x, a.y, zero<T>()}.cross(GVec3<T>{b.x, b.y, zero<T>()});
    auto const pa = a.perp();
    // Rotations compose by adding angles and preserve length; from_angle . rotate agree.
    auto const r1 = GRot2<T>::from_angle(ang1), r2 = GRot2<T>::from_angle(ang2);
    auto const r12 = r1 * r2;
    auto const ra = r1 * a, rb = GVec2<T>::from_angle(ang1).rotate(a);
    auto const back = r1.inverse_mul_vec2(ra);
    auto const at = a.angle_to(ra);
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      auto const ai = lane(a, i);
      double const la = ai.length(), lb = lane(b, i).length();
      CHECK(test::same(lane(pd, i), lane(c3.z, i)));
      CHECK(std::abs(double(lane(pa, i).dot(ai))) == 0);
      CHECK(lane(pa, i).length() == ai.length());
      double const want = double(lane(ang1, i)) + double(lane(ang2, i));
      GVec2<S> const r12v{lane(r12.cos, i), lane(r12.sin, i)};
      INFO("angles " << lane(ang1, i) << " + " << lane(ang2, i));
      CHECK(std::abs(double(r12v.x) - std::cos(want)) <= 8 * eps);
      CHECK(std::abs(double(r12v.y) - std::sin(want)) <= 8 * eps);
      CHECK(std::abs(double(lane(ra, i).length()) - la) <= 8 * eps * la);
      CHECK(double((lane(ra, i) - lane(rb, i)).length()) <= 4 * eps * la);
      CHECK(double((lane(back, i) - ai).length()) <= 8 * eps * la);
      // angle_to recovers the rotation angle (mod 2 pi).
      double d = double(lane(at, i)) - double(lane(ang1, i));
      d = std::remainder(d, 2 * std::numbers::pi);
      CHECK(std::abs(d) <= 64 * eps);
      (void)lb;
    }
  }
  // slerp of rotations turns at constant speed along the shorter way.
  auto const from = GRot2<T>::from_angle(splat<T>(S(0.5))),
             to = GRot2<T>::from_angle(splat<T>(S(-2.5)));
  auto const mid = from.slerp(to, half<T>());
  for (std::size_t i = 0; i < lanes_v<T>; ++i) {
    // shortest path from 0.5 to -2.5 is -3.0 (not +3.28), half way: -1.0
    CHECK(std::abs(double(lane(mid.angle(), i)) + 1.0) <= 64 * eps);
  }
  // Degenerate: a zero rotation pair normalises to IDENTITY; zero vector angle is 0.
  CHECK(plume::all(GRot2<T>{zero<T>(), zero<T>()}.normalize().cos == one<T>()));
  CHECK(plume::all(GVec2<T>::ZERO.to_angle() == zero<T>()));
  CHECK(plume::none(GVec2<T>::ZERO.try_normalize().valid));
}

TEMPLATE_LIST_TEST_CASE("iso2, mat2 and aabb2", "[math][2d]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  using V = GVec2<T>;
  double const eps = test::eps_v<S>;
  test::rng r(22);
  for (int it = 0; it < 100; ++it) {
    GIso2<T> const a{GRot2<T>::from_angle(r.elem<T>(-3, 3)), rand_vec2<T>(r)},
        b{GRot2<T>::from_angle(r.elem<T>(-3, 3)), rand_vec2<T>(r)};
    V const p = rand_vec2<T>(r);
    auto const lhs = (a * b) * p, rhs = a * (b * p), inv = a.inverse() * (a * p),
               rel = a.inv_mul(b) * p, rel2 = (a.inverse() * b) * p;
    // Well-conditioned 2x2: rotation times diag in [0.5, 2].
    auto const m = GRot2<T>::from_angle(r.elem<T>(-3, 3)).to_mat2() *
                   GMat2<T>::from_diagonal(rand_vec2<T>(r, 0.5, 2));
    auto const mi = m * m.inverse();
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      double const scale =
          32 * eps *
          (lane(p, i).length() + lane(a.translation, i).length() + lane(b.translation, i).length());
      CHECK(double((lane(lhs, i) - lane(rhs, i)).length()) <= scale);
      CHECK(double((lane(inv, i) - lane(p, i)).length()) <= scale);
      CHECK(double((lane(rel, i) - lane(rel2, i)).length()) <= scale);
      auto const e = lane(mi, i);
      CHECK(std::abs(double(e.x_axis.x) - 1) <= 32 * eps);
      CHECK(std::abs(double(e.y_axis.y) - 1) <= 32 * eps);
      CHECK(std::abs(double(e.x_axis.y)) <= 32 * eps);
      CHECK(std::abs(double(e.y_axis.x)) <= 32 * eps);
    }
    // The oriented box's bound holds its corners.
    V const h = rand_vec2<T>(r, 0.1, 3);
    auto const box = GAabb2<T>::from_obb(a, h).grow(splat<T>(S(64 * eps * 20)));
    for (int c = 0; c < 4; ++c)
      CHECK(plume::all(box.contains(a * V{(c & 1) ? h.x : -h.x, (c & 2) ? h.y : -h.y})));
  }
  GMat2<T> const singular{V::X, V::X};
  CHECK(plume::none(singular.try_inverse().valid));
  CHECK(plume::all(singular.inverse_or_zero().abs_diff_eq(GMat2<T>::ZERO, zero<T>())));
  auto const unit = GAabb2<T>::from_center_half_extents(V::ZERO, V::ONE);
  CHECK(plume::all(unit.area() == splat<T>(S(4))));
  CHECK(plume::all(unit.perimeter() == splat<T>(S(8))));
  CHECK(plume::all(unit.contains(V::ONE)));
  CHECK(plume::none(unit.contains(V::QNAN)));
  CHECK(plume::none(GAabb2<T>::EMPTY.is_valid()));
  CHECK(plume::all(GAabb2<T>::EMPTY.merge(unit).is_valid()));
}

namespace {
/// Lane-exactness of a 2D expression f(a, b, t) over adversarial lane mixes.
template <class T, class F>
void check_2d_lanes(char const* name, F f) {
  test::lane_pool<T> const p(91);
  test::check_lanes<T>(
      name, p.size(),
      [&](std::size_t k) {
        return std::tuple{GVec2<T>{p.pick(k), p.pick(k + 1)},
                          GVec2<T>{p.pick(k + 3), p.pick(k + 5)}, p.pick(k + 11)};
      },
      f);
}
} // namespace

PLUME_WIDE_TEST_CASE("every 2D method is lane-exact", "[math][2d][lanes]",
                        test::wide_real_types) {
  using T = TestType;
#define L2D(expr)                                                                                  \
  check_2d_lanes<T>(#expr, []([[maybe_unused]] auto a, [[maybe_unused]] auto b,                    \
                              [[maybe_unused]] auto t) { return expr; })
  L2D(a.dot(b));
  L2D(a.perp_dot(b));
  L2D(GVec3<decltype(t)>(a.perp().x, a.perp().y, t));
  L2D(a.length());
  L2D(a.normalize_or_zero().x);
  L2D(a.try_normalize().valid);
  L2D(a.angle_to(b));
  L2D(a.to_angle());
  L2D(decltype(a)::from_angle(t).y);
  L2D(a.rotate(b).x);
  L2D(a.reflect(b).y);
  L2D(a.project_onto(b).x);
  L2D(a.move_towards(b, t).x);
  L2D(a.clamp_length(plume::abs(t), plume::abs(t) * 2).y);
  L2D(a.clamp_length(plume::abs(t), plume::abs(t) * 2));
  L2D(a.clamp_length_max(t));
  L2D(a.clamp_length_min(t));
  L2D(a.lerp(b, t).x);
  L2D(a.min(b).x);
  L2D(a.max(b).y);
  L2D(a.abs_diff_eq(b, t));
  L2D(GRot2<decltype(t)>::from_angle(t).slerp(GRot2<decltype(t)>::from_angle(a.x), b.y).sin);
  L2D(GRot2<decltype(t)>(a.x, a.y).normalize().cos);
  L2D((GRot2<decltype(t)>::from_angle(t) * b).x);
  L2D(GMat2<decltype(t)>(a, b).inverse().x_axis.y);
  L2D(GMat2<decltype(t)>(a, b).try_inverse().valid);
  L2D(GMat2<decltype(t)>(a, b).determinant());
#undef L2D
}

TEMPLATE_LIST_TEST_CASE("mat4 against Eigen and its identities", "[math][mat4]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  using V4 = GVec4<T>;
  double const eps = test::eps_v<S>;
  test::rng r(23);
  auto rand4 = [&](double lo, double hi) {
    return V4{r.elem<T>(lo, hi), r.elem<T>(lo, hi), r.elem<T>(lo, hi), r.elem<T>(lo, hi)};
  };
  for (int it = 0; it < 200; ++it) {
    GMat4<T> const a{rand4(-1, 1), rand4(-1, 1), rand4(-1, 1), rand4(-1, 1)};
    GMat4<T> const b{rand4(-1, 1), rand4(-1, 1), rand4(-1, 1), rand4(-1, 1)};
    auto const ab = a * b, ai = a.inverse();
    auto const det = a.determinant(), dab = ab.determinant(), db = b.determinant();
    // An affine pose: scale, rotation, translation; its inverse undoes transform_point3.
    auto const pose =
        GMat4<T>::from_scale_rotation_translation(r.vec3<T>(0.5, 2), r.quat<T>(), r.vec3<T>());
    auto const p = r.vec3<T>();
    auto const back = pose.inverse().transform_point3(pose.transform_point3(p));
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      Eigen::Matrix4d ea, eb;
      auto const la = lane(a, i), lb = lane(b, i);
      for (std::size_t p_ = 0; p_ < 4; ++p_)
        for (std::size_t q_ = 0; q_ < 4; ++q_) {
          ea(long(p_), long(q_)) = double(la.at(p_, q_));
          eb(long(p_), long(q_)) = double(lb.at(p_, q_));
        }
      Eigen::Matrix4d ep;
      auto const lab = lane(ab, i), lai = lane(ai, i);
      for (std::size_t p_ = 0; p_ < 4; ++p_)
        for (std::size_t q_ = 0; q_ < 4; ++q_)
          ep(long(p_), long(q_)) = double(lab.at(p_, q_));
      CHECK((ep - ea * eb).norm() <= 8 * eps * ea.norm() * eb.norm());
      double const na = ea.norm();
      CHECK(std::abs(double(lane(det, i)) - ea.determinant()) <= 64 * eps * na * na * na * na);
      CHECK(std::abs(double(lane(dab, i)) - double(lane(det, i)) * double(lane(db, i))) <=
            128 * eps * std::pow(na * eb.norm(), 4));
      Eigen::Matrix4d const einv = ea.inverse();
      double const cond = na * einv.norm();
      if (cond < 1e3) {
        Eigen::Matrix4d pi;
        for (std::size_t p_ = 0; p_ < 4; ++p_)
          for (std::size_t q_ = 0; q_ < 4; ++q_)
            pi(long(p_), long(q_)) = double(lai.at(p_, q_));
        INFO("cond " << cond);
        CHECK((pi - einv).norm() <= 32 * eps * cond * einv.norm());
      }
      CHECK(double((lane(back, i) - lane(p, i)).length()) <= 64 * eps * (lane(p, i).length() + 10));
    }
  }
  GMat4<T> const singular{V4::X, V4::X, V4::Z, V4::W};
  CHECK(plume::none(singular.try_inverse().valid));
  CHECK(plume::all(singular.inverse_or_zero().abs_diff_eq(GMat4<T>::ZERO, zero<T>())));
  CHECK(plume::all(GMat4<T>::IDENTITY.inverse().abs_diff_eq(GMat4<T>::IDENTITY, zero<T>())));
  CHECK(plume::all(GMat4<T>::from_translation(GVec3<T>::ONE)
                       .transform_vector3(GVec3<T>::X)
                       .cmpeq(GVec3<T>::X)
                       .all()));
}

TEMPLATE_LIST_TEST_CASE("vec4 methods", "[math][vec4]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  using V = GVec4<T>;
  double const eps = test::eps_v<S>;
  test::rng r(24);
  for (int it = 0; it < 100; ++it) {
    V const a{r.elem<T>(-5, 5), r.elem<T>(-5, 5), r.elem<T>(-5, 5), r.elem<T>(-5, 5)};
    V const b{r.elem<T>(-5, 5), r.elem<T>(-5, 5), r.elem<T>(-5, 5), r.elem<T>(-5, 5)};
    auto const p = a.project_onto(b), q = a.reject_from(b);
    auto const u = a.normalize();
    auto const cl = a.clamp_length(one<T>(), two<T>());
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      double const la = lane(a, i).length(), lb = lane(b, i).length();
      CHECK(double((lane(p, i) + lane(q, i) - lane(a, i)).length()) <= 8 * eps * la);
      CHECK(std::abs(double(lane(q, i).dot(lane(b, i)))) <= 16 * eps * la * lb);
      CHECK(std::abs(double(lane(u, i).length()) - 1) <= 4 * eps);
      CHECK(double(lane(cl, i).length()) >= 1 - 4 * eps);
      CHECK(double(lane(cl, i).length()) <= 2 + 4 * eps);
    }
    CHECK(plume::all(GVec4<T>::extend(a.truncate(), a.w).cmpeq(a).all()));
  }
  CHECK(plume::none(V::ZERO.try_normalize().valid));
  CHECK(plume::all(V::ZERO.normalize_or(V::W).cmpeq(V::W).all()));
  CHECK(plume::all(V::QNAN.is_nan()));
  CHECK(plume::all(V{one<T>(), -two<T>(), splat<T>(S(3)), zero<T>()}.max_element() ==
                   splat<T>(S(3))));
}
