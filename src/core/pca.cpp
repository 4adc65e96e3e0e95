#include <action_flow/pca.h>

#include <Eigen/Eigenvalues>

#include <stdexcept>
#include <utility>

namespace action_flow
{
Pca::Pca(Eigen::VectorXf mean, Eigen::MatrixXf basis, Eigen::VectorXf variances)
  : mean_(std::move(mean)), basis_(std::move(basis)), variances_(std::move(variances))
{
  if (basis_.rows() != mean_.size() || variances_.size() != basis_.cols())
    throw std::invalid_argument("Pca: mean, basis and variances have inconsistent sizes");
}

Pca Pca::fit(const Eigen::MatrixXf& samples, double variance)
{
  if (samples.rows() < 2 || samples.cols() < 1)
    throw std::invalid_argument("Pca: need at least 2 samples");
  if (!(variance > 0.0 && variance <= 1.0))
    throw std::invalid_argument("Pca: variance to keep must be in (0, 1]");
  if (!samples.allFinite())
    throw std::invalid_argument("Pca: samples contain NaN or inf");
  // Double precision for the covariance: 5760 x 540 sums in float lose the small components.
  const Eigen::MatrixXd x = samples.cast<double>();
  const Eigen::RowVectorXd mean = x.colwise().mean();
  const Eigen::MatrixXd centred = x.rowwise() - mean;
  const Eigen::MatrixXd cov = centred.transpose() * centred / static_cast<double>(x.rows() - 1);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov);
  const Eigen::VectorXd values = eig.eigenvalues().reverse().cwiseMax(0.0);  // decreasing
  const Eigen::MatrixXd vectors = eig.eigenvectors().rowwise().reverse();
  const double total = values.sum();
  int keep = 1;
  double acc = values[0];
  while (keep < values.size() && total > 0.0 && acc < variance * total)
    acc += values[keep++];
  Pca p(mean.transpose().cast<float>(), vectors.leftCols(keep).cast<float>(), values.head(keep).cast<float>());
  p.explained_ = total > 0.0 ? acc / total : 1.0;
  return p;
}

Eigen::VectorXf Pca::project(const Eigen::VectorXf& x) const
{
  if (empty())
    return x;
  if (x.size() != inputSize())
    throw std::invalid_argument("Pca: descriptor length " + std::to_string(x.size()) + " does not match the basis (" +
                                std::to_string(inputSize()) + ")");
  return basis_.transpose() * (x - mean_);
}

}  // namespace action_flow
