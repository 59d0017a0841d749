// Compiled (never linked) by the fast_math_refused and fast_math_absent_compiles tests:
// plume's headers must refuse -ffast-math and compile without it.
#include <plume/config.hpp>
