#include "tracker_assignment.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace action_flow
{
namespace
{
// Hungarian method with potentials (shortest augmenting paths), n rows <= m columns.
// a is 1-based: a[i][j], i in 1..n, j in 1..m. Returns the column of each row (1-based).
std::vector<int> hungarian(const std::vector<std::vector<double>>& a, int n, int m)
{
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0);
  std::vector<int> p(m + 1, 0), way(m + 1, 0);
  for (int i = 1; i <= n; ++i)
  {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(m + 1, inf);
    std::vector<char> used(m + 1, 0);
    do
    {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j)
        if (!used[j])
        {
          const double cur = a[i0][j] - u[i0] - v[j];
          if (cur < minv[j])
          {
            minv[j] = cur;
            way[j] = j0;
          }
          if (minv[j] < delta)
          {
            delta = minv[j];
            j1 = j;
          }
        }
      for (int j = 0; j <= m; ++j)
        if (used[j])
        {
          u[p[j]] += delta;
          v[j] -= delta;
        }
        else
          minv[j] -= delta;
      j0 = j1;
    } while (p[j0] != 0);
    do
    {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0);
  }
  std::vector<int> row_to_col(n + 1, 0);
  for (int j = 1; j <= m; ++j)
    if (p[j])
      row_to_col[p[j]] = j;
  return row_to_col;
}
}  // namespace

std::vector<int> solveAssignment(const Eigen::MatrixXf& cost, float gate)
{
  const int rows = static_cast<int>(cost.rows()), cols = static_cast<int>(cost.cols());
  std::vector<int> result(rows, -1);
  if (rows == 0 || cols == 0)
    return result;
  if (!cost.allFinite())
    throw std::invalid_argument("solveAssignment: non-finite cost");
  const bool transpose = rows > cols;
  const int n = transpose ? cols : rows, m = transpose ? rows : cols;
  // Out-of-gate pairs cost more than any set of in-gate pairs could, so the solver first
  // maximises the number of in-gate pairs, then minimises their total cost.
  double worst = 0.0;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j)
      if (cost(i, j) <= gate)
        worst = std::max(worst, std::abs(static_cast<double>(cost(i, j))));
  const double prohibitive = (worst + 1.0) * (n + 1);
  std::vector<std::vector<double>> a(n + 1, std::vector<double>(m + 1, 0.0));
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j)
    {
      const double c = cost(i, j) <= gate ? cost(i, j) : prohibitive;
      if (transpose)
        a[j + 1][i + 1] = c;
      else
        a[i + 1][j + 1] = c;
    }
  const std::vector<int> sol = hungarian(a, n, m);
  for (int k = 1; k <= n; ++k)
  {
    const int r = transpose ? sol[k] - 1 : k - 1;
    const int c = transpose ? k - 1 : sol[k] - 1;
    if (r >= 0 && c >= 0 && cost(r, c) <= gate)
      result[r] = c;
  }
  return result;
}

ConstantVelocityFilter::ConstantVelocityFilter(const Eigen::Vector3f& position, float accel_noise,
                                               float position_noise, float initial_speed_sigma)
  : q_(accel_noise * accel_noise), r_(position_noise * position_noise)
{
  x_.setZero();
  x_.head<3>() = position;
  P_.setZero();
  P_.topLeftCorner<3, 3>() = Eigen::Matrix3f::Identity() * r_;
  P_.bottomRightCorner<3, 3>() = Eigen::Matrix3f::Identity() * initial_speed_sigma * initial_speed_sigma;
}

void ConstantVelocityFilter::predict(double dt_in)
{
  if (!(dt_in > 0.0))
    return;
  const float dt = static_cast<float>(dt_in);
  Eigen::Matrix<float, 6, 6> F = Eigen::Matrix<float, 6, 6>::Identity();
  F.topRightCorner<3, 3>() = Eigen::Matrix3f::Identity() * dt;
  // Discrete white-noise acceleration model.
  Eigen::Matrix<float, 6, 6> Q = Eigen::Matrix<float, 6, 6>::Zero();
  const Eigen::Matrix3f I = Eigen::Matrix3f::Identity();
  Q.topLeftCorner<3, 3>() = I * (dt * dt * dt / 3.0f) * q_;
  Q.topRightCorner<3, 3>() = I * (dt * dt / 2.0f) * q_;
  Q.bottomLeftCorner<3, 3>() = I * (dt * dt / 2.0f) * q_;
  Q.bottomRightCorner<3, 3>() = I * dt * q_;
  x_ = F * x_;
  P_ = F * P_ * F.transpose() + Q;
}

void ConstantVelocityFilter::correct(const Eigen::Vector3f& measured)
{
  // H = [I 0]: the innovation covariance is the position block plus R.
  const Eigen::Matrix3f S = P_.topLeftCorner<3, 3>() + Eigen::Matrix3f::Identity() * r_;
  const Eigen::Matrix<float, 6, 3> K = P_.leftCols<3>() * S.inverse();
  x_ += K * (measured - x_.head<3>());
  Eigen::Matrix<float, 6, 6> IKH = Eigen::Matrix<float, 6, 6>::Identity();
  IKH.leftCols<3>() -= K;
  P_ = IKH * P_;
  P_ = 0.5f * (P_ + P_.transpose()).eval();
}

float ConstantVelocityFilter::positionSigma() const
{
  return std::sqrt(P_.topLeftCorner<3, 3>().diagonal().maxCoeff());
}

}  // namespace action_flow
