// Classifier stage: sequences of frame descriptors per track, classified by ~model (core
// ActionModel: its sequence descriptor and classifier, whichever recognizer it holds), labels on `labels`.
#include <action_flow/ActionLabel.h>
#include <action_flow/Classify.h>
#include <action_flow/action_model.h>
#include <action_flow/ros/lazy_nodelet.h>
#include <action_flow/ros/params.h>
#include <action_flow/ros/stage_types.h>
#include <action_flow/sequence_descriptor.h>

#include <pluginlib/class_list_macros.hpp>
#include <visualization_msgs/MarkerArray.h>

#include <deque>
#include <map>
#include <optional>

namespace action_flow
{
/**
 * Subscribes `descriptors` (FrameDescriptors); publishes `labels` (ActionLabel), `states`
 * (ActionStates, per frame) and `markers` (MarkerArray: flow arrows and the label above each
 * head); service `~classify` (segmented mode: classify the open sequences now).
 * Parameters (private): model (path), mode (segmented|online), window, classify_every,
 * stable_count, min_frames, min_coverage, end_of_input_timeout, arrow_scale, max_arrows, and
 * the recognition parameters the model must have been made with.
 */
class ClassifierNodelet : public LazyNodelet
{
  struct Sequence
  {
    std::deque<Eigen::VectorXf> descriptors;
    std::deque<double> stamps;
    geometry_msgs::Point head;
    std::string published;  // last label published for this track
    std::string candidate;  // online: the label of the last classifications
    int candidate_count = 0;
    int since_classified = 0;
  };

  void onInit() override
  {
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    std::string mode = "segmented";
    pnh.param("mode", mode, mode);
    if (mode != "segmented" && mode != "online")
    {
      NODELET_ERROR("unknown ~mode '%s' (segmented|online): using segmented", mode.c_str());
      mode = "segmented";
    }
    online_ = mode == "online";
    pnh.param("window", window_, window_);
    pnh.param("classify_every", classify_every_, classify_every_);
    pnh.param("stable_count", stable_count_, stable_count_);
    pnh.param("min_frames", min_frames_, min_frames_);
    pnh.param("min_coverage", min_coverage_, min_coverage_);
    pnh.param("end_of_input_timeout", end_of_input_timeout_, end_of_input_timeout_);
    pnh.param("arrow_scale", arrow_scale_, arrow_scale_);
    pnh.param("max_arrows", max_arrows_, max_arrows_);
    loadModel(pnh);

    setSubscribe([this] {
      return getNodeHandle().subscribe("descriptors", 20, &ClassifierNodelet::onDescriptors, this);
    });
    labels_pub_ = advertiseLazy<ActionLabel>("labels", 20);
    states_pub_ = advertiseLazy<ActionStates>("states", 10);
    markers_pub_ = advertiseLazy<visualization_msgs::MarkerArray>("markers", 5);
    service_ = pnh.advertiseService("classify", &ClassifierNodelet::onClassify, this);
    if (!online_)
      timer_ = getNodeHandle().createWallTimer(ros::WallDuration(0.2), &ClassifierNodelet::onTimer, this);
  }

  void loadModel(ros::NodeHandle& pnh)
  {
    std::string path;
    pnh.param("model", path, path);
    if (path.empty())
    {
      model_error_ = "no model file given (set ~model)";
      NODELET_ERROR("%s: not classifying", model_error_.c_str());
      return;
    }
    try
    {
      ActionModel model = ActionModel::load(path);
      model.checkCompatible(readRecognitionParams(pnh), path);
      classifier_.emplace(model.classifier());
      min_frames_ = std::max(min_frames_, 1);
      NODELET_INFO("model '%s': recognizer %s, %zu training sequences of %zu actions, %s", path.c_str(),
                   toString(model.params.recognizer).c_str(), model.labels.size(), classifier_->classes().size(),
                   online_ ? "online" : "segmented");
      model_.emplace(std::move(model));
    }
    catch (const std::exception& e)
    {
      model_error_ = e.what();
      NODELET_ERROR("cannot use the model: %s; not classifying (the rest of the pipeline keeps running)",
                    model_error_.c_str());
    }
  }

  void onDescriptors(const FrameDescriptors::ConstPtr& in)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    last_input_ = ros::WallTime::now();
    const double stamp = in->header.stamp.toSec();
    header_ = in->header;
    if (in->reset || stamp < last_stamp_)
    {
      NODELET_WARN_THROTTLE(5, "time went backwards: dropping %zu open sequences", sequences_.size());
      sequences_.clear();
    }
    last_stamp_ = stamp;
    if (!classifier_)
      NODELET_ERROR_THROTTLE(10, "not classifying: %s", model_error_.c_str());

    auto states = boost::make_shared<ActionStates>();
    states->header = in->header;
    states->source = in;
    for (const auto& d : in->descriptors)
    {
      Sequence& s = sequences_[d.track_id];
      s.head = d.head;
      if (d.status == PeopleFlow::kReset)
      {
        s.descriptors.clear();
        s.stamps.clear();
      }
      if (d.status == PeopleFlow::kFlow && !d.values.empty())
      {
        s.descriptors.emplace_back(Eigen::Map<const Eigen::VectorXf>(d.values.data(), d.values.size()));
        s.stamps.push_back(stamp);
        if (online_)
          stepOnline(d.track_id, s);
      }
      ActionState state;
      state.track_id = d.track_id;
      state.head = d.head;
      state.frames = s.descriptors.size();
      state.label = s.published;
      states->tracks.push_back(state);
    }
    for (std::uint32_t id : in->lost)
    {
      auto it = sequences_.find(id);
      if (it == sequences_.end())
        continue;
      if (!online_)
        finish(id, it->second);
      sequences_.erase(it);
    }
    if (states_pub_.getNumSubscribers() > 0)
      states_pub_.publish(states);
    if (markers_pub_.getNumSubscribers() > 0)
      publishMarkers(*in);
  }

  /** Online mode: keep the last window seconds, re-classify every few frames, publish when stable. */
  void stepOnline(std::uint32_t id, Sequence& s)
  {
    while (!s.stamps.empty() && s.stamps.front() < s.stamps.back() - window_)
    {
      s.stamps.pop_front();
      s.descriptors.pop_front();
    }
    if (++s.since_classified < classify_every_ || !classifier_)
      return;
    if (s.stamps.size() < 2 || s.stamps.back() - s.stamps.front() < min_coverage_ * window_)
      return;
    s.since_classified = 0;
    const auto c = classify(id, s);
    if (!c)
      return;
    if (c->label == s.candidate)
      ++s.candidate_count;
    else
    {
      s.candidate = c->label;
      s.candidate_count = 1;
    }
    if (s.candidate_count >= stable_count_ && s.candidate != s.published)
    {
      s.published = s.candidate;
      publishLabel(id, s, *c, ActionLabel::ONLINE);
    }
  }

  /** Segmented mode: the whole sequence of a track that ended (or was asked for). */
  std::optional<ActionLabel> finish(std::uint32_t id, Sequence& s)
  {
    if (!classifier_)
      return std::nullopt;
    if (static_cast<int>(s.descriptors.size()) < min_frames_)
    {
      NODELET_INFO("track %u ended with %zu frame descriptors (fewer than min_frames %d): not classified", id,
                   s.descriptors.size(), min_frames_);
      return std::nullopt;
    }
    const auto c = classify(id, s);
    if (!c)
      return std::nullopt;
    s.published = c->label;
    return publishLabel(id, s, *c, ActionLabel::SEGMENTED);
  }

  std::optional<Classification> classify(std::uint32_t id, const Sequence& s)
  {
    try
    {
      const std::vector<Eigen::VectorXf> descriptors(s.descriptors.begin(), s.descriptors.end());
      const std::vector<double> stamps(s.stamps.begin(), s.stamps.end());
      return classifier_->classify(model_->sequence(descriptors, stamps));
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR_THROTTLE(5, "cannot classify track %u: %s", id, e.what());
      return std::nullopt;
    }
  }

  ActionLabel publishLabel(std::uint32_t id, const Sequence& s, const Classification& c, std::uint8_t mode)
  {
    auto label = boost::make_shared<ActionLabel>();
    label->header = header_;
    label->track_id = id;
    label->label = c.label;
    label->distance = c.distance;
    label->margin = c.margin;
    label->confidence = c.confidence;
    label->window_start = ros::Time(s.stamps.front());
    label->window_end = ros::Time(s.stamps.back());
    label->mode = mode;
    NODELET_INFO("track %u: %s (confidence %.2f, margin %.3f, %zu frames)", id, c.label.c_str(), c.confidence,
                 c.margin, s.descriptors.size());
    labels_pub_.publish(label);
    return *label;
  }

  void finishAll(std::vector<ActionLabel>* labels)
  {
    for (auto& [id, s] : sequences_)
    {
      auto l = finish(id, s);
      if (l && labels)
        labels->push_back(*l);
    }
    sequences_.clear();
  }

  void onTimer(const ros::WallTimerEvent&)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (sequences_.empty() || (ros::WallTime::now() - last_input_).toSec() < end_of_input_timeout_)
      return;
    NODELET_INFO("no input for %.1f s: end of input, classifying %zu open sequences", end_of_input_timeout_,
                 sequences_.size());
    finishAll(nullptr);
  }

  bool onClassify(Classify::Request&, Classify::Response& res)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!classifier_)
    {
      res.message = "not classifying: " + model_error_;
      return true;
    }
    const std::size_t open = sequences_.size();
    finishAll(&res.labels);
    res.message = std::to_string(res.labels.size()) + " of " + std::to_string(open) + " open sequences classified";
    return true;
  }

  void publishMarkers(const FrameDescriptors& in)
  {
    auto markers = boost::make_shared<visualization_msgs::MarkerArray>();
    auto base = [&](const std::string& ns, std::uint32_t id, int type) {
      visualization_msgs::Marker m;
      m.header = in.header;
      m.ns = ns;
      m.id = static_cast<int>(id);
      m.type = type;
      m.action = visualization_msgs::Marker::ADD;
      m.pose.orientation.w = 1.0;
      m.lifetime = ros::Duration(0.5);
      return m;
    };
    if (in.source)  // in-process: the flow itself is at hand
      for (const auto& p : in.source->people)
      {
        if (!p.flow || p.flow->empty())
          continue;
        auto m = base("flow", p.info.id, visualization_msgs::Marker::LINE_LIST);
        m.scale.x = 0.01;
        m.color.r = 1.0;
        m.color.g = 0.5;
        m.color.a = 1.0;
        const std::size_t step = std::max<std::size_t>(1, p.flow->size() / std::max(1, max_arrows_));
        for (std::size_t i = 0; i < p.flow->size(); i += step)
        {
          const auto& f = (*p.flow)[i];
          geometry_msgs::Point a, b;
          a.x = f.position.x();
          a.y = f.position.y();
          a.z = f.position.z();
          b.x = a.x + arrow_scale_ * f.velocity.x();
          b.y = a.y + arrow_scale_ * f.velocity.y();
          b.z = a.z + arrow_scale_ * f.velocity.z();
          m.points.push_back(a);
          m.points.push_back(b);
        }
        markers->markers.push_back(m);
      }
    std::map<std::uint32_t, Eigen::Vector3f> up;  // each person's up axis, when the flow is at hand
    if (in.source)
      for (const auto& p : in.source->people)
        up[p.info.id] = p.info.frame.axes.col(1);
    for (const auto& d : in.descriptors)
    {
      auto m = base("label", d.track_id, visualization_msgs::Marker::TEXT_VIEW_FACING);
      const auto it = sequences_.find(d.track_id);
      const std::string label = it == sequences_.end() || it->second.published.empty() ? "?" : it->second.published;
      m.text = std::to_string(d.track_id) + ": " + label;
      m.pose.position = d.head;
      const auto u = up.find(d.track_id);
      if (u != up.end())  // 0.2 m above the top of the head
      {
        m.pose.position.x += 0.2 * u->second.x();
        m.pose.position.y += 0.2 * u->second.y();
        m.pose.position.z += 0.2 * u->second.z();
      }
      m.scale.z = 0.15;
      m.color.r = m.color.g = m.color.b = m.color.a = 1.0;
      markers->markers.push_back(m);
    }
    markers_pub_.publish(markers);
  }

  bool online_ = false;
  double window_ = 3.0;
  int classify_every_ = 5;
  int stable_count_ = 3;
  int min_frames_ = 5;
  double min_coverage_ = 0.8;
  double end_of_input_timeout_ = 1.0;
  double arrow_scale_ = 0.1;
  int max_arrows_ = 150;

  std::optional<ActionModel> model_;
  std::optional<SequenceClassifier> classifier_;
  std::string model_error_;

  std::mutex mutex_;
  std::map<std::uint32_t, Sequence> sequences_;
  std_msgs::Header header_;
  double last_stamp_ = -1.0;
  ros::WallTime last_input_;
  ros::Publisher labels_pub_, states_pub_, markers_pub_;
  ros::ServiceServer service_;
  ros::WallTimer timer_;
};

}  // namespace action_flow

PLUGINLIB_EXPORT_CLASS(action_flow::ClassifierNodelet, nodelet::Nodelet)
