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
  auto const make = [&](PairManifold const& f, Contact const* prev) {
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
  };
  struct match {
    float dot;
    std::uint32_t now, before; ///< index into the pair's run of `found`, of contacts_
  };
  std::vector<match> matches;
  std::vector<Contact const*> prev_of;
  std::size_t io = 0; // cursor into the previous contacts, sorted like `found`
  for (std::size_t k = 0; k < found.size();) {
    std::uint64_t const pair = found[k].pair;
    std::size_t kend = k; // this step's manifolds of the pair: found[k, kend)
    while (kend < found.size() && found[kend].pair == pair)
      ++kend;
    while (io < contacts_.size() && key_of(contacts_[io]) < pair)
      ++io;
    std::size_t end = io; // the previous contacts of the pair: contacts_[io, end)
    while (end < contacts_.size() && key_of(contacts_[end]) == pair)
      ++end;
    if (kend - k == 1 && end - io <= 1) {
      // One manifold now and at most one before: it takes the previous contact whatever
      // the normals.
      if (found[k].manifold.count > 0) make(found[k], io < end ? &contacts_[io] : nullptr);
    } else {
      // Several (a mesh): the pairs of a new manifold and a previous contact within 60
      // degrees, most aligned first (ties: earlier manifold, then earlier contact), each
      // taken when both are still free.
      matches.clear();
      for (std::size_t n = k; n < kend; ++n)
        if (found[n].manifold.count > 0)
          for (std::size_t j = io; j < end; ++j)
            if (float const d = contacts_[j].manifold.normal.dot(found[n].manifold.normal);
                d > 0.5f)
              matches.push_back({d, std::uint32_t(n - k), std::uint32_t(j)});
      std::sort(matches.begin(), matches.end(), [](match const& a, match const& b) {
        return a.dot != b.dot ? a.dot > b.dot
                              : (a.now != b.now ? a.now < b.now : a.before < b.before);
      });
      prev_of.assign(kend - k, nullptr);
      std::vector<char> taken(end - io, 0);
      for (match const& m : matches)
        if (prev_of[m.now] == nullptr && !taken[m.before - io]) {
          prev_of[m.now] = &contacts_[m.before];
          taken[m.before - io] = 1;
        }
      for (std::size_t n = k; n < kend; ++n)
        if (found[n].manifold.count > 0) make(found[n], prev_of[n - k]);
    }
    k = kend;
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

namespace {

bool touches(Contact const& c, std::span<std::uint32_t const> bodies) {
  return std::binary_search(bodies.begin(), bodies.end(), c.body_a) ||
         std::binary_search(bodies.begin(), bodies.end(), c.body_b);
}

/// Moves the contacts of `from` that touch one of `bodies` into `to`, both kept sorted by pair
/// (a pair's contacts keep their order: a pair is never in both lists).
void move_contacts(std::vector<Contact>& from, std::vector<Contact>& to,
                   std::span<std::uint32_t const> bodies) {
  if (bodies.empty() || from.empty()) return;
  auto const moved = std::stable_partition(from.begin(), from.end(),
                                           [&](Contact const& c) { return !touches(c, bodies); });
  if (moved == from.end()) return;
  std::size_t const old = to.size();
  to.insert(to.end(), moved, from.end());
  from.erase(moved, from.end());
  std::inplace_merge(to.begin(), to.begin() + std::ptrdiff_t(old), to.end(),
                     [](Contact const& a, Contact const& b) { return key_of(a) < key_of(b); });
}

} // namespace

void ContactCache::remove_bodies(std::span<std::uint32_t const> bodies) {
  if (bodies.empty()) return;
  for (std::vector<Contact>* list : {&contacts_, &asleep_})
    std::erase_if(*list, [&](Contact const& c) {
      if (!touches(c, bodies)) return false;
      graph_.release(c.color, c.body_a, c.body_b, c.dynamic_a, c.dynamic_b);
      return true;
    });
}

void ContactCache::sleep(std::span<std::uint32_t const> bodies) {
  move_contacts(contacts_, asleep_, bodies);
}

void ContactCache::wake(std::span<std::uint32_t const> bodies) {
  move_contacts(asleep_, contacts_, bodies);
}

} // namespace plume
