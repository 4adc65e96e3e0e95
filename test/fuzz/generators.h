/**
 * @file generators.h
 * @brief Generators of malformed inputs for the fuzz suite, each deterministic from a seed: the
 *        same seed gives the same input, byte for byte, so a failing input is reproduced from the
 *        seed the suite prints (or from the file it wrote).
 *
 * Every generator returns what it made and the name of the mutation it chose (its "case"), so
 * that the suite can count per kind and case and mark a case as a known failure.
 */
#pragma once

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace action_flow
{
namespace fuzz
{
/** @brief The random source of one input: a 64-bit Mersenne twister seeded through SplitMix64. */
class Rng
{
public:
  explicit Rng(std::uint64_t seed);
  /** @brief A uniform integer in [lo, hi]. */
  std::uint64_t in(std::uint64_t lo, std::uint64_t hi);
  /** @brief True with probability @p p. */
  bool chance(double p);
  /** @brief One of @p items. */
  template <class T>
  const T& pick(const std::vector<T>& items)
  {
    return items[in(0, items.size() - 1)];
  }
  /** @brief A 32-bit value that is often an edge: 0, 1, powers of two, all ones, or random. */
  std::uint32_t edge32();
  std::mt19937_64& engine() { return engine_; }

private:
  std::mt19937_64 engine_;
};

/** @brief Something generated and the name of the mutation that made it. */
template <class T>
struct Generated
{
  T value;
  std::string variant;
};

// ---- messages ---------------------------------------------------------------------------------

/** @brief A well-formed organized XYZRGB PointCloud2 of @p width x @p height points, a plane 2 m away. */
sensor_msgs::PointCloud2 goodCloud(std::uint32_t width, std::uint32_t height);
/**
 * @brief A malformed or hostile PointCloud2: width/height/point_step/row_step that disagree with the
 *        data, missing or misplaced x/y/z fields, huge claimed sizes, NaN-only or empty clouds, ...
 *        Some cases are well-formed but nasty (NaN-only, empty, infinite coordinates): the checks
 *        pass them and the stage must cope.
 */
Generated<sensor_msgs::PointCloud2> badCloud(std::uint64_t seed);

/** @brief A well-formed image (rgb8 colour or 32FC1 depth at 2 m) of @p width x @p height. */
sensor_msgs::Image goodImage(const std::string& encoding, std::uint32_t width, std::uint32_t height);
/** @brief A well-formed camera_info for @p width x @p height images (f = 0.82 x width). */
sensor_msgs::CameraInfo goodInfo(std::uint32_t width, std::uint32_t height);

/**
 * @brief A malformed image for a @p width x @p height stream (@p depth: the depth stream): unknown
 *        or wrong encodings, 0x0, huge step, short or long data, taller or wider than the stream,
 *        NaN/inf depth.
 */
Generated<sensor_msgs::Image> badImage(std::uint64_t seed, bool depth, std::uint32_t width, std::uint32_t height);

/** @brief A malformed camera_info: zero, NaN, infinite or negative intrinsics, 0x0 or huge sizes. */
Generated<sensor_msgs::CameraInfo> badInfo(std::uint64_t seed, std::uint32_t width, std::uint32_t height);

// ---- files ------------------------------------------------------------------------------------

/** @brief The topics the tools read from a bag (their defaults, the IAS-Lab layout). */
struct BagLayout
{
  std::string points = "/camera/depth_registered/points";
  std::string depth = "/camera/depth_registered/image_raw";
  std::string rgb = "/camera/rgb/image_color";
  std::string info = "/camera/rgb/camera_info";
};

/**
 * @brief Writes a malformed bag to @p path with the rosbag C++ API (64x48 frames): truncated or
 *        short image data, wrong steps, missing camera_info, stamps all equal, zero or going
 *        backwards, mismatched sizes, bad intrinsics, undecodable compressed images, a malformed
 *        points topic; or a good bag afterwards damaged on disk (garbage bytes, truncation).
 * @return the case's name
 */
std::string writeBadBag(const std::string& path, std::uint64_t seed);

/** @brief The bytes of a valid model written by ActionModel::save (the paper's or the default recognizer). */
std::string validModelBytes(const std::string& scratch_dir, bool posture_flow);
/** @brief @p model damaged: byte flips, truncation, inserted or removed bytes, size fields set huge. */
Generated<std::string> mutateModel(const std::string& model, std::uint64_t seed);

/**
 * @brief A malformed dataset index (CSV text) whose sample paths point at @p bag (an existing file)
 *        when a path is needed: missing columns, wrong field counts, non-numeric or huge numbers,
 *        empty fields, duplicates, missing sample files, binary garbage, very long lines.
 */
Generated<std::string> badIndex(std::uint64_t seed, const std::string& bag);

/** @brief A valid MSR Action3D skeleton file's text: @p frames frames of 20 joints of a standing person. */
std::string validSkeleton(int frames);
/**
 * @brief A malformed or hostile skeleton file: NaN/inf, confidences outside [0,1], missing or extra
 *        columns or lines, non-numbers, empty, all joints zero, huge (finite) coordinates, a collapsed
 *        skeleton, binary garbage.
 */
Generated<std::string> badSkeleton(std::uint64_t seed);

// ---- command lines ------------------------------------------------------------------------------

/** @brief A command line for a tool that must be refused, and the word its error line must name. */
struct BadCommand
{
  std::vector<std::string> args;  ///< without the program name
  std::string culprit;            ///< the option (e.g. "--jobs") or argument the error must name
};

/**
 * @brief A bad command line for @p tool ("train", "evaluate" or "synth"): one unknown option name,
 *        out-of-range, negative, huge, hex, fractional or empty values of a known option, a value
 *        missing at the end, a stray argument or a bad choice, among valid options in random order.
 *        @p scratch is a folder the command may name for its outputs (it never gets there).
 */
Generated<BadCommand> badCommand(const std::string& tool, std::uint64_t seed, const std::string& scratch);

/** @brief @p text with every byte outside printable ASCII shown as \\xNN (for messages). */
std::string printable(const std::string& text, std::size_t max = 400);

}  // namespace fuzz
}  // namespace action_flow
