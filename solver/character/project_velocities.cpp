// solver/character/project_velocities.cpp - project_velocities
// (include/plume/solver/character/project_velocities.hpp): the checks, then one call of the
// active instruction set's kernel (character_kernels.cpp; the choice: numerics/isa.cpp).
#include "character_kernels.hpp"

#include <plume/solver/character/project_velocities.hpp>
#include <plume_dispatch_list.hpp>

#include <cstdint>
#include <utility>

#define PLUME_DECLARE_TABLE(suffix)                                                                \
  extern "C" plume::detail::CharacterKernels const* plume_character_table_##suffix() noexcept;
PLUME_DISPATCH_LIST(PLUME_DECLARE_TABLE)
#undef PLUME_DECLARE_TABLE

namespace plume {

namespace {

using Accessor = detail::CharacterKernels const* (*)() noexcept;
#define PLUME_ACCESSOR(suffix) &plume_character_table_##suffix,
constexpr Accessor accessors[] = {PLUME_DISPATCH_LIST(PLUME_ACCESSOR)};
#undef PLUME_ACCESSOR

detail::CharacterKernels const& kernels() noexcept {
  return *accessors[detail::active_isa_index()]();
}

// True if the byte ranges [p, p + n) and [q, q + m) overlap (compared as addresses: ordering
// pointers into different arrays is not defined in C++).
bool overlap(void const* p, std::size_t n, void const* q, std::size_t m) noexcept {
  auto const a = reinterpret_cast<std::uintptr_t>(p), b = reinterpret_cast<std::uintptr_t>(q);
  return n != 0 && m != 0 && a < b + m && b < a + n;
}

template <class Vec>
ProjectVelocitiesError check(std::span<Vec const> velocities, std::span<Vec const> normals,
                             std::span<std::uint32_t const> offsets,
                             std::span<GVelocityProjection<Vec>> out, std::span<float> lambda_out,
                             VelocityProjectionConfig const& cfg) noexcept {
  if (out.size() != velocities.size() || offsets.size() != velocities.size() + 1 ||
      (!lambda_out.empty() && lambda_out.size() != normals.size()))
    return ProjectVelocitiesError::length_mismatch;
  if (offsets.front() != 0 || offsets.back() != normals.size())
    return ProjectVelocitiesError::bad_offsets;
  for (std::size_t i = 1; i < offsets.size(); ++i) {
    if (offsets[i] < offsets[i - 1]) return ProjectVelocitiesError::bad_offsets;
    if (offsets[i] - offsets[i - 1] > (1u << 24)) return ProjectVelocitiesError::too_many_planes;
  }
  for (auto const& [p, n] :
       {std::pair<void const*, std::size_t>{velocities.data(), velocities.size_bytes()},
        {normals.data(), normals.size_bytes()},
        {offsets.data(), offsets.size_bytes()},
        {lambda_out.data(), lambda_out.size_bytes()}})
    if (overlap(out.data(), out.size_bytes(), p, n))
      return ProjectVelocitiesError::overlap;
  for (auto const& [p, n] :
       {std::pair<void const*, std::size_t>{velocities.data(), velocities.size_bytes()},
        {normals.data(), normals.size_bytes()},
        {offsets.data(), offsets.size_bytes()}})
    if (overlap(lambda_out.data(), lambda_out.size_bytes(), p, n))
      return ProjectVelocitiesError::overlap;
  if (!(cfg.epsilon >= 0.0f)) return ProjectVelocitiesError::bad_config;
  return ProjectVelocitiesError::none;
}

} // namespace

std::string_view to_string(ProjectVelocitiesError e) noexcept {
  switch (e) {
  case ProjectVelocitiesError::none:
    return "none";
  case ProjectVelocitiesError::length_mismatch:
    return "project_velocities: out, lambda_out or offsets has the wrong length";
  case ProjectVelocitiesError::bad_offsets:
    return "project_velocities: offsets must start at 0, never decrease and end at normals.size()";
  case ProjectVelocitiesError::too_many_planes:
    return "project_velocities: a problem has more than 2^24 planes";
  case ProjectVelocitiesError::overlap:
    return "project_velocities: an output overlaps an input or the other output";
  case ProjectVelocitiesError::bad_config:
    return "project_velocities: cfg.epsilon must be zero or positive";
  }
  return "project_velocities: unknown error";
}

ProjectVelocitiesError
project_velocities(std::span<Vec3 const> velocities, std::span<Vec3 const> normals,
                   std::span<std::uint32_t const> offsets, std::span<VelocityProjection3> out,
                   std::span<float> lambda_out, VelocityProjectionConfig const& cfg) noexcept {
  ProjectVelocitiesError const e = check(velocities, normals, offsets, out, lambda_out, cfg);
  if (e == ProjectVelocitiesError::none && !velocities.empty())
    kernels().project3(velocities.data(), velocities.size(), normals.data(), offsets.data(), cfg,
                       out.data(), lambda_out.empty() ? nullptr : lambda_out.data());
  return e;
}

ProjectVelocitiesError
project_velocities(std::span<Vec2 const> velocities, std::span<Vec2 const> normals,
                   std::span<std::uint32_t const> offsets, std::span<VelocityProjection2> out,
                   std::span<float> lambda_out, VelocityProjectionConfig const& cfg) noexcept {
  ProjectVelocitiesError const e = check(velocities, normals, offsets, out, lambda_out, cfg);
  if (e == ProjectVelocitiesError::none && !velocities.empty())
    kernels().project2(velocities.data(), velocities.size(), normals.data(), offsets.data(), cfg,
                       out.data(), lambda_out.empty() ? nullptr : lambda_out.data());
  return e;
}

Isa detail::character_kernels_isa() noexcept { return kernels().isa; }

} // namespace plume
