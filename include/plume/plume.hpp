// plume/plume.hpp - everything plume has: every floor's umbrella header (docs/architecture.md).
#pragma once

#include <plume/character.hpp>
#include <plume/collision.hpp>
#include <plume/dispatch.hpp>
#include <plume/math.hpp>
#include <plume/numerics.hpp>
#include <plume/solver.hpp>
#include <plume/spatial.hpp>
#include <plume/world.hpp>
