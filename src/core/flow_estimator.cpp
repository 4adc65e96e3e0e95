#include <action_flow/flow_estimator.h>

#include <algorithm>
#include <cstring>
#include <cstdint>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace action_flow
{
namespace
{
// Grid cell size relative to the mean spacing of the points in their bounding box.
constexpr double kCellScale = 0.8;
}  // namespace

Hsv rgbToHsv(std::uint8_t r8, std::uint8_t g8, std::uint8_t b8)
{
  const float r = r8 / 255.0f, g = g8 / 255.0f, b = b8 / 255.0f;
  const float max = std::max({ r, g, b });
  const float min = std::min({ r, g, b });
  const float delta = max - min;
  Hsv out{ 0.0f, max > 0.0f ? delta / max : 0.0f, max };
  if (delta > 0.0f)
  {
    float h;
    if (max == r)
      h = (g - b) / delta;
    else if (max == g)
      h = 2.0f + (b - r) / delta;
    else
      h = 4.0f + (r - g) / delta;
    h /= 6.0f;
    out.h = h < 0.0f ? h + 1.0f : h;
  }
  return out;
}

Eigen::Vector3f hsvCone(const Hsv& c)
{
  const float chroma = c.s * c.v, angle = 6.2831853f * c.h;
  return { chroma * std::cos(angle), chroma * std::sin(angle), c.v };
}

float hsvDistance(const Hsv& a, const Hsv& b)
{
  return (hsvCone(a) - hsvCone(b)).norm();
}

// ---- the neighbour index --------------------------------------------------------------------
//
// A uniform grid over the frame's bounding box, points sorted by cell (a counting sort), with
// coordinates and colours stored per axis in that order so that distances to a run of candidates
// are one vectorisable loop. A person cloud is voxelised, so its density is nearly uniform and a
// grid answers the exact K-nearest question by looking at a small cube of cells: the cube is
// grown until at least K candidates lie within the distance from the query to the cube's nearest
// face; then every point closer than the K-th candidate is inside the cube, so the K nearest of
// the candidates are the K nearest of the frame.
//
// Order: "nearer" means smaller (squared distance, index). Equal distances are thus ordered by
// index, which makes the neighbour set a pure function of the data (a tree's order among equal
// distances depends on how it was built).
struct FlowFrame::Index
{
  Eigen::Vector3f origin = Eigen::Vector3f::Zero();
  float cell = 1.0f, inv_cell = 1.0f;
  int nx = 1, ny = 1, nz = 1;
  std::vector<std::uint32_t> start;  // points of cell c are slots [start[c], start[c+1])
  std::vector<float> x, y, z;        // per slot
  std::vector<float> c0, c1, c2;     // HSV-cone colour per slot
  std::vector<std::uint32_t> id;     // point index of each slot
  std::vector<std::uint32_t> slot;   // slot of each point index

  Index(const std::vector<Eigen::Vector3f>& pts, const std::vector<Eigen::Vector3f>& colours);

  int coord(float v, float o, int n) const
  {
    const float c = std::floor((v - o) * inv_cell);
    return c < 0.0f ? 0 : (c >= static_cast<float>(n) ? n - 1 : static_cast<int>(c));
  }
  // A cube of cells around a query, clipped to the grid, and the radius of the ball around the
  // query that it surely contains (infinite when the cube is the whole grid).
  struct Cube
  {
    int lo[3], hi[3];
    float safe_sq;
  };
  Cube cube(const float* q, int r) const;
  // Gathers the squared distances and slots of all points in @p c.
  void gather(const float* q, const Cube& c, std::vector<float>& d2, std::vector<std::uint32_t>& slots) const;
  // Gathers a cube that surely holds the k nearest (r is the first cube radius to try, updated).
  void gatherNearest(const float* q, std::size_t k, int& r, std::vector<float>& d2,
                     std::vector<std::uint32_t>& slots) const;
};

FlowFrame::Index::Index(const std::vector<Eigen::Vector3f>& pts, const std::vector<Eigen::Vector3f>& colours)
{
  const std::size_t n = pts.size();
  if (n == 0)
  {
    start.assign(2, 0);
    return;
  }
  Eigen::Vector3f lo = pts[0], hi = pts[0];
  for (const auto& p : pts)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // Cell size: about the mean spacing of n points filling the bounding box (a flat or thin cloud
  // counts as 1/20 of its largest extent thick). For a voxelised person and K = 50 this puts the
  // K-th neighbour two to three cells away; 0.8 used the fewest instructions of 0.6-1.2 for
  // person clouds at 0.06, 0.04 and 0.02 m voxels (docs/bench.md).
  const Eigen::Vector3f ext = hi - lo;
  const float floor_ext = std::max(1e-4f, 0.05f * ext.maxCoeff());
  const double volume = static_cast<double>(std::max(ext.x(), floor_ext)) * std::max(ext.y(), floor_ext) *
                        std::max(ext.z(), floor_ext);
  cell = static_cast<float>(kCellScale * std::cbrt(volume / static_cast<double>(n)));
  // Keep the dense cell array within a few times the point count, whatever the cloud's shape.
  for (;;)
  {
    inv_cell = 1.0f / cell;
    nx = static_cast<int>(ext.x() * inv_cell) + 1;
    ny = static_cast<int>(ext.y() * inv_cell) + 1;
    nz = static_cast<int>(ext.z() * inv_cell) + 1;
    if (static_cast<double>(nx) * ny * nz <= 8.0 * n + 64)
      break;
    cell *= 1.25f;
  }
  origin = lo;
  const std::size_t cells = static_cast<std::size_t>(nx) * ny * nz;
  std::vector<std::uint32_t> cell_of(n);
  start.assign(cells + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::size_t c = coord(pts[i].x(), origin.x(), nx) +
                          static_cast<std::size_t>(nx) * (coord(pts[i].y(), origin.y(), ny) +
                                                          static_cast<std::size_t>(ny) * coord(pts[i].z(), origin.z(), nz));
    cell_of[i] = static_cast<std::uint32_t>(c);
    ++start[c + 1];
  }
  for (std::size_t c = 0; c < cells; ++c)
    start[c + 1] += start[c];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  x.resize(n), y.resize(n), z.resize(n), c0.resize(n), c1.resize(n), c2.resize(n), id.resize(n), slot.resize(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint32_t s = fill[cell_of[i]]++;
    x[s] = pts[i].x(), y[s] = pts[i].y(), z[s] = pts[i].z();
    c0[s] = colours[i].x(), c1[s] = colours[i].y(), c2[s] = colours[i].z();
    id[s] = static_cast<std::uint32_t>(i);
    slot[i] = s;
  }
}

FlowFrame::Index::Cube FlowFrame::Index::cube(const float* q, int r) const
{
  Cube c;
  const int n[3] = { nx, ny, nz };
  float safe = std::numeric_limits<float>::infinity();
  for (int a = 0; a < 3; ++a)
  {
    const int centre = coord(q[a], origin[a], n[a]);
    c.lo[a] = centre - r;
    c.hi[a] = centre + r;
    // A face on the grid's border bounds nothing: no point lies beyond it.
    if (c.lo[a] > 0)
      safe = std::min(safe, q[a] - (origin[a] + c.lo[a] * cell));
    else
      c.lo[a] = 0;
    if (c.hi[a] < n[a] - 1)
      safe = std::min(safe, origin[a] + (c.hi[a] + 1) * cell - q[a]);
    else
      c.hi[a] = n[a] - 1;
  }
  // Shrunk by a relative 1e-5 so that float rounding of squared distances cannot admit a point
  // from outside the cube as nearer than one inside it.
  c.safe_sq = std::isinf(safe) ? safe : (safe > 0.0f ? safe * safe * (1.0f - 1e-5f) : -1.0f);
  return c;
}

void FlowFrame::Index::gather(const float* q, const Cube& c, std::vector<float>& d2,
                              std::vector<std::uint32_t>& slots) const
{
  d2.clear();
  slots.clear();
  const float qx = q[0], qy = q[1], qz = q[2];
  for (int k = c.lo[2]; k <= c.hi[2]; ++k)
    for (int j = c.lo[1]; j <= c.hi[1]; ++j)
    {
      // Cells lo..hi of one row are consecutive, so their points are one run of slots.
      const std::size_t row = static_cast<std::size_t>(nx) * (j + static_cast<std::size_t>(ny) * k);
      const std::uint32_t b = start[row + c.lo[0]], e = start[row + c.hi[0] + 1];
      const std::size_t old = d2.size();
      d2.resize(old + (e - b));
      slots.resize(old + (e - b));
      float* out = d2.data() + old;
      std::uint32_t* so = slots.data() + old;
      for (std::uint32_t s = b; s < e; ++s)
      {
        const float dx = x[s] - qx, dy = y[s] - qy, dz = z[s] - qz;
        out[s - b] = dx * dx + dy * dy + dz * dz;
        so[s - b] = s;
      }
    }
}

void FlowFrame::Index::gatherNearest(const float* q, std::size_t k, int& r, std::vector<float>& d2,
                                     std::vector<std::uint32_t>& slots) const
{
  for (;;)
  {
    const Cube c = cube(q, r);
    gather(q, c, d2, slots);
    if (std::isinf(c.safe_sq))
      return;  // the whole grid
    std::size_t inside = 0;
    for (float d : d2)
      inside += d <= c.safe_sq;
    if (inside >= k)
      return;
    ++r;
  }
}

FlowFrame::FlowFrame(const Cloud& cloud, double stamp) : stamp_(stamp)
{
  xyz_.reserve(cloud.size());
  colour_.reserve(cloud.size());
  for (const auto& p : cloud.points)
  {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      continue;
    xyz_.emplace_back(p.x, p.y, p.z);
    colour_.push_back(hsvCone(rgbToHsv(p.r, p.g, p.b)));
  }
  index_ = std::make_unique<Index>(xyz_, colour_);
}

FlowFrame::~FlowFrame() = default;

void FlowFrame::nearest(const Eigen::Vector3f& q, int k, std::vector<std::size_t>& indices,
                        std::vector<float>& sq_dists) const
{
  const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(std::max(k, 0)), xyz_.size());
  indices.clear();
  sq_dists.clear();
  if (n == 0)
    return;
  std::vector<float> d2;
  std::vector<std::uint32_t> slots;
  int r = 1;
  index_->gatherNearest(q.data(), n, r, d2, slots);
  std::vector<std::uint32_t> order(d2.size());
  for (std::uint32_t i = 0; i < order.size(); ++i)
    order[i] = i;
  const Index& ix = *index_;
  std::partial_sort(order.begin(), order.begin() + n, order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return d2[a] < d2[b] || (d2[a] == d2[b] && ix.id[slots[a]] < ix.id[slots[b]]);
  });
  for (std::size_t i = 0; i < n; ++i)
  {
    indices.push_back(ix.id[slots[order[i]]]);
    sq_dists.push_back(d2[order[i]]);
  }
}

void FlowFrame::within(const Eigen::Vector3f& q, float radius, std::vector<std::size_t>& indices) const
{
  indices.clear();
  if (xyz_.empty() || !(radius > 0.0f))
    return;
  const Index& ix = *index_;
  const float r2 = radius * radius;
  Index::Cube c;
  const int n[3] = { ix.nx, ix.ny, ix.nz };
  for (int a = 0; a < 3; ++a)
  {
    c.lo[a] = ix.coord(q[a] - radius, ix.origin[a], n[a]);
    c.hi[a] = ix.coord(q[a] + radius, ix.origin[a], n[a]);
  }
  std::vector<float> d2;
  std::vector<std::uint32_t> slots;
  ix.gather(q.data(), c, d2, slots);
  for (std::size_t i = 0; i < d2.size(); ++i)
    if (d2[i] < r2)
      indices.push_back(ix.id[slots[i]]);
}

FlowEstimator::FlowEstimator(const FlowParams& params) : params_(params)
{
  if (params_.k < 1)
    throw std::invalid_argument("FlowEstimator: k must be at least 1");
  if (!(params_.min_speed >= 0.0f) || !(params_.isolation_speed >= 0.0f) || !(params_.neighbour_radius > 0.0f))
    throw std::invalid_argument("FlowEstimator: speeds must be >= 0 and neighbour_radius > 0");
}

namespace
{
// The paper's step 1 for a batch of query points, grouped by the cell of @p to's grid they fall
// in: the points of a cube of cells around that cell are copied once into contiguous arrays, and
// every query of the group scans those with vectorisable loops.
class BatchMatcher
{
public:
  BatchMatcher(const FlowFrame::Index& to, std::size_t k) : to_(to), k_(k) {}

  /** Fills out[q] for every q in @p queries (indices into @p from). */
  void run(const FlowFrame& from, const std::vector<std::uint32_t>& queries, std::vector<std::size_t>& out)
  {
    // Counting sort of the queries by the cell of `to` they fall in.
    const FlowFrame::Index& ix = to_;
    const std::size_t cells = ix.start.size() - 1;
    std::vector<std::uint32_t> cell_of(queries.size()), first(cells + 1, 0), order(queries.size());
    for (std::size_t i = 0; i < queries.size(); ++i)
    {
      const Eigen::Vector3f& q = from.point(queries[i]);
      cell_of[i] = static_cast<std::uint32_t>(
          ix.coord(q.x(), ix.origin.x(), ix.nx) +
          static_cast<std::size_t>(ix.nx) *
              (ix.coord(q.y(), ix.origin.y(), ix.ny) + static_cast<std::size_t>(ix.ny) * ix.coord(q.z(), ix.origin.z(), ix.nz)));
      ++first[cell_of[i] + 1];
    }
    for (std::size_t c = 0; c < cells; ++c)
      first[c + 1] += first[c];
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t i = 0; i < queries.size(); ++i)
      order[fill[cell_of[i]]++] = queries[i];

    for (std::size_t c = 0; c < cells; ++c)
    {
      if (first[c] == first[c + 1])
        continue;
      const int centre[3] = { static_cast<int>(c % ix.nx), static_cast<int>((c / ix.nx) % ix.ny),
                              static_cast<int>(c / (static_cast<std::size_t>(ix.nx) * ix.ny)) };
      gatherCube(centre, r_);
      for (std::uint32_t i = first[c]; i < first[c + 1]; ++i)
        out[order[i]] = matchOne(from.point(order[i]), from.colour(order[i]), centre);
      // Neighbouring cells need about the same cube; a roomy one is tried a size smaller next.
      if (x_.size() > 4 * k_ && r_ > 1)
        --r_;
    }
  }

private:
  void gatherCube(const int centre[3], int r)
  {
    const FlowFrame::Index& ix = to_;
    const int n[3] = { ix.nx, ix.ny, ix.nz };
    r_ = r;
    whole_ = true;
    for (int a = 0; a < 3; ++a)
    {
      lo_[a] = std::max(0, centre[a] - r);
      hi_[a] = std::min(n[a] - 1, centre[a] + r);
      lo_open_[a] = lo_[a] == 0;  // on the grid's border: nothing lies beyond, the face bounds nothing
      hi_open_[a] = hi_[a] == n[a] - 1;
      whole_ = whole_ && lo_open_[a] && hi_open_[a];
    }
    x_.clear(), y_.clear(), z_.clear(), c0_.clear(), c1_.clear(), c2_.clear(), id_.clear();
    for (int k = lo_[2]; k <= hi_[2]; ++k)
      for (int j = lo_[1]; j <= hi_[1]; ++j)
      {
        // Cells lo..hi of one row are consecutive, so their points are one run of slots.
        const std::size_t row = static_cast<std::size_t>(ix.nx) * (j + static_cast<std::size_t>(ix.ny) * k);
        const std::uint32_t b = ix.start[row + lo_[0]], e = ix.start[row + hi_[0] + 1];
        x_.insert(x_.end(), ix.x.begin() + b, ix.x.begin() + e);
        y_.insert(y_.end(), ix.y.begin() + b, ix.y.begin() + e);
        z_.insert(z_.end(), ix.z.begin() + b, ix.z.begin() + e);
        c0_.insert(c0_.end(), ix.c0.begin() + b, ix.c0.begin() + e);
        c1_.insert(c1_.end(), ix.c1.begin() + b, ix.c1.begin() + e);
        c2_.insert(c2_.end(), ix.c2.begin() + b, ix.c2.begin() + e);
        id_.insert(id_.end(), ix.id.begin() + b, ix.id.begin() + e);
      }
  }

  // Squared radius of the ball around q that the gathered cube surely contains, shrunk by a
  // relative 1e-5 so that float rounding cannot admit a point from outside as nearer than one inside.
  float safeSq(const Eigen::Vector3f& q) const
  {
    if (whole_)
      return std::numeric_limits<float>::infinity();
    const FlowFrame::Index& ix = to_;
    float safe = std::numeric_limits<float>::infinity();
    for (int a = 0; a < 3; ++a)
    {
      if (!lo_open_[a])
        safe = std::min(safe, q[a] - (ix.origin[a] + lo_[a] * ix.cell));
      if (!hi_open_[a])
        safe = std::min(safe, ix.origin[a] + (hi_[a] + 1) * ix.cell - q[a]);
    }
    return safe > 0.0f ? safe * safe * (1.0f - 1e-5f) : -1.0f;
  }

  // Among the k nearest points (XYZ) the nearest in colour; among equal colours the nearer point.
  // The k nearest are never sorted: candidates are tried in order of colour distance, and the first
  // with fewer than k candidates nearer than it (in the (distance, index) order) wins; usually the
  // first or second try. The cube is grown until k candidates lie within safeSq, so that the
  // candidates' order is the frame's order up to the k-th.
  std::size_t matchOne(const Eigen::Vector3f& q, const Eigen::Vector3f& qc, const int centre[3])
  {
    std::size_t m;
    for (;;)
    {
      m = x_.size();
      d2_.resize(m);
      const float qx = q.x(), qy = q.y(), qz = q.z();
      const float *x = x_.data(), *y = y_.data(), *z = z_.data();
      float* d2 = d2_.data();
      for (std::size_t i = 0; i < m; ++i)
      {
        const float dx = x[i] - qx, dy = y[i] - qy, dz = z[i] - qz;
        d2[i] = dx * dx + dy * dy + dz * dz;
      }
      const float safe = safe_ = safeSq(q);
      if (std::isinf(safe))
        break;
      std::uint32_t inside = 0;  // 32-bit counters keep these loops vectorised
      for (std::size_t i = 0; i < m; ++i)
        inside += d2[i] <= safe ? 1u : 0u;
      if (inside >= k_)
        break;
      gatherCube(centre, r_ + 1);
    }
    const std::size_t kk = std::min(k_, m);
    h_.resize(m);
    {
      const float a = qc.x(), b = qc.y(), c = qc.z();
      const float *c0 = c0_.data(), *c1 = c1_.data(), *c2 = c2_.data();
      float* h = h_.data();
      for (std::size_t i = 0; i < m; ++i)
      {
        const float u = c0[i] - a, v = c1[i] - b, w = c2[i] - c;
        h[i] = u * u + v * v + w * w;
      }
    }
    // The bit patterns of non-negative floats order as the floats do; an integer minimum is
    // vectorised where a float one (NaN rules) is not.
    hbits_.resize(m);
    std::memcpy(hbits_.data(), h_.data(), m * sizeof(float));
    const float* d2 = d2_.data();
    const std::uint32_t* id = id_.data();
    // First try: the candidate with the least (colour distance, distance, index).
    const std::int32_t* hb = hbits_.data();
    std::int32_t hmin = hb[0];
    for (std::size_t i = 1; i < m; ++i)
      hmin = hb[i] < hmin ? hb[i] : hmin;
    std::size_t best = 0;
    while (hb[best] != hmin)
      ++best;
    for (std::size_t i = best + 1; i < m; ++i)  // equal colour distances: rare
      if (hb[i] == hmin && (d2[i] < d2[best] || (d2[i] == d2[best] && id[i] < id[best])))
        best = i;
    const float db = d2[best];
    std::uint32_t less = 0, equal = 0;
    for (std::size_t i = 0; i < m; ++i)
    {
      less += d2[i] < db ? 1u : 0u;
      equal += d2[i] == db ? 1u : 0u;
    }
    if (less + equal <= kk)
      return id[best];  // within the k nearest whatever the order among equal distances
    // Otherwise find the k-th nearest (all k lie within the safe radius) by selecting on integer
    // keys (distance bits, index), then take the best colour among candidates up to it.
    keys_.clear();
    auto key = [&](std::size_t i) {
      std::uint32_t bits;
      std::memcpy(&bits, &d2[i], sizeof bits);  // non-negative floats order as their bits
      return (static_cast<std::uint64_t>(bits) << 32) | id[i];
    };
    for (std::size_t i = 0; i < m; ++i)
      if (d2[i] <= safe_)
        keys_.push_back(key(i));
    std::nth_element(keys_.begin(), keys_.begin() + (kk - 1), keys_.end());
    const std::uint64_t kth = keys_[kk - 1];
    std::int32_t best_h = std::numeric_limits<std::int32_t>::max();
    std::uint64_t best_key = 0;
    for (std::size_t i = 0; i < m; ++i)
    {
      const std::uint64_t k = key(i);
      if (k <= kth && (hb[i] < best_h || (hb[i] == best_h && k < best_key)))
      {
        best_h = hb[i];
        best_key = k;
        best = i;
      }
    }
    return id[best];
  }

  const FlowFrame::Index& to_;
  std::size_t k_;
  int r_ = 1;
  int lo_[3] = { 0, 0, 0 }, hi_[3] = { 0, 0, 0 };
  bool lo_open_[3] = { true, true, true }, hi_open_[3] = { true, true, true };
  bool whole_ = true;
  std::vector<float> x_, y_, z_, c0_, c1_, c2_, d2_, h_;
  std::vector<std::uint32_t> id_;
  std::vector<std::uint64_t> keys_;
  std::vector<std::int32_t> hbits_;
  float safe_ = 0.0f;  // safeSq of the current query
};
}  // namespace

std::vector<std::size_t> FlowEstimator::match(const FlowFrame& from, const FlowFrame& to) const
{
  std::vector<std::size_t> out(from.size(), 0);
  if (to.empty() || from.empty())
    return out;
  std::vector<std::uint32_t> all(from.size());
  for (std::uint32_t i = 0; i < all.size(); ++i)
    all[i] = i;
  BatchMatcher(to.index(), static_cast<std::size_t>(params_.k)).run(from, all, out);
  return out;
}

std::vector<Correspondence> FlowEstimator::correspond(const FlowFrame& source, const FlowFrame& target,
                                                      FlowStats& stats) const
{
  std::vector<Correspondence> out;
  if (source.empty() || target.empty())
    return out;
  const std::vector<std::size_t> t2s = match(target, source);
  stats.matched = t2s.size();
  if (!params_.reciprocal)
  {
    out.reserve(t2s.size());
    for (std::size_t t = 0; t < t2s.size(); ++t)
      out.push_back({ t, t2s[t] });
    return out;
  }
  // The source->target match is needed only for the source points that some target point chose:
  // those alone are matched back, instead of a second full pass.
  std::vector<std::uint8_t> chosen(source.size(), 0);
  std::vector<std::uint32_t> back;
  for (std::size_t s : t2s)
    if (!chosen[s])
    {
      chosen[s] = 1;
      back.push_back(static_cast<std::uint32_t>(s));
    }
  std::vector<std::size_t> s2t(source.size(), 0);
  BatchMatcher(target.index(), static_cast<std::size_t>(params_.k)).run(source, back, s2t);
  for (std::size_t t = 0; t < t2s.size(); ++t)
  {
    if (s2t[t2s[t]] == t)
      out.push_back({ t, t2s[t] });
  }
  stats.removed_reciprocal = stats.matched - out.size();
  return out;
}

FlowVectors FlowEstimator::velocities(const FlowFrame& source, const FlowFrame& target,
                                      const std::vector<Correspondence>& matches, double dt)
{
  FlowVectors out;
  out.reserve(matches.size());
  const float inv_dt = static_cast<float>(1.0 / dt);
  for (const auto& m : matches)
    out.push_back({ target.point(m.target), (target.point(m.target) - source.point(m.source)) * inv_dt });
  return out;
}

FlowVectors FlowEstimator::rejectOutliers(const FlowFrame& target, const std::vector<Correspondence>& matches,
                                          const FlowVectors& flow, FlowStats& stats) const
{
  // Speed of every target point that survived the slow-point rule; 0 for all others.
  std::vector<float> speed(target.size(), 0.0f);
  std::vector<std::size_t> moving;  // indices into matches/flow
  for (std::size_t i = 0; i < flow.size(); ++i)
  {
    const float s = flow[i].velocity.norm();
    if (s < params_.min_speed)
    {
      ++stats.removed_slow;
      continue;
    }
    speed[matches[i].target] = s;
    moving.push_back(i);
  }
  FlowVectors out;
  out.reserve(moving.size());
  // Radius search straight on the grid, stopping at the first fast neighbour.
  const FlowFrame::Index& ix = target.index();
  const float r2 = params_.neighbour_radius * params_.neighbour_radius;
  const int n[3] = { ix.nx, ix.ny, ix.nz };
  for (std::size_t i : moving)
  {
    const std::size_t self = matches[i].target;
    const Eigen::Vector3f& q = target.point(self);
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = ix.coord(q[a] - params_.neighbour_radius, ix.origin[a], n[a]);
      hi[a] = ix.coord(q[a] + params_.neighbour_radius, ix.origin[a], n[a]);
    }
    bool has_fast_neighbour = false;
    for (int c = lo[2]; c <= hi[2] && !has_fast_neighbour; ++c)
      for (int b = lo[1]; b <= hi[1] && !has_fast_neighbour; ++b)
      {
        const std::size_t row = static_cast<std::size_t>(ix.nx) * (b + static_cast<std::size_t>(ix.ny) * c);
        for (std::uint32_t s = ix.start[row + lo[0]], e = ix.start[row + hi[0] + 1]; s < e; ++s)
        {
          const float dx = ix.x[s] - q.x(), dy = ix.y[s] - q.y(), dz = ix.z[s] - q.z();
          const std::uint32_t j = ix.id[s];
          if (dx * dx + dy * dy + dz * dz < r2 && j != self && speed[j] > params_.isolation_speed)
          {
            has_fast_neighbour = true;
            break;
          }
        }
      }
    if (has_fast_neighbour)
      out.push_back(flow[i]);
    else
      ++stats.removed_isolated;
  }
  return out;
}

FlowResult FlowEstimator::estimate(const FlowFrame& source, const FlowFrame& target) const
{
  FlowVectors unfiltered;
  return estimate(source, target, unfiltered);
}

FlowResult FlowEstimator::estimate(const FlowFrame& source, const FlowFrame& target, FlowVectors& unfiltered) const
{
  FlowResult result;
  result.dt = target.stamp() - source.stamp();
  if (!std::isfinite(result.dt) || result.dt <= 0.0)
  {
    std::ostringstream msg;
    msg << "FlowEstimator: target stamp must be later than source stamp (dt = " << result.dt << " s)";
    throw std::invalid_argument(msg.str());
  }
  result.stats.source_points = source.size();
  result.stats.target_points = target.size();
  const auto matches = correspond(source, target, result.stats);
  unfiltered = velocities(source, target, matches, result.dt);
  result.flow = params_.reject_outliers ? rejectOutliers(target, matches, unfiltered, result.stats) : unfiltered;
  result.stats.kept = result.flow.size();
  return result;
}

}  // namespace action_flow
