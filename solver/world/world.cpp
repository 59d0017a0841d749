// The rigid-body world (include/plume/solver/world/world.hpp). Compiled once per build, with
// World::step_with instantiated for float and every f32 width the build enables.
#include <plume/solver/world/world.hpp>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <type_traits>

namespace plume {

std::string_view to_string(BodyError e) noexcept {
  switch (e) {
  case BodyError::none:
    return "none";
  case BodyError::non_finite:
    return "non-finite pose, velocity or material value";
  case BodyError::zero_mass:
    return "dynamic body without a positive finite mass";
  case BodyError::bad_material:
    return "negative density, friction, restitution or damping";
  case BodyError::bad_body:
    return "no such body";
  }
  return "unknown";
}

namespace {

using clock = std::chrono::steady_clock;

double seconds_since(clock::time_point t0) {
  return std::chrono::duration<double>(clock::now() - t0).count();
}

bool finite(float x) { return std::isfinite(x); }
bool finite(Vec3 const& v) { return v.is_finite(); }
bool finite(Quat const& q) { return q.is_finite(); }

MassProperties shape_mass(BodyShape const& shape, float density) {
  return std::visit(
      [&](auto const& s) -> MassProperties {
        if constexpr (std::is_same_v<std::decay_t<decltype(s)>, HalfSpace>)
          return {0.0f, Vec3{}, Mat3::ZERO};
        else
          return s.mass_properties(density);
      },
      shape);
}

Aabb3 shape_aabb(BodyShape const& shape, Iso3 const& pose) {
  return std::visit([&](auto const& s) { return s.aabb(pose); }, shape);
}

Manifold collide(BodyShape const& a, Iso3 const& pa, BodyShape const& b, Iso3 const& pb,
                 ManifoldConfig const& cfg) {
  return std::visit(
      [&](auto const& sa, auto const& sb) { return contact_manifold(sa, pa, sb, pb, cfg); }, a, b);
}

/// v scaled down to length at most max. Not GVec3::clamp_length_max: for components near
/// FLT_MAX the squared length overflows to inf and that scales v to 0; this one rescales first.
Vec3 clamp_speed(Vec3 const& v, float max) {
  float const len = v.length();
  if (len <= max) return v;
  float const m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(m > 0.0f) || !std::isfinite(m)) return v; // NaN or inf: the finite check catches it
  Vec3 const u = v / m;
  return u * (max / u.length());
}

std::uint64_t fnv(std::uint64_t h, float x) {
  std::uint32_t const b = std::bit_cast<std::uint32_t>(x);
  for (int i = 0; i < 4; ++i) {
    h ^= (b >> (8 * i)) & 0xffu;
    h *= 1099511628211ull;
  }
  return h;
}

} // namespace

World::World(WorldConfig const& cfg) : config_(cfg) {
  config_.manifold.prediction = cfg.speculative_distance;
  states_.push_back(BodyState{}); // the identity record static bodies share
}

CreateBodyResult World::create_body(BodyDef const& def) {
  if (!def.pose.is_finite() || !finite(def.linear_velocity) || !finite(def.angular_velocity) ||
      !finite(def.density) || !finite(def.friction) || !finite(def.restitution) ||
      !finite(def.linear_damping) || !finite(def.angular_damping) || !finite(def.gravity_scale))
    return {{}, BodyError::non_finite};
  if (def.density < 0.0f || def.friction < 0.0f || def.restitution < 0.0f ||
      def.linear_damping < 0.0f || def.angular_damping < 0.0f)
    return {{}, BodyError::bad_material};
  float const qlen = def.pose.rotation.length();
  if (!(qlen > 0.0f) || !std::isfinite(qlen)) return {{}, BodyError::non_finite};

  Body b;
  b.type = def.type;
  b.pose = {def.pose.rotation * (1.0f / qlen), def.pose.translation};
  b.shape = def.shape;
  b.friction = def.friction;
  b.restitution = def.restitution;
  b.linear_damping = def.linear_damping;
  b.angular_damping = def.angular_damping;
  b.gravity_scale = def.gravity_scale;
  if (def.type == BodyType::dynamic) {
    MassProperties const mp = shape_mass(def.shape, def.density);
    if (!(mp.mass > 0.0f) || !std::isfinite(mp.mass) || !finite(mp.center) ||
        !mp.inertia.is_finite())
      return {{}, BodyError::zero_mass};
    b.mass = mp.mass;
    b.inv_mass = 1.0f / mp.mass;
    b.local_center = mp.center;
    b.inertia_local = mp.inertia;
    auto const inv = mp.inertia.try_inverse();
    b.inv_inertia_local = inv.valid && inv.value.is_finite() ? inv.value : Mat3::ZERO;
  }
  b.center = b.pose.transform_point(b.local_center);

  BodyState s;
  if (def.type != BodyType::static_body) {
    s.linear_velocity = def.linear_velocity;
    s.angular_velocity = def.angular_velocity;
  }
  BodyId const id{std::uint32_t(bodies_.size())};
  bodies_.push_back(std::move(b));
  states_.back() = s;
  states_.push_back(BodyState{});
  graph_.reserve(bodies_.size());
  return {id, BodyError::none};
}

Aabb3 World::aabb(BodyId id) const {
  Body const& b = bodies_.at(id.index);
  return shape_aabb(b.shape, b.pose);
}

BodyError World::set_pose(BodyId id, Iso3 const& pose) {
  if (id.index >= bodies_.size()) return BodyError::bad_body;
  float const qlen = pose.rotation.length();
  if (!pose.is_finite() || !(qlen > 0.0f) || !std::isfinite(qlen)) return BodyError::non_finite;
  Body& b = bodies_[id.index];
  b.pose = {pose.rotation * (1.0f / qlen), pose.translation};
  b.center = b.pose.transform_point(b.local_center);
  return BodyError::none;
}

BodyError World::set_velocity(BodyId id, Vec3 const& linear, Vec3 const& angular) {
  if (id.index >= bodies_.size()) return BodyError::bad_body;
  if (!finite(linear) || !finite(angular)) return BodyError::non_finite;
  if (bodies_[id.index].type == BodyType::static_body) return BodyError::none;
  states_[id.index].linear_velocity = linear;
  states_[id.index].angular_velocity = angular;
  return BodyError::none;
}

void World::update_contacts() {
  auto const t0 = clock::now();
  std::size_t const n = bodies_.size();
  struct Proxy {
    Aabb3 box;
    std::uint32_t body;
  };
  std::vector<Proxy> proxies(n);
  float const margin = config_.speculative_distance;
  for (std::uint32_t i = 0; i < n; ++i) {
    Aabb3 box = shape_aabb(bodies_[i].shape, bodies_[i].pose);
    box.min = box.min - Vec3::splat(margin);
    box.max = box.max + Vec3::splat(margin);
    proxies[i] = {box, i};
  }
  std::sort(proxies.begin(), proxies.end(), [](Proxy const& a, Proxy const& b) {
    return a.box.min.x < b.box.min.x || (a.box.min.x == b.box.min.x && a.body < b.body);
  });
  std::vector<std::uint64_t> pairs;
  for (std::size_t i = 0; i < n; ++i) {
    Proxy const& p = proxies[i];
    for (std::size_t j = i + 1; j < n && proxies[j].box.min.x <= p.box.max.x; ++j) {
      Proxy const& q = proxies[j];
      if (p.box.max.y < q.box.min.y || q.box.max.y < p.box.min.y || p.box.max.z < q.box.min.z ||
          q.box.max.z < p.box.min.z)
        continue;
      if (!bodies_[p.body].is_dynamic() && !bodies_[q.body].is_dynamic()) continue;
      std::uint32_t const a = std::min(p.body, q.body), b = std::max(p.body, q.body);
      pairs.push_back((std::uint64_t(a) << 32) | b);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  profile_.broad_phase = seconds_since(t0);

  auto const t1 = clock::now();
  std::vector<Contact> next;
  next.reserve(pairs.size());
  std::vector<char> kept(contacts_.size(), 0);
  std::size_t io = 0;
  auto const key = [](Contact const& c) { return (std::uint64_t(c.body_a) << 32) | c.body_b; };
  for (std::uint64_t const k : pairs) {
    std::uint32_t const a = std::uint32_t(k >> 32), b = std::uint32_t(k);
    Body const& ba = bodies_[a];
    Body const& bb = bodies_[b];
    while (io < contacts_.size() && key(contacts_[io]) < k)
      ++io;
    Contact const* prev =
        io < contacts_.size() && key(contacts_[io]) == k ? &contacts_[io] : nullptr;
    Manifold const m = collide(ba.shape, ba.pose, bb.shape, bb.pose, config_.manifold);
    if (m.count == 0) continue;
    Contact c;
    c.body_a = a;
    c.body_b = b;
    c.manifold = m;
    c.friction = std::sqrt(ba.friction * bb.friction);
    c.restitution = std::max(ba.restitution, bb.restitution);
    c.tangent = contact_tangent(m.normal, prev != nullptr ? prev->tangent : Vec3{});
    if (prev != nullptr) {
      kept[io] = 1;
      c.color = prev->color;
      c.dynamic_a = prev->dynamic_a;
      c.dynamic_b = prev->dynamic_b;
      // Warm start: a point takes the impulses of the previous point with its feature id, or
      // else of the nearest unclaimed previous point within contact_match_distance (clipping
      // and reduction relabel points that have not moved).
      auto const& pm = prev->manifold;
      c.impulses.tangent1 = prev->impulses.tangent1;
      c.impulses.tangent2 = prev->impulses.tangent2;
      c.impulses.twist = prev->impulses.twist;
      std::array<bool, 4> claimed{}, matched{};
      for (std::size_t i = 0; i < std::size_t(m.count); ++i)
        for (std::size_t j = 0; j < std::size_t(pm.count); ++j)
          if (!claimed[j] && pm.points[j].id == m.points[i].id) {
            c.impulses.normal[i] = prev->impulses.normal[j];
            claimed[j] = matched[i] = true;
            break;
          }
      float const r2 = config_.contact_match_distance * config_.contact_match_distance;
      for (std::size_t i = 0; i < std::size_t(m.count); ++i) {
        if (matched[i]) continue;
        Vec3 const p = m.points[i].point_a + m.points[i].point_b;
        std::size_t best = 4;
        float best_d2 = 4.0f * r2; // distances between sums of two points: twice the midpoints'
        for (std::size_t j = 0; j < std::size_t(pm.count); ++j) {
          if (claimed[j]) continue;
          Vec3 const d = pm.points[j].point_a + pm.points[j].point_b - p;
          if (float const d2 = d.dot(d); d2 <= best_d2) {
            best = j;
            best_d2 = d2;
          }
        }
        if (best < 4) {
          c.impulses.normal[i] = prev->impulses.normal[best];
          claimed[best] = true;
        }
      }
    } else {
      c.color = -2; // coloured below, after the ended contacts free their colours
      c.dynamic_a = ba.is_dynamic();
      c.dynamic_b = bb.is_dynamic();
    }
    next.push_back(c);
  }
  for (std::size_t i = 0; i < contacts_.size(); ++i)
    if (!kept[i]) {
      Contact const& c = contacts_[i];
      graph_.release(c.color, c.body_a, c.body_b, c.dynamic_a, c.dynamic_b);
    }
  for (Contact& c : next)
    if (c.color == -2) c.color = graph_.add(c.body_a, c.body_b, c.dynamic_a, c.dynamic_b);
  contacts_ = std::move(next);
  profile_.narrow_phase = seconds_since(t1);
}

ContactBody World::contact_body(std::uint32_t i) const {
  Body const& b = bodies_[i];
  ContactBody c;
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

void World::integrate_velocities(float h) {
  Vec3 const g = config_.gravity;
  float const max_w = config_.max_rotation / h;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Body const& b = bodies_[i];
    if (!b.is_dynamic()) continue;
    BodyState& s = states_[i];
    Vec3 v = s.linear_velocity * (1.0f / (1.0f + h * b.linear_damping)) + g * (h * b.gravity_scale);
    Vec3 w = s.angular_velocity * (1.0f / (1.0f + h * b.angular_damping));
    s.linear_velocity = clamp_speed(v, config_.max_linear_speed);
    s.angular_velocity = clamp_speed(w, max_w);
  }
}

void World::integrate_positions(float h) {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (!bodies_[i].moves()) continue;
    BodyState& s = states_[i];
    s.delta_position = s.delta_position + s.linear_velocity * h;
    Vec3 const w = s.angular_velocity;
    Quat const spin = Quat::from_xyzw(w.x, w.y, w.z, 0.0f) * s.delta_rotation;
    Quat const q = s.delta_rotation + spin * (0.5f * h);
    s.delta_rotation = q * (1.0f / q.length());
  }
}

void World::finalize_bodies() {
  std::vector<std::uint32_t> newly_frozen;
  for (std::uint32_t i = 0; i < bodies_.size(); ++i) {
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
      newly_frozen.push_back(i);
      frozen_.push_back(BodyId{i});
      continue;
    }
    b.center = center;
    b.pose.rotation = q;
    b.pose.translation = center - q * b.local_center;
    s.delta_position = Vec3{};
    s.delta_rotation = Quat::IDENTITY;
  }
  if (newly_frozen.empty()) return;
  // Their contacts end now; the next step finds them again with the body static.
  std::vector<Contact> keep;
  keep.reserve(contacts_.size());
  for (Contact const& c : contacts_) {
    bool const hit = std::binary_search(newly_frozen.begin(), newly_frozen.end(), c.body_a) ||
                     std::binary_search(newly_frozen.begin(), newly_frozen.end(), c.body_b);
    if (hit)
      graph_.release(c.color, c.body_a, c.body_b, c.dynamic_a, c.dynamic_b);
    else
      keep.push_back(c);
  }
  contacts_ = std::move(keep);
}

template <class T>
void World::step_with(float dt) {
  if (!(dt > 0.0f) || !std::isfinite(dt)) return;
  auto const t_start = clock::now();
  update_contacts();

  auto const t_prepare = clock::now();
  int const substeps = std::max(1, config_.substeps);
  int const solve_iterations = std::max(1, config_.solve_iterations);
  int const relax_iterations = std::max(0, config_.relax_iterations);
  float const h = dt / float(substeps);
  float const inv_h = 1.0f / h;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Body& b = bodies_[i];
    if (b.is_dynamic()) {
      Mat3 const r = Mat3::from_quat(b.pose.rotation);
      b.inv_inertia_world = b.inv_inertia_local.rotate_inertia(r);
    }
    states_[i].delta_position = Vec3{};
    states_[i].delta_rotation = Quat::IDENTITY;
  }
  float const hertz = std::min(config_.contact_hertz, 0.25f * inv_h);
  Softness const soft = Softness::make(hertz, config_.contact_damping_ratio, h);
  Softness const static_soft =
      Softness::make(config_.static_hertz_scale * hertz, config_.contact_damping_ratio, h);

  constexpr std::size_t W = lanes_v<T>;
  constexpr int colors = ConstraintGraph::color_count;
  std::array<std::vector<std::uint32_t>, colors + 1> buckets; // [colors] = overflow
  for (std::uint32_t i = 0; i < contacts_.size(); ++i) {
    int const c = contacts_[i].color;
    buckets[c >= 0 ? std::size_t(c) : std::size_t(colors)].push_back(i);
  }
  std::array<std::size_t, colors + 1> first{};
  std::size_t block_count = 0;
  for (int c = 0; c < colors; ++c) {
    first[std::size_t(c)] = block_count;
    block_count += (buckets[std::size_t(c)].size() + W - 1) / W;
    color_sizes_[std::size_t(c)] = buckets[std::size_t(c)].size();
  }
  first[colors] = block_count;
  color_sizes_[colors] = buckets[colors].size();
  std::vector<GContactConstraint<T>> blocks(block_count);
  std::vector<std::uint32_t> lane_contact(block_count * W, ~std::uint32_t(0));
  std::vector<GContactConstraint<float>> overflow(buckets[colors].size());
  std::int32_t const identity = std::int32_t(bodies_.size());

  auto const prepare = [&]<class U>(GContactConstraint<U>& block, std::size_t lane,
                                    std::uint32_t ci) {
    Contact const& c = contacts_[ci];
    ContactBody const a = contact_body(c.body_a), b = contact_body(c.body_b);
    bool const against_static = a.write < 0 || b.write < 0;
    prepare_contact_lane(block, lane, a, b, c.manifold, c.tangent, c.impulses, c.friction,
                         c.restitution, against_static ? static_soft : soft);
  };
  for (int c = 0; c < colors; ++c) {
    auto const& list = buckets[std::size_t(c)];
    for (std::size_t k = 0; k < (list.size() + W - 1) / W; ++k) {
      std::size_t const bi = first[std::size_t(c)] + k;
      for (std::size_t lane = 0; lane < W; ++lane) {
        std::size_t const li = k * W + lane;
        if (li < list.size()) {
          prepare(blocks[bi], lane, list[li]);
          lane_contact[bi * W + lane] = list[li];
        } else {
          clear_contact_lane(blocks[bi], lane, identity);
        }
      }
    }
  }
  for (std::size_t k = 0; k < overflow.size(); ++k)
    prepare(overflow[k], 0, buckets[colors][k]);
  profile_.prepare = seconds_since(t_prepare);

  auto const t_solve = clock::now();
  BodyState* const states = states_.data();
  float const push = config_.max_push_speed;
  for (int sub = 0; sub < substeps; ++sub) {
    integrate_velocities(h);
    for (auto& c : overflow)
      warm_start_contacts(c, states);
    for (auto& c : blocks)
      warm_start_contacts(c, states);
    for (int r = 0; r < solve_iterations; ++r) {
      for (auto& c : overflow)
        solve_contacts(c, states, inv_h, push, true);
      for (auto& c : blocks)
        solve_contacts(c, states, inv_h, push, true);
    }
    integrate_positions(h);
    for (int r = 0; r < relax_iterations; ++r) {
      for (auto& c : overflow)
        solve_contacts(c, states, inv_h, push, false);
      for (auto& c : blocks)
        solve_contacts(c, states, inv_h, push, false);
    }
  }
  for (auto& c : overflow)
    apply_restitution(c, states, config_.restitution_threshold);
  for (auto& c : blocks)
    apply_restitution(c, states, config_.restitution_threshold);
  profile_.solve = seconds_since(t_solve);

  auto const t_finalize = clock::now();
  for (std::size_t k = 0; k < overflow.size(); ++k)
    contacts_[buckets[colors][k]].impulses = contact_impulses(overflow[k], 0);
  for (std::size_t bi = 0; bi < blocks.size(); ++bi)
    for (std::size_t lane = 0; lane < W; ++lane)
      if (std::uint32_t const ci = lane_contact[bi * W + lane]; ci != ~std::uint32_t(0))
        contacts_[ci].impulses = contact_impulses(blocks[bi], lane);
  finalize_bodies();
  profile_.finalize = seconds_since(t_finalize);
  profile_.total = seconds_since(t_start);
}

void World::step(float dt) { step_with<f32xN>(dt); }

double World::kinetic_energy() const {
  double e = 0.0;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Body const& b = bodies_[i];
    if (!b.is_dynamic()) continue;
    Vec3 const v = states_[i].linear_velocity, w = states_[i].angular_velocity;
    Mat3 const r = Mat3::from_quat(b.pose.rotation);
    Vec3 const iw = b.inertia_local.rotate_inertia(r).mul_vec3(w);
    e += 0.5 * double(b.mass) * double(v.dot(v)) + 0.5 * double(w.dot(iw));
  }
  return e;
}

std::uint64_t World::state_hash() const {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Iso3 const& p = bodies_[i].pose;
    for (float x : {p.translation.x, p.translation.y, p.translation.z, p.rotation.x, p.rotation.y,
                    p.rotation.z, p.rotation.w})
      h = fnv(h, x);
    BodyState const& s = states_[i];
    for (float x : {s.linear_velocity.x, s.linear_velocity.y, s.linear_velocity.z,
                    s.angular_velocity.x, s.angular_velocity.y, s.angular_velocity.z})
      h = fnv(h, x);
  }
  return h;
}

#define PLUME_INSTANTIATE_STEP(T, lanes) template void World::step_with<T>(float);
PLUME_FOR_EACH_F32_TYPE(PLUME_INSTANTIATE_STEP)
#undef PLUME_INSTANTIATE_STEP

} // namespace plume
