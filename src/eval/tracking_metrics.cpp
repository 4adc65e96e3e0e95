// CLEAR MOT and identity scores of a tracked sequence against its truth (tracking_metrics.h).
#include "tracking_metrics.h"

#include "../tracker/tracker_assignment.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace action_flow
{
namespace
{
double ratio(double num, double den) { return den > 0 ? num / den : 1.0; }

void checkFrame(const TrackingFrame& f, std::size_t index)
{
  for (const auto* list : { &f.truth, &f.predicted })
  {
    std::set<std::uint32_t> ids;
    for (const TrackPoint& p : *list)
    {
      if (!p.position.allFinite())
        throw std::invalid_argument("scoreTracking: frame " + std::to_string(index) + ": a non-finite position");
      if (!ids.insert(p.id).second)
        throw std::invalid_argument("scoreTracking: frame " + std::to_string(index) + ": id " + std::to_string(p.id) +
                                    " twice in the " + (list == &f.truth ? "truth" : "predictions"));
    }
  }
}

/** One frame's matches: for each truth object the prediction matched to it, or -1. */
std::vector<int> matchFrame(const TrackingFrame& f, const std::map<std::uint32_t, std::uint32_t>& last_match, float gate)
{
  const auto& truth = f.truth;
  const auto& pred = f.predicted;
  std::vector<int> pred_of(truth.size(), -1);
  std::vector<char> taken(pred.size(), 0);
  const auto distance = [&](std::size_t i, std::size_t j) { return (truth[i].position - pred[j].position).norm(); };
  // 1. A truth object keeps the track it was last matched to, where that is still within the gate.
  for (std::size_t i = 0; i < truth.size(); ++i)
  {
    const auto last = last_match.find(truth[i].id);
    if (last == last_match.end())
      continue;
    for (std::size_t j = 0; j < pred.size(); ++j)
      if (!taken[j] && pred[j].id == last->second && distance(i, j) <= gate)
      {
        pred_of[i] = int(j);
        taken[j] = 1;
      }
  }
  // 2. The rest: as many pairs within the gate as possible, least total distance.
  std::vector<std::size_t> rows, cols;
  for (std::size_t i = 0; i < truth.size(); ++i)
    if (pred_of[i] < 0)
      rows.push_back(i);
  for (std::size_t j = 0; j < pred.size(); ++j)
    if (!taken[j])
      cols.push_back(j);
  Eigen::MatrixXf cost(rows.size(), cols.size());
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t c = 0; c < cols.size(); ++c)
      cost(Eigen::Index(r), Eigen::Index(c)) = distance(rows[r], cols[c]);
  const std::vector<int> assigned = solveAssignment(cost, gate);
  for (std::size_t r = 0; r < rows.size(); ++r)
    if (assigned[r] >= 0)
      pred_of[rows[r]] = int(cols[size_t(assigned[r])]);
  return pred_of;
}

/**
 * IDTP of the best one-to-one pairing of truth trajectories with tracks (Ristani et al.): the
 * minimum-cost perfect assignment on the graph with a "nobody" for every truth and every track.
 */
std::size_t identityTruePositives(const std::vector<TrackingFrame>& kept, float gate, std::size_t& truth_total,
                                  std::size_t& pred_total)
{
  std::map<std::uint32_t, int> t_index, p_index;
  for (const TrackingFrame& f : kept)
  {
    for (const TrackPoint& t : f.truth)
      t_index.emplace(t.id, int(t_index.size()));
    for (const TrackPoint& p : f.predicted)
      p_index.emplace(p.id, int(p_index.size()));
  }
  const int T = int(t_index.size()), P = int(p_index.size());
  std::vector<double> n_t(size_t(T), 0), n_p(size_t(P), 0);
  Eigen::MatrixXd both = Eigen::MatrixXd::Zero(T, P);  // frames in which a pair is within the gate
  for (const TrackingFrame& f : kept)
  {
    for (const TrackPoint& t : f.truth)
      n_t[size_t(t_index[t.id])] += 1;
    for (const TrackPoint& p : f.predicted)
      n_p[size_t(p_index[p.id])] += 1;
    for (const TrackPoint& t : f.truth)
      for (const TrackPoint& p : f.predicted)
        if ((t.position - p.position).norm() <= gate)
          both(t_index[t.id], p_index[p.id]) += 1;
  }
  truth_total = pred_total = 0;
  for (double n : n_t)
    truth_total += std::size_t(n);
  for (double n : n_p)
    pred_total += std::size_t(n);
  if (T == 0 || P == 0)
    return 0;
  // Rows: the truths, then a "nobody" per track; columns: the tracks, then a "nobody" per truth.
  // The cost of an assignment is IDFN + IDFP.
  const float never = float(truth_total + pred_total + 1) * 4.0f;
  Eigen::MatrixXf cost = Eigen::MatrixXf::Constant(T + P, P + T, never);
  for (int i = 0; i < T; ++i)
  {
    for (int j = 0; j < P; ++j)
      cost(i, j) = float(n_t[size_t(i)] + n_p[size_t(j)] - 2 * both(i, j));
    cost(i, P + i) = float(n_t[size_t(i)]);
  }
  for (int j = 0; j < P; ++j)
    cost(T + j, j) = float(n_p[size_t(j)]);
  cost.bottomRightCorner(P, T).setZero();
  const std::vector<int> col = solveAssignment(cost, 2 * never);
  std::size_t idtp = 0;
  for (int i = 0; i < T; ++i)
    if (col[size_t(i)] >= 0 && col[size_t(i)] < P)
      idtp += std::size_t(both(i, col[size_t(i)]));
  return idtp;
}
}  // namespace

double TrackingScores::mota() const
{
  return 1.0 - double(misses + false_positives + id_switches) / double(std::max<std::size_t>(truth, 1));
}
double TrackingScores::motp() const { return matches > 0 ? distance_sum / double(matches) : 0.0; }
double TrackingScores::precision() const { return ratio(double(matches), double(matches + false_positives)); }
double TrackingScores::recall() const { return ratio(double(matches), double(truth)); }
double TrackingScores::idf1() const { return ratio(2.0 * double(idtp), 2.0 * double(idtp) + double(idfp + idfn)); }
double TrackingScores::idp() const { return ratio(double(idtp), double(idtp + idfp)); }
double TrackingScores::idr() const { return ratio(double(idtp), double(idtp + idfn)); }
double TrackingScores::switchesPerPersonMinute() const
{
  return person_seconds > 0 ? double(id_switches) / (person_seconds / 60.0) : 0.0;
}

std::vector<std::vector<int>> matchTracking(const std::vector<TrackingFrame>& frames, float gate)
{
  if (!(gate > 0.0f) || !std::isfinite(gate))
    throw std::invalid_argument("scoreTracking: the gate must be a positive distance");
  std::vector<std::vector<int>> out(frames.size());
  std::map<std::uint32_t, std::uint32_t> last_match;  // truth id -> track of its last match
  for (std::size_t k = 0; k < frames.size(); ++k)
  {
    checkFrame(frames[k], k);
    out[k] = matchFrame(frames[k], last_match, gate);
    for (std::size_t i = 0; i < frames[k].truth.size(); ++i)
      if (out[k][i] >= 0 && !frames[k].truth[i].ignored)
        last_match[frames[k].truth[i].id] = frames[k].predicted[size_t(out[k][i])].id;
  }
  return out;
}

TrackingScores scoreTracking(const std::vector<TrackingFrame>& frames, float gate, double frame_seconds)
{
  if (!(frame_seconds >= 0.0) || !std::isfinite(frame_seconds))
    throw std::invalid_argument("scoreTracking: the frame duration must be >= 0");
  const std::vector<std::vector<int>> matches = matchTracking(frames, gate);
  TrackingScores s;
  s.frames = frames.size();
  std::map<std::uint32_t, std::uint32_t> last_match;   // truth id -> track of its last match
  std::map<std::uint32_t, bool> matched_before;        // truth id -> matched in its previous counted frame
  std::map<std::uint32_t, std::size_t> counted, hit;  // per truth id: frames to track, frames matched
  std::set<std::uint32_t> pred_ids;
  std::vector<TrackingFrame> kept(frames.size());     // what the identity scores see
  for (std::size_t k = 0; k < frames.size(); ++k)
  {
    const TrackingFrame& f = frames[k];
    const std::vector<int>& pred_of = matches[k];
    std::vector<char> dropped(f.predicted.size(), 0), used(f.predicted.size(), 0);
    for (std::size_t i = 0; i < f.truth.size(); ++i)
    {
      const TrackPoint& t = f.truth[i];
      if (pred_of[i] >= 0)
        (t.ignored ? dropped : used)[size_t(pred_of[i])] = 1;
      if (t.ignored)
        continue;
      ++s.truth;
      ++counted[t.id];
      kept[k].truth.push_back(t);
      if (pred_of[i] < 0)
      {
        ++s.misses;
        if (matched_before.count(t.id))
          matched_before[t.id] = false;
        continue;
      }
      const TrackPoint& p = f.predicted[size_t(pred_of[i])];
      ++s.matches;
      ++hit[t.id];
      s.distance_sum += (t.position - p.position).norm();
      const auto last = last_match.find(t.id);
      if (last != last_match.end() && last->second != p.id)
        ++s.id_switches;
      const auto before = matched_before.find(t.id);
      if (before != matched_before.end() && !before->second)
        ++s.fragmentations;
      last_match[t.id] = p.id;
      matched_before[t.id] = true;
    }
    for (std::size_t j = 0; j < f.predicted.size(); ++j)
    {
      if (dropped[j])
        continue;
      kept[k].predicted.push_back(f.predicted[j]);
      pred_ids.insert(f.predicted[j].id);
      if (!used[j])
        ++s.false_positives;
    }
  }
  s.truth_ids = counted.size();
  s.predicted_ids = pred_ids.size();
  for (const auto& [id, n] : counted)
  {
    const double share = double(hit[id]) / double(n);
    s.mostly_tracked += share >= 0.8 ? 1 : 0;
    s.mostly_lost += share < 0.2 ? 1 : 0;
  }
  std::size_t truth_total = 0, pred_total = 0;
  s.idtp = identityTruePositives(kept, gate, truth_total, pred_total);
  s.idfn = truth_total - s.idtp;
  s.idfp = pred_total - s.idtp;
  s.person_seconds = double(s.truth) * frame_seconds;
  return s;
}

TrackingScores addTrackingScores(const TrackingScores& a, const TrackingScores& b)
{
  TrackingScores s;
  s.frames = a.frames + b.frames;
  s.truth = a.truth + b.truth;
  s.matches = a.matches + b.matches;
  s.misses = a.misses + b.misses;
  s.false_positives = a.false_positives + b.false_positives;
  s.id_switches = a.id_switches + b.id_switches;
  s.fragmentations = a.fragmentations + b.fragmentations;
  s.distance_sum = a.distance_sum + b.distance_sum;
  s.truth_ids = a.truth_ids + b.truth_ids;
  s.predicted_ids = a.predicted_ids + b.predicted_ids;
  s.mostly_tracked = a.mostly_tracked + b.mostly_tracked;
  s.mostly_lost = a.mostly_lost + b.mostly_lost;
  s.idtp = a.idtp + b.idtp;
  s.idfp = a.idfp + b.idfp;
  s.idfn = a.idfn + b.idfn;
  s.person_seconds = a.person_seconds + b.person_seconds;
  return s;
}

}  // namespace action_flow
