// plume/plume.hpp - everything plume has.
#pragma once

#include <plume/numerics.hpp>
#include <plume/math.hpp>
#include <plume/solver.hpp>
