// plume/collision.hpp - the collision layer: shapes and queries, each generic over the
// element type (lanes = different shapes or rays).
//
//   GSphere GCapsule GCuboid GCylinder GHalfSpace  (collision/shapes.hpp)
//   GRay3, GRayHit, ray_cast, ray_cast_local       (collision/ray_cast.hpp)
#pragma once

#include <plume/collision/ray_cast.hpp>
#include <plume/collision/shapes.hpp>
