// Contact and sensor events: when they begin and end, what destroying a body reports, that a
// sensor takes no contact response, and that the events are the same at every width.
#include "../common/types.hpp"

#include <fixtures/scenes.hpp>
#include <plume/solver/world/world.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>

using namespace plume;

namespace {

constexpr float dt = 1.0f / 60.0f;

bool has(std::vector<ColliderPair> const& v, BodyId a, BodyId b) {
  return std::find(v.begin(), v.end(), ColliderPair{a, b}) != v.end();
}

bool sorted(std::vector<ColliderPair> const& v) {
  return std::is_sorted(v.begin(), v.end(), [](ColliderPair const& x, ColliderPair const& y) {
    return body_pair_key(x.a.index, x.b.index) < body_pair_key(y.a.index, y.b.index);
  });
}

} // namespace

TEST_CASE("events: a contact begins once when a ball lands and ends when it leaves",
          "[world][events]") {
  World w;
  BodyId const ground = scenes::add_ground(w);
  BodyId const ball =
      w.create_body({.pose = Iso3::from_translation({0, 2, 0}), .shape = Sphere{0.5f}}).id;
  int begins = 0, first = -1;
  for (int s = 0; s < 90; ++s) {
    w.step(dt);
    StepEvents const& e = w.events();
    CHECK(e.contact_end.empty());
    CHECK(e.sensor_begin.empty());
    if (has(e.contact_begin, ground, ball)) {
      ++begins;
      if (first < 0) first = s;
    }
    CHECK(e.contact_begin.size() == std::size_t(has(e.contact_begin, ground, ball)));
  }
  CHECK(begins == 1);
  // Free fall of 1.5 m takes 0.55 s: the contact begins within the speculative distance of it.
  CHECK(first >= 28);
  CHECK(first <= 34);
  REQUIRE(w.set_pose(ball, Iso3::from_translation({0, 5, 0})) == BodyError::none);
  w.step(dt);
  CHECK(has(w.events().contact_end, ground, ball));
  CHECK(w.events().contact_begin.empty());
  w.step(dt);
  CHECK(w.events().contact_end.empty());
}

TEST_CASE("events: a sensor reports overlaps and takes no contact response", "[world][events]") {
  auto const run = [](bool with_sensor, std::vector<int>& begin_steps,
                      std::vector<int>& end_steps) {
    World w;
    scenes::add_ground(w);
    BodyId sensor{};
    if (with_sensor)
      sensor = w.create_body({.type = BodyType::static_body,
                              .pose = Iso3::from_translation({0, 3, 0}),
                              .shape = Cuboid{Vec3{2, 0.5f, 2}},
                              .sensor = true})
                   .id;
    BodyId const ball =
        w.create_body({.pose = Iso3::from_translation({0, 6, 0}), .shape = Sphere{0.3f}}).id;
    std::vector<Iso3> poses;
    for (int s = 0; s < 120; ++s) {
      w.step(dt);
      poses.push_back(w.pose(ball));
      StepEvents const& e = w.events();
      CHECK(sorted(e.sensor_begin));
      if (with_sensor) {
        if (has(e.sensor_begin, sensor, ball)) begin_steps.push_back(s);
        if (has(e.sensor_end, sensor, ball)) end_steps.push_back(s);
        for (Contact const& c : w.contacts()) // never a contact with the sensor
          CHECK((c.body_a != sensor.index && c.body_b != sensor.index));
        bool const inside = std::abs(w.pose(ball).translation.y - 3.0f) <= 0.8f;
        bool const listed =
            std::binary_search(w.sensor_overlaps().begin(), w.sensor_overlaps().end(),
                               body_pair_key(sensor.index, ball.index));
        // The overlap test runs before the step moves the ball: allow one step of travel.
        if (std::abs(std::abs(w.pose(ball).translation.y - 3.0f) - 0.8f) > 0.2f)
          CHECK(listed == inside);
      }
    }
    return poses;
  };
  std::vector<int> begins, ends, unused;
  auto const with = run(true, begins, ends);
  auto const without = run(false, unused, unused);
  REQUIRE(begins.size() == 1);
  REQUIRE(ends.size() == 1);
  CHECK(begins[0] < ends[0]);
  // The ball falls exactly as if the sensor were not there (same bits, every step).
  for (std::size_t s = 0; s < with.size(); ++s) {
    INFO("step " << s);
    CHECK(with[s].translation.y == without[s].translation.y);
  }
  CHECK(with.back().translation.y == Approx(0.3f).margin(0.02f)); // on the ground
}

TEST_CASE("events: destroying a body ends its contacts and overlaps, reported with its old id",
          "[world][events][destroy]") {
  World w;
  BodyId const ground = scenes::add_ground(w);
  BodyId const sensor = w.create_body({.type = BodyType::static_body,
                                       .pose = Iso3::from_translation({0, 0.5f, 0}),
                                       .shape = Cuboid{Vec3::splat(1.0f)},
                                       .sensor = true})
                            .id;
  BodyId const box = w.create_body({.pose = Iso3::from_translation({0, 0.5f, 0}),
                                    .shape = Cuboid{Vec3::splat(0.5f)}})
                         .id;
  for (int s = 0; s < 10; ++s)
    w.step(dt);
  REQUIRE(!w.contacts().empty());
  REQUIRE(!w.sensor_overlaps().empty());
  REQUIRE(w.destroy_body(box) == BodyError::none);
  // The slot is reused before the next step: the events still name the destroyed body.
  BodyId const reused =
      w.create_body({.pose = Iso3::from_translation({5, 3, 0}), .shape = Sphere{0.2f}}).id;
  REQUIRE(reused.index == box.index);
  w.step(dt);
  StepEvents const& e = w.events();
  CHECK(has(e.contact_end, ground, box));
  CHECK(has(e.sensor_end, sensor, box));
  CHECK(!has(e.contact_end, ground, reused));
  CHECK(e.contact_begin.empty());
  w.step(dt);
  CHECK(w.events().contact_end.empty());
  CHECK(w.events().sensor_end.empty());
}

TEST_CASE("events: the same events at every width", "[world][events][determinism]") {
  auto const run = []<class T>(std::type_identity<T>) {
    World w;
    scenes::add_ground(w);
    scenes::add_box_pyramid(w, 4);
    w.create_body({.type = BodyType::static_body,
                   .pose = Iso3::from_translation({0, 2, 0}),
                   .shape = Sphere{1.5f},
                   .sensor = true});
    w.create_body({.pose = Iso3::from_translation({0.2f, 8, 0.1f}), .shape = Sphere{0.4f}});
    std::vector<std::uint64_t> log;
    for (int s = 0; s < 120; ++s) {
      w.template step_with<T>(dt);
      StepEvents const& e = w.events();
      for (auto const* list : {&e.contact_begin, &e.contact_end, &e.sensor_begin, &e.sensor_end}) {
        log.push_back(0xffffffffffffffffull);
        for (ColliderPair const& p : *list)
          log.push_back(body_pair_key(p.a.index, p.b.index));
      }
    }
    return log;
  };
  auto const scalar = run(std::type_identity<float>{});
  CHECK(std::count(scalar.begin(), scalar.end(), 0xffffffffffffffffull) == 480);
  CHECK(scalar.size() > 480 + 10); // events happened
  for_each_type<test::f32_wide_types>(
      [&]<class T>() { CHECK(run(std::type_identity<T>{}) == scalar); });
}
