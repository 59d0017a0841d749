// The world's joints (include/plume/solver/world/world.hpp, "joints"): creation with its
// checks, destruction, motors, state and reactions. Packing and solving are in step.cpp.
#include <plume/solver/world/world.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace plume {

std::string_view to_string(JointKind k) noexcept {
  switch (k) {
  case JointKind::fixed:
    return "fixed";
  case JointKind::revolute:
    return "revolute";
  case JointKind::prismatic:
    return "prismatic";
  case JointKind::spherical:
    return "spherical";
  case JointKind::distance:
    return "distance";
  }
  return "unknown";
}

std::string_view to_string(JointError e) noexcept {
  switch (e) {
  case JointError::none:
    return "none";
  case JointError::bad_body:
    return "bad_body: a body id names no live body";
  case JointError::same_body:
    return "same_body: a joint needs two different bodies";
  case JointError::bad_axis:
    return "bad_axis: a frame's axis is zero or not finite";
  case JointError::bad_limits:
    return "bad_limits: lower > upper or a limit out of range";
  case JointError::bad_motor:
    return "bad_motor: a NaN target or a negative motor parameter";
  case JointError::bad_value:
    return "bad_value: a NaN or negative break threshold";
  case JointError::bad_joint:
    return "bad_joint: no such joint, or it has no motor";
  }
  return "unknown";
}

std::string_view to_string(MotorModel m) noexcept {
  switch (m) {
  case MotorModel::spring_damper:
    return "spring_damper";
  case MotorModel::acceleration:
    return "acceleration";
  case MotorModel::force:
    return "force";
  case MotorModel::velocity:
    return "velocity";
  }
  return "unknown";
}

namespace {

/// The checks of a joint type's own fields.
JointError check_type(JointType const& type) {
  return std::visit(
      [](auto const& t) -> JointError {
        using J = std::decay_t<decltype(t)>;
        if constexpr (std::is_same_v<J, FixedJoint>) {
          return JointError::none;
        } else {
          if (!t.limits_valid()) return JointError::bad_limits;
          if constexpr (std::is_same_v<J, RevoluteJoint> || std::is_same_v<J, PrismaticJoint>)
            if (!t.motor.valid()) return JointError::bad_motor;
          return JointError::none;
        }
      },
      type);
}

Motor* motor_of(JointType& type) {
  if (auto* r = std::get_if<RevoluteJoint>(&type)) return &r->motor;
  if (auto* p = std::get_if<PrismaticJoint>(&type)) return &p->motor;
  return nullptr;
}

} // namespace

World::Joint const& World::joint(JointId id) const {
  if (!is_alive(id)) throw std::out_of_range("plume::World: no such joint");
  return joints_[id.index];
}

CreateJointResult World::create_joint(JointDef const& def) {
  if (!is_alive(def.body_a) || !is_alive(def.body_b)) return {{}, JointError::bad_body};
  if (def.body_a == def.body_b) return {{}, JointError::same_body};
  auto const ba = def.frame_a.basis(), bb = def.frame_b.basis();
  if (!ba || !bb || !def.frame_a.normal.is_finite() || !def.frame_b.normal.is_finite())
    return {{}, JointError::bad_axis};
  if (JointError const e = check_type(def.type); e != JointError::none) return {{}, e};
  if (std::isnan(def.break_force) || std::isnan(def.break_torque) || def.break_force < 0.0f ||
      def.break_torque < 0.0f)
    return {{}, JointError::bad_value};
  wake(def.body_a.index); // a new joint moves what it holds
  wake(def.body_b.index);
  Joint j;
  j.def = def;
  j.basis_a = *ba;
  j.basis_b = *bb;
  j.params = std::visit([](auto const& t) { return t.lane_params(); }, def.type);
  std::uint32_t index;
  if (!free_joint_slots_.empty()) {
    index = free_joint_slots_.back();
    free_joint_slots_.pop_back();
    j.generation = joints_[index].generation;
    joints_[index] = std::move(j);
  } else {
    index = std::uint32_t(joints_.size());
    joints_.push_back(std::move(j));
  }
  if (!def.collide_connected) {
    std::uint64_t const k = body_pair_key(def.body_a.index, def.body_b.index);
    no_collide_pairs_.insert(
        std::upper_bound(no_collide_pairs_.begin(), no_collide_pairs_.end(), k), k);
    joints_[index].filters = true;
  }
  return {JointId{index, joints_[index].generation}, JointError::none};
}

void World::release_joint_color(Joint& j) {
  if (j.colored)
    cache_.graph().release(j.color, j.def.body_a.index, j.def.body_b.index, j.dynamic_a,
                           j.dynamic_b);
  j.colored = false;
  j.color = ConstraintGraph::overflow;
}

JointError World::destroy_joint(JointId id) {
  if (!is_alive(id)) return JointError::bad_joint;
  Joint& j = joints_[id.index];
  wake(j.def.body_a.index); // what it held is free to move
  wake(j.def.body_b.index);
  release_joint_color(j);
  stop_filtering(j);
  Joint dead;
  dead.alive = false;
  dead.generation = j.generation + 1;
  j = std::move(dead);
  free_joint_slots_.push_back(id.index);
  return JointError::none;
}

void World::stop_filtering(Joint& j) {
  if (!j.filters) return;
  std::uint64_t const k = body_pair_key(j.def.body_a.index, j.def.body_b.index);
  auto const it = std::lower_bound(no_collide_pairs_.begin(), no_collide_pairs_.end(), k);
  if (it != no_collide_pairs_.end() && *it == k) no_collide_pairs_.erase(it);
  j.filters = false;
}

void World::reset_joint_impulses(std::span<std::uint32_t const> bodies) {
  if (bodies.empty()) return;
  for (Joint& j : joints_)
    if (j.alive && std::find_if(bodies.begin(), bodies.end(), [&](std::uint32_t b) {
                     return b == j.def.body_a.index || b == j.def.body_b.index;
                   }) != bodies.end())
      j.impulses = JointImpulses{};
}

bool World::jointed_no_collide(std::uint32_t a, std::uint32_t b) const {
  return std::binary_search(no_collide_pairs_.begin(), no_collide_pairs_.end(),
                            body_pair_key(a, b));
}

JointError World::set_motor(JointId id, Motor const& motor) {
  if (!is_alive(id)) return JointError::bad_joint;
  Joint& j = joints_[id.index];
  Motor* m = motor_of(j.def.type);
  if (!m) return JointError::bad_joint;
  if (!motor.valid()) return JointError::bad_motor;
  wake(j.def.body_a.index);
  wake(j.def.body_b.index);
  *m = motor;
  j.params = std::visit([](auto const& t) { return t.lane_params(); }, j.def.type);
  return JointError::none;
}

JointError World::set_motor_targets(JointId id, float target_velocity, float target_position) {
  if (!is_alive(id)) return JointError::bad_joint;
  Motor const* m = motor_of(joints_[id.index].def.type);
  if (!m) return JointError::bad_joint;
  Motor next = *m;
  next.target_velocity = target_velocity;
  next.target_position = target_position;
  return set_motor(id, next);
}

std::vector<JointId> World::body_joints(BodyId id) const {
  (void)body(id);
  std::vector<JointId> out;
  for (std::uint32_t i = 0; i < joints_.size(); ++i)
    if (Joint const& j = joints_[i]; j.alive && (j.def.body_a == id || j.def.body_b == id))
      out.push_back(JointId{i, j.generation});
  return out;
}

JointFrame World::joint_frame(BodyId id, Vec3 const& world_anchor, Vec3 const& world_axis,
                              Vec3 const& world_normal) const {
  Iso3 const& pose = body(id).pose;
  Quat const inv = pose.rotation.conjugate();
  return {pose.inverse_transform_point(world_anchor), inv * world_axis, inv * world_normal};
}

JointBody World::joint_body(std::uint32_t i) const { return {contact_body(i), bodies_[i].pose}; }

/// Joints take graph colours after the contacts, in joint index order; a joint whose
/// bodies changed type (or froze) gives its colour back and takes a new one.
void World::color_joints() {
  for (Joint& j : joints_) {
    if (!j.alive) continue;
    if (j.broken) {
      release_joint_color(j);
      continue;
    }
    bool const da = bodies_[j.def.body_a.index].is_dynamic();
    bool const db = bodies_[j.def.body_b.index].is_dynamic();
    if (j.colored && (da != j.dynamic_a || db != j.dynamic_b)) release_joint_color(j);
    if (!j.colored) {
      j.dynamic_a = da;
      j.dynamic_b = db;
      j.color = cache_.graph().add(j.def.body_a.index, j.def.body_b.index, da, db);
      j.colored = true;
    }
  }
}

JointState World::joint_state(JointId id) const {
  Joint const& j = joint(id);
  Body const& a = bodies_[j.def.body_a.index];
  Body const& b = bodies_[j.def.body_b.index];
  Quat const qa = a.pose.rotation * j.basis_a, qb = b.pose.rotation * j.basis_b;
  Vec3 const pa = a.pose.transform_point(j.def.frame_a.anchor);
  Vec3 const pb = b.pose.transform_point(j.def.frame_b.anchor);
  Vec3 const x = qa * Vec3::X;
  BodyState const& sa = states_[j.def.body_a.index];
  BodyState const& sb = states_[j.def.body_b.index];
  Vec3 const va = a.type == BodyType::static_body ? Vec3{} : sa.linear_velocity;
  Vec3 const vb = b.type == BodyType::static_body ? Vec3{} : sb.linear_velocity;
  Vec3 const wa = a.type == BodyType::static_body ? Vec3{} : sa.angular_velocity;
  Vec3 const wb = b.type == BodyType::static_body ? Vec3{} : sb.angular_velocity;
  Vec3 const ra = pa - a.center, rb = pb - b.center;
  Vec3 const d = pb - pa;
  Vec3 const vrel = (vb + wb.cross(rb)) - (va + wa.cross(ra));
  JointState s;
  s.kind = j.params.kind;
  s.angular_speed = (wb - wa).dot(x);
  GSwingTwist<float> const st = swing_twist(qa, qb);
  switch (j.params.kind) {
  case JointKind::revolute:
    s.angle = st.twist;
    break;
  case JointKind::spherical:
    s.angle = st.twist;
    s.swing = st.swing_angle;
    s.angular_speed = (wb - wa).dot(twist_axis(qa, qb));
    break;
  case JointKind::prismatic:
    s.translation = d.dot(x);
    s.linear_speed = vrel.dot(x) + wa.cross(x).dot(d);
    break;
  case JointKind::distance:
    s.translation = d.length();
    s.linear_speed = vrel.dot(d.normalize_or(x));
    break;
  case JointKind::fixed:
    break;
  }
  s.reaction_force = j.force;
  s.reaction_torque = j.torque;
  s.broken = j.broken;
  return s;
}

/// Reactions: the stored impulses along the joint's rows at the poses now, over h; a joint
/// past its thresholds breaks.
void World::update_joint_reactions(float h) {
  float const inv_h = 1.0f / h;
  for (std::uint32_t i = 0; i < joints_.size(); ++i) {
    Joint& j = joints_[i];
    if (!j.alive || j.broken) continue;
    Body const& a = bodies_[j.def.body_a.index];
    Body const& b = bodies_[j.def.body_b.index];
    if (!a.active() && !b.active()) continue; // asleep (or between fixed bodies): as it was
    Quat const qa = a.pose.rotation * j.basis_a, qb = b.pose.rotation * j.basis_b;
    Vec3 const x = qa * Vec3::X, y = qa * Vec3::Y, z = qa * Vec3::Z;
    JointImpulses const& l = j.impulses;
    Vec3 lin{}, ang{};
    float const axial = (l.motor + l.lower) - l.upper;
    switch (j.params.kind) {
    case JointKind::fixed:
      lin = l.point;
      ang = (x * l.angular[0] + y * l.angular[1]) + z * l.angular[2];
      break;
    case JointKind::revolute:
      lin = l.point;
      ang = (x * axial + y * l.angular[1]) + z * l.angular[2];
      break;
    case JointKind::prismatic:
      lin = (x * axial + y * l.linear[0]) + z * l.linear[1];
      ang = (x * l.angular[0] + y * l.angular[1]) + z * l.angular[2];
      break;
    case JointKind::spherical: {
      GSwingTwist<float> const st = swing_twist(qa, qb);
      Vec3 const swing_axis = (qa * Vec3{0.0f, st.swing_y, st.swing_z}).normalize_or(y);
      lin = l.point;
      ang = twist_axis(qa, qb) * (l.lower - l.upper) - swing_axis * l.cone;
      break;
    }
    case JointKind::distance: {
      Vec3 const pa = a.pose.transform_point(j.def.frame_a.anchor);
      Vec3 const pb = b.pose.transform_point(j.def.frame_b.anchor);
      lin = (pb - pa).normalize_or(x) * axial;
      break;
    }
    }
    j.force = lin * inv_h;
    j.torque = ang * inv_h;
    if (j.force.length() > j.def.break_force || j.torque.length() > j.def.break_torque) {
      j.broken = true; // stops acting and filtering: the pieces collide from the next step
      j.impulses = JointImpulses{};
      stop_filtering(j);
      events_.joint_broken.push_back(JointId{i, j.generation});
    }
  }
}

} // namespace plume
