/**
 * @file neighbour_grid.h
 * @brief (private to the core) The flow's neighbour search: the uniform grid a FlowFrame builds
 *        over its points, and the batch K-nearest matching of the paper's step 1 on it.
 *
 * Why not the tracker's RadiusGrid (tracker_clustering.h): that one answers "every point within r"
 * over a whole scene's detection voxels, for clustering; this one answers the exact K nearest in
 * XYZ (step 1) and the points within a radius (step 4) over one voxelised person, with its points
 * sorted by cell and stored per axis so that a run of candidates is one vectorisable loop. The
 * two share the idea, not the layout each query needs.
 */
#pragma once

#include <action_flow/flow_estimator.h>

#include <cstdint>
#include <vector>

namespace action_flow
{
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

/**
 * @brief The paper's step 1 for @p queries (indices into @p from): out[q] is the index in @p to of
 *        the point nearest to from.point(q) in colour among its @p k nearest in XYZ.
 */
void matchNearest(const FlowFrame& from, const FlowFrame::Index& to, std::size_t k,
                  const std::vector<std::uint32_t>& queries, std::vector<std::size_t>& out);

}  // namespace action_flow
