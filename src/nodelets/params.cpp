#include <action_flow/ros/params.h>

#include <string>
#include <vector>

namespace action_flow
{
namespace
{
// ros::NodeHandle::param has no float overload that takes a float default with a double value type.
void readFloat(const ros::NodeHandle& nh, const std::string& name, float& value)
{
  double v = value;
  nh.param(name, v, v);
  value = static_cast<float>(v);
}
}  // namespace

RecognitionParams readRecognitionParams(const ros::NodeHandle& nh)
{
  RecognitionParams p = defaultRecognitionParams();
  std::string recognizer = toString(p.recognizer);
  nh.param("recognizer", recognizer, recognizer);
  p.recognizer = recognizerFromString(recognizer);
  readFloat(nh, "voxel_size", p.voxel_size);
  nh.param("flow/k", p.flow.k, p.flow.k);
  nh.param("flow/reciprocal", p.flow.reciprocal, p.flow.reciprocal);
  nh.param("flow/reject_outliers", p.flow.reject_outliers, p.flow.reject_outliers);
  readFloat(nh, "flow/min_speed", p.flow.min_speed);
  readFloat(nh, "flow/isolation_speed", p.flow.isolation_speed);
  readFloat(nh, "flow/neighbour_radius", p.flow.neighbour_radius);
  nh.param("grid/parts_x", p.grid.parts_x, p.grid.parts_x);
  nh.param("grid/parts_y", p.grid.parts_y, p.grid.parts_y);
  nh.param("grid/parts_z", p.grid.parts_z, p.grid.parts_z);
  readFloat(nh, "grid/width", p.grid.width);
  readFloat(nh, "grid/height", p.grid.height);
  readFloat(nh, "grid/depth", p.grid.depth);
  readFloat(nh, "grid/reference_height", p.grid.reference_height);
  std::string descriptor = toString(p.grid.aggregation);
  nh.param("descriptor", descriptor, descriptor);
  p.grid.aggregation = aggregationFromString(descriptor);
  nh.param("frames", p.frames, p.frames);
  nh.param("use_pca", p.use_pca, p.use_pca);
  nh.param("pca_variance", p.pca_variance, p.pca_variance);
  nh.param("neighbours", p.neighbours, p.neighbours);
  return p;
}

PolicyParams readPolicyParams(const ros::NodeHandle& nh)
{
  PolicyParams p;
  std::string mode = "segmented";
  nh.param("mode", mode, mode);
  p.mode = policyModeFromString(mode);
  nh.param("min_frames", p.min_frames, p.min_frames);
  nh.param("classify_every", p.classify_every, p.classify_every);
  nh.param("stable_count", p.stable_count, p.stable_count);
  nh.param("min_confidence", p.min_confidence, p.min_confidence);
  nh.param("idle_labels", p.idle_labels, p.idle_labels);
  nh.param("motion_segments", p.motion_segments, p.motion_segments);
  nh.param("motion_on", p.motion_on, p.motion_on);
  nh.param("motion_off", p.motion_off, p.motion_off);
  nh.param("motion_lag", p.motion_lag, p.motion_lag);
  nh.param("motion_smooth", p.motion_smooth, p.motion_smooth);
  nh.param("rest_time", p.rest_time, p.rest_time);
  nh.param("pre_roll", p.pre_roll, p.pre_roll);
  nh.param("post_roll", p.post_roll, p.post_roll);
  nh.param("min_segment", p.min_segment, p.min_segment);
  nh.param("max_segment", p.max_segment, p.max_segment);
  nh.param("publish_early", p.publish_early, p.publish_early);
  nh.param("window", p.window, p.window);
  nh.param("min_coverage", p.min_coverage, p.min_coverage);
  p.validate();
  return p;
}

TrackerParams readTrackerParams(const ros::NodeHandle& nh)
{
  TrackerParams p;
  readFloat(nh, "detection_voxel_size", p.detection_voxel_size);
  readFloat(nh, "person_voxel_size", p.person_voxel_size);
  readFloat(nh, "max_range", p.max_range);
  readFloat(nh, "min_height", p.min_height);
  readFloat(nh, "max_height", p.max_height);
  readFloat(nh, "min_width", p.min_width);
  readFloat(nh, "max_width", p.max_width);
  readFloat(nh, "ground_tolerance", p.ground_tolerance);
  readFloat(nh, "cluster_tolerance", p.cluster_tolerance);
  nh.param("min_points", p.min_points, p.min_points);
  std::vector<double> ground;
  if (nh.getParam("ground", ground))
  {
    if (ground.size() != 4)
      throw std::invalid_argument("parameter ground must have 4 values a,b,c,d, has " +
                                  std::to_string(ground.size()));
    p.fixed_ground = true;
    p.ground = Eigen::Vector4f(ground[0], ground[1], ground[2], ground[3]);
  }
  nh.param("hog_classifier_file", p.hog_classifier_file, p.hog_classifier_file);
  readFloat(nh, "hog_min_confidence", p.hog_min_confidence);
  std::vector<double> up;
  if (nh.getParam("up_hint", up))
  {
    if (up.size() != 3)
      throw std::invalid_argument("parameter up_hint must have 3 values x,y,z, has " + std::to_string(up.size()));
    p.up_hint = Eigen::Vector3f(up[0], up[1], up[2]);
  }
  readFloat(nh, "ground_max_angle", p.ground_max_angle);
  readFloat(nh, "ground_min_area", p.ground_min_area);
  nh.param("assume_ground_below_points", p.assume_ground_below_points, p.assume_ground_below_points);
  readFloat(nh, "min_head_distance", p.min_head_distance);
  readFloat(nh, "gate", p.gate);
  nh.param("lost_after", p.lost_after, p.lost_after);
  nh.param("hidden_lost_after", p.hidden_lost_after, p.hidden_lost_after);
  nh.param("align_to_facing", p.align_to_facing, p.align_to_facing);
  nh.param("facing_smoothing", p.facing_smoothing, p.facing_smoothing);
  nh.param("confirm_after", p.confirm_after, p.confirm_after);
  readFloat(nh, "camera_height", p.camera_height);
  readFloat(nh, "camera_pitch", p.camera_pitch);
  nh.param("reject_top_at_border", p.reject_top_at_border, p.reject_top_at_border);
  readFloat(nh, "min_free_fraction", p.min_free_fraction);
  readFloat(nh, "free_depth_step", p.free_depth_step);
  readFloat(nh, "tracked_min_height", p.tracked_min_height);
  readFloat(nh, "tracked_max_width", p.tracked_max_width);
  nh.param("remove_walls", p.remove_walls, p.remove_walls);
  readFloat(nh, "max_head_ratio", p.max_head_ratio);
  return p;
}

}  // namespace action_flow
