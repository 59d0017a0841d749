// The world's broad phases (include/plume/solver/world/broad_phase.hpp).
#include <plume/solver/world/broad_phase.hpp>
#include <plume/solver/world/tasks.hpp>

#include <algorithm>

namespace plume {

void SortAndSweep::sort(std::span<Aabb3 const> boxes) {
  proxies_.resize(boxes.size());
  for (std::uint32_t i = 0; i < boxes.size(); ++i)
    proxies_[i] = {boxes[i], i};
  std::sort(proxies_.begin(), proxies_.end(), [](Proxy const& a, Proxy const& b) {
    return a.box.min.x < b.box.min.x || (a.box.min.x == b.box.min.x && a.index < b.index);
  });
}

BvhBroadPhase::BvhBroadPhase() = default;

void BvhBroadPhase::mark_moved(std::uint32_t i) {
  if (is_moved_.size() < slots_.size()) is_moved_.resize(slots_.size(), 0);
  if (is_moved_[i]) return;
  is_moved_[i] = 1;
  moved_.push_back(i);
}

void BvhBroadPhase::remove(std::uint32_t index) {
  if (index >= slots_.size() || !slots_[index].live) return;
  Slot& s = slots_[index];
  if (s.unbounded) {
    unbounded_.erase(std::find(unbounded_.begin(), unbounded_.end(), index));
  } else {
    tree_of(s).remove(s.proxy);
    if (s.kind == ProxyKind::static_body) static_changed_ = true, wide_fresh_ = false;
  }
  s = Slot{}; // its candidate pairs go at the next update (dead slots keep none)
}

void BvhBroadPhase::set_box(std::uint32_t index, Aabb3 const& box, ProxyKind kind) {
  if (index >= slots_.size()) slots_.resize(index + 1);
  bool const unbounded = !bool(box.is_valid());
  Slot& s = slots_[index];
  if (!s.live || s.unbounded != unbounded || s.kind != kind) { // leave the old place, enter anew
    remove(index);
    s.live = true;
    s.unbounded = unbounded;
    s.kind = kind;
    s.box = box;
    if (unbounded) {
      unbounded_.insert(std::lower_bound(unbounded_.begin(), unbounded_.end(), index), index);
    } else {
      s.proxy = tree_of(s).insert(box, index);
      if (kind == ProxyKind::static_body) static_changed_ = true, wide_fresh_ = false;
    }
    mark_moved(index);
    return;
  }
  if (unbounded) {
    auto const eq = [](Vec3 const& a, Vec3 const& b) {
      return a.x == b.x && a.y == b.y && a.z == b.z;
    };
    bool const same = eq(box.min, s.box.min) && eq(box.max, s.box.max);
    s.box = box;
    if (!same) mark_moved(index);
  } else {
    s.box = box;
    if (tree_of(s).move(s.proxy, box)) {
      if (kind == ProxyKind::static_body) static_changed_ = true, wide_fresh_ = false;
      mark_moved(index);
    }
  }
}

void BvhBroadPhase::update_candidates(TaskSystem* tasks) {
  auto const pair = [&](std::uint32_t i, std::uint32_t j) {
    return kinds_pair(slots_[i].kind, slots_[j].kind);
  };
  // Drop the pairs that ended: a body gone or of a kind that no longer pairs, or fat boxes
  // apart.
  auto const ended = [&](std::uint64_t k) {
    std::uint32_t const i = body_pair_first(k), j = body_pair_second(k);
    if (!slots_[i].live || !slots_[j].live || !pair(i, j)) return true;
    return !bool(fat(i).intersects(fat(j)));
  };
  candidates_.erase(std::remove_if(candidates_.begin(), candidates_.end(), ended),
                    candidates_.end());
  // New pairs, from the moved bodies only: read-only queries, in chunks of 32 bodies whose
  // keys go to lists of their own (so any thread may run a chunk), then merged and sorted.
  std::sort(moved_.begin(), moved_.end()); // the same queries in the same order, any history
  last_queries_ = 0;
  for (std::uint32_t i : moved_) {
    is_moved_[i] = 0;
    last_queries_ += slots_[i].live ? 1 : 0;
  }
  constexpr std::uint32_t chunk_size = 32;
  std::uint32_t const moved_count = std::uint32_t(moved_.size());
  std::uint32_t const chunks = (moved_count + chunk_size - 1) / chunk_size;
  if (fresh_chunks_.size() < chunks) fresh_chunks_.resize(chunks);
  parallel_for(tasks, chunks, 2, [&](std::uint32_t begin, std::uint32_t end) {
    for (std::uint32_t chunk = begin; chunk < end; ++chunk) {
      std::vector<std::uint64_t>& out = fresh_chunks_[chunk];
      out.clear();
      std::uint32_t const last = std::min(moved_count, (chunk + 1) * chunk_size);
      for (std::uint32_t m = chunk * chunk_size; m < last; ++m) {
        std::uint32_t const i = moved_[m];
        if (!slots_[i].live) continue;
        Aabb3 const box = fat(i);
        ProxyKind const own = slots_[i].kind;
        auto const consider = [&](std::uint32_t j) {
          if (j != i && bool(box.intersects(fat(j)))) out.push_back(body_pair_key(i, j));
        };
        AabbTree const& statics = trees_[std::size_t(ProxyKind::static_body)];
        if (kinds_pair(own, ProxyKind::static_body))
          query_static(box, [&](ProxyId p) {
            consider(std::uint32_t(statics.user(p)));
            return true;
          });
        for (ProxyKind kind : {ProxyKind::kinematic, ProxyKind::dynamic, ProxyKind::standalone,
                               ProxyKind::sleeping}) {
          if (!kinds_pair(own, kind)) continue;
          AabbTree const& t = trees_[std::size_t(kind)];
          t.query(box, [&](ProxyId p) {
            consider(std::uint32_t(t.user(p)));
            return true;
          });
        }
        for (std::uint32_t j : unbounded_)
          if (pair(i, j)) consider(j);
      }
    }
  });
  moved_.clear();
  fresh_.clear();
  for (std::uint32_t chunk = 0; chunk < chunks; ++chunk)
    fresh_.insert(fresh_.end(), fresh_chunks_[chunk].begin(), fresh_chunks_[chunk].end());
  if (fresh_.empty()) return;
  std::sort(fresh_.begin(), fresh_.end());
  std::size_t const old = candidates_.size();
  candidates_.insert(candidates_.end(), fresh_.begin(), fresh_.end());
  std::inplace_merge(candidates_.begin(), candidates_.begin() + std::ptrdiff_t(old),
                     candidates_.end());
  candidates_.erase(std::unique(candidates_.begin(), candidates_.end()), candidates_.end());
}

void BvhBroadPhase::refresh_static() {
  if (static_changed_ || !wide_fresh_) {
    AabbTree& statics = trees_[std::size_t(ProxyKind::static_body)];
    if (static_changed_) statics.rebuild();
    static_wide_.build(statics);
    static_changed_ = false;
    wide_fresh_ = true;
  }
}

void BvhBroadPhase::optimize() {
  refresh_static();
  for (ProxyKind kind :
       {ProxyKind::kinematic, ProxyKind::dynamic, ProxyKind::standalone, ProxyKind::sleeping})
    last_[std::size_t(kind)] = trees_[std::size_t(kind)].optimize(TreeOptimization::adaptive);
}

} // namespace plume
