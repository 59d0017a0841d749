// plume/character.hpp - the character floor (target plume::character): moving a shape
// through a set of contact planes, generic over the element type so that one call moves a
// lane of characters at once. It asks nothing of the world or the contact solver.
//
//   project_velocity, project_velocity_bruteforce (solver/character/velocity_projection.hpp)
//   GPlaneSet3<T>, GPlaneSet2<T>                  (solver/character/plane_set.hpp)
//   depenetrate, GPenetration<Vec>                (solver/character/depenetration.hpp)
#pragma once

#include <plume/solver/character/depenetration.hpp>
#include <plume/solver/character/plane_set.hpp>
#include <plume/solver/character/velocity_projection.hpp>
