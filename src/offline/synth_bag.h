// Writing synthetic samples as bags in the layout of a Kinect recorded with the ROS OpenNI driver,
// and preview images. Used by the synth executable and its tests.
#pragma once

#include <action_flow/synth/crowd.h>
#include <action_flow/synth/synth.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace action_flow
{
namespace synth
{
/** @brief What goes into a bag and under which names. */
struct BagOptions
{
  std::string points_topic = "/camera/depth_registered/points";
  std::string rgb_topic = "/camera/rgb/image_color";
  std::string depth_topic = "/camera/depth_registered/image_raw";
  std::string info_topic = "/camera/rgb/camera_info";
  std::string mask_topic = "/camera/person_mask";
  std::string tf_topic = "/tf";
  /** stream bags only: the ground-truth action of each frame (std_msgs/String, "" = none). */
  std::string action_topic = "/ground_truth/action";
  /** Also write the organized PointCloud2 (about 10 MB a frame before compression). */
  bool points = false;
  /** sensor_msgs/Image on the topics themselves instead of CompressedImage on <topic>/compressed. */
  bool raw_images = false;
  int jpeg_quality = 80;             ///< image_transport's default
  int png_level = 3;                 ///< zlib level of the depth and mask PNGs
  std::string compression = "lz4";   ///< bag chunk compression: none, lz4, bz2
};

/**
 * @brief The topics and message types a bag of a @p dataset sample written with @p options holds
 *        (a "stream" also has options.action_topic).
 */
std::vector<std::pair<std::string, std::string>> bagTopics(const BagOptions& options, const std::string& dataset = "ias");

/**
 * @brief Renders every frame of @p sample into the bag @p path: written as "<path>.tmp" and renamed
 *        when complete, so an existing @p path is always a complete bag. A stream's bag also gets,
 *        per frame at its stamp, the frame's ground-truth action (SampleRenderer::actionAt) on
 *        options.action_topic.
 * @param cancel checked between frames; when set, the temporary file is removed and false returned
 * @param on_frame called after each frame (progress)
 * @throws std::runtime_error (message naming the file) on write errors or bad options
 */
bool writeSampleBag(const SampleRenderer& sample, const std::string& path, const BagOptions& options,
                    const std::atomic<bool>* cancel = nullptr, const std::function<void()>& on_frame = {});

/**
 * @brief Renders every frame of @p sample as a dump that libfreenect's fakenect replays (what
 *        fakenect-record writes of a Kinect v1): the folder @p dir with INDEX.txt and, per frame,
 *        "r-<time>-<timestamp>.ppm" (640x480 RGB) then "d-<time>-<timestamp>.pgm" (640x480 11-bit
 *        raw depth, kinect_depth.h, little-endian 16 bits as the sensor streams it), each a one-line
 *        header and the raw frame. Depth is registered to colour (fakenect has no registration).
 *        Written as "<dir>.tmp" and renamed when complete (an existing @p dir is replaced).
 * @return false if @p cancel was set (no partial folder left)
 * @throws std::runtime_error (naming the file) on write errors or a camera that is not 640x480
 */
bool writeFakenectDump(const SampleRenderer& sample, const std::string& dir, const std::atomic<bool>* cancel = nullptr,
                       const std::function<void()>& on_frame = {});

/**
 * @brief Writes the ground-truth segments of @p sample as CSV, header
 *        "action,first_frame,last_frame,start,end" (frames inclusive; start and end the stamps of
 *        the first and last frame in seconds), one row per SampleRenderer::segments() entry; written
 *        as "<path>.tmp" and renamed when complete.
 * @throws std::runtime_error (naming the file) if it cannot be written
 */
void writeSegmentsCsv(const SampleRenderer& sample, const std::string& path);

/**
 * @brief Renders every frame of a crowd scene into the bag @p path, as writeSampleBag does (one
 *        openni_tracker user per person present, numbered by mask id; no action topic: the
 *        people's actions are in the segments CSV). @p truth, if given, gets each frame's
 *        CrowdRenderer::truth.
 */
bool writeCrowdBag(const CrowdRenderer& crowd, const std::string& path, const BagOptions& options,
                   std::vector<std::vector<CrowdTruth>>* truth = nullptr, const std::atomic<bool>* cancel = nullptr,
                   const std::function<void()>& on_frame = {});

/**
 * @brief Writes a crowd scene's truth beside its bag (each written whole or not at all):
 *        <prefix>_segments.csv, header "person,action,first_frame,last_frame,start,end" (the
 *        stream's columns after the actor's id), and <prefix>_people.csv, one row per person present
 *        per frame: "frame,stamp,person,mask_id,x,y,z,yaw,visible_pixels,visible_area,head_visible,counted"
 *        (world position and yaw as in CrowdTruth).
 * @throws std::invalid_argument if @p truth has not one entry per frame; std::runtime_error if a file cannot be written
 */
void writeCrowdTruth(const CrowdRenderer& crowd, const std::vector<std::vector<CrowdTruth>>& truth,
                     const std::string& prefix);

/** @brief writePreview of a crowd scene's frame @p i. */
void writeCrowdPreview(const CrowdRenderer& crowd, int i, const std::string& prefix);

/** @brief Writes <prefix>_color.png and <prefix>_depth.png (depth 0.5-4.5 m as grey, black = none) of frame @p i. */
void writePreview(const SampleRenderer& sample, int i, const std::string& prefix);

/** @brief Encodes 8-bit RGB as JPEG / 16-bit or 8-bit single channel as PNG (OpenCV). */
std::vector<std::uint8_t> encodeJpeg(const std::vector<std::uint8_t>& rgb, int width, int height, int quality);
std::vector<std::uint8_t> encodePng16(const std::vector<std::uint16_t>& data, int width, int height, int level);
std::vector<std::uint8_t> encodePng8(const std::vector<std::uint8_t>& data, int width, int height, int level);

/** @brief Depth in metres (NaN = none) to the driver's 16UC1 millimetres (0 = none). */
std::vector<std::uint16_t> depthToMillimetres(const std::vector<float>& depth);

}  // namespace synth
}  // namespace action_flow
