/**
 * @file grid_descriptor.h
 * @brief The per-frame gridded flow descriptor (the paper's MEANFLOW and SUMFLOW).
 */
#pragma once

#include <action_flow/param_table.h>
#include <action_flow/types.h>

#include <Eigen/Core>
#include <string>

namespace action_flow
{
/** @brief How the flow vectors inside one cube are combined. */
enum class FlowAggregation
{
  Sum,  ///< SUMFLOW: the sum of the vectors (the paper's better variant)
  Mean  ///< MEANFLOW: their mean
};

template <>
struct EnumNames<FlowAggregation>
{
  static constexpr const char* names[] = { "sumflow", "meanflow" };
};

/** @brief "sumflow" or "meanflow". */
std::string toString(FlowAggregation a);
/** @throws std::invalid_argument for any other name. */
FlowAggregation aggregationFromString(const std::string& name);

/** @brief Grid size and resolution. Sizes scale with the person's height. */
struct GridParams
{
  int parts_x = 4;  ///< cubes across (width)
  int parts_y = 4;  ///< cubes up (height)
  int parts_z = 4;  ///< cubes along the depth
  /** Grid size for a person of reference_height; the paper's 2.0 x 2.3 x 1.8 m for 1.75 m. */
  float width = 2.0f, height = 2.3f, depth = 1.8f;
  float reference_height = 1.75f;
  FlowAggregation aggregation = FlowAggregation::Sum;

  int cells() const { return parts_x * parts_y * parts_z; }

  template <class Self, class V>
  static void visit(Self& p, V&& v)
  {
    v("grid/parts_x", p.parts_x, "cubes across (width)", Shapes::Frames);
    v("grid/parts_y", p.parts_y, "cubes up (height)", Shapes::Frames);
    v("grid/parts_z", p.parts_z, "cubes along the depth", Shapes::Frames);
    v("grid/width", p.width, "m: the grid's width for a person of reference_height", Shapes::Frames);
    v("grid/height", p.height, "m: its height", Shapes::Frames);
    v("grid/depth", p.depth, "m: its depth", Shapes::Frames);
    v("grid/reference_height", p.reference_height, "m: the grid scales with height / this", Shapes::Frames);
    v("descriptor", p.aggregation, "paper only: how a cube's flow vectors are combined", Shapes::Frames);
  }
};

/**
 * @brief Where a person stands, which fixes the grid.
 *
 * The grid is centred on the person horizontally (origin = the centroid projected along "up"
 * onto the ground), its bottom face lies on the ground (the feet), and its axes are: x = width
 * (to the right in the camera image), y = up, z = depth (toward the camera, along the
 * horizontal part of the viewing ray); a right-handed frame.
 * Flow vectors are expressed in these axes, so a descriptor does not depend on where in the
 * room the person stands or on the camera tilt.
 */
struct PersonFrame
{
  Eigen::Vector3f origin = Eigen::Vector3f::Zero();  ///< on the ground, under the centroid
  Eigen::Matrix3f axes = Eigen::Matrix3f::Identity(); ///< columns: x (width), y (up), z (depth, toward the camera)
  float height = 1.75f;                              ///< the person's height (m)

  /**
   * @brief Builds the frame from the person's centroid, the ground plane and the viewing direction.
   * @param centroid person centroid
   * @param ground plane (a,b,c,d), a x + b y + c z + d = 0, normal (a,b,c) pointing up (need not be unit)
   * @param height person height above the ground (m)
   * @param view direction from the camera to the person (the depth axis is its horizontal part)
   * @throws std::invalid_argument on a degenerate plane or a view direction parallel to the normal
   */
  static PersonFrame fromGround(const Eigen::Vector3f& centroid, const Eigen::Vector4f& ground, float height,
                                const Eigen::Vector3f& view);

  /**
   * @brief The same frame turned about its up axis by @p angle (rad) so that z points where the
   *        person faces: z' = sin(angle) x + cos(angle) z (0 keeps the frame; positive turns z
   *        towards +x, the person's left when they face the camera).
   */
  PersonFrame turned(float angle) const;

  /** @brief Position of a point in grid coordinates (x across, y above the ground, z depth). */
  Eigen::Vector3f toLocal(const Eigen::Vector3f& p) const { return axes.transpose() * (p - origin); }
};

/**
 * @brief The frame descriptor: the flow vectors summed (or averaged) per cube of a grid around
 *        the person, concatenated cube by cube (x fastest, then y, then z; 3 values per cube)
 *        and L2-normalised. A frame with no flow in the grid gives all zeros.
 */
class GridDescriptor
{
public:
  /** @throws std::invalid_argument on non-positive parts or sizes. */
  explicit GridDescriptor(const GridParams& params = GridParams());

  const GridParams& params() const { return params_; }
  /** @brief Length of the descriptor: 3 values per cube. */
  int size() const { return 3 * params_.cells(); }

  /**
   * @brief Index of the cube holding a point given in grid coordinates, or -1 outside the grid.
   * @param person_height scales the grid (its size is params().width * height / reference_height, ...)
   */
  int cellOf(const Eigen::Vector3f& local, float person_height) const;

  /**
   * @brief Where a point given in grid coordinates lies in the grid, as fractions in [0,1) along
   *        x, y and z; false outside the grid. cellOf() cuts these into parts.
   */
  bool normalised(const Eigen::Vector3f& local, float person_height, Eigen::Vector3f& uvw) const;

  /** @brief Computes the descriptor of @p flow for a person at @p person. */
  Eigen::VectorXf compute(const FlowVectors& flow, const PersonFrame& person) const;

private:
  GridParams params_;
};

}  // namespace action_flow
