// The sort-and-sweep broad phase (include/plume/solver/world/broad_phase.hpp).
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

} // namespace plume
