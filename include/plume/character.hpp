// plume/character.hpp - the character floor (target plume::character): moving a shape
// through a set of contact planes, generic over the element type so that one call moves a
// lane of characters at once, and move_and_slide, which moves a shape through any scene that
// models MoveQuery (the world's is WorldMoveQuery, in the world floor). It asks nothing of
// the world or the contact solver.
//
// Every template over the element type T (or a vector of it) is G<Name>; the plain name is
// the float form, D<Name> the double form. Configurations' scaled(length_unit) const gives
// the configuration with every length-valued field multiplied by length_unit.
//
//   project_velocity, project_velocity_bruteforce        (solver/character/velocity_projection.hpp)
//     GVelocityProjectionConfig<S>  VelocityProjectionConfig, DVelocityProjectionConfig
//     GVelocityProjection<Vec>      VelocityProjection3, VelocityProjection2 (results)
//   project_velocities: many float projections in one call, in lanes (compiled; dispatched
//     per instruction set)  ProjectVelocitiesError      (solver/character/project_velocities.hpp)
//   GPlaneSet3<T>, GPlaneSet2<T>  PlaneSet3, PlaneSet2, DPlaneSet3, DPlaneSet2
//     GPlaneSet<Vec>, GPlaneSetConfig<S>  PlaneSetConfig, DPlaneSetConfig
//                                                        (solver/character/plane_set.hpp)
//   depenetrate                                          (solver/character/depenetration.hpp)
//     GPenetration<Vec>             Penetration3, Penetration2 (input pairs)
//     GDepenetration<Vec>           Depenetration3, Depenetration2 (results)
//     GDepenetrationConfig<S>       DepenetrationConfig, DDepenetrationConfig
//   move_and_slide, cast_move, intersections, depenetrate(query, ...)
//                                                        (solver/character/move_and_slide.hpp)
//     MoveQuery (the scene concept)  MoveCastHit<Id>, MoveContact<Id> (what a scene answers)
//     MoveAndSlideConfig            MoveAndSlideResult<Id>, MoveHit<Id>, HitResponse
//   ColliderSetQuery<Shape>, Collider, ColliderShape, ColliderFilter: a user's span of
//     colliders as a scene                               (solver/character/collider_set.hpp)
#pragma once

#include <plume/solver/character/collider_set.hpp>
#include <plume/solver/character/depenetration.hpp>
#include <plume/solver/character/move_and_slide.hpp>
#include <plume/solver/character/plane_set.hpp>
#include <plume/solver/character/project_velocities.hpp>
#include <plume/solver/character/velocity_projection.hpp>
