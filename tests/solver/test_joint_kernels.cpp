// The joint kernels (solver/joints/) lane by lane: W random joints of each kind solved in one
// GJointConstraint<T> give, bit for bit, the W results of T = float, for every pass.
#include "../common/harness.hpp"
#include "../common/types.hpp"

// Each type's kernel, the rows, the storage and the motors, included by name.
#include <plume/solver/joints/distance_joint.hpp>
#include <plume/solver/joints/fixed_joint.hpp>
#include <plume/solver/joints/joint.hpp>
#include <plume/solver/joints/joint_constraint.hpp>
#include <plume/solver/joints/joint_rows.hpp>
#include <plume/solver/joints/motor.hpp>
#include <plume/solver/joints/prismatic_joint.hpp>
#include <plume/solver/joints/revolute_joint.hpp>
#include <plume/solver/joints/spherical_joint.hpp>

#include <catch2/catch.hpp>

#include <random>
#include <vector>

using namespace plume;
using plume::test::same_bits;

namespace {

Vec3 random_vec(std::mt19937& rng, float r) {
  std::uniform_real_distribution<float> u(-r, r);
  return {u(rng), u(rng), u(rng)};
}

Quat random_rotation(std::mt19937& rng, float max_angle) {
  std::uniform_real_distribution<float> a(-max_angle, max_angle);
  return Quat::from_axis_angle(random_vec(rng, 1.0f).normalize_or(Vec3::X), a(rng));
}

struct LaneInput {
  JointBody a, b;
  Vec3 anchor_a, anchor_b;
  Quat basis_a, basis_b;
  JointLaneParams params;
  JointImpulses warm;
};

/// A random joint of `kind` between bodies 2i (dynamic) and 2i+1 (dynamic or static: the
/// shared record `identity`), with limits and a motor of a random model.
LaneInput random_lane(std::mt19937& rng, JointKind kind, std::int32_t i, std::int32_t identity) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  auto const body = [&](std::int32_t state, bool dynamic) {
    JointBody jb;
    jb.pose = Iso3{random_rotation(rng, 3.0f), random_vec(rng, 2.0f)};
    jb.solver.center = jb.pose.translation + random_vec(rng, 0.1f);
    jb.solver.state = dynamic ? state : identity;
    if (dynamic) {
      jb.solver.write = state;
      jb.solver.inv_mass = 0.2f + u(rng);
      Quat const r = random_rotation(rng, 3.0f);
      jb.solver.inv_inertia = Mat3::from_diagonal({0.5f + u(rng), 0.5f + u(rng), 0.5f + u(rng)})
                                  .rotate_inertia(Mat3::from_quat(r));
    }
    return jb;
  };
  LaneInput in;
  in.a = body(2 * i, true);
  in.b = body(2 * i + 1, u(rng) < 0.8f);
  in.anchor_a = random_vec(rng, 0.5f);
  in.anchor_b = random_vec(rng, 0.5f);
  in.basis_a = random_rotation(rng, 3.0f);
  in.basis_b = random_rotation(rng, 3.0f);
  in.params.kind = kind;
  in.params.limit_enabled = u(rng) < 0.7f;
  in.params.lower = -u(rng);
  in.params.upper = u(rng);
  in.params.cone_enabled = u(rng) < 0.7f;
  in.params.cone_angle = u(rng);
  Motor& m = in.params.motor;
  m.enabled =
      kind == JointKind::revolute || kind == JointKind::prismatic || kind == JointKind::distance;
  m.model = MotorModel(int(u(rng) * 3.99f));
  m.target_velocity = 2.0f * u(rng) - 1.0f;
  m.target_position = 6.0f * u(rng) - 3.0f;
  m.max_force = 5.0f * u(rng);
  m.stiffness = 50.0f * u(rng);
  m.damping = 5.0f * u(rng);
  in.warm.point = random_vec(rng, 0.1f);
  for (float& x : in.warm.angular)
    x = 0.1f * u(rng);
  for (float& x : in.warm.linear)
    x = 0.1f * u(rng);
  in.warm.lower = 0.1f * u(rng);
  in.warm.upper = 0.1f * u(rng);
  in.warm.motor = 0.1f * u(rng);
  in.warm.cone = 0.1f * u(rng);
  // The singular places, one lane in four: a distance joint whose anchors coincide (d = 0:
  // the fallback axis), and a half-turn swing (the swing-twist split's n -> 0).
  if (u(rng) < 0.25f) {
    if (kind == JointKind::distance) {
      Vec3 const world_a = in.a.pose.transform_point(in.anchor_a);
      in.anchor_b = in.b.pose.inverse_transform_point(world_a);
    } else {
      Quat const qa = in.a.pose.rotation * in.basis_a;
      in.basis_b = in.b.pose.rotation.conjugate() * qa * Quat::from_rotation_y(3.14159f);
    }
  }
  return in;
}

template <Real T>
void prepare(GJointConstraint<T>& c, std::size_t lane, LaneInput const& in) {
  Softness const soft = Softness::make(60.0f, 2.0f, 1.0f / 240.0f);
  prepare_joint_lane(c, lane, in.a, in.anchor_a, in.basis_a, in.b, in.anchor_b, in.basis_b,
                     in.params, in.warm, soft, 1.0f / 240.0f);
}

template <Real T>
void passes(JointKind kind, GJointConstraint<T>& c, BodyState* states) {
  T const inv_h = T(240.0f);
  joint_pass<JointPass::warm_start>(kind, c, states, inv_h);
  joint_pass<JointPass::solve>(kind, c, states, inv_h);
  joint_pass<JointPass::solve>(kind, c, states, inv_h);
  joint_pass<JointPass::relax>(kind, c, states, inv_h);
}

bool same_state(BodyState const& x, BodyState const& y) {
  auto const v = [](Vec3 const& p, Vec3 const& q) {
    return same_bits(p.x, q.x) && same_bits(p.y, q.y) && same_bits(p.z, q.z);
  };
  return v(x.linear_velocity, y.linear_velocity) && v(x.angular_velocity, y.angular_velocity);
}

} // namespace

namespace {

template <Real T>
void check_lanes() {
  constexpr std::size_t W = lanes_v<T>;
  std::mt19937 rng(1234);
  for (int k = 0; k < joint_kind_count; ++k) {
    JointKind const kind = JointKind(k);
    for (int round = 0; round < 20; ++round) {
      std::int32_t const identity = std::int32_t(2 * W);
      std::vector<BodyState> init(2 * W + 1);
      std::uniform_real_distribution<float> u(-1.0f, 1.0f);
      for (std::size_t s = 0; s < 2 * W; ++s) {
        init[s].linear_velocity = {u(rng), u(rng), u(rng)};
        init[s].angular_velocity = {u(rng), u(rng), u(rng)};
        init[s].delta_position = {0.01f * u(rng), 0.01f * u(rng), 0.01f * u(rng)};
        init[s].delta_rotation =
            Quat::from_axis_angle(Vec3{u(rng), u(rng), 1.0f}.normalize(), 0.05f * u(rng));
      }
      std::vector<LaneInput> inputs;
      for (std::size_t lane = 0; lane < W; ++lane)
        inputs.push_back(random_lane(rng, kind, std::int32_t(lane), identity));
      // Some lanes empty (the padding of a colour's last block), never all.
      std::vector<bool> empty(W, false);
      for (std::size_t lane = 1; lane < W; ++lane)
        empty[lane] = round % 3 == 0 && lane % 3 == 1;
      std::vector<BodyState> wide = init, scalar = init;
      GJointConstraint<T> block;
      for (std::size_t lane = 0; lane < W; ++lane)
        if (empty[lane])
          clear_joint_lane(block, lane, identity);
        else
          prepare(block, lane, inputs[lane]);
      passes(kind, block, wide.data());
      for (std::size_t lane = 0; lane < W; ++lane) {
        if (empty[lane]) {
          JointImpulses const x = joint_impulses(block, lane);
          CHECK(x.point.length() == 0.0f);
          CHECK(x.motor == 0.0f);
          CHECK(x.lower == 0.0f);
          continue;
        }
        GJointConstraint<float> one;
        prepare(one, 0, inputs[lane]);
        passes(kind, one, scalar.data());
        JointImpulses const x = joint_impulses(block, lane), y = joint_impulses(one, 0);
        INFO("kind " << to_string(kind) << " lane " << lane);
        CHECK(same_bits(x.point.x, y.point.x));
        CHECK(same_bits(x.point.z, y.point.z));
        CHECK(same_bits(x.angular[1], y.angular[1]));
        CHECK(same_bits(x.linear[0], y.linear[0]));
        CHECK(same_bits(x.lower, y.lower));
        CHECK(same_bits(x.upper, y.upper));
        CHECK(same_bits(x.motor, y.motor));
        CHECK(same_bits(x.cone, y.cone));
      }
      for (std::size_t s = 0; s < 2 * W + 1; ++s) {
        INFO("kind " << to_string(kind) << " body " << s);
        CHECK(same_state(wide[s], scalar[s]));
        CHECK(wide[s].linear_velocity.is_finite());
      }
      // The kernels did something: a dynamic body's velocity changed.
      CHECK(!same_state(wide[0], init[0]));
    }
  }
}

} // namespace

// Every wide width of the build (none in the scalar build: nothing to compare there).
TEST_CASE("joint kernels: every lane is bitwise the scalar kernel's", "[joints]") {
  for_each_type<test::f32_wide_types>([]<class T>() { check_lanes<T>(); });
}
