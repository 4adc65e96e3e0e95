/**
 * @file posture_flow.h
 * @brief The default recognizer's frame descriptor: where the body is (posture) and how it
 *        moves (flow split by direction), in a coarse-to-fine grid around the person.
 *
 * The paper's SUMFLOW sees only motion: a still arm raised to point and a still arm hanging down
 * give the same all-zero descriptor. This descriptor adds the body's shape and keeps the flow's
 * direction and speed without L2-normalising them away:
 *
 * - The grid is the paper's (GridParams: 2.0 x 2.3 x 1.8 m for a 1.75 m person, on the ground
 *   under the person, axes x right, y up, z toward the camera), cut at three levels: 1, 2 and
 *   4 parts per axis (the finest level is GridParams' parts), 1 + 8 + 64 = 73 cells.
 * - Per cell, 7 values: the share of the person's points inside it (posture), then the flow
 *   vectors' components split by sign, (+x, -x, +y, -y, +z, -z), each summed over the cell and
 *   divided by the person's point count: a 6-bin direction histogram weighted by speed, in m/s
 *   per body point, so it does not depend on how many points the person has (distance).
 * - Levels are stored coarse to fine; cells x fastest, then y, then z, as in GridDescriptor.
 * - Then the body's geometry, 24 values (kGeometryValues) in the grid's coordinates divided by its
 *   size (x and z centred on the person, y from the ground; so 0.5 is the grid's edge): the centroid
 *   of the body's points (3); the mean position of the kExtremePoints points furthest along each of
 *   +x, -x, +y, +z and -z (15: where the hands, the raised arm, the kicking foot are, which the
 *   cells' shares only place to half a metre); and of the flow, per body point, the speed-weighted
 *   offset of the moving points from the centroid (3: where the motion is) and their angular
 *   momentum about the centroid, r x v (3: a circle and its direction, a stroke's slant).
 *
 * Every frame with a person gives a descriptor, with or without flow (a still person has a
 * posture). The full layout is always computed (535 values); which parts a model uses is chosen
 * later by PyramidParams (posture_flow_sequence.h), so the ablations share one computation.
 */
#pragma once

#include <action_flow/grid_descriptor.h>
#include <action_flow/types.h>

#include <Eigen/Core>
#include <array>

namespace action_flow
{
/** @brief Values per cell: posture share, then +x, -x, +y, -y, +z, -z flow. */
constexpr int kPostureFlowValuesPerCell = 7;
/** @brief Values of the body-geometry block after the cells (see the file comment). */
constexpr int kGeometryValues = 24;
/** @brief Points averaged into each extreme of the geometry block. */
constexpr int kExtremePoints = 8;

class PostureFlowDescriptor
{
public:
  /** Levels: the finest is params' parts per axis, then half of it, then one (at least 1 part each). */
  static constexpr int kLevels = 3;

  /** @throws std::invalid_argument on non-positive parts or sizes (as GridDescriptor). */
  explicit PostureFlowDescriptor(const GridParams& params = GridParams());

  const GridParams& params() const { return grid_.params(); }
  /** @brief Parts per axis of level @p l (0 = coarsest). */
  std::array<int, 3> parts(int level) const;
  /** @brief Cells of level @p l. */
  int cells(int level) const;
  /** @brief Offset of level @p l's first value in the descriptor. */
  int offset(int level) const;
  /** @brief Offset of the body-geometry block (after the cells of every level). */
  int geometryOffset() const { return offset(kLevels); }
  /** @brief Length of the descriptor (535 for the default 4x4x4 grid: 511 cell values, 24 geometry). */
  int size() const { return geometryOffset() + kGeometryValues; }

  /**
   * @brief The descriptor of a person: @p cloud (the person's points) for the posture, @p flow
   *        (may be empty) for the motion, both placed by @p where. Non-finite points and points
   *        outside the grid are ignored; a cloud with no point in the grid gives all zeros.
   */
  Eigen::VectorXf compute(const Cloud& cloud, const FlowVectors& flow, const PersonFrame& where) const;

  /**
   * @brief The descriptor of the same person mirrored left to right (x -> -x): cells swap across
   *        the person's centre and +x and -x flow swap; in the geometry block x coordinates change
   *        sign, the +x and -x extremes swap and so do the signs of the angular momentum's y and z
   *        (a pseudovector). Exact for this grid, so a mirrored actor
   *        costs no rendering (training-time augmentation).
   * @throws std::invalid_argument on a descriptor of the wrong length
   */
  Eigen::VectorXf mirrored(const Eigen::VectorXf& descriptor) const;

  /**
   * @brief How much the body's shape changed between two descriptors: the L1 distance of the
   *        finest level's posture shares (0: the same shape; 2: no cell in common). The online mode
   *        cuts actions on its rate: on the recordings it separates gestures from stillness far
   *        better than the flow, whose per-point noise (about one voxel per frame) hides an arm.
   * @throws std::invalid_argument on descriptors of the wrong length
   */
  float postureChange(const Eigen::VectorXf& a, const Eigen::VectorXf& b) const;

private:
  /** The geometry block of the body's points @p uvw (grid-normalised, all inside) and the flow in it. */
  void computeGeometry(const std::vector<Eigen::Vector3f>& uvw, const std::vector<std::pair<Eigen::Vector3f, Eigen::Vector3f>>& moving,
                       Eigen::Ref<Eigen::VectorXf> out) const;

  GridDescriptor grid_;  // the finest level's geometry
};

}  // namespace action_flow
