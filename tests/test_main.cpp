// Catch2 main for plume's tests: prints the build it is testing first.
#define CATCH_CONFIG_RUNNER
#include <plume/config.hpp>

#include <catch2/catch.hpp>

#include <cstdio>

int main(int argc, char* argv[]) {
  std::printf("plume tests: PLUME_SIMD=%s deterministic=%d fma=%d\n", plume::simd_name,
              int(plume::deterministic), int(plume::fused_mul_add));
  return Catch::Session().run(argc, argv);
}
