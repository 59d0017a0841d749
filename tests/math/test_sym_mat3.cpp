// GSymMat3: the six entries of a symmetric matrix, against the full GMat3 they stand for.
#include "../common/types.hpp"

#include <plume/math/sym_mat3.hpp>

#include <catch2/catch.hpp>

using namespace plume;

TEMPLATE_TEST_CASE("symmetric 3x3: round trip through GMat3, products equal the full matrix's",
                   "[math][sym_mat3]", float, double) {
  using S = TestType;
  GMat3<S> const full = GMat3<S>::from_symmetric(S(2), S(3), S(5), S(0.5), S(-0.25), S(0.75));
  GSymMat3<S> const s = GSymMat3<S>::from_mat3(full);
  CHECK(s.xx == S(2));
  CHECK(s.yy == S(3));
  CHECK(s.zz == S(5));
  CHECK(s.xy == S(0.5));
  CHECK(s.xz == S(-0.25));
  CHECK(s.yz == S(0.75));
  GMat3<S> const back = s.to_mat3();
  for (GVec3<S> const* col : {&back.x_axis, &back.y_axis, &back.z_axis}) {
    GVec3<S> const& want = col == &back.x_axis   ? full.x_axis
                           : col == &back.y_axis ? full.y_axis
                                                 : full.z_axis;
    CHECK((col->x == want.x && col->y == want.y && col->z == want.z));
  }
  // Each row summed left to right, as the header says: exact for these small integers/2^k.
  GVec3<S> const v{S(1), S(-2), S(4)};
  GVec3<S> const p = s * v;
  CHECK(p.x == S(2 * 1 + 0.5 * -2 + -0.25 * 4));
  CHECK(p.y == S(0.5 * 1 + 3 * -2 + 0.75 * 4));
  CHECK(p.z == S(-0.25 * 1 + 0.75 * -2 + 5 * 4));
}
