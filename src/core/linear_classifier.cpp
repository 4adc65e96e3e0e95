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
                                   Eigen::VectorXf mean, Eigen::VectorXf scale, double temperature)
  : classes_(std::move(classes)), weights_(std::move(weights)), bias_(std::move(bias)), mean_(std::move(mean)),
    scale_(std::move(scale)), temperature_(temperature)
{
  const Eigen::Index k = static_cast<Eigen::Index>(classes_.size());
  if (weights_.rows() != k || bias_.size() != k || weights_.cols() != mean_.size() || scale_.size() != mean_.size())
    throw std::invalid_argument("LinearClassifier: sizes of classes, weights, bias, mean and scale disagree");
  if (!weights_.allFinite() || !bias_.allFinite() || !mean_.allFinite() || !scale_.allFinite())
    throw std::invalid_argument("LinearClassifier: non-finite weights");
  if (!(temperature_ >= 0.0) || !std::isfinite(temperature_))
    throw std::invalid_argument("LinearClassifier: the temperature must be a finite value >= 0");
}

LinearClassifier LinearClassifier::calibrated(double temperature) const
{
  return LinearClassifier(classes_, weights_, bias_, mean_, scale_, temperature);
}

LinearClassifier LinearClassifier::train(const Eigen::MatrixXf& x, const std::vector<std::string>& labels, double c,
                                         bool in_span)
{
  return train(x, labels, std::vector<double>{ c }, in_span).front();
}

namespace
{
// The rows in the coordinates of their own span: with X = Z V' (V orthonormal, from the
// eigenvectors of X X'), the weights w = V u give the same scores as u on Z and the same norm, and
// weights outside the span only add to the norm; so with fewer rows than columns (a few hundred
// sequences of a few thousand values) liblinear can work on n columns, not d, exactly.
// @p basis is V (empty when the rows are used as they are).
Eigen::MatrixXd inSpan(const Eigen::MatrixXd& xs, Eigen::MatrixXd& basis)
{
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(xs * xs.transpose());
  const double top = eig.eigenvalues().maxCoeff();
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < xs.rows(); ++i)
    if (eig.eigenvalues()[i] > 1e-10 * top && top > 0.0)
      keep.push_back(i);
  const Eigen::VectorXd root = eig.eigenvalues()(keep).cwiseSqrt();
  basis = xs.transpose() * eig.eigenvectors()(Eigen::all, keep) * root.cwiseInverse().asDiagonal();
  return eig.eigenvectors()(Eigen::all, keep) * root.asDiagonal();
}

// liblinear's problem over the rows of @p z: every value (dense), 1-based feature indices, a
// bias feature, and a terminator per row. The vectors own the memory the problem points into.
struct LiblinearProblem
{
  std::vector<feature_node> nodes;
  std::vector<feature_node*> rows;
  std::vector<double> y;
  problem prob{};

  LiblinearProblem(const Eigen::MatrixXd& z, const std::vector<int>& classes_of_rows)
    : nodes(static_cast<std::size_t>(z.rows() * (z.cols() + 2))), rows(z.rows()), y(z.rows())
  {
    const Eigen::Index n = z.rows(), dz = z.cols();
    for (Eigen::Index i = 0; i < n; ++i)
    {
      feature_node* row = &nodes[static_cast<std::size_t>(i * (dz + 2))];
      rows[i] = row;
      for (Eigen::Index j = 0; j < dz; ++j)
        row[j] = { static_cast<int>(j + 1), z(i, j) };
      row[dz] = { static_cast<int>(dz + 1), 1.0 };  // the bias feature
      row[dz + 1] = { -1, 0.0 };
      y[i] = classes_of_rows[i];
    }
    prob.l = static_cast<int>(n);
    prob.n = static_cast<int>(dz + 1);
    prob.y = y.data();
    prob.x = rows.data();
    prob.bias = -1;  // the bias column is already in the rows
  }
};

// One liblinear solve at @p c: the weights per class (in the span's coordinates) and the biases.
void solve(problem& prob, double c, std::size_t classes, Eigen::MatrixXd& u, Eigen::VectorXf& b)
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
  const int dz = prob.n - 1;
  std::vector<int> ids(static_cast<std::size_t>(k));
  get_labels(trained.get(), ids.data());
  u.resize(static_cast<Eigen::Index>(classes), dz);
  b.resize(static_cast<Eigen::Index>(classes));
  for (int li = 0; li < k; ++li)
  {
    const int row = ids[li];
    for (int j = 0; j < dz; ++j)
      u(row, j) = get_decfun_coef(trained.get(), j + 1, li);
    b[row] = static_cast<float>(get_decfun_coef(trained.get(), dz + 1, li));
  }
}
}  // namespace

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
  std::vector<int> class_of_row;
  for (const auto& l : labels)
    class_of_row.push_back(static_cast<int>(std::lower_bound(classes.begin(), classes.end(), l) - classes.begin()));

  // Centre every column and divide all by one spread (the root mean square of the centred values).
  // Not a spread per column: that would blow the many nearly constant columns (cells the body
  // rarely reaches) up to the weight of the informative ones.
  const Eigen::Index n = x.rows(), d = x.cols();
  const Eigen::VectorXf mean = x.colwise().mean().transpose();
  const double rms = std::sqrt((x.rowwise() - mean.transpose()).squaredNorm() / static_cast<double>(n * d));
  const Eigen::VectorXf scale = Eigen::VectorXf::Constant(d, rms > 1e-12 ? static_cast<float>(1.0 / rms) : 1.0f);
  const Eigen::MatrixXd xs = ((x.rowwise() - mean.transpose()) * scale[0]).cast<double>();

  Eigen::MatrixXd basis;  // w = basis * u; empty: the columns as they are
  LiblinearProblem problem(in_span && n < d ? inSpan(xs, basis) : xs, class_of_row);
  std::vector<LinearClassifier> out;
  for (double c : cs)
  {
    Eigen::MatrixXd u;
    Eigen::VectorXf b;
    solve(problem.prob, c, classes.size(), u, b);
    const Eigen::MatrixXf w = (basis.size() ? Eigen::MatrixXd(u * basis.transpose()) : u).cast<float>();
    out.push_back(LinearClassifier(classes, w, b, mean, scale));
  }
  return out;
}

Eigen::VectorXf LinearClassifier::scores(const Eigen::VectorXf& query) const
{
  if (empty())
    throw std::invalid_argument("LinearClassifier: not trained");
  if (query.size() != mean_.size() || !query.allFinite())
    throw std::invalid_argument("LinearClassifier: query of length " + std::to_string(query.size()) + ", expected " +
                                std::to_string(mean_.size()) + " finite values");
  const Eigen::VectorXf z = (query - mean_).cwiseProduct(scale_);
  return weights_ * z + bias_;
}

namespace
{
// softmax(s / T), computed from the largest score down so that no exp overflows.
Eigen::VectorXd softmax(const Eigen::VectorXd& s, double temperature)
{
  const Eigen::ArrayXd e = ((s.array() - s.maxCoeff()) / temperature).exp();
  return (e / e.sum()).matrix();
}
}  // namespace

Eigen::VectorXf LinearClassifier::probabilities(const Eigen::VectorXf& query) const
{
  const Eigen::ArrayXf score = scores(query).array();
  if (temperature_ > 0.0)
    return softmax(score.matrix().cast<double>(), temperature_).cast<float>();
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

double fitTemperature(const Eigen::MatrixXf& scores, const std::vector<int>& truth)
{
  if (scores.rows() == 0 || scores.rows() != static_cast<Eigen::Index>(truth.size()))
    throw std::invalid_argument("fitTemperature: needs one true label per row of scores, and at least one row");
  if (!scores.allFinite())
    throw std::invalid_argument("fitTemperature: non-finite scores");
  for (int t : truth)
    if (t < 0 || t >= scores.cols())
      throw std::invalid_argument("fitTemperature: true label column " + std::to_string(t) + " outside 0.." +
                                  std::to_string(scores.cols() - 1));
  const Eigen::MatrixXd s = scores.cast<double>();
  // Negative log-likelihood at log T = @p u.
  const auto nll = [&](double u) {
    const double t = std::exp(u);
    double sum = 0.0;
    for (Eigen::Index i = 0; i < s.rows(); ++i)
    {
      const double top = s.row(i).maxCoeff();
      sum += top / t + std::log(((s.row(i).array() - top) / t).exp().sum()) - s(i, truth[i]) / t;
    }
    return sum;
  };
  const double golden = (std::sqrt(5.0) - 1.0) / 2.0;
  double lo = std::log(kMinTemperature), hi = std::log(kMaxTemperature);
  double a = hi - golden * (hi - lo), b = lo + golden * (hi - lo), fa = nll(a), fb = nll(b);
  while (hi - lo > 1e-6)
    if (fa <= fb)
    {
      hi = b;
      b = a;
      fb = fa;
      a = hi - golden * (hi - lo);
      fa = nll(a);
    }
    else
    {
      lo = a;
      a = b;
      fa = fb;
      b = lo + golden * (hi - lo);
      fb = nll(b);
    }
  return std::exp((lo + hi) / 2.0);
}

}  // namespace action_flow
