// tests/dispatch/each_isa.hpp - the dispatch tests' loop over instruction sets.
#pragma once

#include <plume/numerics/isa.hpp>

#include <catch2/catch.hpp>

namespace plume::test {

/// Restores the default choice (the best set) when a test that switched ends.
struct RestoreBest {
  RestoreBest() = default;
  RestoreBest(RestoreBest const&) = delete;
  RestoreBest& operator=(RestoreBest const&) = delete;
  ~RestoreBest() { (void)set_isa(best_isa()); }
};

/// Calls f(isa) with each set this binary carries chosen in turn by set_isa (a set this CPU or
/// its OS lacks is reported as skipped, with the reason), then restores the default choice,
/// also when f throws (a failed REQUIRE). Returns how many sets ran: at least one always does
/// (the best set), which the callers check.
template <class F>
int for_each_runnable_isa(F&& f) {
  RestoreBest const restore;
  int ran = 0;
  for (Isa const isa : compiled_isas()) {
    if (!cpu_has(isa)) {
      WARN("skipped " << isa_name(isa) << ": this CPU (or its OS) lacks it");
      continue;
    }
    REQUIRE(set_isa(isa) == IsaError::none);
    REQUIRE(active_isa() == isa);
    INFO("isa " << isa_name(isa));
    f(isa);
    ++ran;
  }
  return ran;
}

} // namespace plume::test
