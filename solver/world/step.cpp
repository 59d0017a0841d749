// The world's step (include/plume/solver/world/world.hpp), stage by stage. Compiled once per
// build, with World::step_with instantiated for float and every f32 width the build enables;
// in a PLUME_DISPATCH=ON build also once per carried instruction set (world_kernels.cpp), with
// step_with instantiated for that set's widest width only. World::step: entry_points.cpp.
#include <plume/math/pack.hpp>
#include <plume/solver/world/world.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace plume {

namespace {

using clock = std::chrono::steady_clock;

double seconds_since(clock::time_point t0) {
  return std::chrono::duration<double>(clock::now() - t0).count();
}

bool finite(Vec3 const& v) { return v.is_finite(); }
bool finite(Quat const& q) { return q.is_finite(); }

// The parallel stages' smallest ranges (tasks.hpp): below these, a range's work costs less than
// handing it to another thread. Pairs go in chunks of collide_chunk, each chunk's manifolds in
// a list of its own (merged in chunk order); a chunk's cuboid pairs go through the manifold
// kernel lanes_v<f32xN> at a time, so a chunk holds two batches of the widest width.
constexpr std::uint32_t collide_chunk = 32;
constexpr std::uint32_t min_chunks = 2;
constexpr std::uint32_t min_bodies = 256;
constexpr std::uint32_t min_blocks = 4;

/// f(i) for every index in ids, as range tasks.
template <class F>
void for_each_body(TaskSystem* tasks, std::vector<std::uint32_t> const& ids, F&& f) {
  parallel_for(tasks, std::uint32_t(ids.size()), min_bodies,
               [&](std::uint32_t begin, std::uint32_t end) {
                 for (std::uint32_t k = begin; k < end; ++k)
                   f(ids[k]);
               });
}

/// GConstraintBlocks' run(n, g): blocks [0, n) as range tasks, one range per worker. A colour's
/// blocks follow the contacts' order, which follows the bodies' (mostly spatial) order, so
/// with one range per worker each thread tends to get the same bodies in every colour and
/// pass, and keeps their states in its cache. Smaller ranges, taken in turn by whichever
/// thread is free, move body states between cores at almost every block (docs/performance.md,
/// "Threads", has the measurements).
auto block_runner(TaskSystem* tasks) {
  std::uint32_t const workers = tasks ? std::max(1u, tasks->worker_count()) : 1u;
  return [tasks, workers](std::uint32_t n, auto&& g) {
    parallel_for(tasks, n, std::max(min_blocks, (n + workers - 1) / workers), g);
  };
}

/// Manifold reuse (WorldConfig::reuse_distance): B's rotation and origin seen from A, and A's
/// origin seen from B.
struct RelativePose {
  Quat rotation;
  Vec3 b_from_a, a_from_b;
};

RelativePose relative_pose(Iso3 const& pa, Iso3 const& pb) {
  Iso3 const b_in_a = pa.inv_mul(pb);
  return {b_in_a.rotation, b_in_a.translation, pb.inverse_transform_point(pa.translation)};
}

/// Whether the pair may keep manifolds computed at `before`: the change of the bodies'
/// relative rotation is at most max_chord (as 2 sin(angle/2), twice the length of its vector
/// part), and no point of the smaller shape moved more than max_drift relative to the other
/// body (bounded by the origin's displacement plus 2 sin(angle/2) x reach). False for NaN.
/// The lever of each bound is the shape's reach plus `pad` (the manifold's deepest |separation|
/// or the prediction distance, the larger): B's points lie that far from A's surface, and a
/// turn about A's origin moves them by the chord times their distance from it.
bool may_reuse(Quat const& rotation_before, Vec3 const& b_before, Vec3 const& a_before,
               RelativePose const& now, float reach_a, float reach_b, float pad, float max_drift,
               float max_chord) {
  Quat const d = rotation_before.conjugate() * now.rotation;
  float const chord = 2.0f * std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  if (!(chord <= max_chord)) return false;
  // chord 0 (no turn) with an infinite reach (a half-space) is no lever at all, not NaN.
  float const lever_a = chord > 0.0f ? chord * (reach_a + pad) : 0.0f;
  float const lever_b = chord > 0.0f ? chord * (reach_b + pad) : 0.0f;
  float const via_b = (now.b_from_a - b_before).length() + lever_b;
  float const via_a = (now.a_from_b - a_before).length() + lever_a;
  return std::min(via_a, via_b) <= max_drift;
}

/// A world manifold in the bodies' frames: the normal and point_a in A's, point_b in B's.
Manifold to_local(Manifold m, Iso3 const& pa, Iso3 const& pb) {
  Mat3 const ra = Mat3::from_quat(pa.rotation), rb = Mat3::from_quat(pb.rotation);
  m.normal = ra.mul_transpose_vec3(m.normal);
  for (int k = 0; k < m.count; ++k) {
    ContactPoint& c = m.points[std::size_t(k)];
    c.point_a = ra.mul_transpose_vec3(c.point_a - pa.translation);
    c.point_b = rb.mul_transpose_vec3(c.point_b - pb.translation);
  }
  return m;
}

/// A manifold kept by to_local moved with its bodies to poses pa and pb, into m: the normal
/// with A, each point_b with B, its separation measured again from A's moved point along the
/// normal, and point_a put back opposite point_b (point_b - separation x normal). A's point is
/// not kept where it was on A: a body sliding over the other would carry its points away
/// from A's, and the pair would push at an angle to the line through them (a ball sliding
/// down a frictionless ramp would start to spin).
void to_world(Manifold const& local, Iso3 const& pa, Iso3 const& pb, Manifold& m) {
  Mat3 const ra = Mat3::from_quat(pa.rotation), rb = Mat3::from_quat(pb.rotation);
  m.normal = ra * local.normal;
  m.count = local.count;
  m.failed = false;
  for (int k = 0; k < local.count; ++k) {
    ContactPoint const& l = local.points[std::size_t(k)];
    ContactPoint& c = m.points[std::size_t(k)];
    Vec3 const on_a = ra * l.point_a + pa.translation;
    c.point_b = rb * l.point_b + pb.translation;
    c.separation = (c.point_b - on_a).dot(m.normal);
    c.point_a = c.point_b - m.normal * c.separation;
    c.id = l.id;
  }
}

} // namespace

int detail::collide(BodyShape const& a, Iso3 const& pa, BodyShape const& b, Iso3 const& pb,
                    ManifoldConfig const& cfg, std::array<Manifold, max_mesh_manifolds>& out) {
  return std::visit(
      [&](auto const& sa, auto const& sb) -> int {
        using A = std::decay_t<decltype(sa)>;
        using B = std::decay_t<decltype(sb)>;
        constexpr bool mesh_a = is_triangle_shape_v<A>;
        constexpr bool mesh_b = is_triangle_shape_v<B>;
        if constexpr (mesh_a && mesh_b) {
          return 0;
        } else if constexpr (mesh_a || mesh_b) {
          if constexpr (std::is_same_v<A, HalfSpace> || std::is_same_v<B, HalfSpace>) {
            return 0;
          } else {
            MeshContactConfig mc;
            mc.manifold = cfg;
            MeshContacts c;
            if constexpr (mesh_a)
              c = mesh_contacts(*sa.source(), pa, sb, pb, mc);
            else
              c = mesh_contacts(*sb.source(), pb, sa, pa, mc);
            if (c.failed) {
              out[0] = Manifold{};
              out[0].failed = true;
              return 1;
            }
            for (int k = 0; k < c.count; ++k) {
              Manifold m = c.manifolds[std::size_t(k)].manifold; // mesh -> shape
              if constexpr (mesh_b) { // A is the shape: turn it to A -> B
                m.normal = -m.normal;
                for (int p = 0; p < m.count; ++p)
                  std::swap(m.points[std::size_t(p)].point_a, m.points[std::size_t(p)].point_b);
              }
              out[std::size_t(k)] = m;
            }
            return c.count;
          }
        } else {
          out[0] = contact_manifold(sa, pa, sb, pb, cfg);
          return out[0].empty() && !out[0].failed ? 0 : 1;
        }
      },
      a, b);
}

Aabb3 World::grown_aabb(std::uint32_t i) const {
  if (!bodies_[i].alive) return Aabb3{}; // EMPTY: overlaps nothing
  float const margin = config_.speculative_distance;
  Aabb3 const box = aabb(collider_at(i));
  return {box.min - Vec3::splat(margin), box.max + Vec3::splat(margin)};
}

/// Broad phase: the pairs of grown AABBs that overlap, at least one body dynamic and awake, or
/// a sleeping body and a kinematic one (which may wake it, or be a sensor it overlaps).
void World::find_pairs() {
  auto const kinematic = [&](Body const& x) { return x.moves() && x.type == BodyType::kinematic; };
  auto const keep = [&](std::uint32_t a, std::uint32_t b) {
    Body const& x = bodies_[a];
    Body const& y = bodies_[b];
    return (x.active() || y.active() || (x.sleeping && kinematic(y)) ||
            (y.sleeping && kinematic(x))) &&
           bodies_[a].layers.interacts(bodies_[b].layers) &&
           (no_collide_pairs_.empty() || !jointed_no_collide(a, b));
  };
  if (config_.broad_phase == BroadPhaseKind::sort_and_sweep) {
    boxes_.resize(bodies_.size());
    parallel_for(config_.tasks, std::uint32_t(bodies_.size()), min_bodies,
                 [&](std::uint32_t begin, std::uint32_t end) {
                   for (std::uint32_t i = begin; i < end; ++i)
                     boxes_[i] = grown_aabb(i);
                 });
    sort_and_sweep_.find_pairs(boxes_, keep, pairs_);
    return;
  }
  sync_trees(config_.tasks); // a no-op when nothing changed since the last step's end
  bvh_.find_pairs(keep, pairs_, config_.tasks);
}

/// Pairs with a sensor leave pairs_ (no manifold, no contact) for sensor_pairs_.
void World::split_sensor_pairs() {
  sensor_pairs_.clear();
  auto const is_sensor_pair = [&](std::uint64_t k) {
    return bodies_[body_pair_first(k)].sensor || bodies_[body_pair_second(k)].sensor;
  };
  for (std::uint64_t k : pairs_)
    if (is_sensor_pair(k)) sensor_pairs_.push_back(k);
  if (!sensor_pairs_.empty())
    pairs_.erase(std::remove_if(pairs_.begin(), pairs_.end(), is_sensor_pair), pairs_.end());
}

ColliderPair World::pair_ids(std::uint64_t key) const {
  return {collider_at(body_pair_first(key)), collider_at(body_pair_second(key))};
}

/// This step's events: the contact pairs and sensor overlaps against the last step's.
void World::update_events() {
  auto const diff = [&](std::vector<std::uint64_t> const& before,
                        std::vector<std::uint64_t> const& now, std::vector<ColliderPair>& begun,
                        std::vector<ColliderPair>& ended) {
    std::size_t i = 0, j = 0;
    while (i < before.size() || j < now.size()) {
      if (j == now.size() || (i < before.size() && before[i] < now[j]))
        ended.push_back(pair_ids(before[i++]));
      else if (i == before.size() || now[j] < before[i])
        begun.push_back(pair_ids(now[j++]));
      else
        ++i, ++j;
    }
  };
  touching_before_.swap(touching_now_);
  touching_now_.clear();
  for (Contact const& c : cache_.contacts()) // a mesh pair may have several contacts
    if (std::uint64_t const k = body_pair_key(c.body_a, c.body_b);
        touching_now_.empty() || touching_now_.back() != k)
      touching_now_.push_back(k);
  diff(touching_before_, touching_now_, events_.contact_begin, events_.contact_end);
  std::vector<std::uint64_t> sensor_before;
  sensor_before.swap(sensor_now_);
  for (std::uint64_t k : sensor_pairs_)
    if (shapes_touch(body_pair_first(k), body_pair_second(k))) sensor_now_.push_back(k);
  if (sleeping_count_ > 0) {
    // A sleeping body's overlap with a body that cannot move (static, frozen, a collider, or
    // asleep itself) is not looked at again: it stays as it was.
    auto const still = [&](Body const& x) {
      return !x.active() && !(x.moves() && x.type == BodyType::kinematic);
    };
    std::size_t const old = sensor_now_.size();
    for (std::uint64_t k : sensor_before) {
      Body const& x = bodies_[body_pair_first(k)];
      Body const& y = bodies_[body_pair_second(k)];
      if ((x.sleeping || y.sleeping) && still(x) && still(y) &&
          !std::binary_search(sensor_pairs_.begin(), sensor_pairs_.end(), k))
        sensor_now_.push_back(k);
    }
    std::inplace_merge(sensor_now_.begin(), sensor_now_.begin() + std::ptrdiff_t(old),
                       sensor_now_.end());
  }
  diff(sensor_before, sensor_now_, events_.sensor_begin, events_.sensor_end);
  // destroy_body's and destroy_collider's ends (already in events_) may interleave: keep each
  // list in pair order.
  auto const by_pair = [](ColliderPair const& x, ColliderPair const& y) {
    return body_pair_key(x.a.index, x.b.index) < body_pair_key(y.a.index, y.b.index);
  };
  std::stable_sort(events_.contact_end.begin(), events_.contact_end.end(), by_pair);
  std::stable_sort(events_.sensor_end.begin(), events_.sensor_end.end(), by_pair);
}

/// Narrow phase: a manifold per pair, then the contact cache matches them with last step's.
/// Cuboid pairs go through box_pair_manifold lanes_v<W> at a time (a chunk's pairs in order,
/// the last batch padded with its last pair), the lanes it leaves to the general path through
/// detail::box_pair_general, every other pair through detail::collide. The kernel's lanes
/// equal its scalar calls, and contact_manifold's cuboid pair is that scalar call, so every
/// build and every width gives the same manifolds. First, a pair that may keep the manifolds
/// of an earlier step (WorldConfig::reuse_distance, may_reuse) takes them moved with its
/// bodies (to_world) and skips the rest; the decision reads only poses, so every width and
/// thread count reuses the same pairs.
template <class W>
void World::collide_pairs() {
  constexpr std::size_t L = lanes_v<W>;
  auto const t_start = clock::now();
  std::uint32_t const pair_count = std::uint32_t(pairs_.size());
  std::uint32_t const chunks = (pair_count + collide_chunk - 1) / collide_chunk;
  if (found_chunks_.size() < chunks) found_chunks_.resize(chunks);
  if (chunk_counts_.size() < chunks) chunk_counts_.resize(chunks);
  if (reuse_chunks_.size() < chunks) reuse_chunks_.resize(chunks);
  if (reuse_manifold_chunks_.size() < chunks) reuse_manifold_chunks_.resize(chunks);
  // Either NaN, 0 or less: off (nothing reused, nothing kept).
  float const reuse_limit = std::min(config_.reuse_distance, 0.5f * config_.manifold.prediction);
  float const reuse_chord = 2.0f * std::sin(0.5f * std::min(config_.reuse_angle, 1.0f));
  bool const reuse_on = reuse_limit > 0.0f && reuse_chord > 0.0f;
  float const prediction = config_.manifold.prediction;
  parallel_for(config_.tasks, chunks, min_chunks, [&](std::uint32_t begin, std::uint32_t end) {
    std::array<Manifold, max_mesh_manifolds> ms;
    std::array<Manifold, collide_chunk> box; // a cuboid pair's manifold, by place in the chunk
    std::array<bool, collide_chunk> boxed;   // ... when the kernel computed it
    std::array<std::uint32_t, collide_chunk> box_pairs;
    std::array<std::uint32_t, collide_chunk> kept; // a reused pair's entry in reuse_, or ~0
    std::array<RelativePose, collide_chunk> rel;
    for (std::uint32_t chunk = begin; chunk < end; ++chunk) {
      std::vector<PairManifold>& out = found_chunks_[chunk];
      std::vector<ReuseEntry>& entries = reuse_chunks_[chunk];
      std::vector<Manifold>& locals = reuse_manifold_chunks_[chunk];
      out.clear();
      entries.clear();
      locals.clear();
      std::uint32_t const first = chunk * collide_chunk;
      std::uint32_t const last = std::min(pair_count, first + collide_chunk);
      std::uint32_t boxes = 0;
      chunk_counts_[chunk] = {};
      // Both lists are sorted by pair: one walk finds each pair's entry of the last step.
      auto entry =
          std::lower_bound(reuse_.begin(), reuse_.end(), first < last ? pairs_[first] : 0,
                           [](ReuseEntry const& e, std::uint64_t k) { return e.pair < k; });
      for (std::uint32_t p = first; p < last; ++p) {
        std::uint64_t const pair = pairs_[p];
        Body const& a = bodies_[body_pair_first(pair)];
        Body const& b = bodies_[body_pair_second(pair)];
        rel[p - first] = relative_pose(a.pose, b.pose);
        kept[p - first] = ~std::uint32_t(0);
        while (entry != reuse_.end() && entry->pair < pair)
          ++entry;
        if (reuse_on && entry != reuse_.end() && entry->pair == pair &&
            entry->generation_a == a.generation && entry->generation_b == b.generation &&
            may_reuse(entry->rotation, entry->b_from_a, entry->a_from_b, rel[p - first], a.reach,
                      b.reach, std::max(entry->depth, prediction), reuse_limit, reuse_chord))
          kept[p - first] = std::uint32_t(entry - reuse_.begin());
      }
      for (std::uint32_t p = first; p < last; ++p) {
        boxed[p - first] = false;
        if (kept[p - first] != ~std::uint32_t(0)) continue;
        if (std::holds_alternative<Cuboid>(bodies_[body_pair_first(pairs_[p])].shape) &&
            std::holds_alternative<Cuboid>(bodies_[body_pair_second(pairs_[p])].shape))
          box_pairs[boxes++] = p - first;
      }
      chunk_counts_[chunk][0] = boxes;
      for (std::uint32_t g = 0; g < boxes; g += std::uint32_t(L)) {
        // The batch's pairs (the last one repeated into unused lanes), packed into lanes.
        std::array<Vec3, L> ea, eb, ta, tb;
        std::array<Quat, L> qa, qb;
        for (std::size_t l = 0; l < L; ++l) {
          std::uint64_t const pair =
              pairs_[first + box_pairs[std::min<std::size_t>(g + l, boxes - 1)]];
          Body const& a = bodies_[body_pair_first(pair)];
          Body const& b = bodies_[body_pair_second(pair)];
          ea[l] = std::get<Cuboid>(a.shape).half_extents,
          eb[l] = std::get<Cuboid>(b.shape).half_extents;
          qa[l] = a.pose.rotation, qb[l] = b.pose.rotation;
          ta[l] = a.pose.translation, tb[l] = b.pose.translation;
        }
        GBoxPairManifold<W> const w =
            box_pair_manifold(pack<W>(ea.data()), GIso3<W>{pack<W>(qa.data()), pack<W>(ta.data())},
                              pack<W>(eb.data()), GIso3<W>{pack<W>(qb.data()), pack<W>(tb.data())},
                              config_.manifold.prediction);
        std::uint64_t const general = bitmask(w.general);
        for (std::size_t l = 0; l < L && g + l < boxes; ++l) {
          std::uint32_t const k = box_pairs[g + l];
          if ((general >> l) & 1u) { // what contact_manifold would do after the kernel
            ++chunk_counts_[chunk][1];
            Body const& a = bodies_[body_pair_first(pairs_[first + k])];
            Body const& b = bodies_[body_pair_second(pairs_[first + k])];
            box[k] = detail::box_pair_general(std::get<Cuboid>(a.shape), a.pose,
                                              std::get<Cuboid>(b.shape), b.pose, config_.manifold);
          } else {
            box[k] = w.lane(l);
          }
          boxed[k] = true;
        }
      }
      for (std::uint32_t p = first; p < last; ++p) {
        std::uint64_t const pair = pairs_[p];
        Body const& a = bodies_[body_pair_first(pair)];
        Body const& b = bodies_[body_pair_second(pair)];
        float const friction = std::sqrt(a.friction * b.friction);
        float const restitution = std::max(a.restitution, b.restitution);
        if (std::uint32_t const e = kept[p - first]; e != ~std::uint32_t(0)) {
          // The manifolds as last computed, moved with the bodies; the entry stays as it was,
          // so the drift is always measured from the poses they were computed at.
          ++chunk_counts_[chunk][2];
          ReuseEntry const& kept_entry = reuse_[e];
          for (std::uint32_t k = 0; k < kept_entry.count; ++k) {
            Manifold const& local = reuse_pool_[kept_entry.first + k];
            if (local.empty()) continue;
            PairManifold& m = out.emplace_back();
            m.pair = pair;
            to_world(local, a.pose, b.pose, m.manifold);
            m.friction = friction, m.restitution = restitution;
            m.dynamic_a = a.is_dynamic(), m.dynamic_b = b.is_dynamic();
          }
          entries.push_back(kept_entry);
          continue;
        }
        Manifold const* found = &box[p - first];
        int n = found->empty() && !found->failed ? 0 : 1; // as detail::collide counts
        if (!boxed[p - first]) {
          n = detail::collide(a.shape, a.pose, b.shape, b.pose, config_.manifold, ms);
          found = ms.data();
        }
        bool failed = false;
        for (int k = 0; k < n; ++k) {
          out.push_back({pair, found[k], friction, restitution, a.is_dynamic(), b.is_dynamic()});
          failed = failed || found[k].failed;
        }
        if (reuse_on && !failed) { // kept for the next steps (a failure never is)
          RelativePose const& r = rel[p - first];
          float depth = 0.0f;
          for (int k = 0; k < n; ++k)
            for (ContactPoint const& c : found[k])
              depth = std::max(depth, std::abs(c.separation));
          entries.push_back({pair, a.generation, b.generation, r.rotation, r.b_from_a, r.a_from_b,
                             depth, std::uint32_t(locals.size()), std::uint32_t(n), true});
          for (int k = 0; k < n; ++k)
            locals.push_back(to_local(found[k], a.pose, b.pose));
        }
      }
    }
  });
  found_.clear();
  reuse_next_.clear();
  profile_.pairs = pair_count;
  profile_.box_pairs = profile_.general_box_pairs = profile_.reused_pairs = 0;
  std::size_t live = 0; // manifolds the entries name
  for (std::uint32_t chunk = 0; chunk < chunks; ++chunk) {
    found_.insert(found_.end(), found_chunks_[chunk].begin(), found_chunks_[chunk].end());
    profile_.box_pairs += chunk_counts_[chunk][0];
    profile_.general_box_pairs += chunk_counts_[chunk][1];
    profile_.reused_pairs += chunk_counts_[chunk][2];
    auto const offset = std::uint32_t(reuse_pool_.size());
    for (ReuseEntry e : reuse_chunks_[chunk]) {
      if (e.fresh) e.first += offset, e.fresh = false;
      live += e.count;
      reuse_next_.push_back(e);
    }
    reuse_pool_.insert(reuse_pool_.end(), reuse_manifold_chunks_[chunk].begin(),
                       reuse_manifold_chunks_[chunk].end());
  }
  reuse_.swap(reuse_next_);
  if (reuse_pool_.size() > 2 * live + 1024) { // mostly unnamed: keep the named ones, in order
    reuse_pool_spare_.clear();
    for (ReuseEntry& e : reuse_) {
      auto const at = std::uint32_t(reuse_pool_spare_.size());
      reuse_pool_spare_.insert(reuse_pool_spare_.end(), reuse_pool_.begin() + e.first,
                               reuse_pool_.begin() + e.first + e.count);
      e.first = at;
    }
    reuse_pool_.swap(reuse_pool_spare_);
  }
  profile_.manifolds = seconds_since(t_start);
  cache_.update(found_, config_.contact_match_distance);
}

/// World inverse inertias at the step's start; the position deltas start at zero.
void World::prepare_bodies() {
  for_each_body(config_.tasks, moving_bodies_,
                [&](std::uint32_t i) { // a static body's state is never written
                  Body& b = bodies_[i];
                  if (b.is_dynamic()) {
                    Mat3 const r = Mat3::from_quat(b.pose.rotation);
                    b.inv_inertia_world = b.inv_inertia_local.rotate_inertia(r);
                  }
                  states_[i].delta_position = Vec3{};
                  states_[i].delta_rotation = Quat::IDENTITY;
                });
}

SolverBody World::contact_body(std::uint32_t i) const {
  Body const& b = bodies_[i];
  SolverBody c;
  if (!b.moves()) {
    c.state = std::int32_t(bodies_.size()); // the identity record
    c.center = b.center;
    return c;
  }
  c.state = std::int32_t(i);
  c.center = b.center;
  c.linear_velocity = states_[i].linear_velocity;
  c.angular_velocity = states_[i].angular_velocity;
  if (b.is_dynamic()) {
    c.write = std::int32_t(i);
    c.inv_mass = b.inv_mass;
    c.inv_inertia = b.inv_inertia_world;
  }
  return c;
}

/// The contacts packed into blocks by colour, each lane prepared for substep h.
template <class T>
void World::pack_contacts(GConstraintBlocks<GContactConstraint, T>& blocks, float h) const {
  float const hertz = std::min(config_.contact_hertz, 0.25f * (1.0f / h));
  Softness const soft = Softness::make(hertz, config_.contact_damping_ratio, h);
  Softness const static_soft =
      Softness::make(config_.static_hertz_scale * hertz, config_.contact_damping_ratio, h);
  std::span<Contact const> const contacts = cache_.contacts();
  std::int32_t const identity = std::int32_t(bodies_.size());
  // Each colour by point count, so one-point manifolds (a sphere on a box) fill blocks of
  // their own and solve one row per lane, not four.
  blocks.template pack_grouped<5>(
      cache_.colors(), [&](std::uint32_t ci) { return std::uint32_t(contacts[ci].manifold.count); },
      [&]<class U>(GContactConstraint<U>& block, std::size_t lane, std::uint32_t ci) {
        Contact const& c = contacts[ci];
        SolverBody const a = contact_body(c.body_a), b = contact_body(c.body_b);
        bool const against_static = a.write < 0 || b.write < 0;
        prepare_contact_lane(block, lane, a, b, c.manifold, c.tangent, c.impulses, c.friction,
                             c.restitution, against_static ? static_soft : soft);
      },
      [&](GContactConstraint<T>& block, std::size_t lane) {
        clear_contact_lane(block, lane, identity);
      },
      block_runner(config_.tasks));
}

/// The joints packed by kind (in JointKind order), each kind by colour, each lane prepared
/// for substep h.
template <class T>
void World::pack_joints(JointBlocks<T>& blocks, float h) const {
  float const hertz = std::min(config_.joint_hertz, 0.25f * (1.0f / h));
  Softness const soft = Softness::make(hertz, config_.joint_damping_ratio, h);
  std::int32_t const identity = std::int32_t(bodies_.size());
  std::vector<int> colors;
  for (int k = 0; k < joint_kind_count; ++k) {
    auto& items = blocks.items[std::size_t(k)];
    items.clear();
    colors.clear();
    for (std::uint32_t i = 0; i < joints_.size(); ++i)
      if (Joint const& j = joints_[i];
          j.alive && !j.broken && int(j.params.kind) == k &&
          (bodies_[j.def.body_a.index].active() || bodies_[j.def.body_b.index].active())) {
        items.push_back(i);
        colors.push_back(j.color);
      }
    if (!items.empty()) blocks.empty = false;
    blocks.by_kind[std::size_t(k)].pack(
        colors,
        [&]<class U>(GJointConstraint<U>& block, std::size_t lane, std::uint32_t local) {
          Joint const& j = joints_[items[local]];
          prepare_joint_lane(block, lane, joint_body(j.def.body_a.index), j.def.frame_a.anchor,
                             j.basis_a, joint_body(j.def.body_b.index), j.def.frame_b.anchor,
                             j.basis_b, j.params, j.impulses, soft, h);
        },
        [&](GJointConstraint<T>& block, std::size_t lane) {
          clear_joint_lane(block, lane, identity);
        },
        block_runner(config_.tasks));
  }
}

/// Pass P of every joint: kind by kind, each kind's overflow and then its colours.
template <JointPass P, class T>
void World::run_joints(JointBlocks<T>& blocks, float inv_h) {
  if (blocks.empty) return;
  auto const t0 = clock::now();
  BodyState* const states = states_.data();
  for (int k = 0; k < joint_kind_count; ++k)
    blocks.by_kind[std::size_t(k)].for_each_by_color(block_runner(config_.tasks), [&](auto& c) {
      using U = typename std::decay_t<decltype(c)>::element_type;
      joint_pass<P>(JointKind(k), c, states, U(inv_h));
    });
  profile_.joints += seconds_since(t0);
}

/// Each joint keeps the impulses its lane accumulated, to warm start the next step.
template <class T>
void World::store_joint_impulses(JointBlocks<T> const& blocks) {
  for (int k = 0; k < joint_kind_count; ++k) {
    auto const& items = blocks.items[std::size_t(k)];
    blocks.by_kind[std::size_t(k)].for_each_lane(
        [&](auto const& c, std::size_t lane, std::uint32_t local) {
          JointImpulses const l = joint_impulses(c, lane);
          // A non-finite impulse (a body that froze this step) must not warm start anything.
          bool ok = l.point.is_finite() && std::isfinite(((l.lower + l.upper) + l.motor) + l.cone);
          for (float x : l.angular)
            ok = ok && std::isfinite(x);
          for (float x : l.linear)
            ok = ok && std::isfinite(x);
          joints_[items[local]].impulses = ok ? l : JointImpulses{};
        });
  }
}

/// The substeps: velocities, warm start, solve, positions, relax (joints before contacts in
/// each pass: contacts get the last word); then restitution.
template <class T>
void World::solve_substeps(GConstraintBlocks<GContactConstraint, T>& blocks, JointBlocks<T>& joints,
                           int substeps, float h) {
  int const solve_iterations = std::max(1, config_.solve_iterations);
  int const relax_iterations = std::max(0, config_.relax_iterations);
  float const inv_h = 1.0f / h;
  float const push = config_.max_push_speed;
  BodyState* const states = states_.data();
  auto const run = block_runner(config_.tasks);
  for (int sub = 0; sub < substeps; ++sub) {
    integrate_velocities(h);
    run_joints<JointPass::warm_start>(joints, inv_h);
    blocks.for_each_by_color(run, [&](auto& c) { warm_start_contacts(c, states); });
    for (int r = 0; r < solve_iterations; ++r) {
      run_joints<JointPass::solve>(joints, inv_h);
      blocks.for_each_by_color(run, [&](auto& c) { solve_contacts(c, states, inv_h, push, true); });
    }
    integrate_positions(h);
    for (int r = 0; r < relax_iterations; ++r) {
      run_joints<JointPass::relax>(joints, inv_h);
      blocks.for_each_by_color(run,
                               [&](auto& c) { solve_contacts(c, states, inv_h, push, false); });
    }
  }
  float const threshold = config_.restitution_threshold;
  blocks.for_each_by_color(run, [&](auto& c) { apply_restitution(c, states, threshold); });
}

void World::integrate_velocities(float h) {
  Vec3 const g = config_.gravity;
  float const max_w = config_.max_rotation / h;
  for_each_body(config_.tasks, moving_bodies_, [&](std::uint32_t i) {
    Body const& b = bodies_[i];
    if (!b.is_dynamic()) return;
    BodyState& s = states_[i];
    Vec3 v = s.linear_velocity * (1.0f / (1.0f + h * b.linear_damping)) + g * (h * b.gravity_scale);
    Vec3 w = s.angular_velocity * (1.0f / (1.0f + h * b.angular_damping));
    s.linear_velocity = v.clamp_length_max(config_.max_linear_speed);
    s.angular_velocity = w.clamp_length_max(max_w);
  });
}

void World::integrate_positions(float h) {
  for_each_body(config_.tasks, moving_bodies_, [&](std::uint32_t i) {
    if (!bodies_[i].moves()) return;
    BodyState& s = states_[i];
    s.delta_position = s.delta_position + s.linear_velocity * h;
    Vec3 const w = s.angular_velocity;
    Quat const spin = Quat::from_xyzw(w.x, w.y, w.z, 0.0f) * s.delta_rotation;
    Quat const q = s.delta_rotation + spin * (0.5f * h);
    s.delta_rotation = q * (1.0f / q.length());
  });
}

/// Each contact keeps the impulses its lane accumulated, to warm start the next step.
template <class T>
void World::store_impulses(GConstraintBlocks<GContactConstraint, T> const& blocks) {
  std::span<Contact> const contacts = cache_.contacts();
  blocks.for_each_lane([&](auto const& c, std::size_t lane, std::uint32_t ci) {
    contacts[ci].impulses = contact_impulses(c, lane);
  });
}

/// Poses from the accumulated deltas; a body whose state turned non-finite is frozen. Dynamic
/// bodies that moved far for their size go to fast_ for the continuous pass.
void World::finalize_bodies() {
  // Each body on any thread (its pose, or frozen), then the lists in body order.
  enum : std::uint8_t { kept, froze, fast };
  finalize_status_.resize(moving_bodies_.size());
  finalize_start_.resize(moving_bodies_.size());
  parallel_for(config_.tasks, std::uint32_t(moving_bodies_.size()), min_bodies,
               [&](std::uint32_t begin, std::uint32_t end) {
                 for (std::uint32_t k = begin; k < end; ++k) {
                   std::uint32_t const i = moving_bodies_[k];
                   finalize_status_[k] = kept;
                   Body& b = bodies_[i];
                   if (!b.moves()) continue;
                   BodyState& s = states_[i];
                   Vec3 const center = b.center + s.delta_position;
                   Quat q = s.delta_rotation * b.pose.rotation;
                   q = q * (1.0f / q.length());
                   if (!finite(center) || !finite(q) || !finite(s.linear_velocity) ||
                       !finite(s.angular_velocity)) {
                     b.frozen = true; // stays where the step began, stopped
                     s = BodyState{};
                     finalize_status_[k] = froze;
                     continue;
                   }
                   if (config_.continuous && b.type == BodyType::dynamic && !b.sensor) {
                     float const moved = s.delta_position.length();
                     if (moved > 0.0f && moved >= config_.ccd_fraction * b.min_extent) {
                       finalize_status_[k] = fast;
                       finalize_start_[k] = b.center;
                     }
                   }
                   b.center = center;
                   b.pose.rotation = q;
                   b.pose.translation = center - q * b.local_center;
                   s.delta_position = Vec3{};
                   s.delta_rotation = Quat::IDENTITY;
                 }
               });
  std::vector<std::uint32_t> newly_frozen;
  fast_.clear();
  for (std::size_t k = 0; k < moving_bodies_.size(); ++k) {
    std::uint32_t const i = moving_bodies_[k];
    if (finalize_status_[k] == froze) {
      newly_frozen.push_back(i);
      frozen_.push_back(BodyId{i, bodies_[i].generation});
    } else if (finalize_status_[k] == fast) {
      fast_.push_back({i, finalize_start_[k]});
    }
  }
  // Their contacts end now; the next step finds them again with the body static.
  cache_.remove_bodies(newly_frozen);
  reset_joint_impulses(newly_frozen); // their joints start afresh
}

template <class T>
void World::step_with(float dt) {
  if (!(dt >= min_dt && dt <= max_dt)) return; // (NaN and infinities fail it too)
  auto const t_start = clock::now();
  flush_woken();
  events_ = std::move(pending_);
  pending_ = StepEvents{};
  find_pairs();
  split_sensor_pairs();
  wake_touched();
  events_.woke_up.insert(events_.woke_up.end(), pending_.woke_up.begin(), pending_.woke_up.end());
  pending_.woke_up.clear();
  profile_.broad_phase = seconds_since(t_start);

  auto const t_narrow = clock::now();
  collide_pairs<T>();
  update_events();
  color_joints();
  profile_.narrow_phase = seconds_since(t_narrow);

  auto const t_prepare = clock::now();
  int const substeps = std::max(1, config_.substeps);
  float const h = dt / float(substeps);
  prepare_bodies();
  GConstraintBlocks<GContactConstraint, T> blocks;
  pack_contacts(blocks, h);
  color_sizes_ = blocks.color_sizes();
  JointBlocks<T> joints;
  pack_joints(joints, h);
  profile_.prepare = seconds_since(t_prepare);

  auto const t_solve = clock::now();
  profile_.joints = 0.0;
  solve_substeps(blocks, joints, substeps, h);
  profile_.solve = seconds_since(t_solve);

  auto const t_finalize = clock::now();
  store_impulses(blocks);
  store_joint_impulses(joints);
  finalize_bodies();
  auto const t_continuous = clock::now();
  bool const synced = solve_continuous();
  profile_.continuous = seconds_since(t_continuous);
  update_joint_reactions(h);
  if (!synced) {
    trees_synced_ = false;    // bodies moved: the trees follow now (BVH), or at the first query
    all_moving_stale_ = true; // the list of single edits is moot until the next sync
    stale_moving_.clear();
  }
  if (config_.broad_phase == BroadPhaseKind::bvh) sync_trees(config_.tasks);
  profile_.finalize = seconds_since(t_finalize) - profile_.continuous;
  auto const t_sleep = clock::now();
  update_sleep(dt);
  events_.fell_asleep.insert(events_.fell_asleep.end(), pending_.fell_asleep.begin(),
                             pending_.fell_asleep.end());
  pending_.fell_asleep.clear();
  auto const by_body = [](BodyId a, BodyId b) {
    return a.index != b.index ? a.index < b.index : a.generation < b.generation;
  };
  for (std::vector<BodyId>* list : {&events_.woke_up, &events_.fell_asleep}) {
    std::sort(list->begin(), list->end(), by_body);
    list->erase(std::unique(list->begin(), list->end()), list->end());
  }
  // Destroyed since (a generation behind), or woken again since they fell asleep: left out.
  std::erase_if(events_.woke_up, [&](BodyId b) { return !is_alive(b); });
  std::erase_if(events_.fell_asleep, [&](BodyId b) { return !is_alive(b) || !is_sleeping(b); });
  profile_.sleep = seconds_since(t_sleep);
  profile_.total = seconds_since(t_start);
}

#if defined(PLUME_DISPATCH_ISA) // one set's copy of the step: its widest width
template void World::step_with<f32xN>(float);
#else
#define PLUME_INSTANTIATE_STEP(T, lanes) template void World::step_with<T>(float);
PLUME_FOR_EACH_F32_TYPE(PLUME_INSTANTIATE_STEP)
#undef PLUME_INSTANTIATE_STEP
#endif

} // namespace plume
