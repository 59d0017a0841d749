// One function-object type per plume function, so that a test calling plume::sin in forty
// places instantiates (and the compiler inlines) it once per element type, not forty times.
#pragma once

#include <plume/numerics.hpp>

namespace plume::test::fn {
#define PLUME_TEST_FUNCTOR(name)                                                                   \
  struct name {                                                                                    \
    template <class V>                                                                             \
    PLUME_NOINLINE V operator()(V a) const {                                                       \
      return plume::name(a);                                                                       \
    }                                                                                              \
    template <class V>                                                                             \
    PLUME_NOINLINE V operator()(V a, V b) const {                                                  \
      return plume::name(a, b);                                                                    \
    }                                                                                              \
  };
PLUME_TEST_FUNCTOR(sin)
PLUME_TEST_FUNCTOR(cos)
PLUME_TEST_FUNCTOR(tan)
PLUME_TEST_FUNCTOR(asin)
PLUME_TEST_FUNCTOR(acos)
PLUME_TEST_FUNCTOR(atan)
PLUME_TEST_FUNCTOR(atan2)
PLUME_TEST_FUNCTOR(exp)
PLUME_TEST_FUNCTOR(exp2)
PLUME_TEST_FUNCTOR(expm1)
PLUME_TEST_FUNCTOR(log)
PLUME_TEST_FUNCTOR(log2)
PLUME_TEST_FUNCTOR(log1p)
PLUME_TEST_FUNCTOR(pow)
PLUME_TEST_FUNCTOR(hypot)
#undef PLUME_TEST_FUNCTOR
} // namespace plume::test::fn
