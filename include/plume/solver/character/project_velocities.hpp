// plume/solver/character/project_velocities.hpp - many velocity projections in one call (a
// crowd's sliding steps, a batch of user problems), run lanes at a time at the widest width of
// the build, or in a PLUME_DISPATCH=ON build at that of the chosen instruction set
// (plume/numerics/isa.hpp). Compiled: link plume::character.
//
//   project_velocities(velocities, normals, offsets, out [, lambda_out] [, cfg])   3D and 2D
//
// Problem i projects velocities[i] against its planes normals[offsets[i] .. offsets[i + 1]):
//  - offsets has velocities.size() + 1 entries, offsets[0] == 0, never decreasing, and the
//    last equal to normals.size() (the compressed layout of a list of lists);
//  - out[i] is, bit for bit, project_velocity<float>(velocities[i], problem i's normals,
//    cfg) (solver/character/velocity_projection.hpp gives the algorithm, the meaning of every
//    field and what bad values in a problem get), on every build and every instruction set;
//  - lambda_out, if not empty, has normals.size() entries and receives each plane's multiplier
//    at the plane's own index, as project_velocity's lambda_out does.
//
// Bad arguments (the call writes nothing and returns the error): out or lambda_out of the
// wrong length or offsets of the wrong length (length_mismatch); offsets not starting at 0,
// decreasing, or not ending at normals.size() (bad_offsets); a problem of more than 2^24
// planes (too_many_planes: plane indices are carried as floats, exact up to 2^24); an output
// that overlaps an input or the other output (overlap); cfg.epsilon negative or NaN
// (bad_config: the padding's zero normals would then count as violated planes). Empty
// batches are fine. Bad values inside a problem (non-finite, out of range) are the single
// call's business: that problem comes back invalid_input, its neighbours in the lanes are
// unaffected. Offsets are 32-bit: a batch holds fewer than 2^32 normals.
//
// The call allocates scratch space for one packet (its largest problem's planes); it is
// noexcept, so running out of memory there terminates.
//
// Speed: problems share packets of lanes in the order of their plane counts (a counting sort
// inside the call), each packet padded with zero normals (which never change a result) to its
// largest count; a packet runs as many steps as its slowest lane. Answers do not depend on
// the packing: each lane is its own problem.
#pragma once

#include <plume/solver/character/velocity_projection.hpp>

#include <cstdint>
#include <span>
#include <string_view>

namespace plume {

/// What project_velocities refused (nothing written).
enum class ProjectVelocitiesError {
  none,
  length_mismatch, ///< out, lambda_out (when not empty) or offsets of the wrong length
  bad_offsets,     ///< offsets not 0-based, decreasing, or not ending at normals.size()
  too_many_planes, ///< a problem of more than 2^24 planes
  overlap,         ///< out or lambda_out overlaps an input or the other output
  bad_config,      ///< cfg.epsilon negative or NaN
};

/// A one-line description of e, for logs.
std::string_view to_string(ProjectVelocitiesError e) noexcept;

/// The 3D batch: out[i] = project_velocity<float>(velocities[i], normals of problem i, cfg).
ProjectVelocitiesError project_velocities(std::span<Vec3 const> velocities,
                                          std::span<Vec3 const> normals,
                                          std::span<std::uint32_t const> offsets,
                                          std::span<VelocityProjection3> out,
                                          std::span<float> lambda_out = {},
                                          VelocityProjectionConfig const& cfg = {}) noexcept;

/// The 2D batch, as the 3D one.
ProjectVelocitiesError project_velocities(std::span<Vec2 const> velocities,
                                          std::span<Vec2 const> normals,
                                          std::span<std::uint32_t const> offsets,
                                          std::span<VelocityProjection2> out,
                                          std::span<float> lambda_out = {},
                                          VelocityProjectionConfig const& cfg = {}) noexcept;

namespace detail {
/// The instruction set of the kernels project_velocities runs now: active_isa() (the tests
/// check that the character floor's tables follow the choice).
Isa character_kernels_isa() noexcept;
} // namespace detail

} // namespace plume
