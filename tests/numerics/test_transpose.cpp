// load_transposed / store_transposed: every lane and column against a plain loop, rows that
// are null left untouched, at every f32 width of the build.
#include "../common/harness.hpp"
#include "../common/types.hpp"

#include <plume/numerics.hpp>
#include <plume/numerics/transpose.hpp>

#include <catch2/catch.hpp>

#include <array>
#include <tuple>
#include <vector>

using namespace plume;

TEMPLATE_LIST_TEST_CASE("transpose: rows to lanes and back", "[numerics][transpose]",
                        plume::test::f32_types) {
  using T = TestType;
  constexpr std::size_t W = lanes_v<T>, K = 16;
  struct alignas(64) Row {
    std::array<float, K> v;
  };
  std::vector<Row> mem(3 * W);
  for (std::size_t r = 0; r < mem.size(); ++r)
    for (std::size_t k = 0; k < K; ++k)
      mem[r].v[k] = float(r * 100 + k) + 0.25f;
  // Lane i reads row (3 i + 1) % size: scattered, not in order.
  float const* rows[W];
  for (std::size_t i = 0; i < W; ++i)
    rows[i] = mem[(3 * i + 1) % mem.size()].v.data();
  T cols[K];
  load_transposed<T, K>(rows, cols);
  for (std::size_t k = 0; k < K; ++k)
    for (std::size_t i = 0; i < W; ++i)
      CHECK(lane(cols[k], i) == rows[i][k]);

  // Back: negate 8 columns and store them to every other lane's row.
  std::vector<Row> out(W);
  for (auto& r : out)
    r.v.fill(-1.0f);
  float* dst[W];
  for (std::size_t i = 0; i < W; ++i)
    dst[i] = i % 2 == 0 ? out[i].v.data() : nullptr;
  T neg[8];
  for (std::size_t k = 0; k < 8; ++k)
    neg[k] = -cols[k];
  store_transposed<T, 8>(neg, dst);
  for (std::size_t i = 0; i < W; ++i)
    for (std::size_t k = 0; k < K; ++k) {
      float const want = i % 2 == 0 && k < 8 ? -rows[i][k] : -1.0f;
      CHECK(out[i].v[k] == want);
    }
}
