// plume/solver/character/move_and_slide.hpp - moves a shape by velocity * dt through a scene,
// sliding along what it touches: the movement step of a kinematic character controller.
//
//   MoveAndSlideResult<Id> r = move_and_slide(query, shape, pose, velocity, dt, cfg, filter,
//                                             on_hit);
//   r.position, r.velocity (the projected velocity, to keep for the next frame), r.hits
//
// The scene is any MoveQuery provider (the concept below): the world's (WorldMoveQuery in
// solver/world/move_query.hpp) or a user's own set of colliders. The loop (Avian 0.6's):
//  1. depenetrate: the contacts within the skin become push-out pairs (depth = skin -
//     separation), solved by depenetrate(); a fix longer than the distance the contacts came
//     from gathers them again within |fix| + skin and solves again (depenetrate(query, ...));
//     the shape moves by the fix;
//  2. up to cfg.iterations sweeps: sweep = velocity * time left, stop when shorter than
//     cfg.min_sweep. Cast the shape along it, cast length |sweep| + skin, initial overlaps
//     that the motion leaves ignored; no hit: take the whole sweep and stop. A hit at cast
//     distance d with normal n: move by max(d - skin / max(dir . -n, 0.005), 0) along the
//     sweep (so the gap to the surface is the skin, measured along n: the + skin in the cast
//     length keeps a character standing on a walkable slope from creeping down it). Then
//     collect the contacts around the new position (every collider within
//     cfg.plane_distance, 2 x skin by default: the deepest point of its contact manifold);
//     the touched ones (separation <= skin + cfg.touch_tolerance), the sweep's plane and
//     cfg.user_planes are merged within 5 degrees keeping the one most against the velocity
//     (PlaneSet3), and the velocity is projected onto all of them at once (project_velocity);
//  3. depenetrate once more.
// Units: positions and skin in length units, velocity in length units per second, dt in
// seconds; the shape keeps pose.rotation throughout. What is better than Avian's: every hit
// the callback sees names the collider actually touched (a contact plane's own, not the
// sweep's), distance is the real distance travelled to the hit, and a normal, position or
// velocity the callback changes is honoured for every hit, the sweep's included. And a contact
// not yet touched (between the skin and 2 x skin) does not clip the velocity, as Avian's does:
// its plane, linearised at a distance, is a ghost (the edge of the next box of a flat floor,
// seen from before the seam, tilts up and bumps the character over a seam that is not there);
// the sweep's exact cast stops the shape at anything it would really reach.
//
// The callback, on_hit(MoveHit<Id>& hit) -> HitResponse, is called for the sweep's hit and
// for each contact plane of every iteration (a floor touched during four sweeps is reported
// four times), in the provider's order:
//  - accept: the plane (hit.normal, which the callback may change) clips the velocity, if
//    touched (hit.touching);
//  - ignore: the plane does not clip (the sweep still stops at the hit);
//  - abort: no more sweeps (the final depenetration still runs).
// hit.position and hit.velocity are the shape's at that moment; changes are kept. The callback
// may also add a second plane for an accepted, touched hit (hit.extra_normal).
//
// Bad input: a non-finite pose, velocity or dt, or a negative dt, returns the input unchanged
// with invalid_input set (nothing is queried). dt = 0, or a sweep shorter than cfg.min_sweep
// (1e-4: under 6 mm/s at 60 Hz), only depenetrates. Each sweep is at most cfg.max_move long, so
// a call moves at most iterations x max_move whatever dt is (|v| dt beyond a float's range
// included), plus its two depenetrations, each at most max_depenetration_move(cfg) long. A shape
// that starts deeper than the depenetration's rejection threshold in something is pushed out by
// at most those two depenetrations per call and does not sweep (deep_start). A callback that sets a
// non-finite position or velocity is not followed (the previous value is kept). Every loop is
// bounded: cfg.iterations sweeps, cfg.depenetration.iterations passes, at most
// max_depenetration_queries contact queries per depenetration, at most cfg.planes.max_planes
// planes. A sweep blocked at once by planes it cannot satisfy (an acute wedge) leaves the velocity
// zero: the character stops, it does not jitter.
#pragma once

#include <plume/math/iso3.hpp>
#include <plume/math/pack.hpp>
#include <plume/math/vec3.hpp>
#include <plume/solver/character/depenetration.hpp>
#include <plume/solver/character/plane_set.hpp>
#include <plume/solver/character/velocity_projection.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace plume {

/// A provider's first hit of a cast: the fraction toi in [0, 1] of the motion at which the
/// shape first touches the collider; the point on the collider; the unit normal out of the
/// collider toward the shape.
template <class Id>
struct MoveCastHit {
  Id collider;
  float toi = 0.0f;
  Vec3 point{};
  Vec3 normal{};
};

/// A provider's contact: the deepest point of a collider's contact manifold with the shape.
/// normal: unit, out of the collider toward the shape; separation: signed gap along it
/// (negative = overlap); point: on the collider's surface.
template <class Id>
struct MoveContact {
  Id collider;
  Vec3 point{};
  Vec3 normal{};
  float separation = 0.0f;
};

namespace detail {
/// The callable type MoveQuery::contacts is checked with: returns false to stop.
template <class Id>
struct move_contact_sink {
  bool operator()(MoveContact<Id> const&) const { return true; }
};
} // namespace detail

/// A scene that move_and_slide can move through.
///  - cast(shape, pose, motion, filter): the first collider the shape at pose touches moving
///    by t * motion, t in [0, 1] (target distance 0); a collider the shape already overlaps
///    is ignored when the motion leaves it or runs along its surface (within about 1e-3 rad;
///    stopping there would stop a character touching both walls of a corridor its width).
///  - contacts(shape, pose, distance, filter, sink): every collider within `distance` of the
///    shape, as a MoveContact each; sink returns false to stop. A deterministic order (the
///    results of move_and_slide depend on it only through merges of equal planes).
template <class Q>
concept MoveQuery = requires(Q const& q, typename Q::shape_type const& shape, Iso3 const& pose,
                             Vec3 const& motion, float distance,
                             typename Q::filter_type const& filter,
                             detail::move_contact_sink<typename Q::collider_id> sink) {
  typename Q::collider_id;
  {
    q.cast(shape, pose, motion, filter)
    } -> std::same_as<std::optional<MoveCastHit<typename Q::collider_id>>>;
  q.contacts(shape, pose, distance, filter, sink);
};

/// Where a hit came from.
enum class MoveHitKind : std::uint8_t {
  sweep,   ///< the first thing a sweep hit
  contact, ///< a contact plane collected after a sweep
};

/// What the callback answers for a hit.
enum class HitResponse : std::uint8_t {
  accept, ///< the plane clips the velocity
  ignore, ///< the plane does not clip the velocity (a sweep still stops at its hit)
  abort,  ///< stop sweeping after this hit (the final depenetration still runs)
};

/// One hit as the callback sees it (normal, position and velocity may be changed).
template <class Id>
struct MoveHit {
  Id collider; ///< the collider touched
  MoveHitKind kind = MoveHitKind::sweep;
  int iteration = 0;       ///< the sweep it belongs to, from 0
  Vec3 point{};            ///< on the collider's surface, world
  Vec3 normal{};           ///< unit, out of the collider toward the shape; may be changed
  Vec3 position{};         ///< the shape's position now (after the move to the hit)
  Vec3 velocity{};         ///< the velocity now (before this hit clips it)
  float distance = 0.0f;   ///< length travelled by this sweep to the hit (0 for contacts)
  float separation = 0.0f; ///< the gap to the collider's surface (negative = overlap)
  /// Within skin + touch_tolerance: only a touched plane clips the velocity (a sweep's hit is
  /// always touched).
  bool touching = true;
  /// A second plane the callback may add for this hit (unit; zero, the default, adds none):
  /// it clips the velocity with hit.normal when the hit is accepted and touched. A character
  /// controller adds a vertical wall in front of a slope too steep to climb this way.
  Vec3 extra_normal{};
};

/// The loop's parameters (Avian 0.6's defaults, in length units of 1 m; scaled(unit) for
/// other units).
struct MoveAndSlideConfig {
  int iterations = 4;           ///< sweeps at most
  float skin = 0.01f;           ///< the gap kept to surfaces, length units
  float plane_distance = 0.02f; ///< contacts are reported within this (2 x skin)
  /// A contact clips the velocity only when touched: separation <= skin + touch_tolerance.
  float touch_tolerance = 0.001f;
  float min_sweep = 1e-4f; ///< sweeps shorter than this (or zero) end the loop, length units
  float max_move = 100.0f; ///< longest sweep, length units (huge dt is capped)
  /// Planes added at every iteration (unit normals, e.g. an invisible floor); not copied:
  /// the span must outlive the call.
  std::span<Vec3 const> user_planes{};
  DepenetrationConfig depenetration{};   ///< 16 passes, 1e-4 error, 0.5 rejection
  PlaneSetConfig planes{};               ///< merge within 5 degrees, 20 planes at most
  VelocityProjectionConfig projection{}; ///< epsilon 0.005 length units per second

  /// This configuration with every length-valued field multiplied by length_unit.
  MoveAndSlideConfig scaled(float length_unit) const noexcept {
    MoveAndSlideConfig c = *this;
    c.skin *= length_unit;
    c.plane_distance *= length_unit;
    c.touch_tolerance *= length_unit;
    c.min_sweep *= length_unit;
    c.max_move *= length_unit;
    c.depenetration = c.depenetration.scaled(length_unit);
    c.projection.epsilon *= length_unit;
    return c;
  }
};

/// The result of move_and_slide: where the shape ended and the velocity it keeps.
template <class Id>
struct MoveAndSlideResult {
  /// Hits kept in the result (more are only reported to the callback).
  static constexpr std::size_t max_hits = 16;

  Vec3 position{};            ///< the shape's final position (pose.rotation is unchanged)
  Vec3 velocity{};            ///< the projected velocity
  int sweeps = 0;             ///< sweeps cast
  bool aborted = false;       ///< a callback answered abort
  bool invalid_input = false; ///< non-finite or negative input: nothing was done
  bool depenetrated = true;   ///< both depenetrations converged (or had nothing to do)
  /// The shape started deeper than cfg.depenetration.rejection_threshold in something: it
  /// was pushed out by that much and did not sweep (it gets out over a few calls).
  bool deep_start = false;
  std::size_t planes = 0;         ///< planes of the last projection, after merging
  bool planes_overflowed = false; ///< a projection was offered more than max_planes planes
  std::array<MoveHit<Id>, max_hits> hits{}; ///< the accepted hits, in order
  std::size_t hit_count = 0;
  std::size_t hits_dropped = 0; ///< accepted hits beyond max_hits

  std::span<MoveHit<Id> const> accepted() const noexcept { return {hits.data(), hit_count}; }
};

/// A callback that accepts every hit.
struct AcceptAllHits {
  template <class Hit>
  HitResponse operator()(Hit&) const noexcept {
    return HitResponse::accept;
  }
  /// move_and_slide_lanes' form (lane, hit).
  template <class Hit>
  HitResponse operator()(std::size_t, Hit&) const noexcept {
    return HitResponse::accept;
  }
};

/// The contacts around the shape at `pose`: every collider within `distance` (length units)
/// as the deepest point of its manifold, in the scene's order; f(MoveContact<Id> const&)
/// returns false to stop. move_and_slide's contact planes and depenetration use it.
template <MoveQuery Q, class F>
void intersections(Q const& query, typename Q::shape_type const& shape, Iso3 const& pose,
                   float distance, typename Q::filter_type const& filter, F&& f) {
  query.contacts(shape, pose, distance, filter, f);
}

/// The result of depenetrate(query, ...).
struct MoveDepenetration {
  Vec3 correction{}; ///< the translation to apply
  /// A pass moved less than cfg.depenetration.max_error (or no pairs), and the correction
  /// stays within the distance the contacts were gathered from (nothing unseen in the way).
  bool converged = true;
  bool deep = false; ///< a contact was deeper than cfg.depenetration.rejection_threshold
};

/// Contact queries one depenetrate(query, ...) makes at most: the first within the skin, and
/// further ones while the correction leaves the distance gathered so far.
inline constexpr int max_depenetration_queries = 4;

/// The longest correction one depenetrate(query, ...) gives: one pair's longest push (the
/// rejection threshold, or the skin if larger) and a skin more,
/// max(cfg.depenetration.rejection_threshold, cfg.skin) + cfg.skin (length units). Fixes out
/// of a narrow V (the depths over the cosine of half the angle between the normals) or from
/// several deep contacts can be far longer; they are cut to this length along their
/// direction and reported not converged, and the next call goes on.
inline float max_depenetration_move(MoveAndSlideConfig const& cfg) noexcept {
  return std::max(cfg.depenetration.rejection_threshold, cfg.skin) + cfg.skin;
}

/// The depenetration step of move_and_slide on its own: every contact within cfg.skin
/// pushed out to the skin (depenetrate() over the pairs). A contact deeper than
/// cfg.depenetration.rejection_threshold is pushed by that much only (`deep`), so a shape
/// that starts deep inside is pushed out over several calls instead of being left there. Pairs
/// that cannot all be satisfied (a corridor narrower than the shape plus two skins) get the
/// mean of the fixes along one more pass (for two opposing planes, the push halfway between
/// them) instead of whichever plane the last pass happened to end on.
/// A correction longer than the distance its contacts were gathered from (a push out of a
/// deep contact, or between planes at an obtuse angle, where the fix is the depths over the
/// cosine of half the angle between the normals) could carry the shape into a collider it never
/// saw: the contacts are gathered again from the same pose within |correction| + skin, those not
/// yet within the skin joining as pairs of depth <= 0 (skin - separation: they push only when the
/// fix comes nearer them than the skin), and the pairs solved again; at most
/// max_depenetration_queries queries, and a correction still beyond the last distance is cut
/// to it and not converged. A correction within the skin (the usual case) makes one query. The
/// correction is at most max_depenetration_move(cfg) long (a non-finite one is zero, not
/// converged).
template <MoveQuery Q>
MoveDepenetration depenetrate(Q const& query, typename Q::shape_type const& shape, Iso3 const& pose,
                              MoveAndSlideConfig const& cfg = {},
                              typename Q::filter_type const& filter = {}) {
  std::vector<Penetration3> pairs;
  MoveDepenetration out;
  float const limit = cfg.depenetration.rejection_threshold;
  float reach = cfg.skin; // every collider within this of the shape at pose is a pair
  for (int round = 1;; ++round) {
    pairs.clear();
    out = MoveDepenetration{};
    query.contacts(shape, pose, reach, filter, [&](MoveContact<typename Q::collider_id> const& c) {
      if (!(c.separation < reach)) return true;
      float depth = cfg.skin - c.separation;
      if (depth > limit) {
        out.deep = true;
        depth = limit;
      }
      pairs.push_back({c.normal, depth});
      return true;
    });
    if (pairs.empty()) return out;
    std::span<Penetration3 const> const view(pairs);
    Depenetration3 const d = plume::depenetrate(view, cfg.depenetration);
    out.correction = d.correction;
    out.converged = bool(d.converged);
    if (!out.converged) {
      // One more pass from the result, keeping the mean of the fixes along it.
      Vec3 fix = d.correction, sum{};
      int n = 0;
      for (Penetration3 const& q : pairs) {
        float const need = q.depth - fix.dot(q.normal);
        if (!(need > 0.0f)) continue;
        fix = fix + q.normal * need;
        sum = sum + fix;
        ++n;
      }
      if (n > 0) out.correction = sum / float(n);
    }
    // At most one push per call (max_depenetration_move): a longer fix is cut to it.
    float moved = out.correction.length();
    if (!std::isfinite(moved)) {
      out.correction = Vec3{};
      out.converged = false;
      return out;
    }
    float const most = max_depenetration_move(cfg);
    if (moved > most) {
      out.correction = out.correction * (most / moved);
      moved = out.correction.length();
      out.converged = false;
    }
    // Within what was gathered: nothing unseen can be reached (a collider beyond reach
    // stays beyond reach - |correction| >= 0).
    if (!(moved > reach)) return out;
    if (round >= max_depenetration_queries) { // cut to what was gathered
      out.correction = out.correction * (reach / moved);
      out.converged = false;
      return out;
    }
    reach = moved + cfg.skin;
  }
}

/// The sweep of move_and_slide on its own: how far the shape can move along `motion` and
/// keep cfg.skin to what it hits (`safe`, length units), and the hit.
template <class Id>
struct CastMove {
  float safe = 0.0f; ///< length the shape may move along the motion
  std::optional<MoveCastHit<Id>> hit;
  float hit_distance = 0.0f; ///< cast distance to the hit (length units)
  float approach = 0.0f;     ///< dir . -normal of the hit: how straight the motion goes in
};

namespace detail {
/// cast_move's cast: the motion cast (|motion| + skin along it), none for a zero or
/// non-finite motion.
inline std::optional<Vec3> cast_move_motion(Vec3 const& motion, MoveAndSlideConfig const& cfg) {
  float const len = motion.length();
  if (!(len > 0.0f) || !std::isfinite(len)) return std::nullopt;
  return (motion / len) * (len + cfg.skin);
}
/// cast_move's answer from the cast's hit (the cast was cast_move_motion's).
template <class Id>
CastMove<Id> cast_move_result(Vec3 const& motion, std::optional<MoveCastHit<Id>> const& hit,
                              MoveAndSlideConfig const& cfg) {
  CastMove<Id> out;
  float const len = motion.length();
  if (!(len > 0.0f) || !std::isfinite(len)) return out;
  Vec3 const dir = motion / len;
  out.hit = hit;
  if (!out.hit) {
    out.safe = len;
    return out;
  }
  out.hit_distance = out.hit->toi * (len + cfg.skin);
  out.approach = std::max(dir.dot(-out.hit->normal), 0.0f);
  out.safe = std::clamp(out.hit_distance - cfg.skin / std::max(out.approach, 0.005f), 0.0f, len);
  return out;
}
} // namespace detail

/// Casts the shape along `motion` (length units) with cast length |motion| + cfg.skin and
/// returns how far it may move keeping the skin to the first hit: max(d - skin / max(dir . -n,
/// 0.005), 0), at most |motion|, with the hit and its cast distance. Zero or non-finite
/// motion: no hit and safe = 0.
template <MoveQuery Q>
CastMove<typename Q::collider_id>
cast_move(Q const& query, typename Q::shape_type const& shape, Iso3 const& pose, Vec3 const& motion,
          MoveAndSlideConfig const& cfg = {}, typename Q::filter_type const& filter = {}) {
  std::optional<Vec3> const cast = detail::cast_move_motion(motion, cfg);
  if (!cast) return {};
  return detail::cast_move_result(motion, query.cast(shape, pose, *cast, filter), cfg);
}

namespace detail {

/// move_and_slide's loop, cut at its casts so that W characters can run it in lock step and
/// cast together (move_and_slide_lanes) while each one takes exactly the scalar call's steps:
/// start(); while (next_sweep()) take_cast(cast_motion ? query.cast(shape, pose_now(),
/// *cast_motion, filter) : std::nullopt); finish().
template <MoveQuery Q, class OnHit>
struct MoveAndSlideRun {
  using Id = typename Q::collider_id;

  MoveAndSlideRun(Q const& q, typename Q::shape_type const& s, Iso3 const& p,
                  MoveAndSlideConfig const& c, typename Q::filter_type const& f, OnHit& h)
      : query(q), shape(s), pose(p), cfg(c), filter(f), on_hit(h) {}

  Q const& query;
  typename Q::shape_type const& shape;
  Iso3 pose;
  MoveAndSlideConfig const& cfg;
  typename Q::filter_type const& filter;
  OnHit& on_hit;

  MoveAndSlideResult<Id> r{};
  Vec3 pos{}, v{};
  float time_left = 0.0f;
  int it = 0;
  bool looping = false;
  Vec3 sweep{};                    ///< this iteration's sweep (after next_sweep())
  float len = 0.0f;                ///< its length
  std::optional<Vec3> cast_motion; ///< what to cast (none: the sweep needs no cast)
  std::vector<Vec3> normals;       ///< the accepted planes of one sweep

  Iso3 at(Vec3 const& p) const { return Iso3{pose.rotation, p}; }
  void keep(MoveHit<Id> const& h) {
    if (r.hit_count < r.hits.size())
      r.hits[r.hit_count++] = h;
    else
      ++r.hits_dropped;
  }
  void add_planes(MoveHit<Id> const& h) {
    normals.push_back(h.normal);
    if (h.extra_normal.length_squared() > 0.0f && bool(h.extra_normal.is_finite()))
      normals.push_back(h.extra_normal);
  }
  /// A callback's change is kept when finite (a NaN position or velocity is not taken).
  void take(MoveHit<Id> const& h) {
    if (bool(h.position.is_finite())) pos = h.position;
    if (bool(h.velocity.is_finite())) v = h.velocity;
  }
  void project() {
    PlaneSet3 planes(v, cfg.planes);
    for (Vec3 const& n : normals)
      planes.add(n);
    for (Vec3 const& n : cfg.user_planes)
      planes.add(n);
    r.planes = std::size_t(planes.count());
    r.planes_overflowed = r.planes_overflowed || bool(planes.overflowed());
    v = project_velocity(v, planes.normals(), cfg.projection).velocity;
  }

  /// Checks the input and depenetrates; false (r.invalid_input) when nothing is to be done.
  bool start(Vec3 const& velocity, float dt) {
    r.position = pose.translation;
    r.velocity = velocity;
    if (!bool(pose.is_finite()) || !bool(velocity.is_finite()) || !std::isfinite(dt) ||
        !(dt >= 0.0f)) {
      r.invalid_input = true;
      return false;
    }
    pos = pose.translation;
    v = velocity;
    MoveDepenetration const first = plume::depenetrate(query, shape, at(pos), cfg, filter);
    pos = pos + first.correction;
    r.depenetrated = first.converged;
    r.deep_start = first.deep;
    time_left = dt;
    looping = true;
    return true;
  }

  /// The head of the next iteration: false when the loop is over; else sweep, len and
  /// cast_motion are set, and the caller casts cast_motion (when set) at pose_now().
  bool next_sweep() {
    // A shape that started deeper than the rejection threshold only depenetrates this call:
    // its casts cannot tell in from out, and a sweep could carry it further through.
    if (!looping || it >= cfg.iterations || r.aborted || r.deep_start) return looping = false;
    if (!cfg.user_planes.empty()) { // the user planes hold before anything is hit
      normals.clear();
      project();
    }
    sweep = v * time_left;
    len = sweep.length();
    if (!std::isfinite(len)) { // |v| dt overflows a float: move at most max_move along v
      float const m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
      sweep = (v / m).normalize() * cfg.max_move;
      len = cfg.max_move;
    }
    // (A zero sweep ends it too, whatever min_sweep: a min_sweep <= 0 would cast nothing.)
    if (!(len >= cfg.min_sweep) || !(len > 0.0f)) return looping = false;
    if (len > cfg.max_move) {
      sweep = sweep * (cfg.max_move / len);
      len = cfg.max_move;
    }
    ++r.sweeps;
    cast_motion = cast_move_motion(sweep, cfg);
    return true;
  }
  Iso3 pose_now() const { return at(pos); }

  /// The rest of the iteration, given the cast's hit (none when cast_motion was none).
  void take_cast(std::optional<MoveCastHit<Id>> const& cast) {
    CastMove<Id> const move = cast_motion ? cast_move_result(sweep, cast, cfg) : CastMove<Id>{};
    if (!move.hit) {
      pos = pos + sweep;
      time_left = 0.0f;
      looping = false;
      return;
    }
    pos = pos + sweep * (move.safe / len);
    time_left = time_left * (1.0f - move.safe / len);

    // The sweep's hit, then the contact planes around the new position.
    normals.clear();
    MoveHit<Id> hit{move.hit->collider,
                    MoveHitKind::sweep,
                    it,
                    move.hit->point,
                    move.hit->normal,
                    pos,
                    v,
                    move.safe,
                    (move.hit_distance - move.safe) * move.approach};
    HitResponse const answer = on_hit(hit);
    take(hit);
    if (answer == HitResponse::abort) r.aborted = true;
    if (answer == HitResponse::accept) {
      add_planes(hit);
      keep(hit);
    }
    if (r.aborted) {
      looping = false;
      return;
    }

    Vec3 const here = pos; // contacts are found at the position after the sweep's callback
    plume::intersections(query, shape, at(here), cfg.plane_distance, filter,
                         [&](MoveContact<Id> const& c) {
                           MoveHit<Id> h{c.collider,
                                         MoveHitKind::contact,
                                         it,
                                         c.point,
                                         c.normal,
                                         pos,
                                         v,
                                         move.safe,
                                         c.separation,
                                         c.separation <= cfg.skin + cfg.touch_tolerance};
                           HitResponse const a = on_hit(h);
                           take(h);
                           if (a == HitResponse::accept && h.touching) {
                             add_planes(h);
                             keep(h);
                           }
                           if (a == HitResponse::abort) r.aborted = true;
                           return !r.aborted;
                         });
    // Merged against the velocity the callbacks left, then projected onto all at once.
    project();
    ++it;
  }

  /// The final depenetration; the result.
  MoveAndSlideResult<Id> const& finish() {
    if (r.invalid_input) return r;
    MoveDepenetration const last = plume::depenetrate(query, shape, at(pos), cfg, filter);
    pos = pos + last.correction;
    r.depenetrated = r.depenetrated && last.converged;
    r.position = pos;
    r.velocity = v;
    return r;
  }
};

} // namespace detail

/// Moves the shape by velocity * dt through the query's scene (the file comment says how).
template <MoveQuery Q, class OnHit = AcceptAllHits>
MoveAndSlideResult<typename Q::collider_id>
move_and_slide(Q const& query, typename Q::shape_type const& shape, Iso3 const& pose,
               Vec3 const& velocity, float dt, MoveAndSlideConfig const& cfg = {},
               typename Q::filter_type const& filter = {}, OnHit&& on_hit = {}) {
  detail::MoveAndSlideRun<Q, std::remove_reference_t<OnHit>> run(query, shape, pose, cfg, filter,
                                                                 on_hit);
  if (run.start(velocity, dt))
    while (run.next_sweep())
      run.take_cast(run.cast_motion ? query.cast(shape, run.pose_now(), *run.cast_motion, filter)
                                    : std::nullopt);
  return run.finish();
}

/// A scene that casts many shapes at once: cast_lanes(shapes, poses, motions, filter, out)
/// writes out[i] = cast(shapes[i], poses[i], motions[i], filter), each the same as the single
/// cast (WorldMoveQuery's runs them in the world's lanes). move_and_slide_lanes uses it when
/// the scene has it, else one cast at a time.
template <class Q>
concept LaneMoveQuery = MoveQuery<Q> &&
    requires(Q const& q, std::span<typename Q::shape_type const> shapes,
             std::span<Iso3 const> poses, std::span<Vec3 const> motions,
             typename Q::filter_type const& filter,
             std::span<std::optional<MoveCastHit<typename Q::collider_id>>> out) {
  q.cast_lanes(shapes, poses, motions, filter, out);
};

/// W = lanes_v<T> characters moved together.
template <Real T, class Id>
struct MoveAndSlideLanes {
  GVec3<T> position;                                    ///< each lane's final position
  GVec3<T> velocity;                                    ///< each lane's projected velocity
  std::array<MoveAndSlideResult<Id>, lanes_v<T>> lanes; ///< each lane's whole result
};

/// move_and_slide for lanes_v<T> characters at once (T float or a batch of float): lane k
/// moves shapes[k] (any sizes, one scene and filter for all) from poses lane k with
/// velocities lane k, and gets exactly what move_and_slide(query, shapes[k], pose_k,
/// velocity_k, dt, cfg, filter, hit-callback of lane k) gives, bit for bit (position,
/// velocity, hits, flags). The lanes run the loop in lock step; each iteration's sweeps are
/// cast together through the scene's cast_lanes (a LaneMoveQuery; else one by one), which is
/// where the lanes gain: characters near each other share candidate colliders and casts
/// (docs/performance.md). on_hit(lane, MoveHit<Id>&) -> HitResponse is called for each lane's
/// hits in that lane's order. shapes must hold exactly lanes_v<T> shapes
/// (std::invalid_argument otherwise).
template <Real T, MoveQuery Q, class OnHit>
MoveAndSlideLanes<T, typename Q::collider_id>
move_and_slide_lanes(Q const& query, std::span<typename Q::shape_type const> shapes,
                     GIso3<T> const& poses, GVec3<T> const& velocities, float dt,
                     MoveAndSlideConfig const& cfg, typename Q::filter_type const& filter,
                     OnHit&& on_hit) {
  using Id = typename Q::collider_id;
  constexpr std::size_t W = lanes_v<T>;
  if (shapes.size() != W) throw std::invalid_argument("move_and_slide_lanes: one shape per lane");
  std::array<Vec3, W> at, vel;
  std::array<Quat, W> rot;
  unpack(poses.translation, at.data());
  unpack(poses.rotation, rot.data());
  unpack(velocities, vel.data());
  struct LaneHit {
    std::remove_reference_t<OnHit>* f;
    std::size_t lane;
    HitResponse operator()(MoveHit<Id>& h) const { return (*f)(lane, h); }
  };
  using Run = detail::MoveAndSlideRun<Q, LaneHit>;
  std::array<LaneHit, W> hits;
  std::vector<Run> runs;
  runs.reserve(W);
  for (std::size_t k = 0; k < W; ++k) {
    hits[k] = LaneHit{&on_hit, k};
    runs.emplace_back(query, shapes[k], Iso3{rot[k], at[k]}, cfg, filter, hits[k]);
  }
  std::array<bool, W> going{};
  for (std::size_t k = 0; k < W; ++k)
    going[k] = runs[k].start(Vec3(vel[k]), dt);
  std::vector<typename Q::shape_type> cast_shapes;
  std::vector<Iso3> cast_poses;
  std::vector<Vec3> cast_motions;
  std::vector<std::size_t> cast_lane;
  std::vector<std::optional<MoveCastHit<Id>>> cast_hits;
  for (;;) {
    cast_shapes.clear();
    cast_poses.clear();
    cast_motions.clear();
    cast_lane.clear();
    bool any = false;
    for (std::size_t k = 0; k < W; ++k) {
      if (!going[k] || !(going[k] = runs[k].next_sweep())) continue;
      any = true;
      if (!runs[k].cast_motion) continue;
      cast_shapes.push_back(shapes[k]);
      cast_poses.push_back(runs[k].pose_now());
      cast_motions.push_back(*runs[k].cast_motion);
      cast_lane.push_back(k);
    }
    if (!any) break;
    cast_hits.assign(cast_shapes.size(), std::nullopt);
    if constexpr (LaneMoveQuery<Q>) {
      query.cast_lanes(std::span<typename Q::shape_type const>(cast_shapes),
                       std::span<Iso3 const>(cast_poses), std::span<Vec3 const>(cast_motions),
                       filter, std::span<std::optional<MoveCastHit<Id>>>(cast_hits));
    } else {
      for (std::size_t c = 0; c < cast_shapes.size(); ++c)
        cast_hits[c] = query.cast(cast_shapes[c], cast_poses[c], cast_motions[c], filter);
    }
    std::size_t c = 0;
    for (std::size_t k = 0; k < W; ++k) {
      if (!going[k]) continue;
      bool const cast = c < cast_lane.size() && cast_lane[c] == k;
      runs[k].take_cast(cast ? cast_hits[c] : std::nullopt);
      c += cast ? 1 : 0;
    }
  }
  MoveAndSlideLanes<T, Id> out;
  std::array<Vec3, W> p, u;
  for (std::size_t k = 0; k < W; ++k) {
    out.lanes[k] = runs[k].finish();
    p[k] = out.lanes[k].position;
    u[k] = out.lanes[k].velocity;
  }
  out.position = pack<T>(p.data());
  out.velocity = pack<T>(u.data());
  return out;
}

} // namespace plume
