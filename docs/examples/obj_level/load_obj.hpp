// load_obj.hpp - a TriangleMesh from a Wavefront OBJ file, through tinyobjloader (Debian's
// libtinyobjloader-dev). Part of plume's OBJ example, not of the library: copy it into a
// project that loads its levels from OBJ files.
//
//   ObjMesh level = load_obj_mesh("level.obj");
//   if (!level.error.empty()) fail(level.error);   // unreadable file, or a MeshError
//   TriangleMesh const& mesh = level.built.mesh;    // level.built.degenerate were dropped
//
// Every object and group of the file goes into one mesh, polygons triangulated by
// tinyobjloader (fans); positions only (normals, texture coordinates and materials are
// ignored). The vertices are the file's, shared as the file shares them, so the mesh's edge
// adjacency (internal edges, ghost-bump correction) sees which faces meet.
#pragma once

#include <plume/spatial/triangle_mesh.hpp>

#include <tiny_obj_loader.h>

#include <cstdint>
#include <string>
#include <vector>

namespace plume_example {

struct ObjMesh {
  std::string error;            ///< empty when the file was read and the mesh built
  std::string warning;          ///< tinyobjloader's warnings (unsupported statements, ...)
  plume::MeshBuildResult built; ///< the mesh, and what TriangleMesh::build counted
};

inline ObjMesh load_obj_mesh(std::string const& path) {
  ObjMesh out;
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config)) {
    out.error = "cannot read " + path + ": " + reader.Error();
    return out;
  }
  out.warning = reader.Warning();
  std::vector<float> const& xyz = reader.GetAttrib().vertices;
  std::vector<plume::Vec3> vertices;
  vertices.reserve(xyz.size() / 3);
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3)
    vertices.push_back({xyz[i], xyz[i + 1], xyz[i + 2]});
  std::vector<std::uint32_t> indices;
  for (tinyobj::shape_t const& shape : reader.GetShapes())
    for (tinyobj::index_t const& index : shape.mesh.indices) {
      if (index.vertex_index < 0) { // tinyobjloader resolves relative indices: not expected
        out.error = path + ": a face refers to no vertex";
        return out;
      }
      indices.push_back(std::uint32_t(index.vertex_index));
    }
  out.built = plume::TriangleMesh::build(vertices, indices); // validates: NaN, range, empty
  if (!out.built.ok())
    out.error = path + ": " + plume::to_string(out.built.error) + " (item " +
                std::to_string(out.built.bad_item) + ")";
  return out;
}

} // namespace plume_example
