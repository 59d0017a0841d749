// plume/world.hpp - the world floor (target plume::world): bodies with shapes, the step
// (broad phase, narrow phase and contact cache, the soft-step solver) and its profile.
//
//   World, BodyDef, BodyId, WorldConfig, Contact  (solver/world/world.hpp)
//   TaskSystem, ThreadPool, InlineTasks (the step on threads)  (solver/world/tasks.hpp)
//   SortAndSweep (the broad phase)                (solver/world/broad_phase.hpp)
//   ContactCache, carry_impulses (warm starts)    (solver/world/contact_cache.hpp)
//   WorldMoveQuery (the world as move_and_slide's scene)  (solver/world/move_query.hpp)
//   CharacterController, GroundState, CharacterConfig      (solver/world/character_controller.hpp)
#pragma once

#include <plume/solver/world/broad_phase.hpp>
#include <plume/solver/world/character_controller.hpp>
#include <plume/solver/world/contact_cache.hpp>
#include <plume/solver/world/move_query.hpp>
#include <plume/solver/world/tasks.hpp>
#include <plume/solver/world/world.hpp>
