// plume/spatial.hpp - the spatial layer: bounding volume hierarchies and the queries on them.
//
//   GAabbTree, AabbTree, ProxyId, TreeOptimization, GTreeConfig   (spatial/aabb_tree.hpp)
//   GWideBvh, WideBvh, GTreeRayHit                                (spatial/wide_bvh.hpp)
#pragma once

#include <plume/spatial/aabb_tree.hpp>
#include <plume/spatial/triangle_mesh.hpp>
#include <plume/spatial/wide_bvh.hpp>
