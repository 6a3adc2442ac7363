#include "virtual_tryon/core/body/scan_meshing.h"

#include <pcl/common/centroid.h>
#include <pcl/common/common.h>
#include <pcl/common/eigen.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/surface/poisson.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <numeric>
#include <queue>
#include <sstream>
#include <thread>
#include <utility>
#include <vector>

namespace virtual_tryon {

namespace {

using Clock = std::chrono::steady_clock;

double since(const Clock::time_point& t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string num(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

// The symmetric kNN graph in compressed rows: the neighbours of i are adj[off[i] .. off[i+1]).
struct Graph {
  std::vector<int> off, adj;
};

// k nearest neighbours of every point (itself excluded), #P * k indices (-1 where fewer exist).
std::vector<int> nearestNeighbours(const pcl::PointCloud<pcl::PointNormal>::ConstPtr& cloud, int k) {
  pcl::KdTreeFLANN<pcl::PointNormal> tree;
  tree.setInputCloud(cloud);
  const std::size_t n = cloud->size();
  std::vector<int> knn(n * static_cast<std::size_t>(k), -1);
  pcl::Indices idx;
  std::vector<float> d2;
  for (std::size_t i = 0; i < n; ++i) {
    tree.nearestKSearch((*cloud)[i], k + 1, idx, d2);
    int m = 0;
    for (std::size_t j = 0; j < idx.size() && m < k; ++j)
      if (static_cast<std::size_t>(idx[j]) != i) knn[i * static_cast<std::size_t>(k) + m++] = idx[j];
  }
  return knn;
}

Graph symmetricGraph(const std::vector<int>& knn, std::size_t n, int k) {
  Graph g;
  g.off.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (int m = 0; m < k; ++m) {
      const int j = knn[i * static_cast<std::size_t>(k) + m];
      if (j < 0) continue;
      ++g.off[i + 1];
      ++g.off[static_cast<std::size_t>(j) + 1];
    }
  for (std::size_t i = 0; i < n; ++i) g.off[i + 1] += g.off[i];
  g.adj.resize(static_cast<std::size_t>(g.off[n]));
  std::vector<int> fill(g.off.begin(), g.off.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    for (int m = 0; m < k; ++m) {
      const int j = knn[i * static_cast<std::size_t>(k) + m];
      if (j < 0) continue;
      g.adj[static_cast<std::size_t>(fill[i]++)] = j;
      g.adj[static_cast<std::size_t>(fill[static_cast<std::size_t>(j)]++)] = static_cast<int>(i);
    }
  return g;
}

// PCA normal of each point from itself and its k neighbours (the eigenvector of the smallest
// eigenvalue of the covariance); unoriented.
void estimateNormals(pcl::PointCloud<pcl::PointNormal>& cloud, const std::vector<int>& knn, int k) {
  const std::size_t n = cloud.size();
  pcl::Indices idx;
  Eigen::Matrix3f cov;
  Eigen::Vector4f centroid;
  for (std::size_t i = 0; i < n; ++i) {
    idx.assign(1, static_cast<int>(i));
    for (int m = 0; m < k; ++m) {
      const int j = knn[i * static_cast<std::size_t>(k) + m];
      if (j >= 0) idx.push_back(j);
    }
    pcl::PointNormal& p = cloud[i];
    if (idx.size() < 3 || pcl::computeMeanAndCovarianceMatrix(cloud, idx, cov, centroid) == 0) {
      p.normal_x = 0, p.normal_y = 0, p.normal_z = 1;
      continue;
    }
    float eigenvalue;
    Eigen::Vector3f eigenvector;
    pcl::eigen33(cov, eigenvalue, eigenvector);
    if (!eigenvector.allFinite() || eigenvector.norm() == 0) eigenvector = Eigen::Vector3f::UnitZ();
    eigenvector.normalize();
    p.normal_x = eigenvector.x(), p.normal_y = eigenvector.y(), p.normal_z = eigenvector.z();
  }
}

// The connected components of the graph (breadth-first, from the lowest index not yet reached) and
// one seed per component, the point farthest from the centre of the component's bounding box (the
// first such in breadth-first order), its normal turned to point away from that centre. Counts the
// normals turned in `flipped`.
std::vector<std::size_t> componentSeeds(pcl::PointCloud<pcl::PointNormal>& cloud, const Graph& g,
                                        std::size_t& flipped) {
  const std::size_t n = cloud.size();
  auto normal = [&](std::size_t i) { return cloud[i].getNormalVector3fMap(); };
  std::vector<int> comp(n, -1);
  std::vector<int> order;
  order.reserve(n);
  std::vector<std::size_t> seeds;
  for (std::size_t s = 0; s < n; ++s) {
    if (comp[s] >= 0) continue;
    const int c = static_cast<int>(seeds.size());
    const std::size_t begin = order.size();
    comp[s] = c;
    order.push_back(static_cast<int>(s));
    Eigen::Vector3f lo = cloud[s].getVector3fMap(), hi = lo;
    for (std::size_t q = begin; q < order.size(); ++q) {
      const std::size_t i = static_cast<std::size_t>(order[q]);
      lo = lo.cwiseMin(cloud[i].getVector3fMap());
      hi = hi.cwiseMax(cloud[i].getVector3fMap());
      for (int e = g.off[i]; e < g.off[i + 1]; ++e) {
        const int j = g.adj[static_cast<std::size_t>(e)];
        if (comp[static_cast<std::size_t>(j)] < 0) {
          comp[static_cast<std::size_t>(j)] = c;
          order.push_back(j);
        }
      }
    }
    const Eigen::Vector3f centre = 0.5f * (lo + hi);
    std::size_t seed = s;
    float best = -1;
    for (std::size_t q = begin; q < order.size(); ++q) {
      const std::size_t i = static_cast<std::size_t>(order[q]);
      const float d = (cloud[i].getVector3fMap() - centre).squaredNorm();
      if (d > best) best = d, seed = i;
    }
    if (normal(seed).dot(cloud[seed].getVector3fMap() - centre) < 0) {
      normal(seed) = -normal(seed);
      ++flipped;
    }
    seeds.push_back(seed);
  }
  return seeds;
}

// Grows Prim's minimum spanning tree (weights 1 - |ni . nj|) from each seed in turn, each point taking
// the sign that agrees with its tree parent; returns the number of normals flipped. A best-known
// weight per point means each point is pushed only when its key drops.
std::size_t propagateSigns(pcl::PointCloud<pcl::PointNormal>& cloud, const Graph& g,
                           const std::vector<std::size_t>& seeds) {
  const std::size_t n = cloud.size();
  auto normal = [&](std::size_t i) { return cloud[i].getNormalVector3fMap(); };
  std::size_t flipped = 0;
  std::vector<float> key(n, std::numeric_limits<float>::infinity());
  std::vector<int> parent(n, -1);
  std::vector<char> done(n, 0);
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
  for (std::size_t seed : seeds) {
    key[seed] = 0;
    heap.push({0.0f, static_cast<int>(seed)});
    while (!heap.empty()) {
      const int i = heap.top().second;
      const float w = heap.top().first;
      heap.pop();
      const std::size_t ui = static_cast<std::size_t>(i);
      if (done[ui] || w > key[ui]) continue;
      done[ui] = 1;
      if (parent[ui] >= 0 && normal(ui).dot(normal(static_cast<std::size_t>(parent[ui]))) < 0) {
        normal(ui) = -normal(ui);
        ++flipped;
      }
      for (int e = g.off[ui]; e < g.off[ui + 1]; ++e) {
        const std::size_t j = static_cast<std::size_t>(g.adj[static_cast<std::size_t>(e)]);
        if (done[j]) continue;
        const float wj = 1.0f - std::abs(normal(ui).dot(normal(j)));
        if (wj < key[j]) {
          key[j] = wj;
          parent[j] = i;
          heap.push({wj, static_cast<int>(j)});
        }
      }
    }
  }
  return flipped;
}

// Orients the normals consistently and outward: Prim's minimum spanning tree over the graph with
// weights 1 - |ni . nj|, one tree per connected component, seeded at the point farthest from the
// component's bounding-box centre (its normal must point away from that centre); each point takes
// the sign that agrees with its tree parent. Returns the number of normals flipped; `components`
// receives the number of trees.
std::size_t orientNormals(pcl::PointCloud<pcl::PointNormal>& cloud, const Graph& g, std::size_t& components) {
  std::size_t flipped = 0;
  const std::vector<std::size_t> seeds = componentSeeds(cloud, g, flipped);
  components = seeds.size();
  return flipped + propagateSigns(cloud, g, seeds);
}

// Removes vertices no face uses (indices remapped).
void removeUnusedVertices(TriMesh& m) {
  std::vector<int> map(static_cast<std::size_t>(m.V.rows()), -1);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) map[static_cast<std::size_t>(m.F(f, k))] = 0;
  int next = 0;
  for (int& x : map)
    if (x == 0) x = next++;
  MatrixX3d V(next, 3);
  for (std::size_t i = 0; i < map.size(); ++i)
    if (map[i] >= 0) V.row(map[i]) = m.V.row(static_cast<Eigen::Index>(i));
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) m.F(f, k) = map[static_cast<std::size_t>(m.F(f, k))];
  m.V = std::move(V);
}

// Drops the pieces (connected over vertices) with fewer faces than fraction x the largest piece's.
std::size_t dropSmallPieces(TriMesh& m, double fraction) {
  if (fraction <= 0 || m.F.rows() == 0) return 0;
  std::vector<int> label;
  const int count = connectedComponents(m, label);
  std::vector<std::size_t> faces(static_cast<std::size_t>(count), 0);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) ++faces[static_cast<std::size_t>(label[static_cast<std::size_t>(m.F(f, 0))])];
  const std::size_t largest = *std::max_element(faces.begin(), faces.end());
  std::size_t dropped = 0;
  for (std::size_t c : faces)
    if (c > 0 && static_cast<double>(c) < fraction * static_cast<double>(largest)) ++dropped;
  if (dropped == 0) return 0;
  MatrixX3i F(m.F.rows(), 3);
  Eigen::Index nf = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    if (static_cast<double>(faces[static_cast<std::size_t>(label[static_cast<std::size_t>(m.F(f, 0))])]) >=
        fraction * static_cast<double>(largest))
      F.row(nf++) = m.F.row(f);
  F.conservativeResize(nf, 3);
  m.F = std::move(F);
  removeUnusedVertices(m);
  return dropped;
}

// Poisson's surface is a level set of one indicator function, so all its pieces share one winding
// convention: a piece wound opposite to the largest one (by |volume|) is the inner wall of a cavity
// (an air bubble in the indicator, e.g. a pocket closed off between touching thighs). Removes those
// pieces; returns how many.
std::size_t removeCavities(TriMesh& m) {
  if (m.F.rows() == 0) return 0;
  std::vector<int> label;
  const int count = connectedComponents(m, label);
  if (count < 2) return 0;
  std::vector<double> volume(static_cast<std::size_t>(count), 0.0);
  const Eigen::RowVector3d c = m.V.colwise().mean();  // any origin: each piece is closed or nearly
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d a = (m.V.row(m.F(f, 0)) - c).transpose();
    const Eigen::Vector3d b = (m.V.row(m.F(f, 1)) - c).transpose();
    const Eigen::Vector3d d = (m.V.row(m.F(f, 2)) - c).transpose();
    volume[static_cast<std::size_t>(label[static_cast<std::size_t>(m.F(f, 0))])] += a.dot(b.cross(d)) / 6.0;
  }
  std::size_t largest = 0;
  for (std::size_t i = 1; i < volume.size(); ++i)
    if (std::abs(volume[i]) > std::abs(volume[largest])) largest = i;
  const double sign = volume[largest] >= 0 ? 1.0 : -1.0;
  std::size_t removed = 0;
  std::vector<char> cavity(volume.size(), 0);
  for (std::size_t i = 0; i < volume.size(); ++i)
    if (sign * volume[i] < 0) cavity[i] = 1, ++removed;
  if (removed == 0) return 0;
  MatrixX3i F(m.F.rows(), 3);
  Eigen::Index nf = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    if (!cavity[static_cast<std::size_t>(label[static_cast<std::size_t>(m.F(f, 0))])]) F.row(nf++) = m.F.row(f);
  F.conservativeResize(nf, 3);
  m.F = std::move(F);
  removeUnusedVertices(m);
  return removed;
}

// The boundary edges of `m` (a -> b as wound in their only face), sorted.
std::vector<std::pair<int, int>> boundaryEdges(const TriMesh& m) {
  std::vector<std::pair<std::pair<int, int>, int>> half;  // ((lo, hi), a) per face corner edge
  half.reserve(static_cast<std::size_t>(3 * m.F.rows()));
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = m.F(f, k), b = m.F(f, (k + 1) % 3);
      half.push_back({{std::min(a, b), std::max(a, b)}, a});
    }
  std::sort(half.begin(), half.end());
  std::vector<std::pair<int, int>> boundary;  // (from, to)
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i + 1;
    while (j < half.size() && half[j].first == half[i].first) ++j;
    if (j - i == 1) {
      const int a = half[i].second;
      const int b = a == half[i].first.first ? half[i].first.second : half[i].first.first;
      boundary.push_back({a, b});
    }
    i = j;
  }
  std::sort(boundary.begin(), boundary.end());
  return boundary;
}

// The first boundary edge leaving v that is not used yet (its index in the sorted `boundary`), or -1.
std::ptrdiff_t nextUnused(const std::vector<std::pair<int, int>>& boundary, const std::vector<char>& used,
                          int v) {
  auto it =
      std::lower_bound(boundary.begin(), boundary.end(), std::make_pair(v, std::numeric_limits<int>::min()));
  for (; it != boundary.end() && it->first == v; ++it)
    if (!used[static_cast<std::size_t>(it - boundary.begin())]) return it - boundary.begin();
  return -1;
}

// Chains the boundary edges into loops: a path walks on from each unused edge, and whenever it comes
// back to one of its vertices the loop closed there is cut off (so a loop that passes a vertex twice
// is split there); what is left of a path that dead-ends is not a loop.
std::vector<std::vector<int>> boundaryLoops(const std::vector<std::pair<int, int>>& boundary,
                                            Eigen::Index vertices) {
  std::vector<char> used(boundary.size(), 0);
  std::vector<std::vector<int>> loops;
  std::vector<int> pos(static_cast<std::size_t>(vertices), -1);  // index in the current path
  for (std::size_t s = 0; s < boundary.size(); ++s) {
    if (used[s]) continue;
    std::vector<int> path{boundary[s].first};
    pos[static_cast<std::size_t>(path[0])] = 0;
    used[s] = 1;
    int v = boundary[s].second;
    while (true) {
      const int at = pos[static_cast<std::size_t>(v)];
      if (at >= 0) {  // a loop closes at v: cut it off, go on from v
        loops.emplace_back(path.begin() + at, path.end());
        for (std::size_t q = static_cast<std::size_t>(at) + 1; q < path.size(); ++q)
          pos[static_cast<std::size_t>(path[q])] = -1;
        path.resize(static_cast<std::size_t>(at) + 1);
      } else {
        pos[static_cast<std::size_t>(v)] = static_cast<int>(path.size());
        path.push_back(v);
      }
      const std::ptrdiff_t e = nextUnused(boundary, used, v);
      if (e < 0) break;  // path closed and nothing leaves v, or a dead end (left open)
      used[static_cast<std::size_t>(e)] = 1;
      v = boundary[static_cast<std::size_t>(e)].second;
    }
    for (int x : path) pos[static_cast<std::size_t>(x)] = -1;
  }
  return loops;
}

// Closes the loops of 3 .. maxEdges edges: a triangle, or a fan round a new vertex at the centroid,
// wound to match the faces around the loop (so opposite to the loop, which follows their boundary
// edges). Returns how many.
std::size_t fillLoops(TriMesh& m, const std::vector<std::vector<int>>& loops, int maxEdges,
                      std::size_t* facesAdded) {
  std::vector<Eigen::Vector3d> newV;
  std::vector<Eigen::Vector3i> newF;
  std::size_t filled = 0;
  for (const std::vector<int>& loop : loops) {
    const int n = static_cast<int>(loop.size());
    if (n < 3 || n > maxEdges) continue;
    ++filled;
    if (n == 3) {
      newF.emplace_back(loop[2], loop[1], loop[0]);
      continue;
    }
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : loop) c += m.V.row(v).transpose();
    const int ci = static_cast<int>(m.V.rows() + static_cast<Eigen::Index>(newV.size()));
    newV.push_back(c / n);
    for (int j = 0; j < n; ++j)
      newF.emplace_back(loop[static_cast<std::size_t>((j + 1) % n)], loop[static_cast<std::size_t>(j)], ci);
  }
  if (newF.empty()) return filled;
  const Eigen::Index v0 = m.V.rows(), f0 = m.F.rows();
  m.V.conservativeResize(v0 + static_cast<Eigen::Index>(newV.size()), 3);
  for (std::size_t i = 0; i < newV.size(); ++i)
    m.V.row(v0 + static_cast<Eigen::Index>(i)) = newV[i].transpose();
  m.F.conservativeResize(f0 + static_cast<Eigen::Index>(newF.size()), 3);
  for (std::size_t i = 0; i < newF.size(); ++i)
    m.F.row(f0 + static_cast<Eigen::Index>(i)) = newF[i].transpose();
  if (facesAdded) *facesAdded = newF.size();
  return filled;
}

}  // namespace

std::size_t closeSmallHoles(TriMesh& m, int maxEdges, std::size_t* facesAdded) {
  if (facesAdded) *facesAdded = 0;
  if (maxEdges < 3) return 0;
  const std::vector<std::pair<int, int>> boundary = boundaryEdges(m);
  if (boundary.empty()) return 0;
  return fillLoops(m, boundaryLoops(boundary, m.V.rows()), maxEdges, facesAdded);
}

int chooseScanDepth(double extent, double spacing, double sigma, int max_depth) {
  const int hi = std::max(5, max_depth);
  const double cell = std::max(1.5 * spacing, 2.0 * sigma);
  if (!(extent > 0) || !(cell > 0) || !std::isfinite(extent / cell)) return hi;
  const int depth = static_cast<int>(std::ceil(std::log2(1.1 * extent / cell) - 1e-9));
  return std::min(hi, std::max(5, depth));
}

std::string validateScanMeshingParams(const ScanMeshingParams& p) {
  if (!(p.voxel_size >= 0) || !std::isfinite(p.voxel_size))
    return "voxel_size must be finite and >= 0 metres (0 = no downsampling), got " + num(p.voxel_size);
  if (p.normal_neighbours < 3 || p.normal_neighbours > 100)
    return "normal_neighbours must be in [3, 100], got " + std::to_string(p.normal_neighbours);
  if (!(p.max_normal_disagreement >= 0 && p.max_normal_disagreement <= 1))
    return "max_normal_disagreement must be in [0, 1], got " + num(p.max_normal_disagreement);
  if (p.depth != 0 && (p.depth < 4 || p.depth > 12))
    return "depth must be 0 (chosen from the scan) or in [4, 12], got " + std::to_string(p.depth);
  if (p.max_auto_depth < 4 || p.max_auto_depth > 12)
    return "max_auto_depth must be in [4, 12], got " + std::to_string(p.max_auto_depth);
  if (!(p.samples_per_node >= 1 && p.samples_per_node <= 50))
    return "samples_per_node must be in [1, 50], got " + num(p.samples_per_node);
  if (!(p.point_weight >= 0) || !std::isfinite(p.point_weight))
    return "point_weight must be finite and >= 0, got " + num(p.point_weight);
  if (p.threads < 0) return "threads must be >= 0 (0 = one per core), got " + std::to_string(p.threads);
  if (p.max_hole_edges < 0) return "max_hole_edges must be >= 0 (0 = no filling), got " + std::to_string(p.max_hole_edges);
  if (!(p.min_piece_fraction >= 0 && p.min_piece_fraction <= 1))
    return "min_piece_fraction must be in [0, 1], got " + num(p.min_piece_fraction);
  if (p.min_points < static_cast<std::size_t>(p.normal_neighbours) + 1)
    return "min_points must be at least normal_neighbours + 1 = " + std::to_string(p.normal_neighbours + 1) +
           ", got " + std::to_string(p.min_points);
  return "";
}

namespace {

// The parameters and the shape of the input; returns the first problem, or "" when meshScan may go on.
std::string checkInput(const MatrixX3d& points, const MatrixX3d& normals, const ScanMeshingParams& params) {
  const std::string bad = validateScanMeshingParams(params);
  if (!bad.empty()) return bad;
  if (points.rows() == 0) return "scan has no points";
  if (normals.rows() > 0 && normals.rows() != points.rows())
    return "normals must be empty or one per point: " + std::to_string(normals.rows()) + " normals for " +
           std::to_string(points.rows()) + " points";
  return "";
}

// 1. The finite points, with their normals normalised when given (else +z, a placeholder); a point
// whose normal is not finite or zero, or that is out of float range, is dropped too.
pcl::PointCloud<pcl::PointNormal>::Ptr finitePoints(const MatrixX3d& points, const MatrixX3d& normals) {
  const bool haveNormals = normals.rows() > 0;
  pcl::PointCloud<pcl::PointNormal>::Ptr cloud(new pcl::PointCloud<pcl::PointNormal>);
  cloud->reserve(static_cast<std::size_t>(points.rows()));
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    if (!points.row(i).allFinite()) continue;
    Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
    if (haveNormals) {
      n = normals.row(i).transpose();
      const double len = n.norm();
      if (!std::isfinite(len) || len == 0) continue;
      n /= len;
    }
    pcl::PointNormal p;
    p.x = static_cast<float>(points(i, 0)), p.y = static_cast<float>(points(i, 1));
    p.z = static_cast<float>(points(i, 2));
    p.normal_x = static_cast<float>(n.x()), p.normal_y = static_cast<float>(n.y());
    p.normal_z = static_cast<float>(n.z());
    p.curvature = 0;
    if (!p.getVector3fMap().allFinite()) continue;  // finite double, but out of float range
    cloud->push_back(p);
  }
  return cloud;
}

// 2. The voxel count as pcl::VoxelGrid computes it; beyond int32 it warns and returns the input, so
// such a grid is refused: returns why, or "" when the grid fits.
std::string voxelGridTooFine(const pcl::PointCloud<pcl::PointNormal>& cloud, double voxelSize) {
  Eigen::Vector4f lo, hi;
  pcl::getMinMax3D(cloud, lo, hi);
  const double inv = 1.0 / static_cast<float>(voxelSize);
  double cells = 1;
  for (int a = 0; a < 3; ++a) cells *= std::floor(hi[a] * inv) - std::floor(lo[a] * inv) + 1;
  if (cells > static_cast<double>(std::numeric_limits<std::int32_t>::max()))
    return "voxel_size " + num(voxelSize) + " m is too small for a scan of " + num(hi.x() - lo.x()) + " x " +
           num(hi.y() - lo.y()) + " x " + num(hi.z() - lo.z()) + " m (more than 2^31 voxels, PCL's limit)";
  return "";
}

// 2. The voxel grid: one point per occupied voxel, the mean. Averaged given normals are renormalised;
// a voxel whose normals cancel out is dropped.
pcl::PointCloud<pcl::PointNormal>::Ptr downsample(const pcl::PointCloud<pcl::PointNormal>::Ptr& cloud,
                                                  double voxelSize) {
  pcl::VoxelGrid<pcl::PointNormal> grid;
  grid.setInputCloud(cloud);
  const float leaf = static_cast<float>(voxelSize);
  grid.setLeafSize(leaf, leaf, leaf);
  pcl::PointCloud<pcl::PointNormal>::Ptr down(new pcl::PointCloud<pcl::PointNormal>);
  grid.filter(*down);
  pcl::PointCloud<pcl::PointNormal>::Ptr kept(new pcl::PointCloud<pcl::PointNormal>);
  kept->reserve(down->size());
  for (pcl::PointNormal p : *down) {
    const float len = p.getNormalVector3fMap().norm();
    if (!(len > 1e-3f)) continue;
    p.getNormalVector3fMap() /= len;
    kept->push_back(p);
  }
  return kept;
}

// 1-2. The points meshScan works on, in `cloud`: the finite ones, downsampled (seconds_downsample
// covers both). Returns why there are too few, or "".
std::string preparePoints(const MatrixX3d& points, const MatrixX3d& normals, const ScanMeshingParams& params,
                          pcl::PointCloud<pcl::PointNormal>::Ptr& cloud, ScanMeshingResult& r) {
  const auto t0 = Clock::now();
  cloud = finitePoints(points, normals);
  r.non_finite_points = r.input_points - cloud->size();
  if (cloud->size() < params.min_points) {
    r.seconds_downsample = since(t0);
    return "too few valid points: " + std::to_string(cloud->size()) + " of " +
           std::to_string(r.input_points) + " (" + std::to_string(r.non_finite_points) + " non-finite" +
           (normals.rows() > 0 ? " or with a bad normal" : "") +
           "), min_points = " + std::to_string(params.min_points);
  }
  if (params.voxel_size > 0) {
    const std::string tooFine = voxelGridTooFine(*cloud, params.voxel_size);
    if (!tooFine.empty()) return tooFine;
    cloud = downsample(cloud, params.voxel_size);
  }
  r.points_after_downsampling = cloud->size();
  r.seconds_downsample = since(t0);
  if (cloud->size() < params.min_points)
    return "too few points after downsampling: " + std::to_string(cloud->size()) + " (voxel_size " +
           num(params.voxel_size) + " m), min_points = " + std::to_string(params.min_points);
  return "";
}

// The fraction of the kNN edges whose normals point opposite ways (dot < 0); 0 without edges.
double normalDisagreement(const pcl::PointCloud<pcl::PointNormal>& cloud, const std::vector<int>& knn,
                          int k) {
  std::size_t edges = 0, disagree = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    for (int m = 0; m < k; ++m) {
      const int j = knn[i * static_cast<std::size_t>(k) + m];
      if (j < 0) continue;
      ++edges;
      if (cloud[i].getNormalVector3fMap().dot(cloud[static_cast<std::size_t>(j)].getNormalVector3fMap()) < 0)
        ++disagree;
    }
  return edges > 0 ? static_cast<double>(disagree) / static_cast<double>(edges) : 0.0;
}

// 3. The k nearest neighbours of every point (into `knn`), then the normals estimated when none are
// given, or the given ones tested for consistency (seconds_normals). Returns whether the normals
// need orienting.
bool prepareNormals(const pcl::PointCloud<pcl::PointNormal>::Ptr& cloud, bool haveNormals,
                    const ScanMeshingParams& params, std::vector<int>& knn, ScanMeshingResult& r) {
  const auto t0 = Clock::now();
  const int k = params.normal_neighbours;
  knn = nearestNeighbours(cloud, k);
  bool orient = true;
  if (!haveNormals) {
    estimateNormals(*cloud, knn, k);
    r.normals_estimated = true;
  } else {
    r.normal_disagreement = normalDisagreement(*cloud, knn, k);
    orient = r.normal_disagreement > params.max_normal_disagreement;
  }
  r.seconds_normals = since(t0);
  return orient;
}

// 3. Orients the normals over the symmetric kNN graph when `orient` (seconds_orient either way).
void orientIfNeeded(pcl::PointCloud<pcl::PointNormal>& cloud, const std::vector<int>& knn, int k, bool orient,
                    ScanMeshingResult& r) {
  const auto t0 = Clock::now();
  if (orient) {
    const Graph graph = symmetricGraph(knn, cloud.size(), k);
    r.normals_flipped = orientNormals(cloud, graph, r.graph_components);
    r.normals_reoriented = true;
  }
  r.seconds_orient = since(t0);
}

// The median distance from a point to its nearest neighbour (the first of its kNN list).
double medianSpacing(const pcl::PointCloud<pcl::PointNormal>& cloud, const std::vector<int>& knn, int k) {
  std::vector<float> d;
  d.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const int j = knn[i * static_cast<std::size_t>(k)];
    if (j >= 0) d.push_back((cloud[i].getVector3fMap() - cloud[static_cast<std::size_t>(j)].getVector3fMap()).norm());
  }
  if (d.empty()) return 0;
  auto mid = d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2);
  std::nth_element(d.begin(), mid, d.end());
  return *mid;
}

// 4. The depth: given, or chosen from the cloud's extent, spacing and noise (into r.depth).
void chooseDepth(const pcl::PointCloud<pcl::PointNormal>& cloud, const std::vector<int>& knn,
                 const ScanMeshingParams& params, ScanMeshingResult& r) {
  r.point_spacing = medianSpacing(cloud, knn, params.normal_neighbours);
  if (params.depth > 0) {
    r.depth = params.depth;
    return;
  }
  Eigen::Vector4f lo, hi;
  pcl::getMinMax3D(cloud, lo, hi);
  const double extent = static_cast<double>((hi - lo).head<3>().maxCoeff());
  r.depth = chooseScanDepth(extent, r.point_spacing, r.noise.sigma, params.max_auto_depth);
}

// 4. pcl::Poisson at r.depth (seconds_reconstruct).
void reconstruct(const pcl::PointCloud<pcl::PointNormal>::Ptr& cloud, const ScanMeshingParams& params,
                 pcl::PointCloud<pcl::PointNormal>& meshPoints, std::vector<pcl::Vertices>& polygons,
                 ScanMeshingResult& r) {
  const auto t0 = Clock::now();
  pcl::Poisson<pcl::PointNormal> poisson;
  poisson.setDepth(r.depth);
  poisson.setSamplesPerNode(static_cast<float>(params.samples_per_node));
  poisson.setPointWeight(static_cast<float>(params.point_weight));
  const unsigned cores = std::thread::hardware_concurrency();
  poisson.setThreads(params.threads > 0 ? params.threads : static_cast<int>(std::max(1u, cores)));
  poisson.setInputCloud(cloud);
  poisson.performReconstruction(meshPoints, polygons);  // no search tree needed (reconstruct() builds one)
  r.seconds_reconstruct = since(t0);
}

// 5. Poisson's output to r.mesh: fans for any polygon (a triangle with an index out of range is
// skipped); the raw counts into poisson_vertices, poisson_faces.
void toTriMesh(const pcl::PointCloud<pcl::PointNormal>& meshPoints,
               const std::vector<pcl::Vertices>& polygons, ScanMeshingResult& r) {
  r.poisson_vertices = meshPoints.size();
  std::size_t triangles = 0;
  for (const pcl::Vertices& poly : polygons)
    if (poly.vertices.size() >= 3) triangles += poly.vertices.size() - 2;
  r.poisson_faces = triangles;
  TriMesh& m = r.mesh;
  m.V.resize(static_cast<Eigen::Index>(meshPoints.size()), 3);
  for (std::size_t i = 0; i < meshPoints.size(); ++i)
    m.V.row(static_cast<Eigen::Index>(i)) = meshPoints[i].getVector3fMap().cast<double>().transpose();
  m.F.resize(static_cast<Eigen::Index>(triangles), 3);
  Eigen::Index nf = 0;
  const auto nv = static_cast<long long>(meshPoints.size());
  auto inRange = [nv](long long i) { return i >= 0 && i < nv; };
  for (const pcl::Vertices& poly : polygons) {
    for (std::size_t j = 2; j < poly.vertices.size(); ++j) {
      if (!inRange(poly.vertices[0]) || !inRange(poly.vertices[j - 1]) || !inRange(poly.vertices[j]))
        continue;
      m.F.row(nf++) << static_cast<int>(poly.vertices[0]), static_cast<int>(poly.vertices[j - 1]),
          static_cast<int>(poly.vertices[j]);
    }
  }
  m.F.conservativeResize(nf, 3);
}

// 5-6. The conversion to r.mesh, unused vertices, cavities and small pieces removed, small holes
// closed, then the body check, which flips inverted pieces (seconds_cleanup covers it all). Returns
// why there is no mesh, or "".
std::string cleanUp(const pcl::PointCloud<pcl::PointNormal>& meshPoints,
                    const std::vector<pcl::Vertices>& polygons, std::size_t points,
                    const ScanMeshingParams& params, ScanMeshingResult& r) {
  const auto t0 = Clock::now();
  toTriMesh(meshPoints, polygons, r);
  TriMesh& m = r.mesh;
  if (m.F.rows() == 0) {
    r.seconds_cleanup = since(t0);
    return "Poisson reconstruction produced no faces (" + std::to_string(points) + " points, depth " +
           std::to_string(r.depth) + ")";
  }
  removeUnusedVertices(m);
  if (params.remove_cavities) r.cavities_removed = removeCavities(m);
  r.dropped_pieces = dropSmallPieces(m, params.min_piece_fraction);
  r.holes_filled = closeSmallHoles(m, params.max_hole_edges, &r.hole_faces_added);
  r.check = orientBody(m);
  r.seconds_cleanup = since(t0);
  return "";
}

// 6. The final mesh's figures from its body check; returns why it is not a closed, outward body, or "".
std::string checkResult(ScanMeshingResult& r) {
  r.flipped = r.check.flipped;
  r.vertices = static_cast<std::size_t>(r.mesh.V.rows());
  r.faces = static_cast<std::size_t>(r.mesh.F.rows());
  r.closed = r.check.closed;
  r.boundary_edges = r.check.boundary_edges;
  r.non_manifold_edges = r.check.non_manifold_edges;
  r.signed_volume = r.check.signed_volume;
  if (!r.check.ok) return "reconstructed mesh unusable: " + r.check.message;
  if (!r.closed) return "reconstructed mesh is not closed: " + r.check.summary;
  if (!(r.signed_volume > 0) || r.check.orientation != BodyOrientation::Outward)
    return "reconstructed mesh is not outward: " + r.check.summary;
  return "";
}

}  // namespace

ScanMeshingResult meshScan(const MatrixX3d& points, const MatrixX3d& normals, const ScanMeshingParams& params) {
  const auto tStart = Clock::now();
  ScanMeshingResult r;
  r.input_points = static_cast<std::size_t>(points.rows());
  auto fail = [&](const std::string& message) {
    r.success = false;
    r.message = message;
    r.seconds_total = since(tStart);
    return r;
  };
  const std::string bad = checkInput(points, normals, params);
  if (!bad.empty()) return fail(bad);

  try {
    pcl::PointCloud<pcl::PointNormal>::Ptr cloud;
    std::string error = preparePoints(points, normals, params, cloud, r);
    if (!error.empty()) return fail(error);
    r.noise = estimateScanNoise(points);
    r.seconds_noise = r.noise.seconds;
    std::vector<int> knn;
    const bool orient = prepareNormals(cloud, normals.rows() > 0, params, knn, r);
    orientIfNeeded(*cloud, knn, params.normal_neighbours, orient, r);
    chooseDepth(*cloud, knn, params, r);
    pcl::PointCloud<pcl::PointNormal> meshPoints;
    std::vector<pcl::Vertices> polygons;
    reconstruct(cloud, params, meshPoints, polygons, r);
    error = cleanUp(meshPoints, polygons, cloud->size(), params, r);
    if (error.empty()) error = checkResult(r);
    if (!error.empty()) return fail(error);
    r.error = measureScanError(points, r.mesh, params.error_points);
    r.seconds_error = r.error.seconds;
    if (r.noise.sigma > 0) r.error_ratio = r.error.p95 / (1.959963984540054 * r.noise.sigma);
    r.success = true;
    r.message = r.check.summary;
    r.seconds_total = since(tStart);
    return r;
  } catch (const std::exception& e) {
    return fail(std::string("PCL failure: ") + e.what());
  } catch (...) {
    return fail("PCL failure: unknown exception");
  }
}

}  // namespace virtual_tryon
