// The contact cache (include/plume/solver/world/contact_cache.hpp).
#include <plume/solver/world/contact_cache.hpp>

#include <algorithm>
#include <array>

namespace plume {

namespace {

/// Marks a new contact until it is coloured, after the ended contacts freed their colours.
constexpr int uncolored = -2;

std::uint64_t key_of(Contact const& c) noexcept { return body_pair_key(c.body_a, c.body_b); }

} // namespace

ContactImpulses carry_impulses(Manifold const& now, Manifold const& before,
                               ContactImpulses const& impulses, float match_distance) noexcept {
  ContactImpulses out;
  out.tangent1 = impulses.tangent1;
  out.tangent2 = impulses.tangent2;
  out.twist = impulses.twist;
  std::array<bool, 4> claimed{}, matched{};
  for (std::size_t i = 0; i < std::size_t(now.count); ++i)
    for (std::size_t j = 0; j < std::size_t(before.count); ++j)
      if (!claimed[j] && before.points[j].id == now.points[i].id) {
        out.normal[i] = impulses.normal[j];
        claimed[j] = matched[i] = true;
        break;
      }
  float const r2 = match_distance * match_distance;
  for (std::size_t i = 0; i < std::size_t(now.count); ++i) {
    if (matched[i]) continue;
    Vec3 const p = now.points[i].point_a + now.points[i].point_b;
    std::size_t best = 4;
    float best_d2 = 4.0f * r2; // distances between sums of two points: twice the midpoints'
    for (std::size_t j = 0; j < std::size_t(before.count); ++j) {
      if (claimed[j]) continue;
      Vec3 const d = before.points[j].point_a + before.points[j].point_b - p;
      if (float const d2 = d.dot(d); d2 <= best_d2) {
        best = j;
        best_d2 = d2;
      }
    }
    if (best < 4) {
      out.normal[i] = impulses.normal[best];
      claimed[best] = true;
    }
  }
  return out;
}

std::vector<int> ContactCache::colors() const {
  std::vector<int> out(contacts_.size());
  for (std::size_t i = 0; i < contacts_.size(); ++i)
    out[i] = contacts_[i].color;
  return out;
}

void ContactCache::update(std::span<PairManifold const> found, float match_distance) {
  std::vector<Contact> next;
  next.reserve(found.size());
  std::vector<char> kept(contacts_.size(), 0);
  std::size_t io = 0; // cursor into the previous contacts, sorted like `found`
  for (std::size_t k = 0; k < found.size(); ++k) {
    PairManifold const& f = found[k];
    while (io < contacts_.size() && key_of(contacts_[io]) < f.pair)
      ++io;
    // The previous contacts of this pair: contacts_[io, end).
    std::size_t end = io;
    while (end < contacts_.size() && key_of(contacts_[end]) == f.pair)
      ++end;
    if (f.manifold.count == 0) continue;
    Contact const* prev = nullptr;
    bool const several = end - io > 1 || (k + 1 < found.size() && found[k + 1].pair == f.pair) ||
                         (k > 0 && found[k - 1].pair == f.pair);
    if (!several) {
      prev = io < end ? &contacts_[io] : nullptr;
    } else {
      // A pair with several manifolds (a mesh): each takes the unclaimed previous contact
      // whose normal is closest to its own, within 60 degrees.
      float best = 0.5f;
      for (std::size_t j = io; j < end; ++j) {
        float const d = contacts_[j].manifold.normal.dot(f.manifold.normal);
        if (!kept[j] && d > best) {
          best = d;
          prev = &contacts_[j];
        }
      }
    }
    Contact c;
    c.body_a = body_pair_first(f.pair);
    c.body_b = body_pair_second(f.pair);
    c.manifold = f.manifold;
    c.friction = f.friction;
    c.restitution = f.restitution;
    c.tangent = contact_tangent(f.manifold.normal, prev != nullptr ? prev->tangent : Vec3{});
    if (prev != nullptr) {
      kept[std::size_t(prev - contacts_.data())] = 1;
      c.color = prev->color;
      c.dynamic_a = prev->dynamic_a;
      c.dynamic_b = prev->dynamic_b;
      c.impulses = carry_impulses(f.manifold, prev->manifold, prev->impulses, match_distance);
    } else {
      c.color = uncolored;
      c.dynamic_a = f.dynamic_a;
      c.dynamic_b = f.dynamic_b;
    }
    next.push_back(c);
  }
  for (std::size_t i = 0; i < contacts_.size(); ++i)
    if (!kept[i]) {
      Contact const& c = contacts_[i];
      graph_.release(c.color, c.body_a, c.body_b, c.dynamic_a, c.dynamic_b);
    }
  for (Contact& c : next)
    if (c.color == uncolored) c.color = graph_.add(c.body_a, c.body_b, c.dynamic_a, c.dynamic_b);
  contacts_ = std::move(next);
}

void ContactCache::remove_bodies(std::span<std::uint32_t const> bodies) {
  if (bodies.empty()) return;
  std::vector<Contact> keep;
  keep.reserve(contacts_.size());
  for (Contact const& c : contacts_) {
    bool const hit = std::binary_search(bodies.begin(), bodies.end(), c.body_a) ||
                     std::binary_search(bodies.begin(), bodies.end(), c.body_b);
    if (hit)
      graph_.release(c.color, c.body_a, c.body_b, c.dynamic_a, c.dynamic_b);
    else
      keep.push_back(c);
  }
  contacts_ = std::move(keep);
}

} // namespace plume
