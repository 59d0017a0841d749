// The world's broad phases (include/plume/solver/world/broad_phase.hpp).
#include <plume/solver/world/broad_phase.hpp>

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

void BvhBroadPhase::remove(std::uint32_t index) {
  if (index >= slots_.size()) return;
  Slot& s = slots_[index];
  if (s.where == Where::static_tree) {
    static_.remove(s.proxy);
    static_changed_ = true;
  } else if (s.where == Where::moving_tree) {
    moving_.remove(s.proxy);
  } else if (s.where == Where::unbounded) {
    unbounded_.erase(std::find(unbounded_.begin(), unbounded_.end(), index));
  }
  s = Slot{};
}

void BvhBroadPhase::set_box(std::uint32_t index, Aabb3 const& box, bool moving) {
  if (index >= slots_.size()) slots_.resize(index + 1);
  Slot& s = slots_[index];
  s.box = box;
  Where const want = !bool(box.is_valid()) ? Where::unbounded
                     : moving              ? Where::moving_tree
                                           : Where::static_tree;
  if (s.where != want) { // leave the old place, enter the new one
    remove(index);
    s.box = box;
    if (want == Where::static_tree) {
      s.proxy = static_.insert(box, index);
      static_changed_ = true;
    } else if (want == Where::moving_tree) {
      s.proxy = moving_.insert(box, index);
    } else {
      unbounded_.insert(std::lower_bound(unbounded_.begin(), unbounded_.end(), index), index);
    }
    s.where = want;
    return;
  }
  if (want == Where::static_tree) {
    if (static_.move(s.proxy, box)) static_changed_ = true;
  } else if (want == Where::moving_tree) {
    moving_.move(s.proxy, box);
  }
}

void BvhBroadPhase::optimize() {
  if (static_changed_) {
    static_.rebuild();
    static_changed_ = false;
  }
  last_ = moving_.optimize(TreeOptimization::adaptive);
}

} // namespace plume
