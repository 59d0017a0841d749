// GIso3, GDir3, GAabb3, AoS <-> SoA packing and the Eigen interop header.
#include "math_support.hpp"

#include <plume/math/aabb3.hpp>
#include <plume/math/dir3.hpp>
#include <plume/math/iso3.hpp>
#include <plume/math/pack.hpp>

#include <plume/math/eigen.hpp>

using namespace plume;

TEMPLATE_LIST_TEST_CASE("isometries compose and invert", "[math][iso3]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  double const eps = test::eps_v<S>;
  test::rng r(11);
  for (int it = 0; it < 200; ++it) {
    GIso3<T> const a{r.quat<T>(), r.vec3<T>()}, b{r.quat<T>(), r.vec3<T>()};
    auto const p = r.vec3<T>();
    auto const ab_p = (a * b) * p, a_b_p = a * (b * p);
    auto const back = a.inverse_transform_point(a.transform_point(p));
    auto const via_inverse = a.inverse() * (a * p);
    auto const rel = a.inv_mul(b).transform_point(p), rel2 = (a.inverse() * b).transform_point(p);
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      double const scale =
          32 * eps *
          (lane(p, i).length() + lane(a.translation, i).length() + lane(b.translation, i).length());
      INFO("a = " << lane(a, i) << ", b = " << lane(b, i) << ", p = " << lane(p, i));
      CHECK(double((lane(ab_p, i) - lane(a_b_p, i)).length()) <= scale);
      CHECK(double((lane(back, i) - lane(p, i)).length()) <= scale);
      CHECK(double((lane(via_inverse, i) - lane(p, i)).length()) <= scale);
      CHECK(double((lane(rel, i) - lane(rel2, i)).length()) <= scale);
    }
    // Vectors ignore the translation.
    auto const v = a.transform_vector(p) - (a.transform_point(p) - a.translation);
    for (std::size_t i = 0; i < lanes_v<T>; ++i)
      CHECK(double(lane(v, i).length()) <=
            8 * eps * (lane(p, i).length() + lane(a.translation, i).length()));
  }
}

TEMPLATE_LIST_TEST_CASE("directions are checked", "[math][dir3]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  using V = GVec3<T>;
  using D = GDir3<T>;
  double const eps = test::eps_v<S>;
  auto const ok = D::try_new(V{splat<T>(S(3)), splat<T>(S(4)), zero<T>()});
  CHECK(plume::all(ok.valid));
  CHECK(plume::all(plume::abs(ok.value.x() - splat<T>(S(0.6))) <= splat<T>(S(2 * eps))));
  for (V const& bad : {V::ZERO, V::QNAN, V::INF}) {
    auto const c = D::try_new(bad);
    CHECK(plume::none(c.valid));
    CHECK(plume::all(c.value.as_vec3().cmpeq(V::X).all())); // documented fallback
  }
  if constexpr (ScalarReal<T>) {
    CHECK(!D::new_checked(V::ZERO).has_value());
    CHECK(D::new_checked(V::Y).has_value());
  }
  // renormalize pulls a drifted direction back to unit length (error squared).
  auto const drift = D::from_unchecked(V{splat<T>(S(1.0005)), zero<T>(), zero<T>()}).renormalize();
  CHECK(plume::all(plume::abs(drift.as_vec3().length() - one<T>()) <=
                   splat<T>(S(1e-6) + S(4 * eps))));
  // Rotating a direction keeps it unit; slerp of directions stays unit.
  test::rng r(12);
  for (int it = 0; it < 50; ++it) {
    auto const q = r.quat<T>();
    D const a = D::from_unchecked(r.unit3<T>()), b = D::from_unchecked(r.unit3<T>());
    auto const qa = q * a;
    auto const s = a.slerp(b, r.elem<T>(0, 1));
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      CHECK(std::abs(double(lane(qa.as_vec3(), i).length()) - 1) <= 8 * eps);
      CHECK(std::abs(double(lane(s.as_vec3(), i).length()) - 1) <= 64 * eps);
    }
  }
}

TEMPLATE_LIST_TEST_CASE("axis-aligned boxes", "[math][aabb3]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  using V = GVec3<T>;
  using B = GAabb3<T>;
  double const eps = test::eps_v<S>;
  B const unit = B::from_center_half_extents(V::ZERO, V::ONE);
  CHECK(plume::all(unit.is_valid()));
  CHECK(plume::none(B::EMPTY.is_valid()));
  CHECK(plume::all(unit.volume() == splat<T>(S(8))));
  CHECK(plume::all(unit.surface_area() == splat<T>(S(24))));
  CHECK(plume::all(unit.contains(V::ONE))); // closed faces
  CHECK(plume::none(unit.contains(V::ONE * splat<T>(S(1.0001)))));
  CHECK(plume::none(unit.contains(V::QNAN))); // NaN is never inside
  B const touching = B::from_center_half_extents(V::X * two<T>(), V::ONE);
  CHECK(plume::all(unit.intersects(touching)));
  CHECK(plume::none(unit.intersects(touching.grow(splat<T>(S(-0.01))))));
  CHECK(plume::all(B::EMPTY.merge(unit).center().cmpeq(V::ZERO).all()));
  CHECK(plume::all(unit.merge(touching).contains_aabb(touching)));
  // from_points holds every point; from_obb and transformed hold every corner.
  test::rng r(13);
  for (int it = 0; it < 50; ++it) {
    std::array<V, 8> pts;
    for (auto& p : pts)
      p = r.vec3<T>();
    B const b = B::from_points(pts);
    for (auto const& p : pts)
      CHECK(plume::all(b.contains(p)));
    GIso3<T> const pose{r.quat<T>(), r.vec3<T>()};
    V const h = r.vec3<T>(0.1, 3);
    B const ob = B::from_obb(pose, h).grow(splat<T>(S(64 * eps * 20)));
    B const tb =
        B::from_center_half_extents(V::ZERO, h).transformed(pose).grow(splat<T>(S(64 * eps * 20)));
    for (int c = 0; c < 8; ++c) {
      V const corner{(c & 1) ? h.x : -h.x, (c & 2) ? h.y : -h.y, (c & 4) ? h.z : -h.z};
      V const w = pose.transform_point(corner);
      CHECK(plume::all(ob.contains(w)));
      CHECK(plume::all(tb.contains(w)));
    }
    // The bound is tight: some corner touches each face of from_obb (within rounding).
    V const he = B::from_obb(pose, h).half_extents();
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      double best = 0;
      for (int c = 0; c < 8; ++c) {
        auto const hi = lane(h, i);
        GVec3<S> const corner{(c & 1) ? hi.x : -hi.x, (c & 2) ? hi.y : -hi.y,
                              (c & 4) ? hi.z : -hi.z};
        best = std::max(best, double((lane(pose, i).rotation * corner).x));
      }
      CHECK(std::abs(best - double(lane(he, i).x)) <= 64 * eps * 10);
    }
  }
  // Capsules and spheres.
  B const cap = B::from_capsule(V::NEG_X, V::X, half<T>());
  CHECK(
      plume::all(cap.min.cmpeq(V{splat<T>(S(-1.5)), splat<T>(S(-0.5)), splat<T>(S(-0.5))}).all()));
  CHECK(plume::all(B::from_sphere(V::ONE, one<T>()).volume() == splat<T>(S(8))));
}

TEMPLATE_LIST_TEST_CASE("packing between arrays of vectors and wide vectors", "[math][pack]",
                        test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  constexpr std::size_t L = lanes_v<T>;
  std::vector<GVec3<S>> aos(L + 3);
  for (std::size_t i = 0; i < aos.size(); ++i)
    aos[i] = {S(i), S(10 + i), S(-S(i))};
  for (std::size_t n = 0; n <= L; ++n) {
    auto const v = pack<T>(aos.data(), n, GVec3<S>{S(7), S(7), S(7)});
    for (std::size_t i = 0; i < L; ++i)
      CHECK(test::same(lane(v, i), i < n ? aos[i] : GVec3<S>{S(7), S(7), S(7)}));
    std::vector<GVec3<S>> out(L + 1, GVec3<S>{S(-9), S(-9), S(-9)});
    unpack(v, out.data(), n);
    for (std::size_t i = 0; i <= L; ++i)
      CHECK(test::same(out[i], i < n ? aos[i] : GVec3<S>{S(-9), S(-9), S(-9)}));
    auto const m = tail_mask<T>(n);
    for (std::size_t i = 0; i < L; ++i)
      CHECK(plume::lane(m, i) == (i < n));
  }
  // Strided: vectors inside a larger struct.
  struct body {
    double mass;
    S pos[3];
    int id;
  };
  std::vector<body> bodies(L);
  for (std::size_t i = 0; i < L; ++i)
    bodies[i] = {1.0, {S(i), S(2 * i), S(3 * i)}, int(i)};
  auto const sv = pack_strided<T>(&bodies[0].pos, sizeof(body));
  for (std::size_t i = 0; i < L; ++i)
    CHECK(test::same(lane(sv, i), GVec3<S>{S(i), S(2 * i), S(3 * i)}));
  // Separate x/y/z arrays, aligned and with a tail.
  alignas(64) S xs[L], ys[L], zs[L];
  for (std::size_t i = 0; i < L; ++i)
    xs[i] = S(i), ys[i] = S(i) + S(0.5), zs[i] = -S(i);
  auto const soa = load_soa_aligned<T>(xs, ys, zs);
  auto const part = load_soa<T>(xs, ys, zs, L > 1 ? L - 1 : 1);
  for (std::size_t i = 0; i < L; ++i) {
    CHECK(test::same(lane(soa, i), GVec3<S>{xs[i], ys[i], zs[i]}));
    if (i < (L > 1 ? L - 1 : 1))
      CHECK(test::same(lane(part, i), GVec3<S>{xs[i], ys[i], zs[i]}));
    else
      CHECK(test::same(lane(part, i), GVec3<S>{}));
  }
  alignas(64) S ox[L], oy[L], oz[L];
  store_soa_aligned(soa, ox, oy, oz);
  for (std::size_t i = 0; i < L; ++i)
    CHECK((ox[i] == xs[i] && oy[i] == ys[i] && oz[i] == zs[i]));
  // Quaternions.
  std::vector<GQuat<S>> qs(L);
  for (std::size_t i = 0; i < L; ++i)
    qs[i] = GQuat<S>::from_rotation_z(S(i));
  auto const qw = pack<T>(qs.data());
  std::vector<GQuat<S>> qo(L);
  unpack(qw, qo.data());
  for (std::size_t i = 0; i < L; ++i)
    CHECK(test::same(qo[i], qs[i]));
}

TEMPLATE_TEST_CASE("Eigen interop round trips and zero-copy views", "[math][eigen]", float,
                   double) {
  using S = TestType;
  GVec3<S> v{S(1), S(2), S(3)};
  CHECK(test::same(from_eigen(to_eigen(v)), v));
  as_eigen(v) *= S(2);
  CHECK(test::same(v, GVec3<S>{S(2), S(4), S(6)}));
  GQuat<S> const q = GQuat<S>::from_axis_angle(GVec3<S>::Y, S(0.5));
  CHECK(test::same(from_eigen(to_eigen(q)), q));
  // Eigen's rotation of v equals plume's within a few ulps.
  Eigen::Matrix<S, 3, 1> const ev = to_eigen(q) * to_eigen(v);
  auto const pv = q * v;
  CHECK((ev - to_eigen(pv)).norm() <= 16 * test::eps_v<S> * to_eigen(v).norm());
  GMat3<S> m = GMat3<S>::from_quat(q);
  CHECK(test::same(from_eigen(to_eigen(m)), m));
  CHECK(as_eigen(m)(0, 2) == m.at(0, 2));
  as_eigen(m)(1, 0) = S(42);
  CHECK(m.x_axis.y == S(42));
  // 2D and 4D.
  GVec2<S> v2{S(1), S(-2)};
  CHECK(test::same(from_eigen(to_eigen(v2)), v2));
  as_eigen(v2)(1) = S(5);
  CHECK(v2.y == S(5));
  GVec4<S> v4{S(1), S(2), S(3), S(4)};
  CHECK(test::same(from_eigen(to_eigen(v4)), v4));
  GMat2<S> const m2 = GRot2<S>::from_angle(S(0.3)).to_mat2();
  CHECK(test::same(from_eigen(to_eigen(m2)), m2));
  CHECK((to_eigen(m2) * to_eigen(v2) - to_eigen(m2 * v2)).norm() <=
        8 * test::eps_v<S> * to_eigen(v2).norm());
  GMat4<S> m4 = GMat4<S>::from_rotation_translation(q, GVec3<S>{S(1), S(2), S(3)});
  CHECK(test::same(from_eigen(to_eigen(m4)), m4));
  CHECK(as_eigen(m4)(1, 3) == S(2));                             // translation in column 3
  Eigen::Matrix<S, 4, 1> const e4 = to_eigen(m4) * to_eigen(v4); // not auto: Eigen expression
  CHECK((e4 - to_eigen(m4 * v4)).norm() <= 16 * test::eps_v<S> * to_eigen(v4).norm() * 4);
}
