/**
 * @file pca.h
 * @brief Principal component analysis of frame descriptors (the paper's "SUMFLOW after PCA").
 */
#pragma once

#include <Eigen/Core>

namespace action_flow
{
/**
 * @brief A PCA basis: mean and principal directions. Default-constructed it is empty and
 *        project() returns its input unchanged.
 */
class Pca
{
public:
  Pca() = default;
  /** @brief A basis given explicitly (columns orthonormal); used when loading a model. */
  Pca(Eigen::VectorXf mean, Eigen::MatrixXf basis, Eigen::VectorXf variances);

  /**
   * @brief Fits on @p samples (one descriptor per row), keeping the fewest leading components
   *        that explain at least @p variance of the total variance (at least one component).
   * @throws std::invalid_argument with fewer than 2 samples, non-finite values or variance not in (0,1]
   */
  static Pca fit(const Eigen::MatrixXf& samples, double variance = 0.99);

  bool empty() const { return basis_.size() == 0; }
  int inputSize() const { return static_cast<int>(basis_.rows()); }
  int outputSize() const { return static_cast<int>(basis_.cols()); }
  /** @brief Projects @p x on the basis: basis^T (x - mean). Returns x itself when empty. */
  Eigen::VectorXf project(const Eigen::VectorXf& x) const;

  const Eigen::VectorXf& mean() const { return mean_; }
  /** @brief Principal directions as columns, by decreasing variance. */
  const Eigen::MatrixXf& basis() const { return basis_; }
  /** @brief Variance along each kept direction. */
  const Eigen::VectorXf& variances() const { return variances_; }
  /** @brief Fraction of the training variance the kept components explain (1 when empty). */
  double explained() const { return explained_; }

private:
  Eigen::VectorXf mean_;
  Eigen::MatrixXf basis_;
  Eigen::VectorXf variances_;
  double explained_ = 1.0;
};

}  // namespace action_flow
