// plume/solver.hpp - the constraint solver floor (target plume::solver): constraint kernels
// over the element type, so that W constraints solve per instruction, and the storage they
// run on. Contacts today; joints next, on the same rows and blocks.
//
//   Softness                                      (solver/softness.hpp)
//   ConstraintGraph (the colouring)               (solver/constraint_graph.hpp)
//   BodyState, GBodyState<T>, gather/scatter      (solver/body_state.hpp)
//   GLaneArray, GLaneVec3, GLaneSym3              (solver/lane_storage.hpp)
//   GContactConstraint<T> and its kernels         (solver/contact_constraint.hpp)
//   GConstraintBlocks: overflow + coloured SoA blocks (solver/constraint_blocks.hpp)
#pragma once

#include <plume/solver/body_state.hpp>
#include <plume/solver/constraint_blocks.hpp>
#include <plume/solver/constraint_graph.hpp>
#include <plume/solver/contact_constraint.hpp>
#include <plume/solver/lane_storage.hpp>
#include <plume/solver/softness.hpp>
