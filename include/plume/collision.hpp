// plume/collision.hpp - the collision layer: shapes and queries, each generic over the
// element type (lanes = different shapes or rays).
//
//   GSphere GCapsule GCuboid GCylinder GHalfSpace GTriangle GSegment  (collision/shapes.hpp)
//   GMassProperties                                  (collision/mass_properties.hpp)
//   GConvexPolytope, GConvexHull (quickhull)         (collision/convex_hull.hpp)
//   GRay3, GRayHit, ray_cast, ray_cast_local         (collision/ray_cast.hpp)
//   closest_points, shape_cast, ray_cast_gjk         (collision/gjk.hpp)
//   penetration (GJK + EPA; scalar)                  (collision/epa.hpp)
//   contact_manifold, GManifold (scalar)             (collision/manifold.hpp)
#pragma once

#include <plume/collision/convex_hull.hpp>
#include <plume/collision/epa.hpp>
#include <plume/collision/gjk.hpp>
#include <plume/collision/manifold.hpp>
#include <plume/collision/mass_properties.hpp>
#include <plume/collision/ray_cast.hpp>
#include <plume/collision/shapes.hpp>
