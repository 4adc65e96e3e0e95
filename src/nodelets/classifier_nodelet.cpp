// Classifier stage: frame descriptors per track to labels on `labels`, by the core's
// RecognitionPolicy over ~model (whichever recognizer it holds).
#include <action_flow/ActionLabel.h>
#include <action_flow/Classify.h>
#include <action_flow/action_model.h>
#include <action_flow/ros/lazy_nodelet.h>
#include <action_flow/ros/stage_diagnostics.h>
#include <action_flow/ros/params.h>
#include <action_flow/ros/stage_types.h>
#include <action_flow/recognition_policy.h>
#include <action_flow/track_table.h>

#include <pluginlib/class_list_macros.hpp>
#include <visualization_msgs/MarkerArray.h>

#include <map>
#include <optional>

namespace action_flow
{
/**
 * Subscribes `descriptors` (FrameDescriptors); publishes `labels` (ActionLabel), `states`
 * (ActionStates, per frame) and `markers` (MarkerArray: flow arrows and the label above each
 * head); service `~classify` (classify the open sequences now). When to classify and what to
 * publish is the core's RecognitionPolicy: this nodelet converts messages and publishes.
 * Parameters (private): model (path), the policy's (readPolicyParams: mode, ...),
 * end_of_input_timeout, arrow_scale, max_arrows, and the recognition parameters the model must
 * have been made with.
 */
class ClassifierNodelet : public LazyNodelet
{
  void onInit() override
  {
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    try
    {
      policy_params_ = readPolicyParams(pnh);
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR("%s: using the defaults (segmented)", e.what());
      policy_params_ = PolicyParams();
    }
    pnh.param("end_of_input_timeout", end_of_input_timeout_, end_of_input_timeout_);
    pnh.param("arrow_scale", arrow_scale_, arrow_scale_);
    pnh.param("max_arrows", max_arrows_, max_arrows_);
    diag_.start(getNodeHandle(), pnh, getName(), "classifier");
    loadModel(pnh);
    if (policy_)
      diag_.set("model", "loaded: " + pnh.param<std::string>("model", ""));
    else
      diag_.setProblem("no model: " + model_error_);
    diag_.set("labels published", "0");

    setSubscribe([this] {
      return getNodeHandle().subscribe("descriptors", 20, &ClassifierNodelet::onDescriptors, this);
    });
    labels_pub_ = advertiseLazy<ActionLabel>("labels", 20);
    states_pub_ = advertiseLazy<ActionStates>("states", 10);
    markers_pub_ = advertiseLazy<visualization_msgs::MarkerArray>("markers", 5);
    service_ = pnh.advertiseService("classify", &ClassifierNodelet::onClassify, this);
    if (!online())
      timer_ = getNodeHandle().createWallTimer(ros::WallDuration(0.2), &ClassifierNodelet::onTimer, this);
  }

  bool online() const { return policy_params_.mode == PolicyParams::Mode::Online; }

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
      const RecognitionParams runtime = readRecognitionParams(pnh);
      tracks_ = TrackTable<Seen>(runtime.flow.max_gap);
      auto model = std::make_shared<ActionModel>(ActionModel::load(path));
      model->checkCompatible(runtime, path);
      policy_.emplace(model, policy_params_);
      NODELET_INFO("model '%s': recognizer %s, %zu training sequences of %zu actions, %s%s", path.c_str(),
                   toString(model->params.recognizer).c_str(), model->labels.size(),
                   model->classifier().classes().size(), online() ? "online" : "segmented",
                   online() ? (policy_->usesMotion() ? " (motion segments)" : " (sliding window)") : "");
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
    diag_.received();
    last_input_ = ros::WallTime::now();
    const double stamp = in->header.stamp.toSec();
    header_ = in->header;
    if (!policy_)
      NODELET_ERROR_THROTTLE(10, "not classifying: %s", model_error_.c_str());
    // Tracks end by the same rules as the flow's (TrackTable): reset, time going back, lost, unseen.
    const auto frame = tracks_.begin(stamp, in->reset, in->lost);
    if (policy_ && frame.cleared)
    {
      NODELET_WARN_THROTTLE(5, "%s: dropping %zu open sequences", in->reset ? "reset" : "time went backwards",
                            policy_->tracks());
      policy_->clear();
    }
    for (const auto& ended : frame.ended)
      if (policy_ && !frame.cleared)
        publish(endTrack(ended.first));

    auto states = boost::make_shared<ActionStates>();
    states->header = in->header;
    states->source = in;
    for (const auto& d : in->descriptors)
    {
      tracks_.at(d.track_id, [] { return Seen(); });
      if (policy_ && d.status == PeopleFlow::kReset)
        policy_->restart(d.track_id);
      if (policy_ && d.status == PeopleFlow::kFlow && !d.values.empty())
      {
        try
        {
          publish(policy_->add(d.track_id, Eigen::Map<const Eigen::VectorXf>(d.values.data(), d.values.size()), stamp));
        }
        catch (const std::exception& e)
        {
          NODELET_ERROR_THROTTLE(5, "cannot classify track %u: %s", d.track_id, e.what());
        }
      }
      ActionState state;
      state.track_id = d.track_id;
      state.head = d.head;
      state.frames = policy_ ? policy_->frames(d.track_id) : 0;
      state.label = policy_ ? policy_->current(d.track_id) : std::string();
      states->tracks.push_back(state);
    }
    if (states_pub_.getNumSubscribers() > 0)
      states_pub_.publish(states);
    if (markers_pub_.getNumSubscribers() > 0)
      publishMarkers(*in);
    diag_.published(in->header.stamp);
    diag_.set("open tracks", std::to_string(policy_ ? policy_->tracks() : 0));
  }

  std::vector<LabelEvent> endTrack(std::uint32_t id)
  {
    const std::size_t frames = policy_->frames(id);
    auto events = policy_->end(id);
    if (!online() && events.empty() && frames > 0)
      NODELET_INFO("track %u ended with %zu frame descriptors (fewer than min_frames %d): not classified", id,
                   frames, policy_params_.min_frames);
    return events;
  }

  std::vector<ActionLabel> publish(const std::vector<LabelEvent>& events)
  {
    std::vector<ActionLabel> out;
    for (const LabelEvent& e : events)
    {
      auto label = boost::make_shared<ActionLabel>();
      label->header = header_;
      label->track_id = e.track;
      label->label = e.result.label;
      label->distance = e.result.distance;
      label->margin = e.result.margin;
      label->confidence = e.result.confidence;
      label->window_start = ros::Time(e.start);
      label->window_end = ros::Time(e.end);
      label->mode = e.kind == LabelEvent::Kind::Segmented ? ActionLabel::SEGMENTED
                    : e.closes_published                   ? ActionLabel::ONLINE_END
                                                           : ActionLabel::ONLINE;
      if (label->mode == ActionLabel::ONLINE_END)
        NODELET_INFO("track %u: %s ended (%.2f s)", e.track, e.result.label.c_str(), e.end - e.start);
      else
        NODELET_INFO("track %u: %s (confidence %.2f, margin %.3f, %zu frames)", e.track, e.result.label.c_str(),
                     e.result.confidence, e.result.margin, e.frames);
      labels_pub_.publish(label);
      diag_.set("labels published", std::to_string(++labels_published_));
      out.push_back(*label);
    }
    return out;
  }

  void onTimer(const ros::WallTimerEvent&)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!policy_ || policy_->tracks() == 0 || (ros::WallTime::now() - last_input_).toSec() < end_of_input_timeout_)
      return;
    NODELET_INFO("no input for %.1f s: end of input, classifying %zu open sequences", end_of_input_timeout_,
                 policy_->tracks());
    publish(policy_->endAll());
    tracks_.endAll();
  }

  bool onClassify(Classify::Request&, Classify::Response& res)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!policy_)
    {
      res.message = "not classifying: " + model_error_;
      return true;
    }
    const std::size_t open = policy_->tracks();
    res.labels = publish(policy_->endAll());
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
      const std::string published = policy_ ? policy_->current(d.track_id) : std::string();
      const std::string label = published.empty() ? "?" : published;
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

  PolicyParams policy_params_;
  double end_of_input_timeout_ = 1.0;
  double arrow_scale_ = 0.1;
  int max_arrows_ = 150;
  std::optional<RecognitionPolicy> policy_;
  std::string model_error_;

  std::mutex mutex_;
  std_msgs::Header header_;
  struct Seen
  {
  };
  TrackTable<Seen> tracks_{ FlowParams().max_gap };
  ros::WallTime last_input_;
  ros::Publisher labels_pub_, states_pub_, markers_pub_;
  StageDiagnostics diag_;
  std::size_t labels_published_ = 0;
  ros::ServiceServer service_;
  ros::WallTimer timer_;
};

}  // namespace action_flow

PLUGINLIB_EXPORT_CLASS(action_flow::ClassifierNodelet, nodelet::Nodelet)
