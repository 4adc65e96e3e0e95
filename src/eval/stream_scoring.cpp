#include "stream_scoring.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace action_flow
{
namespace
{
// tIoU within this of the threshold still matches (so 0.5 computed as 0.49999999 matches at 0.5).
constexpr double kIouTolerance = 1e-9;

void checkTime(double t, const char* what)
{
  if (!std::isfinite(t))
    throw std::invalid_argument(std::string("scoreStream: non-finite ") + what);
}

void checkSpan(double start, double end, const std::string& what)
{
  if (!std::isfinite(start) || !std::isfinite(end))
    throw std::invalid_argument(what + ": non-finite time");
  if (end < start)
    throw std::invalid_argument(what + ": end " + std::to_string(end) + " before start " + std::to_string(start));
}

bool covers(double start, double end, double t)
{
  return start <= t && t <= end;
}

// Recomputes precision, recall and F1 from the counts.
void segmentFigures(StreamScore& s)
{
  s.precision = s.predictions > 0 ? static_cast<double>(s.matched) / s.predictions : 0.0;
  s.recall = s.truths > 0 ? static_cast<double>(s.matched) / s.truths : 0.0;
  s.f1 = s.precision + s.recall > 0 ? 2.0 * s.precision * s.recall / (s.precision + s.recall) : 0.0;
}

double perMinute(int count, double seconds)
{
  return seconds > 0 ? count * 60.0 / seconds : 0.0;
}

// Length of the union of the truth spans clipped to [from, to].
double coveredSeconds(const std::vector<TruthSegment>& truth, double from, double to)
{
  std::vector<std::pair<double, double>> spans;
  for (const auto& t : truth)
  {
    const double s = std::max(t.start, from), e = std::min(t.end, to);
    if (e > s)
      spans.emplace_back(s, e);
  }
  std::sort(spans.begin(), spans.end());
  double covered = 0.0, reach = from;
  for (const auto& [s, e] : spans)
  {
    const double b = std::max(s, reach);
    if (e > b)
    {
      covered += e - b;
      reach = e;
    }
  }
  return covered;
}
}  // namespace

double temporalIou(double a_start, double a_end, double b_start, double b_end)
{
  checkSpan(a_start, a_end, "temporalIou");
  checkSpan(b_start, b_end, "temporalIou");
  const double inter = std::max(0.0, std::min(a_end, b_end) - std::max(a_start, b_start));
  const double uni = (a_end - a_start) + (b_end - b_start) - inter;
  return uni > 0 && inter > 0 ? inter / uni : 0.0;
}

double StreamScore::idle_false_per_minute() const
{
  return perMinute(idle_false, idle_seconds);
}

double StreamScore::false_per_minute() const
{
  return perMinute(false_labels, stream_seconds);
}

namespace
{
using Truths = std::vector<TruthSegment>;
using Predictions = std::vector<PredictedSegment>;

// Every time given is finite, every span ends after it starts, the threshold is in (0, 1].
void checkStreamInputs(const Truths& truth, const Predictions& predicted,
                       const std::vector<double>& frame_stamps, double stream_start,
                       double stream_end, double iou_threshold)
{
  if (!(iou_threshold > 0.0 && iou_threshold <= 1.0))
    throw std::invalid_argument("scoreStream: iou_threshold must be in (0, 1], got " +
                                std::to_string(iou_threshold));
  checkSpan(stream_start, stream_end, "scoreStream: stream span");
  for (std::size_t i = 0; i < truth.size(); ++i)
    checkSpan(truth[i].start, truth[i].end, "scoreStream: truth segment " + std::to_string(i));
  for (std::size_t j = 0; j < predicted.size(); ++j)
  {
    checkSpan(predicted[j].start, predicted[j].end,
              "scoreStream: predicted segment " + std::to_string(j));
    checkTime(predicted[j].published, "publish time");
  }
  for (const double t : frame_stamps)
    checkTime(t, "frame stamp");
}

// A truth and a prediction that may match: same label, tIoU at the threshold or above.
struct CandidatePair
{
  double iou;
  int t, p;
};

// The candidate pairs, sorted by decreasing tIoU (ties: earlier truth, earlier prediction); fills
// first_correct, per truth the earliest published qualifying prediction (-1: none).
std::vector<CandidatePair> candidatePairs(const Truths& truth, const Predictions& predicted,
                                          double iou_threshold, std::vector<int>& first_correct)
{
  std::vector<CandidatePair> pairs;
  first_correct.assign(truth.size(), -1);
  for (std::size_t i = 0; i < truth.size(); ++i)
    for (std::size_t j = 0; j < predicted.size(); ++j)
    {
      if (truth[i].label != predicted[j].label)
        continue;
      const double iou =
          temporalIou(truth[i].start, truth[i].end, predicted[j].start, predicted[j].end);
      if (iou <= 0.0 || iou < iou_threshold - kIouTolerance)
        continue;
      pairs.push_back({ iou, static_cast<int>(i), static_cast<int>(j) });
      int& f = first_correct[i];
      if (f < 0 || predicted[j].published < predicted[f].published)
        f = static_cast<int>(j);
    }
  std::sort(pairs.begin(), pairs.end(), [](const CandidatePair& a, const CandidatePair& b) {
    if (a.iou != b.iou)
      return a.iou > b.iou;
    return a.t != b.t ? a.t < b.t : a.p < b.p;
  });
  return pairs;
}

// Greedy one-to-one matching in the pairs' order: fills the match vectors and the matched count.
void matchGreedily(const std::vector<CandidatePair>& pairs, StreamScore& s)
{
  s.match_of_truth.assign(static_cast<std::size_t>(s.truths), -1);
  s.match_of_prediction.assign(static_cast<std::size_t>(s.predictions), -1);
  for (const auto& pr : pairs)
    if (s.match_of_truth[pr.t] < 0 && s.match_of_prediction[pr.p] < 0)
    {
      s.match_of_truth[pr.t] = pr.p;
      s.match_of_prediction[pr.p] = pr.t;
      ++s.matched;
    }
}

// Per truth with a qualifying prediction: the earliest one's publish time from its start and end.
void addLatencies(const Truths& truth, const Predictions& predicted,
                  const std::vector<int>& first_correct, StreamScore& s)
{
  for (std::size_t i = 0; i < truth.size(); ++i)
    if (first_correct[i] >= 0)
    {
      const double published = predicted[first_correct[i]].published;
      s.start_latency.push_back(published - truth[i].start);
      s.end_latency.push_back(published - truth[i].end);
    }
}

// False labels published while nobody acts; a right one published just after its action ended is
// not one.
int idleFalseLabels(const Truths& truth, const Predictions& predicted,
                    const std::vector<int>& match_of_prediction)
{
  int idle_false = 0;
  for (std::size_t i = 0; i < predicted.size(); ++i)
  {
    const double at = predicted[i].published;
    const bool under_way = std::any_of(truth.begin(), truth.end(), [&](const TruthSegment& t) {
      return covers(t.start, t.end, at);
    });
    if (!under_way && match_of_prediction[i] < 0)
      ++idle_false;
  }
  return idle_false;
}

// The frames whose label was right: the covering truth (the latest started) against the covering
// prediction (the latest published), "" where none covers.
int correctFrames(const Truths& truth, const Predictions& predicted,
                  const std::vector<double>& frame_stamps)
{
  int correct = 0;
  for (const double t : frame_stamps)
  {
    const TruthSegment* tr = nullptr;
    for (const auto& c : truth)
      if (covers(c.start, c.end, t) && (!tr || c.start >= tr->start))
        tr = &c;
    const PredictedSegment* pr = nullptr;
    for (const auto& c : predicted)
      if (covers(c.start, c.end, t) && (!pr || c.published >= pr->published))
        pr = &c;
    if ((tr ? tr->label : std::string()) == (pr ? pr->label : std::string()))
      ++correct;
  }
  return correct;
}
}  // namespace

StreamScore scoreStream(const std::vector<TruthSegment>& truth, const std::vector<PredictedSegment>& predicted,
                        const std::vector<double>& frame_stamps, double stream_start, double stream_end,
                        double iou_threshold)
{
  checkStreamInputs(truth, predicted, frame_stamps, stream_start, stream_end, iou_threshold);

  StreamScore s;
  s.truths = static_cast<int>(truth.size());
  s.predictions = static_cast<int>(predicted.size());
  s.stream_seconds = stream_end - stream_start;

  std::vector<int> first_correct;
  matchGreedily(candidatePairs(truth, predicted, iou_threshold, first_correct), s);
  segmentFigures(s);
  s.false_labels = s.predictions - s.matched;
  addLatencies(truth, predicted, first_correct, s);

  s.idle_false = idleFalseLabels(truth, predicted, s.match_of_prediction);
  s.idle_seconds = s.stream_seconds - coveredSeconds(truth, stream_start, stream_end);

  const int correct = correctFrames(truth, predicted, frame_stamps);
  s.frames = static_cast<int>(frame_stamps.size());
  s.frame_accuracy = s.frames > 0 ? static_cast<double>(correct) / s.frames : 0.0;
  return s;
}

StreamScore combineScores(const std::vector<StreamScore>& scores)
{
  StreamScore sum;
  long correct_frames = 0;
  for (const auto& s : scores)
  {
    sum.truths += s.truths;
    sum.predictions += s.predictions;
    sum.matched += s.matched;
    sum.frames += s.frames;
    correct_frames += std::lround(s.frame_accuracy * s.frames);
    sum.idle_seconds += s.idle_seconds;
    sum.idle_false += s.idle_false;
    sum.false_labels += s.false_labels;
    sum.stream_seconds += s.stream_seconds;
    sum.start_latency.insert(sum.start_latency.end(), s.start_latency.begin(), s.start_latency.end());
    sum.end_latency.insert(sum.end_latency.end(), s.end_latency.begin(), s.end_latency.end());
  }
  segmentFigures(sum);
  sum.frame_accuracy = sum.frames > 0 ? static_cast<double>(correct_frames) / sum.frames : 0.0;
  return sum;
}

double median(std::vector<double> values)
{
  if (values.empty())
    return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace action_flow
