// plume/dispatch.hpp - one binary for every CPU: what a PLUME_DISPATCH=ON build dispatches and
// how to choose the instruction set (also part of <plume/numerics.hpp>).
//
//   Isa, set_isa, active_isa, best_isa, cpu_has, compiled_isas   (numerics/isa.hpp)
//   sin, cos, ..., pow, sincos over std::span; SpanError          (numerics/spans.hpp)
//   project_velocities (batch velocity projection) (solver/character/project_velocities.hpp)
//   World::step, the batch World::ray_cast and World::shape_cast  (solver/world/world.hpp)
//     (and through them WorldMoveQuery::cast_lanes, the sweeps of move_and_slide_lanes)
#pragma once

#include <plume/numerics/isa.hpp>
#include <plume/numerics/spans.hpp>
#include <plume/solver/character/project_velocities.hpp>
