// plume/plume.hpp - everything plume has.
#pragma once

#include <plume/numerics.hpp>
#include <plume/math.hpp>
#include <plume/collision.hpp>
#include <plume/solver.hpp>
