// plume/solver/world/contact_cache.hpp - the world's touching pairs from step to step: each
// step's manifolds matched with the previous step's contacts of the same body pair, so that
// the solver starts from last step's impulses (warm starting) and keeps the friction axes
// and the graph colour of a contact for its whole life.
//
// Matching a new manifold point to an old one (carry_impulses):
//   1. the old point with the same feature id (collision/manifold.hpp), if unclaimed;
//   2. else the nearest unclaimed old point within `match_distance` (m) of it, measured
//      between the midpoints of the two surface points: clipping and reduction relabel
//      points that have not moved.
// An unmatched point starts from zero. The patch friction impulses carry over whole.
// A pair with several manifolds (a body on a mesh: one per group of triangles with one
// normal) matches its manifolds and previous contacts by their normals: of the pairs within
// 60 degrees, the most aligned first (ties: the earlier manifold, then the earlier contact),
// each manifold and contact used once; a pair with one manifold now and at most one contact
// before matches them whatever the normals.
// Colours: a contact keeps its colour; the colours of ended contacts are freed before new
// contacts are coloured, in pair order, so the colouring depends only on the sequence of
// steps, never on the SIMD width.
// Sleeping: the contacts of sleeping bodies are set aside (sleep()) with their manifolds,
// impulses and colours, untouched by update(), until wake() puts them back among the awake
// contacts, where the next update() matches them as any previous contact.
#pragma once

#include <plume/collision/manifold.hpp>
#include <plume/math/vec3.hpp>
#include <plume/solver/constraint_graph.hpp>
#include <plume/solver/contact_constraint.hpp>
#include <plume/solver/world/broad_phase.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace plume {

/// A touching pair: manifold points and the impulses they carry to the next step.
struct Contact {
  std::uint32_t body_a = 0, body_b = 0; ///< body_a < body_b; the normal points from A to B
  Manifold manifold;
  Vec3 tangent{}; ///< first friction axis (unit, in the contact plane), kept across steps
  ContactImpulses impulses{}; ///< per point along the normal, and the patch friction
  float friction = 0.0f, restitution = 0.0f;
  int color = ConstraintGraph::overflow;
  bool dynamic_a = false, dynamic_b = false; ///< as the colouring saw them (for release)
};

/// What the narrow phase found for one body pair this step (manifold.count == 0: apart); a
/// pair with a mesh may have several, one after the other.
struct PairManifold {
  std::uint64_t pair = 0; ///< body_pair_key(body_a, body_b)
  Manifold manifold;
  float friction = 0.0f, restitution = 0.0f; ///< the pair's combined material
  bool dynamic_a = false, dynamic_b = false;
};

/// The warm-start impulses of manifold `now` taken from the previous step's manifold
/// `before` of the same pair and its impulses (the matching rule at the top of this header).
ContactImpulses carry_impulses(Manifold const& now, Manifold const& before,
                               ContactImpulses const& impulses, float match_distance) noexcept;

class ContactCache {
public:
  /// This step's contacts of awake bodies, sorted by (body_a, body_b); a pair's several
  /// contacts (a mesh) in the narrow phase's order.
  std::span<Contact const> contacts() const noexcept { return contacts_; }
  std::span<Contact> contacts() noexcept { return contacts_; }
  /// The contacts set aside by sleep(), sorted as contacts().
  std::span<Contact const> sleeping_contacts() const noexcept { return asleep_; }
  /// The graph colour of every contact, in contact order (what the solver packs by).
  std::vector<int> colors() const;

  /// The colouring, shared with the world's joints (a colour holds contacts and joints with
  /// no dynamic body twice).
  ConstraintGraph& graph() noexcept { return graph_; }

  /// Room in the colouring for bodies 0..body_count-1.
  void reserve_bodies(std::size_t body_count) { graph_.reserve(body_count); }

  /// Replaces the contacts by the touching pairs of `found` (sorted by pair; pairs with an
  /// empty manifold are dropped), each carrying over the tangent, impulses and colour of the
  /// previous contact of its pair; contacts that ended free their colours, then the new
  /// ones are coloured.
  void update(std::span<PairManifold const> found, float match_distance);

  /// Ends every contact (awake or set aside) of one of `bodies` (sorted indices), freeing its
  /// colour.
  void remove_bodies(std::span<std::uint32_t const> bodies);

  /// Sets aside the awake contacts of one of `bodies` (sorted indices): update() keeps them
  /// as they are (their colours stay taken) until wake().
  void sleep(std::span<std::uint32_t const> bodies);
  /// Puts back among the awake contacts the set-aside contacts of one of `bodies` (sorted).
  void wake(std::span<std::uint32_t const> bodies);

private:
  std::vector<Contact> contacts_;
  std::vector<Contact> asleep_; ///< set aside by sleep(), sorted as contacts_
  ConstraintGraph graph_;
};

} // namespace plume
