#include <action_flow/facing.h>
#include <action_flow/people_tracker.h>
#include "tracker_appearance.h"
#include "tracker_assignment.h"
#include "tracker_detector.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace action_flow
{
namespace
{
struct Track
{
  explicit Track(const ConstantVelocityFilter& f) : filter(f) {}
  ConstantVelocityFilter filter;
  std::uint32_t id = 0;  // 0 until confirmed
  int hits = 1;
  double last_seen = 0.0;
  double last_tall = 0.0;  // when a cluster at least min_height high last continued it
  Eigen::Vector3f last_position = Eigen::Vector3f::Zero();  // the centroid when last seen
  Appearance appearance;                                     // while confirmed
  bool fresh = false;     // confirmed in this frame: may be a lost person coming back (reid_after)
  bool merged = false;    // continued by a fresh track that looked like it: dropped, not lost
  // align_to_facing: the smoothed facing as (cos, sin) of twice its angle (a turn by 180 degrees is
  // the same ellipse), zero until the first estimate.
  Eigen::Vector2f facing2 = Eigen::Vector2f::Zero();
  double facing_stamp = 0.0;
};

// The track's facing after this frame's estimate @p raw (NaN: none), smoothed with time constant
// @p tau; NaN while there has been no estimate.
float smoothFacing(Track& t, float raw, double stamp, double tau)
{
  if (std::isfinite(raw))
  {
    const Eigen::Vector2f now(std::cos(2.0f * raw), std::sin(2.0f * raw));
    const bool first = t.facing2.isZero();
    const double dt = std::max(0.0, stamp - t.facing_stamp);
    const float w = first || tau <= 0.0 ? 1.0f : static_cast<float>(1.0 - std::exp(-dt / tau));
    t.facing2 = (1.0f - w) * t.facing2 + w * now;
    t.facing_stamp = stamp;
  }
  if (t.facing2.norm() < 1e-6f)
    return std::numeric_limits<float>::quiet_NaN();
  return 0.5f * std::atan2(t.facing2.y(), t.facing2.x());
}

// The fastest a person is taken to move while unseen (m/s, a brisk walk), for re-identification.
constexpr float kReidSpeed = 2.0f;

// How fast an unseen track's gate widens (m/s), up to twice the gate: where a hidden person comes
// back out is less certain the longer they were hidden.
constexpr float kGateGrowth = 0.5f;
// A weak detection's colours are read from every this-many-th of its points (thousands).
constexpr std::size_t kColourStride = 4;
// Half the width of a person's shadow (m) at the person's own distance: a body about 0.5 m wide
// plus the hidden person's half width.
constexpr float kShadowHalfWidth = 0.45f;
// Two parts of one body lie side by side: their distances from the camera differ by less than this
// (a body is about 0.3 m deep; a person passing behind another is farther by more than that).
constexpr float kSplitDepth = 0.25f;

/**
 * Whether @p hidden (a predicted position) lies in the shadow of @p front (a person seen in this
 * frame) as the camera at @p origin sees them, measured on the ground plane (@p up, unit or zero):
 * @p front is nearer, and the line of sight to @p hidden passes within the front person's shadow,
 * which widens with distance behind them.
 */
bool inShadowOf(const Eigen::Vector3f& hidden, const Eigen::Vector3f& front, const Eigen::Vector3f& origin,
                const Eigen::Vector3f& up)
{
  const Eigen::Vector3f h = onGround(hidden - origin, up), f = onGround(front - origin, up);
  const float dh = h.norm(), df = f.norm();
  if (!(df > 0.1f) || dh <= df)
    return false;
  const float lateral = (h - h.dot(f / df) * (f / df)).norm();  // from the line of sight through front
  return lateral < kShadowHalfWidth * dh / df;
}
/**
 * The association costs: horizontal distance between each track's prediction and each detection
 * (a person bending is still the same person), in units of the track's gate (wider while unseen;
 * the plain gate for a weak detection), so that solveAssignment gates them at 1. A weak detection
 * (a body bending, crouching, kicking; or failing HOG) only continues a confirmed track, and only one
 * whose colours it has (TrackerParams::weak_max_colour_distance, points of @p cloud): it neither
 * confirms a tentative one nor starts one, and a track back from hiding takes only a person-like
 * detection beyond the plain gate.
 */
Eigen::MatrixXf associationCosts(const std::vector<Track>& tracks, const std::vector<PersonDetection>& people,
                                 const Cloud& cloud, const Eigen::Vector3f& up, double stamp, const TrackerParams& params)
{
  const float gate = params.gate;
  Eigen::MatrixXf cost(tracks.size(), people.size());
  std::vector<std::optional<Appearance::Histogram>> colours(people.size());  // weak detections', when needed
  for (std::size_t i = 0; i < tracks.size(); ++i)
  {
    const float unseen = static_cast<float>(stamp - tracks[i].last_seen);
    const float wide = std::min(2.0f * gate, gate + kGateGrowth * std::max(0.0f, unseen - 0.1f));
    for (std::size_t j = 0; j < people.size(); ++j)
    {
      const Eigen::Vector3f d = people[j].centroid - tracks[i].filter.position();
      cost(i, j) = people[j].weak && tracks[i].id == 0 ? 2.0f + 1e3f
                                                       : onGround(d, up).norm() / (people[j].weak ? gate : wide);
      // A weak detection that does not look like the track is something else beside them.
      if (people[j].weak && cost(i, j) < 1.0f && tracks[i].appearance.frames() > 0 &&
          params.weak_max_colour_distance < 1.0f)
      {
        if (!colours[j])
          colours[j] = Appearance::histogram(cloud, people[j].indices, kColourStride);
        if (tracks[i].appearance.colourDistance(*colours[j]) > params.weak_max_colour_distance)
          cost(i, j) = 2.0f + 1e3f;
      }
    }
  }
  return cost;
}
/**
 * A body split in two (a raised or thrown arm gives a second "head" beside the real one): a
 * person-like detection that no confirmed track took, lying within @p max_distance on the ground of
 * one a confirmed track took, at about the same distance from the camera (side by side in the view:
 * a person passing behind is farther), is that person's other part: its points join theirs and it
 * starts no track. A person who walks up beside another is confirmed on their own detection long
 * before they come this close. Updates @p match (each track's detection) to the shortened list.
 */
void absorbSplitBodies(const std::vector<Track>& tracks, std::vector<int>& match, std::vector<PersonDetection>& people,
                       const Eigen::Vector3f& origin, const Eigen::Vector3f& up, float max_distance)
{
  if (!(max_distance > 0.0f))
    return;
  std::vector<char> owned(people.size(), 0);  // taken by a confirmed track
  for (std::size_t i = 0; i < tracks.size(); ++i)
    if (match[i] >= 0 && tracks[i].id != 0)
      owned[match[i]] = 1;
  std::vector<char> absorbed(people.size(), 0);
  for (std::size_t j = 0; j < people.size(); ++j)
  {
    if (owned[j] || people[j].weak)
      continue;
    int into = -1;
    float nearest = max_distance;
    for (std::size_t m = 0; m < people.size(); ++m)
    {
      if (!owned[m])
        continue;
      const float d = onGround(people[j].centroid - people[m].centroid, up).norm();
      const float depth = std::abs(onGround(people[j].centroid - origin, up).norm() -
                                   onGround(people[m].centroid - origin, up).norm());
      if (d < nearest && depth < kSplitDepth)
        nearest = d, into = static_cast<int>(m);
    }
    if (into < 0)
      continue;
    joinDetection(people[into], people[j], nearest);
    absorbed[j] = 1;
  }
  std::vector<int> renumber(people.size(), -1);
  std::size_t kept = 0;
  for (std::size_t j = 0; j < people.size(); ++j)
    if (!absorbed[j])
    {
      renumber[j] = static_cast<int>(kept);
      if (kept != j)
        people[kept] = std::move(people[j]);
      ++kept;
    }
  people.resize(kept);
  for (int& m : match)
    m = m >= 0 ? renumber[m] : -1;
}
}  // namespace

struct PeopleTracker::Impl
{
  explicit Impl(const TrackerParams& p) : detector(p) {}
  PeopleDetector detector;
  std::vector<Track> tracks;
  std::uint32_t next_id = 1;
  // The confirmed tracks lost within reid_after, for giving their ids back.
  struct Gone
  {
    std::uint32_t id;
    Appearance appearance;
    Eigen::Vector3f position;
    double last_seen;
  };
  std::vector<Gone> gone;
  bool has_stamp = false;
  double last_stamp = 0.0;

  /// Time went back (a bag restarting): every track is dropped into @p result (lost, reset), since
  /// continuing them would mean negative velocities and nonsense matches. Returns the time step.
  double advanceClock(double stamp, TrackerResult& result);
  /// Corrects the matched tracks, drops the lost ones into @p lost and starts tentative tracks on
  /// the unmatched person-like detections; returns each kept track's detection in this frame (-1:
  /// none).
  std::vector<int> updateTracks(const std::vector<PersonDetection>& people, const std::vector<int>& match,
                                double stamp, const Eigen::Vector3f& camera_origin, const Eigen::Vector3f& up,
                                const TrackerParams& params, std::vector<std::uint32_t>& lost);
  /// The confirmed track seen in this frame, set in its person frame with its own cloud; false when it
  /// stands right below the camera (no viewing direction to set the grid by).
  bool trackedPerson(Track& t, const PersonDetection& d, const DetectionResult& det, const Cloud& cloud,
                     double stamp, const Eigen::Vector3f& camera_origin, const TrackerParams& params,
                     TrackedPerson& p);
  /// A tentative track becomes a person: a new id, fresh (re-identification may still give it an old one).
  void confirm(Track& t)
  {
    t.id = next_id++;
    t.fresh = true;
  }
  /// Track @p i, confirmed in this frame with its first appearance in @p look, takes the id of the
  /// lost or unseen confirmed track that looks most like it, if any is close enough in height,
  /// colours and place (TrackerParams::reid_after); @p seen as updateTracks returns it.
  void reidentify(std::size_t i, const Appearance& look, const std::vector<int>& seen, double stamp,
                  const Eigen::Vector3f& up, const TrackerParams& params);
};

PeopleTracker::PeopleTracker(const TrackerParams& params) : params_(params), impl_(std::make_unique<Impl>(params))
{
}

PeopleTracker::~PeopleTracker() = default;

void PeopleTracker::reset()
{
  impl_->tracks.clear();
  impl_->gone.clear();
  impl_->detector.reset();
  impl_->has_stamp = false;
}

bool PeopleTracker::setGroundPrior(const Eigen::Vector4f& plane, const Eigen::Vector3f& camera)
{
  return impl_->detector.setGroundPrior(plane, camera);
}

double PeopleTracker::Impl::advanceClock(double stamp, TrackerResult& result)
{
  if (has_stamp && stamp < last_stamp)
  {
    result.reset = true;
    for (const Track& t : tracks)
      if (t.id != 0)
        result.lost.push_back(t.id);
    tracks.clear();
    gone.clear();
  }
  const double dt = has_stamp && !result.reset ? stamp - last_stamp : 0.0;
  has_stamp = true;
  last_stamp = stamp;
  return dt;
}

std::vector<int> PeopleTracker::Impl::updateTracks(const std::vector<PersonDetection>& people,
                                                   const std::vector<int>& match, double stamp,
                                                   const Eigen::Vector3f& camera_origin, const Eigen::Vector3f& up,
                                                   const TrackerParams& params, std::vector<std::uint32_t>& lost)
{
  // Hidden behind a person (a person-like detection) seen in this frame: not lost yet (re-identification when they come back).
  const auto hiddenBySomeone = [&](const Eigen::Vector3f& position) {
    for (const PersonDetection& d : people)
      if (!d.weak && inShadowOf(position, d.centroid, camera_origin, up))
        return true;
    return false;
  };
  std::vector<char> used(people.size(), 0);
  std::vector<Track> kept;
  std::vector<int> kept_detection;
  for (std::size_t i = 0; i < tracks.size(); ++i)
  {
    Track& t = tracks[i];
    if (match[i] >= 0 && people[match[i]].height >= params.min_height)
      t.last_tall = stamp;
    const bool low_too_long = t.id != 0 && params.low_lost_after > 0.0 && stamp - t.last_tall > params.low_lost_after;
    if (match[i] >= 0 && !low_too_long)
    {
      used[match[i]] = 1;
      t.filter.correct(people[match[i]].centroid);
      t.hits += 1;
      t.last_seen = stamp;
      t.last_position = people[match[i]].centroid;
      if (t.id == 0 && t.hits >= params.confirm_after)
        confirm(t);
      kept.push_back(t);
      kept_detection.push_back(match[i]);
    }
    else if (t.id == 0)
    {
      // A tentative track missing a frame was most likely clutter: dropped silently.
    }
    else if (low_too_long || (stamp - t.last_seen > params.lost_after &&
                              (stamp - t.last_seen > params.hidden_lost_after || !hiddenBySomeone(t.filter.position()))))
    {
      lost.push_back(t.id);
      if (params.reid_after > 0.0 && t.appearance.frames() > 0)
        gone.push_back({ t.id, t.appearance, t.last_position, t.last_seen });
    }
    else
    {
      kept.push_back(t);
      kept_detection.push_back(-1);
    }
  }
  for (std::size_t j = 0; j < people.size(); ++j)
    if (!used[j] && !people[j].weak)
    {
      Track t(ConstantVelocityFilter(people[j].centroid));
      t.last_seen = stamp;
      t.last_tall = stamp;
      t.last_position = people[j].centroid;
      if (params.confirm_after <= 1)
        confirm(t);
      kept.push_back(t);
      kept_detection.push_back(static_cast<int>(j));
    }
  tracks.swap(kept);
  gone.erase(std::remove_if(gone.begin(), gone.end(),
                            [&](const Gone& g) { return stamp - g.last_seen > params.reid_after; }),
             gone.end());
  return kept_detection;
}

void PeopleTracker::Impl::reidentify(std::size_t i, const Appearance& look, const std::vector<int>& seen,
                                     double stamp, const Eigen::Vector3f& up, const TrackerParams& params)
{
  Track& t = tracks[i];
  // Whether a person last seen at @p where at @p when could be this one; the colour distance if so.
  const auto likeness = [&](const Appearance& a, const Eigen::Vector3f& where, double when) {
    const Eigen::Vector3f d = t.last_position - where;
    const float reach = params.gate + kReidSpeed * static_cast<float>(stamp - when);
    const float colours = a.colourDistance(look);
    const bool close = onGround(d, up).norm() <= reach &&
                       std::abs(a.height() - look.height()) <= params.reid_max_height_difference &&
                       colours <= params.reid_max_colour_distance;
    return close ? colours : 2.0f;
  };
  float best = 1.5f;
  int best_gone = -1, best_track = -1;
  for (std::size_t g = 0; g < gone.size(); ++g)
  {
    const float c = likeness(gone[g].appearance, gone[g].position, gone[g].last_seen);
    if (c < best)
      best = c, best_gone = static_cast<int>(g), best_track = -1;
  }
  for (std::size_t j = 0; j < tracks.size(); ++j)
  {
    const Track& o = tracks[j];
    if (j == i || o.id == 0 || o.fresh || o.merged || seen[j] >= 0 || o.appearance.frames() == 0)
      continue;
    const float c = likeness(o.appearance, o.last_position, o.last_seen);
    if (c < best)
      best = c, best_track = static_cast<int>(j), best_gone = -1;
  }
  if (best_gone >= 0)
  {
    t.id = gone[best_gone].id;
    t.appearance = gone[best_gone].appearance;
    gone.erase(gone.begin() + best_gone);
  }
  else if (best_track >= 0)
  {
    t.id = tracks[best_track].id;
    t.appearance = tracks[best_track].appearance;
    tracks[best_track].merged = true;
  }
}

bool PeopleTracker::Impl::trackedPerson(Track& t, const PersonDetection& d, const DetectionResult& det,
                                        const Cloud& cloud, double stamp, const Eigen::Vector3f& camera_origin,
                                        const TrackerParams& params, TrackedPerson& p)
{
  p.id = t.id;
  p.position = d.centroid;
  p.velocity = t.filter.velocity();
  p.height = d.height;
  p.hog_confidence = d.hog_confidence;
  try
  {
    p.frame = PersonFrame::fromGround(d.centroid, det.ground, d.height, d.centroid - camera_origin);
  }
  catch (const std::invalid_argument&)
  {
    return false;
  }
  p.cloud = detector.personCloud(cloud, d);
  if (params.align_to_facing)
  {
    p.facing = smoothFacing(t, facingFromTrunk(*p.cloud, p.frame), stamp, params.facing_smoothing);
    if (std::isfinite(p.facing))
      p.frame = p.frame.turned(p.facing);
  }
  return true;
}

TrackerResult PeopleTracker::update(const Cloud& cloud, double stamp, const Eigen::Vector3f& camera_origin)
{
  TrackerResult result;
  Impl& s = *impl_;
  if (!std::isfinite(stamp) || !camera_origin.allFinite() ||
      cloud.size() != static_cast<std::size_t>(cloud.width) * cloud.height)
    return result;  // ignored: state unchanged
  const double dt = s.advanceClock(stamp, result);

  DetectionResult det = s.detector.detect(cloud, camera_origin);
  result.ground = det.ground;
  result.ground_valid = det.ground_valid;
  result.ground_assumed = det.ground_assumed;
  for (const auto& d : det.people)
    result.detections += d.weak ? 0 : 1;
  result.hog_applied = det.hog_applied;

  for (Track& t : s.tracks)
    t.filter.predict(dt);

  // Gated optimal assignment on the ground.
  const Eigen::Vector3f up = det.ground_valid ? Eigen::Vector3f(det.ground.head<3>()) : Eigen::Vector3f::Zero();
  std::vector<int> match = solveAssignment(associationCosts(s.tracks, det.people, cloud, up, stamp, params_), 1.0f);
  absorbSplitBodies(s.tracks, match, det.people, camera_origin, up, params_.split_max_distance);
  const std::vector<int> seen = s.updateTracks(det.people, match, stamp, camera_origin, up, params_, result.lost);

  for (std::size_t i = 0; i < s.tracks.size(); ++i)
  {
    TrackedPerson p;
    Track& t = s.tracks[i];
    if (t.id == 0 || seen[i] < 0 || !s.trackedPerson(t, det.people[seen[i]], det, cloud, stamp, camera_origin, params_, p))
      continue;
    if (params_.reid_after > 0.0)  // the appearance serves re-identification only
    {
      const Appearance::Histogram colours = Appearance::histogram(*p.cloud);
      if (t.fresh)
      {
        Appearance look;
        look.add(colours, p.height);
        s.reidentify(i, look, seen, stamp, up, params_);
        p.id = t.id;
      }
      t.appearance.add(colours, p.height);
    }
    t.fresh = false;
    result.people.push_back(std::move(p));
  }
  // Tracks continued under a fresh track's id end here, silently: their id lives on.
  s.tracks.erase(std::remove_if(s.tracks.begin(), s.tracks.end(), [](const Track& t) { return t.merged; }),
                 s.tracks.end());
  return result;
}

}  // namespace action_flow
