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
// Each solve starts from 0: started from the previous C's solution (liblinear's init_sol) they
// stop elsewhere within the tolerance, and the cross-validation chose another C on MSR Action3D.
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

void checkCs(const std::vector<double>& cs)
{
  for (double c : cs)
    if (!(c > 0.0) || !std::isfinite(c))
      throw std::invalid_argument("LinearClassifier::train: C must be positive");
  if (cs.empty())
    throw std::invalid_argument("LinearClassifier::train: no C given");
}

// The sorted labels, and each row's index into them; @throws with fewer than 2 labels.
std::vector<std::string> classesOf(const std::vector<std::string>& labels, std::vector<int>& class_of_row)
{
  std::vector<std::string> classes = labels;
  std::sort(classes.begin(), classes.end());
  classes.erase(std::unique(classes.begin(), classes.end()), classes.end());
  if (classes.size() < 2)
    throw std::invalid_argument("LinearClassifier::train: needs at least 2 labels");
  class_of_row.clear();
  for (const auto& l : labels)
    class_of_row.push_back(static_cast<int>(std::lower_bound(classes.begin(), classes.end(), l) - classes.begin()));
  return classes;
}

// A fit on a subset T of a GramRows' rows, in the coordinates of the centred rows' span. With the
// rows centred on T's mean and scaled by s, X = Z V' (V orthonormal): from the centred Gram matrix
// s^2 Gc = E L E', Z = E L^(1/2) and V = X' E L^(-1/2). Weights w = V u give the same scores as u
// on Z and the same norm, and weights outside the span only add to the norm, so liblinear works on
// n columns instead of d, exactly. A row t's coordinates are L^(-1/2) E' k_t, with k_t its centred,
// scaled inner products with T's rows, all read off the Gram matrix.
struct SpanFit
{
  std::vector<std::string> classes;
  Eigen::VectorXd row_mean;  // per row of T: its mean (shifted) inner product with T's rows
  double all_mean = 0.0;     // the mean of those
  double scale = 1.0;        // 1 / the root mean square of T's centred values
  Eigen::MatrixXd project;   // E L^(-1/2): a row's centred, scaled inner products -> its coordinates
  std::vector<Eigen::MatrixXd> u;  // per C: classes x span
  std::vector<Eigen::VectorXf> b;  // per C: biases

  SpanFit(const GramRows& g, const std::vector<Eigen::Index>& rows, const std::vector<std::string>& labels,
          const std::vector<double>& cs)
  {
    if (rows.empty() || rows.size() != labels.size())
      throw std::invalid_argument("LinearClassifier::train: needs one label per row, and at least one row");
    for (Eigen::Index r : rows)
      if (r < 0 || r >= g.rows())
        throw std::invalid_argument("LinearClassifier::train: row " + std::to_string(r) + " outside the rows given");
    checkCs(cs);
    std::vector<int> class_of_row;
    classes = classesOf(labels, class_of_row);
    const Eigen::Index n = static_cast<Eigen::Index>(rows.size()), d = g.x().cols();
    const Eigen::MatrixXd gt = g.gram()(rows, rows);
    row_mean = gt.rowwise().mean();
    all_mean = row_mean.mean();
    Eigen::MatrixXd centred = gt;
    centred.colwise() -= row_mean;
    centred.rowwise() -= row_mean.transpose();
    centred.array() += all_mean;
    // Centre every column and divide all by one spread (the root mean square of the centred values).
    // Not a spread per column: that would blow the many nearly constant columns (cells the body
    // rarely reaches) up to the weight of the informative ones.
    const double rms = std::sqrt(std::max(0.0, centred.trace()) / static_cast<double>(n * d));
    scale = rms > 1e-12 ? 1.0 / rms : 1.0;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(centred * (scale * scale));
    const double top = eig.eigenvalues().maxCoeff();
    std::vector<Eigen::Index> keep;
    for (Eigen::Index i = 0; i < n; ++i)
      if (eig.eigenvalues()[i] > 1e-10 * top && top > 0.0)
        keep.push_back(i);
    const Eigen::VectorXd root = eig.eigenvalues()(keep).cwiseSqrt();
    project = eig.eigenvectors()(Eigen::all, keep) * root.cwiseInverse().asDiagonal();
    LiblinearProblem problem(eig.eigenvectors()(Eigen::all, keep) * root.asDiagonal(), class_of_row);
    for (double c : cs)
    {
      u.emplace_back();
      b.emplace_back();
      solve(problem.prob, c, classes.size(), u.back(), b.back());
    }
  }

  // Each C's scores (rows x classes) of rows @p queries of @p g.
  std::vector<Eigen::MatrixXf> scores(const GramRows& g, const std::vector<Eigen::Index>& rows,
                                      const std::vector<Eigen::Index>& queries) const
  {
    Eigen::MatrixXd k = g.gram()(rows, queries);
    const Eigen::RowVectorXd query_mean = k.colwise().mean();
    k.colwise() -= row_mean;
    k.rowwise() -= query_mean;
    k.array() += all_mean;
    const Eigen::MatrixXd z = project.transpose() * (k * (scale * scale));
    std::vector<Eigen::MatrixXf> out;
    for (std::size_t i = 0; i < u.size(); ++i)
      out.push_back(((u[i] * z).colwise() + b[i].cast<double>()).transpose().cast<float>());
    return out;
  }
};
}  // namespace

GramRows::GramRows(Eigen::MatrixXf x) : x_(std::move(x))
{
  if (!x_.allFinite())
    throw std::invalid_argument("LinearClassifier::train: non-finite training values");
  // Less the rows' mean (the Gram matrix of any shift gives the same centred products; this one
  // keeps them well conditioned), in column blocks: the double copy of all rows at once can take
  // hundreds of megabytes.
  const Eigen::RowVectorXf mean = x_.colwise().mean();
  const Eigen::Index n = x_.rows(), block = 2048;
  gram_ = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index c0 = 0; c0 < x_.cols(); c0 += block)
  {
    const Eigen::Index w = std::min(block, x_.cols() - c0);
    const Eigen::MatrixXd part = (x_.middleCols(c0, w).rowwise() - mean.segment(c0, w)).cast<double>();
    gram_.selfadjointView<Eigen::Lower>().rankUpdate(part);
  }
  gram_ = gram_.selfadjointView<Eigen::Lower>();
}

std::vector<LinearClassifier> LinearClassifier::train(const GramRows& g, const std::vector<Eigen::Index>& rows,
                                                      const std::vector<std::string>& labels,
                                                      const std::vector<double>& cs)
{
  const SpanFit fit(g, rows, labels, cs);
  // w = V u = s X' E L^(-1/2) u: the rows, centred on their mean, weighted by a = u L^(-1/2) E'.
  const Eigen::VectorXf mean = g.x()(rows, Eigen::all).colwise().mean().transpose();
  const Eigen::MatrixXf centred = g.x()(rows, Eigen::all).rowwise() - mean.transpose();
  const Eigen::VectorXf scale = Eigen::VectorXf::Constant(g.x().cols(), static_cast<float>(fit.scale));
  std::vector<LinearClassifier> out;
  for (std::size_t i = 0; i < cs.size(); ++i)
  {
    const Eigen::MatrixXf a = (fit.u[i] * fit.project.transpose() * fit.scale).cast<float>();
    out.push_back(LinearClassifier(fit.classes, a * centred, fit.b[i], mean, scale));
  }
  return out;
}

std::vector<Eigen::MatrixXf> LinearClassifier::heldOutScores(const GramRows& g, const std::vector<Eigen::Index>& rows,
                                                             const std::vector<std::string>& labels,
                                                             const std::vector<Eigen::Index>& queries,
                                                             const std::vector<double>& cs,
                                                             std::vector<std::string>& classes)
{
  for (Eigen::Index q : queries)
    if (q < 0 || q >= g.rows())
      throw std::invalid_argument("LinearClassifier::heldOutScores: row " + std::to_string(q) + " outside the rows given");
  const SpanFit fit(g, rows, labels, cs);
  classes = fit.classes;
  return fit.scores(g, rows, queries);
}

std::vector<LinearClassifier> LinearClassifier::train(const Eigen::MatrixXf& x, const std::vector<std::string>& labels,
                                                      const std::vector<double>& cs, bool in_span)
{
  if (x.rows() == 0 || x.rows() != static_cast<Eigen::Index>(labels.size()))
    throw std::invalid_argument("LinearClassifier::train: needs one label per row, and at least one row");
  if (!x.allFinite())
    throw std::invalid_argument("LinearClassifier::train: non-finite training values");
  checkCs(cs);
  std::vector<int> class_of_row;
  const std::vector<std::string> classes = classesOf(labels, class_of_row);
  const Eigen::Index n = x.rows(), d = x.cols();
  if (in_span && n < d)
  {
    std::vector<Eigen::Index> all(static_cast<std::size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i)
      all[static_cast<std::size_t>(i)] = i;
    return train(GramRows(x), all, labels, cs);
  }
  // All columns as they are, standardised as SpanFit does.
  const Eigen::VectorXf mean = x.colwise().mean().transpose();
  const double rms = std::sqrt((x.rowwise() - mean.transpose()).squaredNorm() / static_cast<double>(n * d));
  const Eigen::VectorXf scale = Eigen::VectorXf::Constant(d, rms > 1e-12 ? static_cast<float>(1.0 / rms) : 1.0f);
  const Eigen::MatrixXd xs = ((x.rowwise() - mean.transpose()) * scale[0]).cast<double>();
  LiblinearProblem problem(xs, class_of_row);
  std::vector<LinearClassifier> out;
  for (double c : cs)
  {
    Eigen::MatrixXd u;
    Eigen::VectorXf b;
    solve(problem.prob, c, classes.size(), u, b);
    out.push_back(LinearClassifier(classes, u.cast<float>(), b, mean, scale));
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
