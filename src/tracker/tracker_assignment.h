/**
 * @file tracker_assignment.h
 * @brief Data association for the people tracker: optimal gated assignment (Hungarian method)
 *        and a constant-velocity Kalman filter. ROS-free.
 */
#pragma once

#include <Eigen/Core>

#include <vector>

namespace action_flow
{
/**
 * @brief Minimum-cost assignment of rows to columns (Hungarian method, O(n^3)).
 * @param cost rows x cols matrix of finite costs (any shape)
 * @param gate pairs costing more than this are never assigned
 * @return for each row the column assigned to it, or -1. Costs above the gate are replaced by a
 *         prohibitive cost before solving, so the kept pairs (all within the gate) are a
 *         minimum-cost assignment among those with the most pairs within the gate
 * @throws std::invalid_argument on a non-finite cost
 */
std::vector<int> solveAssignment(const Eigen::MatrixXf& cost, float gate);

/**
 * @brief Constant-velocity Kalman filter on a 3D position (state: position, velocity).
 *
 * Process noise: white acceleration of spectral density accel_noise^2; measurement noise:
 * isotropic, position_noise (m, standard deviation).
 */
class ConstantVelocityFilter
{
public:
  ConstantVelocityFilter(const Eigen::Vector3f& position, float accel_noise = 2.0f, float position_noise = 0.05f,
                         float initial_speed_sigma = 1.0f);

  /** @brief Moves the state forward by @p dt seconds (dt <= 0 does nothing). */
  void predict(double dt);
  /** @brief Corrects the state with a measured position. */
  void correct(const Eigen::Vector3f& measured);

  Eigen::Vector3f position() const { return x_.head<3>(); }
  Eigen::Vector3f velocity() const { return x_.tail<3>(); }
  /** @brief Standard deviation of the position (square root of the covariance's largest position variance). */
  float positionSigma() const;

private:
  Eigen::Matrix<float, 6, 1> x_;
  Eigen::Matrix<float, 6, 6> P_;
  float q_, r_;
};

}  // namespace action_flow
