// plume/math.hpp - the geometry layer: generic vectors, quaternions and matrices.
//
//   GVec3<T> (vec3.hpp)  GBVec3<M> (bvec3.hpp)  GQuat<T> (quat.hpp)  GMat3<T> (mat3.hpp)
//   GIso3<T> (iso3.hpp)  GDir3<T> (dir3.hpp)    GAabb3<T> (aabb3.hpp) AoS <-> SoA (pack.hpp)
//   GSymMat3<T> (sym_mat3.hpp: symmetric 3x3, six entries)
//   4D: GVec4<T> GBVec4<M> GMat4<T> (vec4.hpp, mat4.hpp)
//   2D: GVec2<T> GBVec2<M> GMat2<T> GRot2<T> GIso2<T> GAabb2<T> (vec2.hpp, ... aabb2.hpp)
// Eigen conversions: <plume/math/eigen.hpp> (not included here).
// Each works for scalar and wide element types with one code path; aliases Vec3, DVec3,
// Vec3xN (the widest), Quat, DMat3, ... name the common instantiations; a fixed width is
// spelled out: GVec3<f32x8>.
#pragma once

#include <plume/math/aabb2.hpp>
#include <plume/math/aabb3.hpp>
#include <plume/math/bvec2.hpp>
#include <plume/math/bvec3.hpp>
#include <plume/math/dir3.hpp>
#include <plume/math/iso2.hpp>
#include <plume/math/iso3.hpp>
#include <plume/math/mat2.hpp>
#include <plume/math/mat3.hpp>
#include <plume/math/mat4.hpp>
#include <plume/math/pack.hpp>
#include <plume/math/quat.hpp>
#include <plume/math/rot2.hpp>
#include <plume/math/sym_mat3.hpp>
#include <plume/math/vec2.hpp>
#include <plume/math/vec3.hpp>
#include <plume/math/vec4.hpp>
