// plume/solver/character/plane_set.hpp - collects contact normals into the plane set that
// project_velocity takes: normalised, nearly parallel normals merged, at most a maximum count.
//
//   GPlaneSet3<T> set(velocity, cfg);   set.add(normal) ...;   set.normals()  (span of GVec3<T>)
//   GPlaneSet2<T> the same in 2D; PlaneSet3, PlaneSet2 for float (DPlaneSet3, DPlaneSet2).
//
// Normals are directions in the frame of the velocity (any length in, unit out); the set
// has no length unit. Why: project_velocity's cost grows with the plane count, and nearly
// parallel planes add steps without changing the answer.
//
// Rules, per lane (wide sets keep one set per lane; a lane's unused slots are zero normals,
// which project_velocity ignores):
//  - add() normalises its argument; a zero or non-finite normal is rejected (add returns
//    false for that lane, the set is unchanged).
//  - A normal whose dot product with a kept one is at least cfg.merge_cos (default cos 5°) is
//    merged into the first such slot: the slot keeps whichever of the two is more against the
//    velocity (smaller n . v). Merging is relative to the slot's current normal.
//  - When cfg.max_planes (default 20) are kept, a new normal replaces the kept one with the
//    largest n . v (the least relevant to the motion) if the new one has a smaller n . v, and
//    overflowed() is set for the lane; otherwise it is dropped.
#pragma once

#include <plume/math/vec2.hpp>
#include <plume/math/vec3.hpp>
#include <plume/numerics.hpp>

#include <cstddef>
#include <span>
#include <vector>

PLUME_MASK_CODE_BEGIN

namespace plume {

/// Merge rule and capacity of a plane set (dimensionless: no length-unit scaling).
template <ScalarReal S>
struct GPlaneSetConfig {
  S merge_cos = S(0.99619469809174553); ///< cos 5°: normals closer than this are merged
  std::size_t max_planes = 20;          ///< planes kept per lane
};
using PlaneSetConfig = GPlaneSetConfig<float>;
using DPlaneSetConfig = GPlaneSetConfig<double>;

/// A set of contact planes per lane for velocity `velocity` (see the file comment).
template <class Vec>
class GPlaneSet {
public:
  using T = typename Vec::element_type;
  using M = mask_t<T>;
  using S = scalar_t<T>;

  explicit GPlaneSet(Vec const& velocity, GPlaneSetConfig<S> const& cfg = {})
      : velocity_(velocity), cfg_(cfg), count_(zero<T>()), overflowed_(no_lanes<T>()) {
    slots_.reserve(cfg.max_planes);
  }

  /// Adds `normal` (any length) per lane; returns the lanes where it was kept or merged.
  M add(Vec const& normal) {
    // Scaled by the largest component first, so that no finite normal's square over- or
    // underflows (1e30 and 1e-30 are directions like any other).
    T const big = normal.abs().max_element();
    Vec const scaled = normal / big; // (not * (1 / big): that overflows for a subnormal big)
    T const len2 = scaled.dot(scaled);
    Vec const unit = scaled * (one<T>() / plume::sqrt(len2));
    M const usable = ((big > zero<T>()) & plume::is_finite(big)) & unit.is_finite();
    Vec const n = Vec::select(usable, unit, Vec{});
    T const nv = n.dot(velocity_);
    T const merge_cos = splat<T>(cfg_.merge_cos);

    // Merge into the first slot within the merge angle (unused slots are zero: never).
    M merged = no_lanes<T>();
    for (Vec& slot : slots_) {
      M const near = usable & !merged & (n.dot(slot) >= merge_cos);
      M const replace = near & (nv < slot.dot(velocity_));
      slot = Vec::select(replace, n, slot);
      merged = merged | near;
    }
    // Append into slot `count` where there is room.
    T const cap = splat<T>(static_cast<double>(cfg_.max_planes));
    M const fresh = usable & !merged;
    M const append = fresh & (count_ < cap);
    if (plume::any(append)) {
      T const idx_end = splat<T>(static_cast<double>(slots_.size()));
      if (plume::any(append & (count_ == idx_end))) slots_.push_back(Vec{});
      for (std::size_t i = 0; i < slots_.size(); ++i)
        slots_[i] =
            Vec::select(append & (count_ == splat<T>(static_cast<double>(i))), n, slots_[i]);
      count_ = plume::select(append, count_ + one<T>(), count_);
    }
    // Full: replace the least relevant kept plane if the new one is more against v.
    M const full = fresh & !append;
    M kept = merged | append;
    if (plume::any(full)) {
      T worst = -infinity<T>();
      T worst_idx = splat<T>(-1);
      for (std::size_t i = 0; i < slots_.size(); ++i) {
        T const idx = splat<T>(static_cast<double>(i));
        T const s = slots_[i].dot(velocity_);
        M const later = (idx < count_) & (s > worst);
        worst = plume::select(later, s, worst);
        worst_idx = plume::select(later, idx, worst_idx);
      }
      M const swap = full & (nv < worst);
      for (std::size_t i = 0; i < slots_.size(); ++i)
        slots_[i] =
            Vec::select(swap & (worst_idx == splat<T>(static_cast<double>(i))), n, slots_[i]);
      overflowed_ = overflowed_ | full;
      kept = kept | swap;
    }
    return kept;
  }

  /// The kept unit normals; slot i of a lane with fewer planes is a zero vector.
  std::span<Vec const> normals() const noexcept { return slots_; }
  /// Planes kept per lane (a small whole number).
  T count() const noexcept { return count_; }
  /// Lanes that were offered more than max_planes distinct planes.
  M overflowed() const noexcept { return overflowed_; }
  Vec const& velocity() const noexcept { return velocity_; }
  /// Empties the set (keeps the velocity and configuration).
  void clear() noexcept {
    slots_.clear();
    count_ = zero<T>();
    overflowed_ = no_lanes<T>();
  }

private:
  Vec velocity_;
  GPlaneSetConfig<S> cfg_;
  std::vector<Vec> slots_;
  T count_;
  M overflowed_;
};

template <class T>
using GPlaneSet3 = GPlaneSet<GVec3<T>>;
template <class T>
using GPlaneSet2 = GPlaneSet<GVec2<T>>;
using PlaneSet3 = GPlaneSet3<float>;
using PlaneSet2 = GPlaneSet2<float>;
using DPlaneSet3 = GPlaneSet3<double>;
using DPlaneSet2 = GPlaneSet2<double>;

} // namespace plume

PLUME_MASK_CODE_END
