/**
 * @file people_tracker.h
 * @brief People detection and tracking on colored point clouds, ROS-free (the pipeline's second
 *        stage): ground plane found by itself, people detected standing on it, tracked with
 *        stable ids, each person's cloud cut out at the flow's voxel size.
 */
#pragma once

#include <action_flow/grid_descriptor.h>
#include <action_flow/types.h>

#include <boost/shared_ptr.hpp>

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace action_flow
{
/** @brief Parameters of detection and tracking. Lengths in metres, times in seconds. */
struct TrackerParams
{
  /** Voxel size for detection (Munaro et al. 2012 found 0.06 m ideal for tracking). */
  float detection_voxel_size = 0.06f;
  /** Voxel size of the published person clouds (the flow's 0.02 m). */
  float person_voxel_size = 0.02f;
  /** Points farther than this from the camera are ignored (the Kinect's useful range). */
  float max_range = 6.0f;
  /** Person height limits (top of head above the ground). */
  float min_height = 1.1f, max_height = 2.3f;
  /** Person width limits (horizontal extent of a cluster). */
  float min_width = 0.1f, max_width = 1.2f;
  /** Points closer than this to the ground plane are ground. */
  float ground_tolerance = 0.05f;
  /** Euclidean clustering tolerance (at the detection voxel size). */
  float cluster_tolerance = 0.12f;
  /** Minimum points of a person cluster at the detection voxel size. */
  int min_points = 30;
  /** Use this ground plane (a,b,c,d, normal up, in the input frame) instead of estimating it. */
  std::optional<Eigen::Vector4f> ground;
  /** PCL HOG+SVM person classifier file; empty = no HOG confirmation; "default" = PCL's trained
   *  classifier shipped with the package (defaultHogClassifierFile(); no HOG if it is not found).
   *  Off by default: PCL's classifier was trained on photographs of people and rejects the virtual
   *  Kinect's rendered ones (p03_sit_down_3: 0 of 106 frames with it, 104 without), which every
   *  tool, test and demo here plays. kinect.launch turns it on for a real sensor (`hog` arg). */
  std::string hog_classifier_file = "";
  /** Association gate: a detection farther than this from a track's prediction starts a new track. */
  float gate = 0.6f;
  /** A track not seen for this long is lost. */
  double lost_after = 0.5;
  /** A new track is reported only after this many detections. */
  int confirm_after = 2;

  // ---- added with the implementation (defaults follow pcl::people where it has one) ----
  /** Organized clouds: only every n-th row and column feed the detection voxel grid (pcl::people's
   *  sampling factor; at 0.06 m voxels 2 loses nothing beyond 1 m). Person clouds use every point. */
  int sampling_factor = 2;
  /** Roughly "up" in the input frame, used to look for the ground (the camera's -y by default;
   *  e.g. (0,0,1) for clouds already in a z-up fixed frame such as odom). Need not be exact. */
  Eigen::Vector3f up_hint = Eigen::Vector3f(0, -1, 0);
  /** Largest angle (radians) between up_hint and the ground's normal: how far the camera may be tilted. */
  float ground_max_angle = 0.8f;
  /** Least floor area (m^2, counted in detection voxels) that makes a ground plane. */
  float ground_min_area = 0.5f;
  /** Where no floor is visible (dark or shiny floors give no depth), assume the ground below the
   *  lowest points when those lie at one level over at least 1 m (feet, chair legs, furniture). */
  bool assume_ground_below_points = true;
  /** Heads closer than this (on the ground) belong to one person (pcl::people's 0.3 m). */
  float min_head_distance = 0.3f;
  /** With a HOG classifier: detections scoring below this are rejected (pcl::people's examples use -1.5). */
  float hog_min_confidence = -1.5f;

  // ---- added against walls, furniture and lost non-upright bodies (issue: false detections) ----
  /** The camera's height above the floor (m); 0 = unknown. When given, the ground is known from the
   *  start: the plane camera_height below the camera, pitched with it by camera_pitch, in the camera's
   *  optical frame (x right, y down, z ahead). It is kept while the floor is hidden and refined by
   *  the measured floor where that agrees (a strongly supported floor that disagrees replaces it). */
  float camera_height = 0.0f;
  /** The camera's downward pitch (rad, about its x axis; positive = looking down); with camera_height. */
  float camera_pitch = 0.0f;
  /** Organized clouds: a cluster whose top reaches the image's top edge (within 2 rows) about as wide
   *  as its widest row (half of it or more) is no person: its height is the image's, not a head's
   *  (walls, curtains, doors, shelves cut by the image border). A raised hand or a head leaving the
   *  image is much narrower than the body, and is kept; what the edge cuts must also span less than
   *  0.35 m (a side wall seen along its length is narrow in pixels there but a metre deep). */
  bool reject_top_at_border = true;
  /** Organized clouds: a person stands free of what is behind them; at least this share of the rows
   *  of the head (its top 0.25 m) must show a depth step of free_depth_step (or no depth) on both sides
   *  in the image. A wall, door or curtain cut into columns has none. 0 disables the check. */
  float min_free_fraction = 0.8f;
  /** The depth step (m) that separates a head from what is beside it in the image. */
  float free_depth_step = 0.25f;
  /** A cluster continuing a confirmed track (within gate of its prediction) may be lower and wider
   *  than a new person: a body that bends, crouches, lunges or kicks keeps its track. HOG is not
   *  required of it either (HOG wants upright people). */
  float tracked_min_height = 0.7f;
  float tracked_max_width = 1.8f;
  /** ... and only if its colours are within this distance of the track's (the Hellinger distance of
   *  tracker_appearance.h's colour histograms; needs reid_after > 0, which keeps the appearance): a
   *  chair or table beside a person whose detection is missing for a frame is then not taken for
   *  them. 1 turns it off. */
  float weak_max_colour_distance = 0.35f;
  /** A confirmed track continued only by clusters lower than min_height for this long (s) is lost:
   *  it has gone on to a chair, a table or a box beside the person (a phantom track that would be
   *  labelled for as long as the furniture stands). A person crouches or bends for less; one who
   *  stays down longer is a new track when they stand up, and gets their id back
   *  (re-identification). 0 turns it off. */
  double low_lost_after = 4.0;

  // ---- added against cluttered rooms (evaluate --protocol detection) ----
  /** Walls (vertical planes at least 0.6 m wide and 1.2 m tall reaching 2.1 m above the ground, with
   *  nothing behind them: tracker_walls.h) are removed before
   *  clustering: a person close in front of one is not absorbed into it, and none of its columns is
   *  taken for a person. Beside a head, a pixel on a removed wall counts as free. */
  bool remove_walls = true;
  /** A new person's head is narrower than their shoulders: the width (across the line of sight) of
   *  the top 0.15 m may be at most this share of the widest of the 0.3-0.6 m below the top. Cabinets,
   *  shelves, doors and chair backs are as wide at the top as below. 0 disables the check. */
  float max_head_ratio = 0.8f;

  // ---- added for several people (evaluate_tracking) ----
  /** A confirmed track that is not seen while its predicted place lies in the shadow of a person
   *  nearer to the camera (hidden behind them, seen along the ground) is kept this long instead of
   *  lost_after, coasting at its velocity; while unseen its gate widens (by 0.5 m a second, to at
   *  most twice gate), so a person passing behind another comes back under their own id.
   *  Must be at least lost_after; equal to it turns the re-identification off. */
  double hidden_lost_after = 2.0;
  /** A person who was lost (out of view, or hidden for longer than hidden_lost_after) gets their id
   *  back when a new track, as it is confirmed, looks like them: their height within
   *  reid_max_height_difference, their clothes' colours within reid_max_colour_distance (the Hellinger
   *  distance of the colour histograms of tracker_appearance.h, 0 = the same, 1 = disjoint), and no
   *  farther from where they were last seen than gate plus 2 m/s for the time in between. A lost
   *  person is remembered this long (s); 0 turns it off. A confirmed track still coasting unseen
   *  (its detection jumped beyond the gate) is continued the same way, and then never reported lost. */
  double reid_after = 20.0;
  float reid_max_colour_distance = 0.2f;
  float reid_max_height_difference = 0.25f;  // loose: a person acting (arms up, bending) changes height
  /** A raised or thrown arm can give a body a second "head" and split it in two: a person-like
   *  detection that no confirmed track takes, this close on the ground (m) to one a confirmed track
   *  takes and side by side with it as the camera sees them (distances from the camera within
   *  0.25 m), joins that person instead of starting a track. Splits measured 0.28-0.44 m apart on
   *  the crowd scenes of seed 2; two people shoulder to shoulder stand about 0.45 m apart, but each
   *  is confirmed on their own detection before they come so close. 0 turns it off. */
  float split_max_distance = 0.45f;

  // ---- added for orientation (evaluate --protocol cross-view) ----
  /** The descriptor grid turns with the person: its depth axis points where they face, estimated
   *  from their trunk's shape (facing.h: always towards the camera side, so a back view is taken as
   *  a front view) and smoothed over facing_smoothing s. Off: the depth axis lies along the line of
   *  sight (the paper's grid). */
  bool align_to_facing = false;
  /** Time constant (s) of the facing's exponential smoothing per track; 0 takes each frame's own. */
  double facing_smoothing = 0.5;

  template <class Self, class V>
  static void visit(Self& p, V&& v)
  {
    const Shapes s = Shapes::Frames;  // every tracker parameter shapes which clouds make the descriptors
    v("detection_voxel_size", p.detection_voxel_size, "m: voxel size for detection", s);
    v("person_voxel_size", p.person_voxel_size, "m: voxel size of the published person clouds (the paper's 0.02)", s);
    v("max_range", p.max_range, "m: farther points are ignored", s);
    v("min_height", p.min_height, "m: a new person's least height (top of head above the ground)", s);
    v("max_height", p.max_height, "m: a person's greatest height", s);
    v("min_width", p.min_width, "m: a person's least horizontal extent", s);
    v("max_width", p.max_width, "m: a new person's greatest horizontal extent", s);
    v("ground_tolerance", p.ground_tolerance, "m: points this close to the ground plane are ground", s);
    v("cluster_tolerance", p.cluster_tolerance, "m: Euclidean clustering tolerance", s);
    v("min_points", p.min_points, "least points of a person cluster at the detection voxel size", s);
    v("ground", p.ground, "a fixed ground plane (normal up, input frame); [] = estimated", s);
    v("hog_classifier_file", p.hog_classifier_file, "PCL HOG+SVM file; \"\" = no HOG, \"default\" = PCL's shipped one", s);
    v("gate", p.gate, "m: a detection farther from a track's prediction starts a new track", s);
    v("lost_after", p.lost_after, "s: a track not seen this long is lost", s);
    v("confirm_after", p.confirm_after, "detections before a new track is reported", s);
    v("sampling_factor", p.sampling_factor, "organized clouds: every n-th row and column feed detection", s);
    v("up_hint", p.up_hint, "roughly up in the input frame (camera -y; +z with a z-up fixed frame)", s);
    v("ground_max_angle", p.ground_max_angle, "rad: how far the ground's normal may be from up_hint", s);
    v("ground_min_area", p.ground_min_area, "m^2 of floor that make a ground plane", s);
    v("assume_ground_below_points", p.assume_ground_below_points, "no floor visible: assume it below the lowest points", s);
    v("min_head_distance", p.min_head_distance, "m: heads closer than this belong to one person", s);
    v("hog_min_confidence", p.hog_min_confidence, "with a HOG file: lower scores are rejected", s);
    v("camera_height", p.camera_height, "m above the floor; 0 = unknown (the ground is then estimated)", s);
    v("camera_pitch", p.camera_pitch, "rad, downward; with camera_height", s);
    v("reject_top_at_border", p.reject_top_at_border, "a cluster whose top is the image's top edge is no person", s);
    v("min_free_fraction", p.min_free_fraction, "share of head rows with a depth step on both sides (0 = off)", s);
    v("free_depth_step", p.free_depth_step, "m: the depth step around a free-standing head", s);
    v("tracked_min_height", p.tracked_min_height, "m: a confirmed track continues on clusters this low", s);
    v("tracked_max_width", p.tracked_max_width, "m: ... and this wide", s);
    v("weak_max_colour_distance", p.weak_max_colour_distance, "... and colours this close to the track's (Hellinger, 0-1; 1 = off)", s);
    v("low_lost_after", p.low_lost_after, "s: a track seen only lower than min_height this long is lost (0 = off)", s);
    v("remove_walls", p.remove_walls, "remove walls before clustering", s);
    v("max_head_ratio", p.max_head_ratio, "a new person's head width / shoulder width at most (0 = off)", s);
    v("hidden_lost_after", p.hidden_lost_after, "s: a track hidden behind a nearer person is kept this long", s);
    v("reid_after", p.reid_after, "s: a lost person is given their id back when they return this soon (0 = off)", s);
    v("reid_max_colour_distance", p.reid_max_colour_distance, "... with clothes' colours this close (Hellinger, 0-1)", s);
    v("reid_max_height_difference", p.reid_max_height_difference, "m: ... and a height this close", s);
    v("split_max_distance", p.split_max_distance, "m: an untracked detection this close beside a tracked person is part of them (0 = off)", s);
    v("align_to_facing", p.align_to_facing, "the grid turns to where the person faces", s);
    v("facing_smoothing", p.facing_smoothing, "s: time constant of the facing's smoothing", s);
  }
};

/**
 * @brief Where hog_classifier_file "default" is found: $ACTION_FLOW_HOG_CLASSIFIER if set, else the
 *        package's installed share/action_flow/data/, else the source tree's ../shared/data/pcl_people/
 *        (trainedLinearSVMForPeopleDetectionWithHOG.yaml); "" if none is readable.
 */
std::string defaultHogClassifierFile();

/** @brief One tracked person in one frame. */
struct TrackedPerson
{
  /** Stable over the track's life; a person re-identified after being lost (reid_after) gets their
   *  old id back, and the ids of different people never repeat. */
  std::uint32_t id = 0;
  Eigen::Vector3f position = Eigen::Vector3f::Zero(); ///< centroid (input frame)
  Eigen::Vector3f velocity = Eigen::Vector3f::Zero(); ///< from the motion model (m/s)
  float height = 0.0f;                              ///< top of head above the ground
  PersonFrame frame;                                ///< where the descriptor grid sits
  /** With align_to_facing: the facing (rad, 0 = towards the camera, facing.h) the frame is turned by,
   *  smoothed; NaN otherwise, and while no estimate has been possible. */
  float facing = std::numeric_limits<float>::quiet_NaN();
  /** HOG+SVM score of this frame's detection; NaN when no classifier ran (none given, unorganized cloud). */
  double hog_confidence = std::numeric_limits<double>::quiet_NaN();
  /** The person's points at person_voxel_size, in the input frame; never modified after update(). */
  boost::shared_ptr<Cloud> cloud;
};

/** @brief What one update found. */
struct TrackerResult
{
  std::vector<TrackedPerson> people;  ///< confirmed tracks seen in this frame
  std::vector<std::uint32_t> lost;    ///< tracks that ended at this frame
  Eigen::Vector4f ground = Eigen::Vector4f::Zero();
  bool ground_valid = false;          ///< false until a ground plane has been found
  bool ground_assumed = false;        ///< the ground is assumed below the lowest points (no floor visible)
  bool reset = false;                 ///< time went backwards: all tracks were dropped first (their ids are in lost)
  std::size_t detections = 0;         ///< people detected in this frame (confirmed tracks or not; not counting
                                      ///< clusters that only passed the tracked_* limits)
  bool hog_applied = false;           ///< the HOG classifier checked this frame's detections (needs an organized cloud)
};

/**
 * @brief Detects and tracks people. One instance per camera stream; not thread-safe.
 */
class PeopleTracker
{
public:
  /** @throws std::invalid_argument on bad parameters or an unreadable HOG classifier file. */
  explicit PeopleTracker(const TrackerParams& params = TrackerParams());
  ~PeopleTracker();

  /**
   * @brief Processes one cloud (organized or not; y of the camera roughly down unless the ground
   *        is given) taken at @p stamp, with the camera at @p camera_origin in the cloud's frame.
   * Empty, all-NaN or floorless clouds give a result with no people (and ground_valid false
   * until a floor is seen); they never throw. Nor do clouds whose width*height does not match
   * their size, or a non-finite stamp: those are ignored (an empty result, state unchanged).
   * A stamp earlier than the previous one drops every track first (TrackerResult::reset).
   * A track lost (not seen for lost_after seconds) is listed once in TrackerResult::lost (again
   * when a person re-identified under that id is lost once more).
   * TrackedPerson::position is this frame's measured centroid; velocity comes from the
   * constant-velocity filter.
   */
  TrackerResult update(const Cloud& cloud, double stamp,
                       const Eigen::Vector3f& camera_origin = Eigen::Vector3f::Zero());

  /** @brief Drops all tracks and the ground estimate (back to the given ground, if any). */
  void reset();

  /**
   * @brief Gives the ground from outside (a,b,c,d in the input frame, normal up), e.g. from tf: used
   *        as camera_height/camera_pitch are (kept while the floor is hidden, refined by a floor that
   *        agrees). Ignored with fixed_ground.
   * @param camera the camera's position in the input frame (the plane is oriented toward it)
   * @return false for a degenerate plane
   */
  bool setGroundPrior(const Eigen::Vector4f& plane, const Eigen::Vector3f& camera = Eigen::Vector3f::Zero());

  const TrackerParams& params() const { return params_; }

private:
  struct Impl;
  TrackerParams params_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace action_flow
