// tools/kernel_loops.cpp - plume's hot wide kernels, each alone in a loop over arrays, for
// tools/kernel_loops.py to compile with a build's own flags and read the generated code of:
// instructions, stack references and calls per iteration of each loop. A wide kernel whose
// loop references the stack (beyond reloads of a few hoisted constants) or calls out of line
// has a register or inlining problem worth a look.
//
// k_<kernel>_x<width>(...) for every f32 width of the build: x1 (float), x4, x8, x16.
#include <plume/collision.hpp>
#include <plume/math.hpp>

#include <cstddef>

using namespace plume;

/// One loop per kernel over SoA-packed inputs (one element = one batch of lanes); restrict
/// pointers, so that the loop body is the kernel and nothing else.
#define PLUME_KERNEL_LOOP(name, W, T, R, expr)                                                     \
  extern "C" void k_##name##_##W(                                                                  \
      GVec3<T> const* __restrict o, GVec3<T> const* __restrict d, GVec3<T> const* __restrict c,    \
      GVec3<T> const* __restrict e, T const* __restrict r, T const* __restrict h,                  \
      GQuat<T> const* __restrict q, GQuat<T> const* __restrict q2,                                 \
      GAabb3<T> const* __restrict box, R* __restrict out, std::size_t n) {                         \
    T const inf = infinity<T>();                                                                   \
    (void)o, (void)d, (void)c, (void)e, (void)r, (void)h, (void)q, (void)q2, (void)box;            \
    (void)inf;                                                                                     \
    for (std::size_t i = 0; i < n; ++i)                                                            \
      out[i] = expr;                                                                               \
  }

#define PLUME_KERNEL_LOOPS(W, T)                                                                   \
  PLUME_KERNEL_LOOP(ray_sphere, W, T, GRayHit<T>,                                                  \
                    ray_cast_local(GSphere<T>{r[i]}, GRay3<T>{o[i] - c[i], d[i]}, inf))            \
  PLUME_KERNEL_LOOP(ray_aabb, W, T, GRayHit<T>, ray_cast(box[i], GRay3<T>{o[i], d[i]}, inf))       \
  PLUME_KERNEL_LOOP(ray_capsule, W, T, GRayHit<T>,                                                 \
                    ray_cast_local(GCapsule<T>{h[i], r[i]}, GRay3<T>{o[i] - c[i], d[i]}, inf))     \
  PLUME_KERNEL_LOOP(ray_cylinder, W, T, GRayHit<T>,                                                \
                    ray_cast_local(GCylinder<T>{h[i], r[i]}, GRay3<T>{o[i] - c[i], d[i]}, inf))    \
  PLUME_KERNEL_LOOP(ray_oriented_box, W, T, GRayHit<T>,                                            \
                    ray_cast(GCuboid<T>{e[i]}, GIso3<T>{q[i], c[i]}, GRay3<T>{o[i], d[i]}, inf))   \
  PLUME_KERNEL_LOOP(                                                                               \
      ray_triangle, W, T, GRayHit<T>,                                                              \
      ray_cast_local(GTriangle<T>{c[i], c[i] + e[i], o[i] - e[i]}, GRay3<T>{o[i], d[i]}, inf))     \
  PLUME_KERNEL_LOOP(quat_rotate, W, T, GVec3<T>, q[i] * o[i])                                      \
  PLUME_KERNEL_LOOP(quat_mul, W, T, GQuat<T>, q[i] * q2[i])                                        \
  PLUME_KERNEL_LOOP(quat_slerp, W, T, GQuat<T>, q[i].slerp(q2[i], r[i]))                           \
  PLUME_KERNEL_LOOP(vec3_normalize, W, T, GVec3<T>, o[i].normalize())                              \
  PLUME_KERNEL_LOOP(mat3_mul_vec3, W, T, GVec3<T>, GMat3<T>::from_quat(q[i]) * o[i])               \
  PLUME_KERNEL_LOOP(asin, W, T, T, plume::asin(r[i]))                                              \
  PLUME_KERNEL_LOOP(acos, W, T, T, plume::acos(r[i]))                                              \
  PLUME_KERNEL_LOOP(pow, W, T, T, plume::pow(r[i], h[i]))

#define PLUME_KERNEL_LOOPS_OF(T, lanes) PLUME_KERNEL_LOOPS(x##lanes, T)
PLUME_FOR_EACH_F32_TYPE(PLUME_KERNEL_LOOPS_OF)
