// plume/solver.hpp - the solver layer: velocity projection, plane sets and depenetration
// (move-and-slide's building blocks), each generic over the element type.
//
//   project_velocity, project_velocity_bruteforce (solver/velocity_projection.hpp)
//   PlaneSet3<T>, PlaneSet2<T>                    (solver/plane_set.hpp)
//   depenetrate, Penetration<Vec>                 (solver/depenetration.hpp)
#pragma once

#include <plume/solver/depenetration.hpp>
#include <plume/solver/plane_set.hpp>
#include <plume/solver/velocity_projection.hpp>
