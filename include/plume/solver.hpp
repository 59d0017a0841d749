// plume/solver.hpp - the solver layer: velocity projection, plane sets and depenetration
// (move-and-slide's building blocks), the soft-step contact solver and a minimal rigid-body
// world, each generic over the element type where it runs wide.
//
//   project_velocity, project_velocity_bruteforce (solver/velocity_projection.hpp)
//   PlaneSet3<T>, PlaneSet2<T>                    (solver/plane_set.hpp)
//   depenetrate, Penetration<Vec>                 (solver/depenetration.hpp)
//   Softness                                      (solver/softness.hpp)
//   ConstraintGraph                               (solver/constraint_graph.hpp)
//   BodyState, GBodyState<T>, gather/scatter      (solver/body_state.hpp)
//   GContactConstraint<T> and its kernels         (solver/contact_constraint.hpp)
//   World, BodyDef, WorldConfig, Contact          (solver/world.hpp, compiled: solver/world.cpp)
//   add_ground, add_box_pyramid, add_box_stack... (solver/scenes.hpp)
#pragma once

#include <plume/solver/body_state.hpp>
#include <plume/solver/constraint_graph.hpp>
#include <plume/solver/contact_constraint.hpp>
#include <plume/solver/depenetration.hpp>
#include <plume/solver/plane_set.hpp>
#include <plume/solver/scenes.hpp>
#include <plume/solver/softness.hpp>
#include <plume/solver/velocity_projection.hpp>
#include <plume/solver/world.hpp>
