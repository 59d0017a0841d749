// plume/spatial.hpp - the spatial layer: bounding volume hierarchies and the queries on them.
//
//   GAabbTree, AabbTree, ProxyId, TreeOptimization, GTreeConfig   (spatial/aabb_tree.hpp)
//   GWideBvh, WideBvh, GTreeRayHit                                (spatial/wide_bvh.hpp)
//   TriangleMesh, MeshRayHit, EdgeKind, MeshError                 (spatial/triangle_mesh.hpp)
//   HeightField, HeightFieldError                                 (spatial/height_field.hpp)
//   mesh_contacts, mesh_shape_cast, mesh_overlaps, MeshContacts   (spatial/mesh_queries.hpp)
#pragma once

#include <plume/spatial/aabb_tree.hpp>
#include <plume/spatial/height_field.hpp>
#include <plume/spatial/mesh_queries.hpp>
#include <plume/spatial/triangle_mesh.hpp>
#include <plume/spatial/wide_bvh.hpp>
