// plume/math.hpp - the geometry layer: generic vectors, quaternions and matrices.
//
//   GVec3<T> (vec3.hpp)  GBVec3<M> (bvec3.hpp)  GQuat<T> (quat.hpp)  GMat3<T> (mat3.hpp)
// Each works for scalar and wide element types with one code path; aliases Vec3, DVec3,
// Vec3x8, Vec3xN, Quat, Mat3x4, ... name the common instantiations.
#pragma once

#include <plume/math/bvec3.hpp>
#include <plume/math/mat3.hpp>
#include <plume/math/quat.hpp>
#include <plume/math/vec3.hpp>
