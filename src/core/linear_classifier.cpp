#include <action_flow/linear_classifier.h>

#include <linear.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>

namespace action_flow
{
namespace
{
void quiet(const char*)
{
}
}  // namespace

LinearClassifier::LinearClassifier(std::vector<std::string> classes, Eigen::MatrixXf weights, Eigen::VectorXf bias,
                                   Eigen::VectorXf mean, Eigen::VectorXf scale)
  : classes_(std::move(classes)), weights_(std::move(weights)), bias_(std::move(bias)), mean_(std::move(mean)),
    scale_(std::move(scale))
{
  const Eigen::Index k = static_cast<Eigen::Index>(classes_.size());
  if (weights_.rows() != k || bias_.size() != k || weights_.cols() != mean_.size() || scale_.size() != mean_.size())
    throw std::invalid_argument("LinearClassifier: sizes of classes, weights, bias, mean and scale disagree");
  if (!weights_.allFinite() || !bias_.allFinite() || !mean_.allFinite() || !scale_.allFinite())
    throw std::invalid_argument("LinearClassifier: non-finite weights");
}

LinearClassifier LinearClassifier::train(const Eigen::MatrixXf& x, const std::vector<std::string>& labels, double c,
                                         bool in_span)
{
  return train(x, labels, std::vector<double>{ c }, in_span).front();
}

std::vector<LinearClassifier> LinearClassifier::train(const Eigen::MatrixXf& x, const std::vector<std::string>& labels,
                                                      const std::vector<double>& cs, bool in_span)
{
  if (x.rows() == 0 || x.rows() != static_cast<Eigen::Index>(labels.size()))
    throw std::invalid_argument("LinearClassifier::train: needs one label per row, and at least one row");
  if (!x.allFinite())
    throw std::invalid_argument("LinearClassifier::train: non-finite training values");
  for (double c : cs)
    if (!(c > 0.0) || !std::isfinite(c))
      throw std::invalid_argument("LinearClassifier::train: C must be positive");
  if (cs.empty())
    throw std::invalid_argument("LinearClassifier::train: no C given");
  std::vector<std::string> classes = labels;
  std::sort(classes.begin(), classes.end());
  classes.erase(std::unique(classes.begin(), classes.end()), classes.end());
  if (classes.size() < 2)
    throw std::invalid_argument("LinearClassifier::train: needs at least 2 labels");
  std::map<std::string, int> class_index;
  for (std::size_t i = 0; i < classes.size(); ++i)
    class_index[classes[i]] = static_cast<int>(i);

  // Centre every column and divide all by one spread (the root mean square of the centred values).
  // Not a spread per column: that would blow the many nearly constant columns (cells the body
  // rarely reaches) up to the weight of the informative ones.
  const Eigen::Index n = x.rows(), d = x.cols();
  const Eigen::VectorXf mean = x.colwise().mean().transpose();
  const double rms = std::sqrt((x.rowwise() - mean.transpose()).squaredNorm() / static_cast<double>(n * d));
  const Eigen::VectorXf scale = Eigen::VectorXf::Constant(d, rms > 1e-12 ? static_cast<float>(1.0 / rms) : 1.0f);

  // With fewer rows than columns (the usual case: a few hundred sequences of a few thousand values)
  // the problem is solved exactly in the rows' own span: with X = Z V' (V orthonormal, from the
  // eigenvectors of X X'), the weights w = V u give the same scores as u on Z and the same norm,
  // and weights outside the span only add to the norm. liblinear then works on n columns, not d.
  const Eigen::MatrixXd xs = ((x.rowwise() - mean.transpose()) * scale[0]).cast<double>();
  Eigen::MatrixXd z = xs, basis;  // rows in the span's coordinates; w = basis * u
  if (in_span && n < d)
  {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(xs * xs.transpose());
    const double top = eig.eigenvalues().maxCoeff();
    std::vector<Eigen::Index> keep;
    for (Eigen::Index i = 0; i < n; ++i)
      if (eig.eigenvalues()[i] > 1e-10 * top && top > 0.0)
        keep.push_back(i);
    const Eigen::VectorXd root = eig.eigenvalues()(keep).cwiseSqrt();
    z = eig.eigenvectors()(Eigen::all, keep) * root.asDiagonal();
    basis = xs.transpose() * eig.eigenvectors()(Eigen::all, keep) * root.cwiseInverse().asDiagonal();
  }
  const Eigen::Index dz = z.cols();

  // liblinear's problem: every value of every row (dense), 1-based feature indices, a bias
  // feature, and a terminator per row.
  std::vector<feature_node> nodes(static_cast<std::size_t>(n * (dz + 2)));
  std::vector<feature_node*> rows(static_cast<std::size_t>(n));
  std::vector<double> y(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i)
  {
    feature_node* row = &nodes[static_cast<std::size_t>(i * (dz + 2))];
    rows[i] = row;
    for (Eigen::Index j = 0; j < dz; ++j)
      row[j] = { static_cast<int>(j + 1), z(i, j) };
    row[dz] = { static_cast<int>(dz + 1), 1.0 };  // the bias feature
    row[dz + 1] = { -1, 0.0 };
    y[i] = class_index[labels[i]];
  }
  problem prob{};
  prob.l = static_cast<int>(n);
  prob.n = static_cast<int>(dz + 1);
  prob.y = y.data();
  prob.x = rows.data();
  prob.bias = -1;  // the bias column is already in the rows
  std::vector<LinearClassifier> out;
  for (double c : cs)
  {
    parameter param{};
    // The primal solver (trust-region Newton) is deterministic; liblinear's dual solvers draw from rand().
    param.solver_type = L2R_LR;
    param.eps = 0.01;
    param.C = c;
    set_print_string_function(&quiet);
    if (const char* error = check_parameter(&prob, &param))
      throw std::invalid_argument(std::string("LinearClassifier::train: liblinear: ") + error);
    std::unique_ptr<model, void (*)(model*)> trained(::train(&prob, &param), [](model* m) { free_and_destroy_model(&m); });

    // Read the weights back per label (get_decfun_* handle liblinear's two-label layout).
    const int k = get_nr_class(trained.get());
    std::vector<int> ids(static_cast<std::size_t>(k));
    get_labels(trained.get(), ids.data());
    Eigen::MatrixXd u(static_cast<Eigen::Index>(classes.size()), dz);
    Eigen::VectorXf b(static_cast<Eigen::Index>(classes.size()));
    for (int li = 0; li < k; ++li)
    {
      const int row = ids[li];
      for (Eigen::Index j = 0; j < dz; ++j)
        u(row, j) = get_decfun_coef(trained.get(), static_cast<int>(j + 1), li);
      b[row] = static_cast<float>(get_decfun_coef(trained.get(), static_cast<int>(dz + 1), li));
    }
    const Eigen::MatrixXf w = (basis.size() ? Eigen::MatrixXd(u * basis.transpose()) : u).cast<float>();
    out.push_back(LinearClassifier(classes, w, b, mean, scale));
  }
  return out;
}

Eigen::VectorXf LinearClassifier::probabilities(const Eigen::VectorXf& query) const
{
  if (empty())
    throw std::invalid_argument("LinearClassifier: not trained");
  if (query.size() != mean_.size() || !query.allFinite())
    throw std::invalid_argument("LinearClassifier: query of length " + std::to_string(query.size()) + ", expected " +
                                std::to_string(mean_.size()) + " finite values");
  const Eigen::VectorXf z = (query - mean_).cwiseProduct(scale_);
  const Eigen::ArrayXf score = (weights_ * z + bias_).array();
  Eigen::VectorXf p = (1.0f / (1.0f + (-score).exp())).matrix();
  const float sum = p.sum();
  return sum > 0.0f ? Eigen::VectorXf(p / sum) : Eigen::VectorXf(Eigen::VectorXf::Constant(p.size(), 1.0f / p.size()));
}

Classification LinearClassifier::classify(const Eigen::VectorXf& query) const
{
  const Eigen::VectorXf p = probabilities(query);
  Eigen::Index best = 0;
  p.maxCoeff(&best);
  float second = 0.0f;
  for (Eigen::Index i = 0; i < p.size(); ++i)
    if (i != best)
      second = std::max(second, p[i]);
  Classification c;
  c.label = classes_[best];
  c.confidence = p[best];
  c.margin = p[best] - second;
  c.distance = 1.0f - p[best];
  return c;
}

}  // namespace action_flow
