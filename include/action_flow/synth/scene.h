/**
 * @file scene.h
 * @brief The virtual Kinect v1: camera model, a room of boxes, textured articulated bodies posed by
 *        a 15-joint skeleton, and the renderer that turns them into depth, colour and a person mask
 *        with the sensor's noise. ROS-free.
 *
 * Frames: the world has its origin on the floor below the camera, x forward (horizontal part of
 * the viewing direction), y left, z up. Rendered clouds are in the camera's optical frame
 * (x right, y down, z forward).
 */
#pragma once

#include <action_flow/synth/skeleton.h>
#include <action_flow/types.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <memory>
#include <vector>

namespace action_flow
{
namespace synth
{
/** @brief A Kinect v1 and where it stands. Defaults are the sensor. */
struct CameraModel
{
  int width = 640, height = 480;
  double fx = 525.0, fy = 525.0, cx = 319.5, cy = 239.5;
  double fps = 30.0;
  double min_depth = 0.5, max_depth = 4.5;  ///< no depth outside (m)
  double baseline = 0.075;                  ///< projector-camera baseline (m), for disparity
  double disparity_step = 0.125;            ///< disparity quantisation (pixels; the Kinect's 1/8 px)
  /** Depth noise, standard deviation = noise_coefficient * z^2 (Khoshelham & Elberink 2012),
   *  quantisation included. */
  double noise_coefficient = 1.425e-3;
  /** Depth noise is shared by blocks of this many pixels square: the sensor correlates the speckle
   *  pattern over a window, so its errors are spatially correlated, not independent per pixel. */
  int noise_block = 3;
  double color_noise = 3.0;                 ///< colour sensor noise, standard deviation (0-255 scale)
  double edge_dropout = 0.5;                ///< probability that a pixel at a depth edge has no depth
  bool noise = true;                        ///< false: exact depth and colour, no dropout (tests)
  double height_above_floor = 1.1;          ///< optical centre above the floor (m)
  double tilt = 0.08;                       ///< downward pitch (rad)

  /** @brief Camera pose in the world: optical frame axes (columns) and origin. */
  Eigen::Isometry3f worldFromOptical() const;
};

/** @brief An RGB colour, components 0..1. */
using Rgb = Eigen::Vector3f;

/** @brief Surface patterns; every one carries fine noise as well. */
enum class Pattern : int
{
  Plain,
  HorizontalStripes,
  VerticalStripes,
  Checks,
  Print,   ///< irregular blotches (a printed shirt)
  Denim,   ///< fine diagonal weave with fading
  Planks,  ///< wooden floor boards (room)
  Tiles    ///< square tiles (room)
};

/** @brief What a surface looks like. */
struct Material
{
  Rgb base = Rgb(0.5f, 0.5f, 0.5f);
  Rgb second = Rgb(0.3f, 0.3f, 0.3f);  ///< the pattern's other colour
  Pattern pattern = Pattern::Plain;
  float period = 0.05f;                  ///< pattern period (m)
  float grain = 0.08f;                   ///< amplitude of the fine noise (relative)
  std::uint32_t seed = 0;                ///< varies the print and the grain
};

/** @brief An axis-aligned-in-yaw box of the room (furniture, walls' fittings). */
struct Box
{
  Eigen::Vector3f center = Eigen::Vector3f::Zero();  ///< world
  Eigen::Vector3f half = Eigen::Vector3f::Constant(0.1f);  ///< half sizes along its own axes
  float yaw = 0.0f;                                   ///< rotation about world z
  Material material;
};

/** @brief The static room: a floor, optional walls and ceiling, boxes. Planes not wanted: disable. */
struct Room
{
  bool floor = true;
  Material floor_material;
  bool walls = true;
  float back_wall = 4.3f;   ///< x of the wall facing the camera
  float left_wall = 2.3f;   ///< y of the wall on the camera's left (world +y)
  float right_wall = -2.1f; ///< y of the wall on the camera's right
  float ceiling = 2.7f;
  Material wall_material, ceiling_material;
  std::vector<Box> boxes;

  /** @brief The boxes of a chair whose seat centre is at (x, y), facing @p yaw (front = +x rotated). */
  static std::vector<Box> chair(float x, float y, float yaw, float seat_height, const Material& m);
  /** @brief The lab room used by the datasets: floor, walls, a cabinet, a poster; no chair. */
  static Room lab(std::uint32_t seed);
};

/** @brief Size and build of a body; the volumes scale with both. */
struct BodyShape
{
  float height = 1.75f;  ///< top of the head above the floor when standing (m)
  float build = 1.0f;    ///< girth factor, ~0.85 (slim) .. 1.25 (heavy)
};

/** @brief A person's looks. */
struct Appearance
{
  Material skin, hair, shirt, trousers, shoes;
  bool long_sleeves = true;
  bool long_hair = false;
};

/** @brief A body to draw in one frame: its shape, looks, pose (world frame) and mask id (1..255). */
struct PosedBody
{
  BodyShape shape;
  const Appearance* appearance = nullptr;  ///< must outlive the render call
  Skeleton joints;                         ///< world frame
  Eigen::Vector3f forward = Eigen::Vector3f::UnitX();  ///< body facing (world), used for the feet and textures
  std::uint8_t id = 1;
};

/** @brief One rendered frame as the sensor delivers it (row-major, width x height). */
struct FrameImages
{
  int width = 0, height = 0;
  std::vector<float> depth;          ///< metres along the optical axis, NaN = no depth
  std::vector<std::uint8_t> rgb;     ///< 3 bytes per pixel, R G B
  std::vector<std::uint8_t> mask;    ///< person id whose surface is seen at the pixel (0 = none), depth valid or not
};

/**
 * @brief Renders a static room plus posed bodies as a Kinect v1 sees them.
 *
 * The room is ray-cast once at construction (per camera pose); each frame only the body is
 * ray-cast inside the image boxes of its 18 volumes, then the sensor model is applied: disparity
 * noise and quantisation, the projector's shadow left of near edges, random dropout along depth
 * edges, range limits, colour noise. Noise is a pure function of (noise_seed, frame, pixel), so a
 * frame renders identically wherever and whenever it is rendered. const methods are thread-safe.
 */
class SceneRenderer
{
public:
  SceneRenderer(const CameraModel& camera, const Room& room);
  ~SceneRenderer();
  SceneRenderer(SceneRenderer&&) noexcept;
  SceneRenderer& operator=(SceneRenderer&&) noexcept;

  /** @brief Renders the bodies over the room; @p frame and @p noise_seed select the noise. */
  void render(const std::vector<PosedBody>& bodies, std::uint64_t noise_seed, int frame, FrameImages& out) const;

  /** @brief Organized cloud (optical frame, NaN where no depth) from rendered images. */
  void toCloud(const FrameImages& images, Cloud& cloud) const;
  /** @brief toCloud for frame @p frame of a sequence: stamped (@p stamp s, as PCL's microseconds) and
   *         numbered, and the images' person ids copied into @p mask when given. */
  void toFrameCloud(const FrameImages& images, double stamp, int frame, Cloud& cloud,
                    std::vector<std::uint8_t>* mask) const;

  const CameraModel& camera() const;
  /** @brief Noise-free depth of the empty room (m, +inf where nothing is hit), row-major. */
  const std::vector<float>& roomDepth() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/** @brief The frame id of rendered clouds. */
constexpr const char* kOpticalFrame = "camera_rgb_optical_frame";

}  // namespace synth
}  // namespace action_flow
