// plume_soak: a world whose bodies and joints are created and destroyed at random for many
// steps, with its invariants checked every 1,000 steps and its heap use recorded, to show
// that nothing leaks, drifts or goes non-finite over a long run.
//
//   plume_soak [steps = 100000] [seed = 1]
//
// Each step creates a body with probability 0.3 (a sphere, box or capsule dropped into a
// 20 m x 20 m pen over a ground plane), destroys a random live one with probability 0.3 once
// more than 150 are alive, and with probability 0.05 each creates a joint of a random kind
// between two live dynamic bodies or destroys a random joint. Bodies that leave the pen (below
// y = -50, beyond 100 m) are destroyed. Every 1,000 steps: every live body's pose and
// velocity are finite, the world's body and joint counts match the program's own lists,
// destroyed ids are not alive, and the heap in use (glibc mallinfo2: small blocks and mmapped ones)
// is printed. At the end the heap in use over the second half of the run must not exceed the first
// half's peak by more than 25% + 1 MiB (the world's arrays grow to the steady population's size,
// then stay). Exit status 0 when every check held.
#include <plume/world.hpp>

#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

using namespace plume;

namespace {

bool finite(Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

int failures = 0;
void check(bool ok, char const* what, long step) {
  if (!ok) {
    std::printf("soak: step %ld: %s\n", step, what);
    ++failures;
  }
}

} // namespace

int main(int argc, char** argv) {
  long const steps = argc > 1 ? std::atol(argv[1]) : 100000;
  unsigned const seed = argc > 2 ? static_cast<unsigned>(std::atol(argv[2])) : 1u;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);

  World world;
  {
    BodyDef ground;
    ground.type = BodyType::static_body;
    ground.shape = HalfSpace{Vec3::Y};
    world.create_body(ground);
  }
  std::vector<BodyId> live, dead;
  std::vector<JointId> joints, dead_joints;
  std::vector<std::size_t> heap;
  long created = 0, destroyed = 0, joints_made = 0, joints_gone = 0;

  auto destroy = [&](std::size_t k) {
    BodyId const id = live[k];
    // Destroying a body destroys its joints: drop them from the list first.
    for (JointId j : world.body_joints(id)) {
      auto it = std::find(joints.begin(), joints.end(), j);
      if (it != joints.end()) {
        dead_joints.push_back(*it);
        joints.erase(it);
        ++joints_gone;
      }
    }
    check(world.destroy_body(id) == BodyError::none, "destroy_body failed", 0);
    dead.push_back(id);
    live.erase(live.begin() + static_cast<std::ptrdiff_t>(k));
    ++destroyed;
  };

  for (long s = 1; s <= steps; ++s) {
    if (u(rng) < 0.3f) {
      BodyDef def;
      def.pose.translation = {20.0f * u(rng) - 10.0f, 2.0f + 8.0f * u(rng), 20.0f * u(rng) - 10.0f};
      def.linear_velocity = {4.0f * u(rng) - 2.0f, 0.0f, 4.0f * u(rng) - 2.0f};
      float const r = 0.15f + 0.35f * u(rng);
      switch (rng() % 3) {
      case 0:
        def.shape = Sphere{r};
        break;
      case 1:
        def.shape = Cuboid{{r, 0.5f * r + 0.1f, r}};
        break;
      default:
        def.shape = Capsule{0.5f * r, r};
        break;
      }
      if (rng() % 10 == 0) def.type = BodyType::static_body;
      CreateBodyResult const res = world.create_body(def);
      check(static_cast<bool>(res), "create_body failed", s);
      if (res) {
        live.push_back(res.id);
        ++created;
      }
    }
    if (live.size() > 150 && u(rng) < 0.3f) destroy(rng() % live.size());
    if (u(rng) < 0.05f && live.size() >= 2) {
      BodyId const a = live[rng() % live.size()], b = live[rng() % live.size()];
      if (a != b && world.type(a) == BodyType::dynamic && world.type(b) == BodyType::dynamic) {
        JointDef jd;
        jd.body_a = a;
        jd.body_b = b;
        jd.frame_b.anchor = world.pose(a).translation - world.pose(b).translation;
        switch (rng() % 5) {
        case 0:
          jd.type = FixedJoint{};
          break;
        case 1:
          jd.type = RevoluteJoint{};
          break;
        case 2:
          jd.type = PrismaticJoint{};
          break;
        case 3:
          jd.type = SphericalJoint{};
          break;
        default:
          jd.type = DistanceJoint{};
          break;
        }
        jd.break_force = 2000.0f;
        CreateJointResult const res = world.create_joint(jd);
        check(static_cast<bool>(res), "create_joint failed", s);
        if (res) {
          joints.push_back(res.id);
          ++joints_made;
        }
      }
    }
    if (u(rng) < 0.05f && !joints.empty()) {
      std::size_t const k = rng() % joints.size();
      check(world.destroy_joint(joints[k]) == JointError::none, "destroy_joint failed", s);
      dead_joints.push_back(joints[k]);
      joints.erase(joints.begin() + static_cast<std::ptrdiff_t>(k));
      ++joints_gone;
    }
    world.step(1.0f / 60.0f);
    for (std::size_t k = live.size(); k-- > 0;) {
      Vec3 const p = world.pose(live[k]).translation;
      if (!(p.y > -50.0f && std::abs(p.x) < 100.0f && std::abs(p.z) < 100.0f)) destroy(k);
    }
    if (dead.size() > 4096) dead.erase(dead.begin(), dead.begin() + 2048);
    if (dead_joints.size() > 4096)
      dead_joints.erase(dead_joints.begin(), dead_joints.begin() + 2048);

    if (s % 1000 == 0) {
      for (BodyId id : live) {
        check(world.is_alive(id), "a live body is not alive", s);
        check(finite(world.pose(id).translation) && finite(world.linear_velocity(id)) &&
                  finite(world.angular_velocity(id)),
              "a body's pose or velocity is not finite", s);
      }
      for (BodyId id : dead)
        check(!world.is_alive(id), "a destroyed body is alive", s);
      for (JointId id : dead_joints)
        check(!world.is_alive(id), "a destroyed joint is alive", s);
      check(world.alive_count() == live.size() + 1, "alive_count differs from the list", s);
      check(world.joint_count() == joints.size(), "joint_count differs from the list", s);
      check(std::isfinite(world.kinetic_energy()), "kinetic energy is not finite", s);
      struct mallinfo2 const mi = mallinfo2();
      std::size_t const in_use = mi.uordblks + mi.hblkhd; // small blocks + mmapped ones
      heap.push_back(in_use);
      std::printf("soak: step %6ld  bodies %4zu  joints %3zu  contacts %5zu  heap %8.2f MiB\n", s,
                  live.size(), joints.size(), world.contacts().size(),
                  static_cast<double>(in_use) / (1024.0 * 1024.0));
    }
  }
  if (heap.size() >= 4) {
    std::size_t const half = heap.size() / 2;
    std::size_t const first_peak =
        *std::max_element(heap.begin(), heap.begin() + static_cast<std::ptrdiff_t>(half));
    std::size_t const second_peak =
        *std::max_element(heap.begin() + static_cast<std::ptrdiff_t>(half), heap.end());
    std::printf("soak: heap peak %.2f MiB in the first half, %.2f MiB in the second\n",
                static_cast<double>(first_peak) / 1048576.0,
                static_cast<double>(second_peak) / 1048576.0);
    check(static_cast<double>(second_peak) <= 1.25 * static_cast<double>(first_peak) + 1048576.0,
          "the heap grew in the second half", steps);
  }
  std::printf("soak: %ld steps, %ld bodies created, %ld destroyed, %ld joints made, %ld gone: %s\n",
              steps, created, destroyed, joints_made, joints_gone,
              failures == 0 ? "every check held" : "CHECKS FAILED");
  return failures == 0 ? 0 : 1;
}
