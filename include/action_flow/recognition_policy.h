/**
 * @file recognition_policy.h
 * @brief When to classify whom, and which labels to publish: the per-track sequences of frame
 *        descriptors, the segmented mode, the online mode (motion segments, or a sliding window)
 *        with its stability and rejection rules. ROS-free: the classifier nodelet converts
 *        messages and publishes what this decides, and `evaluate --protocol online` runs the
 *        same class on recorded streams.
 *
 * Online, with a model whose frame descriptors carry the body's shape (posture_flow): a track's
 * motion (how fast its shape changes: PostureFlowDescriptor::postureChange over motion_lag
 * seconds, per second, smoothed over motion_smooth seconds) opens a segment when it rises above
 * motion_on and closes it when it has stayed below motion_off for rest_time seconds. The segment's frames, with pre_roll and post_roll seconds of stillness
 * around them (the training samples have such lead-ins), are classified every classify_every
 * frames while it is open; once stable_count classifications in a row agree, with confidence at
 * least min_confidence and a label that is not an idle label, the label is published (Started).
 * When the segment closes, a label already published is closed with its final span (Ended); if
 * none was, the whole segment is classified once and published if it passes the same tests
 * (Ended too). Stillness between actions therefore produces no label at all.
 *
 * With a model whose descriptors carry no shape (the paper's), online falls back to a sliding
 * window of the last `window` seconds, with the same stability and rejection rules; a label is
 * published (Started) when it differs from the last one published for that track, and closed
 * (Ended, its span up to the last window that still showed it) when another stable label or an
 * idle one takes over, or the track ends.
 */
#pragma once

#include <action_flow/action_model.h>
#include <action_flow/posture_flow.h>

#include <Eigen/Core>

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace action_flow
{
/**
 * @brief The label of the class an online model learns from transitions and idle periods of
 *        training streams (train --no-action-windows; no_action.h in the evaluation library).
 */
inline constexpr const char* kNoActionLabel = "no_action";

/** @brief The policy's parameters (the classifier nodelet reads them from its private namespace). */
struct PolicyParams
{
  enum class Mode
  {
    Segmented,  ///< classify a track's whole sequence when it ends (or when asked)
    Online      ///< classify while the person acts
  };
  Mode mode = Mode::Segmented;
  int min_frames = 5;             ///< fewer frame descriptors are never classified
  int classify_every = 5;         ///< online: frames between classifications of a track
  int stable_count = 3;           ///< online: equal classifications in a row before a label is published
  double min_confidence = 0.0;    ///< online: a label less sure than this is not published (rejection)
  /** Online: labels that mean "no action" and are never published (idle periods look like them). */
  std::vector<std::string> idle_labels = { "standing", kNoActionLabel };
  /** Online: use motion segments when the model's descriptors carry motion (else the sliding window). */
  bool motion_segments = true;
  double motion_on = 0.5;         ///< 1/s: smoothed shape change rate that opens a segment
  double motion_off = 0.3;        ///< 1/s: below this the body counts as still
  double motion_lag = 0.2;        ///< s: the shape is compared with the one this long before
  double motion_smooth = 0.3;     ///< s: moving mean of the shape change rate
  double rest_time = 0.5;         ///< s of stillness that close a segment
  double pre_roll = 0.4;          ///< s of frames before the segment's start that are classified with it
  double post_roll = 0.4;         ///< s after its end, likewise
  double min_segment = 0.8;       ///< s: shorter segments are neither labelled early nor at their end
  double max_segment = 8.0;       ///< s: a longer segment is classified over its last max_segment seconds
  bool publish_early = true;      ///< publish during a segment once stable; false: only when it closes
  /**
   * s: a segment labelled when it closes is also classified with trim / 2 or trim cut from its start,
   * its end or both; the surest of those answers is taken, with its span (0: the whole segment).
   */
  double trim = 0.0;
  double window = 3.0;            ///< sliding window (no motion): seconds classified
  double min_coverage = 0.8;      ///< sliding window: share of `window` the frames must span first

  /** @throws std::invalid_argument naming the first parameter out of range. */
  void validate() const;

  template <class Self, class V>
  static void visit(Self& p, V&& v)
  {
    const Shapes s = Shapes::Runtime;
    v("mode", p.mode, "segmented: a label per sequence; online: labels while people act", s);
    v("min_frames", p.min_frames, "a sequence of fewer frame descriptors is never classified", s);
    v("classify_every", p.classify_every, "online: frames between classifications of a track", s);
    v("stable_count", p.stable_count, "online: equal classifications in a row before a label is published", s);
    v("min_confidence", p.min_confidence, "online: a label less sure than this is not published", s);
    v("idle_labels", p.idle_labels, "online: labels that mean no action, never published", s);
    v("motion_segments", p.motion_segments, "online: actions are cut where the body's shape changes", s);
    v("motion_on", p.motion_on, "1/s: smoothed shape change rate that opens a segment", s);
    v("motion_off", p.motion_off, "1/s: below this the body counts as still", s);
    v("motion_lag", p.motion_lag, "s: the shape is compared with the one this long before", s);
    v("motion_smooth", p.motion_smooth, "s: moving mean of the shape change rate", s);
    v("rest_time", p.rest_time, "s of stillness that close a segment", s);
    v("pre_roll", p.pre_roll, "s before the segment classified with it", s);
    v("post_roll", p.post_roll, "s after its end, likewise", s);
    v("min_segment", p.min_segment, "s: shorter segments give no label", s);
    v("max_segment", p.max_segment, "s: a longer one is classified over its last max_segment seconds", s);
    v("publish_early", p.publish_early, "publish while the action is under way once stable", s);
    v("trim", p.trim, "s: a closing segment is also classified with trim/2 or trim cut from each end; the surest wins", s);
    v("window", p.window, "sliding window (models without motion): seconds classified", s);
    v("min_coverage", p.min_coverage, "sliding window: share of window the frames must span first", s);
  }
};

template <>
struct EnumNames<PolicyParams::Mode>
{
  static constexpr const char* names[] = { "segmented", "online" };
};

/** @brief Mode by name: "segmented" or "online". @throws std::invalid_argument otherwise. */
PolicyParams::Mode policyModeFromString(const std::string& name);

/** @brief A label the policy decided to publish. */
struct LabelEvent
{
  enum class Kind
  {
    Segmented,  ///< a whole sequence (track ended, end of input, or asked for)
    Started,    ///< online: published while the action is under way
    Ended       ///< online: the action ended; same label as a Started one when that was published, else new
  };
  Kind kind = Kind::Segmented;
  std::uint32_t track = 0;
  Classification result;
  double start = 0.0, end = 0.0;  ///< stamps of the first and last classified frame
  std::size_t frames = 0;          ///< frame descriptors classified
  /** Ended only: true when it closes a label already published (Started), false when the label is new. */
  bool closes_published = false;
};

/**
 * @brief Per-track sequences and the rules above, for one model. Not thread-safe (the nodelet
 *        holds a lock). Tracks are independent: one person's frames never reach another's sequence.
 */
class RecognitionPolicy
{
public:
  /** @throws std::invalid_argument if @p params are invalid or @p model is null */
  RecognitionPolicy(std::shared_ptr<const ActionModel> model, const PolicyParams& params);

  /**
   * @brief The next frame descriptor of track @p id at @p stamp. Returns the labels decided now
   *        (online: at most an Ended and a Started; segmented: none).
   * @throws std::invalid_argument if @p frame does not have the model's frame descriptor length
   */
  std::vector<LabelEvent> add(std::uint32_t id, const Eigen::VectorXf& frame, double stamp);
  /** @brief Track @p id restarted (its flow was reset): its frames so far are forgotten. */
  void restart(std::uint32_t id);
  /**
   * @brief Track @p id ended. Segmented: its whole sequence is classified (if it has min_frames).
   *        Online: an open segment is closed as if the person had come to rest.
   */
  std::vector<LabelEvent> end(std::uint32_t id);
  /** @brief Ends every track (end of input, or the classify service). */
  std::vector<LabelEvent> endAll();
  /** @brief Forgets every track without classifying (time went backwards). */
  void clear() { tracks_.clear(); }

  /** @brief The last label published for @p id ("" if none, or the track is unknown). */
  std::string current(std::uint32_t id) const;
  /** @brief Frame descriptors held for @p id. */
  std::size_t frames(std::uint32_t id) const;
  std::size_t tracks() const { return tracks_.size(); }
  /** @brief True when the online mode uses motion segments with this model (else the sliding window). */
  bool usesMotion() const { return use_motion_; }
  const PolicyParams& params() const { return params_; }
  const ActionModel& model() const { return *model_; }

private:
  struct Frame
  {
    Eigen::VectorXf values;
    double stamp;
    float motion;
  };
  struct Track
  {
    std::deque<Frame> frames;
    std::string published;  // last label published
    // online
    int since_classified = 0;
    std::string candidate;
    int candidate_count = 0;
    bool active = false;       // a motion segment is open
    double segment_start = 0;  // stamp where the motion began
    double last_motion = 0;    // last stamp with motion above motion_off (sliding window: that showed the published label)
    bool published_in_segment = false;
    std::string segment_label;
    double published_start = 0;
  };

  std::vector<LabelEvent> addOnline(std::uint32_t id, Track& t);
  std::vector<LabelEvent> addWindowed(std::uint32_t id, Track& t);   // the sliding window
  std::vector<LabelEvent> addSegmented(std::uint32_t id, Track& t);  // the motion cut
  /** Drops frames older than @p keep seconds before the newest (keeps at least one). */
  static void trim(Track& t, double keep);
  /** The first (or last) frame of the smoothing span that moved: where the motion began (or ended). */
  std::optional<double> firstOrLastMoving(const Track& t, bool first) const;
  std::optional<LabelEvent> closeSegment(std::uint32_t id, Track& t);
  std::optional<Classification> classify(const Track& t, double from, double to, std::size_t* count) const;
  /** classify() of [from, to] and, with params_.trim, of it cut at its ends; the surest, and its span. */
  std::optional<Classification> classifyTrimmed(const Track& t, double& from, double& to, std::size_t* count) const;
  bool stable(Track& t, const Classification& c) const;
  bool publishable(const Classification& c) const;
  double smoothedMotion(const Track& t) const;

  std::shared_ptr<const ActionModel> model_;
  SequenceClassifier classifier_;
  PostureFlowDescriptor layout_;
  PolicyParams params_;
  bool use_motion_ = false;
  Eigen::Index frame_length_ = 0;
  std::map<std::uint32_t, Track> tracks_;
};

}  // namespace action_flow
