#include <action_flow/recognition_policy.h>

#include <action_flow/posture_flow.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>

namespace action_flow
{
namespace
{
void require(bool ok, const char* what)
{
  if (!ok)
    throw std::invalid_argument(std::string("policy parameter out of range: ") + what);
}
LabelEvent event(LabelEvent::Kind kind, std::uint32_t track, const Classification& c, double start, double end,
                 std::size_t frames)
{
  LabelEvent e;
  e.kind = kind;
  e.track = track;
  e.result = c;
  e.start = start;
  e.end = end;
  e.frames = frames;
  return e;
}

// The end of a label published earlier: the same label, its final span.
LabelEvent closing(std::uint32_t track, const std::string& label, double start, double end)
{
  LabelEvent e = event(LabelEvent::Kind::Ended, track, Classification(), start, end, 0);
  e.result.label = label;
  e.closes_published = true;
  return e;
}
}  // namespace

void PolicyParams::validate() const
{
  require(min_frames >= 1, "min_frames >= 1");
  require(classify_every >= 1, "classify_every >= 1");
  require(stable_count >= 1, "stable_count >= 1");
  require(min_confidence >= 0.0 && min_confidence <= 1.0, "min_confidence in [0,1]");
  require(motion_on > 0.0 && motion_off > 0.0 && motion_off <= motion_on, "0 < motion_off <= motion_on");
  require(motion_smooth >= 0.0 && rest_time > 0.0 && motion_lag > 0.0, "motion_smooth >= 0, rest_time > 0, motion_lag > 0");
  require(pre_roll >= 0.0 && post_roll >= 0.0 && post_roll <= rest_time, "pre_roll >= 0, 0 <= post_roll <= rest_time");
  require(min_segment >= 0.0 && max_segment > min_segment, "0 <= min_segment < max_segment");
  require(trim >= 0.0 && trim < max_segment, "0 <= trim < max_segment");
  require(window > 0.0 && min_coverage >= 0.0 && min_coverage <= 1.0, "window > 0, min_coverage in [0,1]");
  for (double v : { motion_on, motion_off, motion_lag, motion_smooth, rest_time, pre_roll, post_roll, min_segment, max_segment,
                    window, min_coverage, min_confidence, trim })
    require(std::isfinite(v), "finite values");
}

PolicyParams::Mode policyModeFromString(const std::string& name)
{
  PolicyParams::Mode m;
  parseParam(name, m);
  return m;
}

RecognitionPolicy::RecognitionPolicy(std::shared_ptr<const ActionModel> model, const PolicyParams& params)
  : model_(std::move(model)), classifier_(model_ ? model_->classifier() : throw std::invalid_argument("no model")),
    params_(params)
{
  params_.validate();
  use_motion_ = params_.motion_segments && model_->params.recognizer == Recognizer::PostureFlow;
  frame_length_ = frameDescriptorLength(model_->params);
  if (use_motion_)
    layout_ = PostureFlowDescriptor(model_->params.grid);
}

std::vector<LabelEvent> RecognitionPolicy::add(std::uint32_t id, const Eigen::VectorXf& frame, double stamp)
{
  if (frame.size() != frame_length_)
    throw std::invalid_argument("frame descriptor of length " + std::to_string(frame.size()) + ", the model's are " +
                                std::to_string(frame_length_));
  Track& t = tracks_[id];
  float motion = 0.0f;
  if (use_motion_)  // shape change per second against the frame motion_lag before (or the oldest held)
    for (auto it = t.frames.rbegin(); it != t.frames.rend(); ++it)
      if (it->stamp <= stamp - params_.motion_lag || std::next(it) == t.frames.rend())
      {
        if (stamp > it->stamp)
          motion = layout_.postureChange(frame, it->values) / static_cast<float>(stamp - it->stamp);
        break;
      }
  t.frames.push_back({ frame, stamp, motion });
  if (params_.mode == PolicyParams::Mode::Segmented)
    return {};
  return addOnline(id, t);
}

double RecognitionPolicy::smoothedMotion(const Track& t) const
{
  const double from = t.frames.back().stamp - params_.motion_smooth;
  double sum = 0.0;
  int n = 0;
  for (auto it = t.frames.rbegin(); it != t.frames.rend() && it->stamp >= from; ++it, ++n)
    sum += it->motion;
  return sum / std::max(n, 1);
}

std::vector<LabelEvent> RecognitionPolicy::addOnline(std::uint32_t id, Track& t)
{
  return use_motion_ ? addSegmented(id, t) : addWindowed(id, t);
}

void RecognitionPolicy::trim(Track& t, double keep)
{
  const double now = t.frames.back().stamp;
  while (t.frames.size() > 1 && t.frames.front().stamp < now - keep)
    t.frames.pop_front();
}

std::vector<LabelEvent> RecognitionPolicy::addWindowed(std::uint32_t id, Track& t)
{
  const double now = t.frames.back().stamp;
  trim(t, params_.window);
  if (++t.since_classified < params_.classify_every)
    return {};
  const double span = now - t.frames.front().stamp;
  if (t.frames.size() < 2 || span < params_.min_coverage * params_.window)
    return {};
  t.since_classified = 0;
  std::size_t n = 0;
  const auto c = classify(t, t.frames.front().stamp, now, &n);
  if (!c)
    return {};
  if (c->label == t.published)
    t.last_motion = now;  // the window still shows the published action
  if (!stable(t, *c))
    return {};
  const bool keep = publishable(*c);
  if (keep && c->label == t.published)
    return {};
  std::vector<LabelEvent> out;
  if (!t.published.empty())  // the published action is over: its span ends at the last window that showed it
  {
    out.push_back(closing(id, t.published, t.published_start, t.last_motion));
    t.published.clear();  // stillness: the same action after it is a new one
  }
  if (keep)
  {
    t.published = c->label;
    t.published_start = t.frames.front().stamp;
    t.last_motion = now;
    out.push_back(event(LabelEvent::Kind::Started, id, *c, t.published_start, now, n));
  }
  return out;
}

std::optional<double> RecognitionPolicy::firstOrLastMoving(const Track& t, bool first) const
{
  // The smoothed rate lags the body: the motion began (or ended) at the first (or last) moving
  // frame it averages.
  const double now = t.frames.back().stamp;
  std::optional<double> at;
  for (auto it = t.frames.rbegin(); it != t.frames.rend() && it->stamp >= now - params_.motion_smooth; ++it)
    if (it->motion > params_.motion_off)
    {
      at = it->stamp;
      if (!first)
        break;
    }
  return at;
}

std::vector<LabelEvent> RecognitionPolicy::addSegmented(std::uint32_t id, Track& t)
{
  const double now = t.frames.back().stamp;
  const double motion = smoothedMotion(t);
  if (!t.active)
  {
    trim(t, params_.pre_roll + params_.motion_smooth + params_.motion_lag);
    if (motion > params_.motion_on)
    {
      t.active = true;
      t.segment_start = firstOrLastMoving(t, true).value_or(now);
      t.last_motion = now;
      t.published_in_segment = false;
      t.candidate.clear();
      t.candidate_count = 0;
      t.since_classified = 0;
    }
    return {};
  }
  if (motion > params_.motion_off)
    t.last_motion = firstOrLastMoving(t, false).value_or(t.last_motion);
  trim(t, params_.max_segment + params_.pre_roll + params_.rest_time);
  if (now - t.last_motion >= params_.rest_time)
  {
    auto e = closeSegment(id, t);
    return e ? std::vector<LabelEvent>{ *e } : std::vector<LabelEvent>{};
  }
  if (!params_.publish_early || t.published_in_segment || ++t.since_classified < params_.classify_every ||
      now - t.segment_start < params_.min_segment)
    return {};
  t.since_classified = 0;
  const double from = std::max(t.segment_start - params_.pre_roll, now - params_.max_segment);
  std::size_t n = 0;
  const auto c = classify(t, from, now, &n);
  if (!c || !stable(t, *c) || !publishable(*c))
    return {};
  t.published_in_segment = true;
  t.segment_label = c->label;
  t.published = c->label;
  t.published_start = std::max(from, t.frames.front().stamp);
  return { event(LabelEvent::Kind::Started, id, *c, t.published_start, now, n) };
}

std::optional<LabelEvent> RecognitionPolicy::closeSegment(std::uint32_t id, Track& t)
{
  t.active = false;
  const double end = std::min(t.last_motion + params_.post_roll, t.frames.back().stamp);
  if (t.published_in_segment)
  {
    t.published_in_segment = false;
    LabelEvent e = closing(id, t.segment_label, t.published_start, end);
    for (const Frame& f : t.frames)
      e.frames += f.stamp >= e.start && f.stamp <= end;
    return e;
  }
  LabelEvent e = event(LabelEvent::Kind::Ended, id, Classification(), 0.0, end, 0);
  if (t.last_motion - t.segment_start < params_.min_segment)
    return std::nullopt;
  double from = std::max(t.segment_start - params_.pre_roll, end - params_.max_segment);
  const auto c = classifyTrimmed(t, from, e.end, &e.frames);
  if (!c || !publishable(*c))
    return std::nullopt;
  e.result = *c;
  e.start = std::max(from, t.frames.front().stamp);
  t.published = c->label;
  return e;
}

std::optional<Classification> RecognitionPolicy::classifyTrimmed(const Track& t, double& from, double& to,
                                                                 std::size_t* count) const
{
  std::optional<Classification> best = classify(t, from, to, count);
  const double whole_from = from, whole_to = to;
  for (int cut_start = 0; params_.trim > 0.0 && cut_start <= 2; ++cut_start)
    for (int cut_end = 0; cut_end <= 2; ++cut_end)
    {
      const double f = whole_from + cut_start * params_.trim / 2, e = whole_to - cut_end * params_.trim / 2;
      if ((cut_start == 0 && cut_end == 0) || e - f < params_.min_segment)
        continue;
      std::size_t n = 0;
      const auto c = classify(t, f, e, &n);
      if (c && (!best || c->confidence > best->confidence))
      {
        best = c;
        from = f;
        to = e;
        if (count)
          *count = n;
      }
    }
  return best;
}

std::optional<Classification> RecognitionPolicy::classify(const Track& t, double from, double to,
                                                          std::size_t* count) const
{
  std::vector<Eigen::VectorXf> frames;
  std::vector<double> stamps;
  for (const Frame& f : t.frames)
    if (f.stamp >= from && f.stamp <= to)
    {
      frames.push_back(f.values);
      stamps.push_back(f.stamp);
    }
  if (count)
    *count = frames.size();
  if (static_cast<int>(frames.size()) < params_.min_frames)
    return std::nullopt;
  return classifier_.classify(model_->sequence(frames, stamps));
}

bool RecognitionPolicy::stable(Track& t, const Classification& c) const
{
  if (c.label == t.candidate)
    ++t.candidate_count;
  else
  {
    t.candidate = c.label;
    t.candidate_count = 1;
  }
  return t.candidate_count >= params_.stable_count;
}

bool RecognitionPolicy::publishable(const Classification& c) const
{
  return c.confidence >= params_.min_confidence &&
         std::find(params_.idle_labels.begin(), params_.idle_labels.end(), c.label) == params_.idle_labels.end();
}

void RecognitionPolicy::restart(std::uint32_t id)
{
  const auto it = tracks_.find(id);
  if (it != tracks_.end())
  {
    const std::string published = it->second.published;
    it->second = Track();
    it->second.published = published;
  }
}

std::vector<LabelEvent> RecognitionPolicy::end(std::uint32_t id)
{
  const auto it = tracks_.find(id);
  if (it == tracks_.end())
    return {};
  Track& t = it->second;
  std::vector<LabelEvent> out;
  if (params_.mode == PolicyParams::Mode::Segmented)
  {
    if (!t.frames.empty())
    {
      LabelEvent e;
      e.track = id;
      const auto c = classify(t, t.frames.front().stamp, t.frames.back().stamp, &e.frames);
      if (c)
      {
        e.result = *c;
        e.start = t.frames.front().stamp;
        e.end = t.frames.back().stamp;
        out.push_back(e);
      }
    }
  }
  else if (use_motion_ && t.active && !t.frames.empty())
  {
    if (auto e = closeSegment(id, t))
      out.push_back(*e);
  }
  else if (!use_motion_ && !t.published.empty())  // sliding window: the published action ends with the track
    out.push_back(closing(id, t.published, t.published_start, t.last_motion));
  tracks_.erase(it);
  return out;
}

std::vector<LabelEvent> RecognitionPolicy::endAll()
{
  std::vector<std::uint32_t> ids;
  for (const auto& kv : tracks_)
    ids.push_back(kv.first);
  std::vector<LabelEvent> out;
  for (std::uint32_t id : ids)
    for (auto& e : end(id))
      out.push_back(std::move(e));
  return out;
}

std::string RecognitionPolicy::current(std::uint32_t id) const
{
  const auto it = tracks_.find(id);
  return it == tracks_.end() ? std::string() : it->second.published;
}

std::size_t RecognitionPolicy::frames(std::uint32_t id) const
{
  const auto it = tracks_.find(id);
  return it == tracks_.end() ? 0 : it->second.frames.size();
}

}  // namespace action_flow
