// solver/character/character_kernels.hpp - the table of the character floor's array kernels
// that one instruction set provides (private to the floor): character_kernels.cpp fills one
// per carried set of a PLUME_DISPATCH=ON build (else one, the build's own), and
// project_velocities.cpp calls through the active one.
#pragma once

#include <plume/solver/character/velocity_projection.hpp>

#include <cstddef>
#include <cstdint>

namespace plume::detail {

/// project_velocities over n problems whose arguments project_velocities.cpp has checked;
/// lambda is null when the caller wants no multipliers.
template <class Vec>
using project_batch_fn = void (*)(Vec const* velocities, std::size_t n, Vec const* normals,
                                  std::uint32_t const* offsets, VelocityProjectionConfig const& cfg,
                                  GVelocityProjection<Vec>* out, float* lambda) noexcept;

struct CharacterKernels {
  Isa isa;        // the set the kernels were compiled for
  unsigned lanes; // lanes of the float batch they run on
  project_batch_fn<Vec3> project3;
  project_batch_fn<Vec2> project2;
};

} // namespace plume::detail

// Each character_kernels.cpp object defines its table's accessor
// `extern "C" CharacterKernels const* plume_character_table_<suffix>() noexcept` (suffix: the
// set's name, or static_build): in a PLUME_DISPATCH=ON build the one global symbol of its
// isolated object (cmake/PlumeDispatch.cmake).
