// plume/plume.hpp - everything plume has, floor by floor (docs/architecture.md).
#pragma once

#include <plume/numerics.hpp>
#include <plume/math.hpp>
#include <plume/collision.hpp>
#include <plume/character.hpp>
#include <plume/solver.hpp>
#include <plume/world.hpp>
