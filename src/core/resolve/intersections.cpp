#include "virtual_tryon/core/resolve/intersections.h"

#include "virtual_tryon/core/geometry/edge_face_crossing.h"

#include "core/geometry/body_bvh.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <thread>
#include <tuple>

namespace virtual_tryon {

namespace {

Eigen::Vector3d row(const MatrixX3d& V, int i) { return V.row(i).transpose(); }

bool sameKey(const EdgeFaceCrossing& a, const EdgeFaceCrossing& b) {
  return a.edge == b.edge && a.face == b.face;
}
bool lessKey(const EdgeFaceCrossing& a, const EdgeFaceCrossing& b) {
  return std::tie(a.edge, a.face) < std::tie(b.edge, b.face);
}
void sortUnique(std::vector<EdgeFaceCrossing>& v) {
  std::sort(v.begin(), v.end(), lessKey);
  v.erase(std::unique(v.begin(), v.end(), sameKey), v.end());
}

}  // namespace

GarmentTopology::GarmentTopology(const TriMesh& garment) { edges = uniqueEdges(garment, &face_edges); }

namespace {

// Whether a segment whose end-points lie at sa, sb (unnormalised, as segmentCrossesTriangle()
// computes them) crosses the plane by that predicate's convention.
bool crossesPlane(double sa, double sb) {
  return (sa < 0 && sb > 0) || (sa > 0 && sb < 0) || (sa == 0 && sb < 0) || (sb == 0 && sa < 0);
}

// Signed (unnormalised) distances of q0, q1, q2 from the plane through p0 with normal
// n = (p1 - p0) x (p2 - p0), computed exactly as segmentCrossesTriangle() computes them, so that a
// segment it would see cross is never skipped.
Eigen::Vector3d planeSides(const Eigen::Vector3d& n, const Eigen::Vector3d& p0, const Eigen::Vector3d& q0,
                           const Eigen::Vector3d& q1, const Eigen::Vector3d& q2) {
  return Eigen::Vector3d(n.dot(q0 - p0), n.dot(q1 - p0), n.dot(q2 - p0));
}

// Whether three plane sides (as planeSides() gives them) lie all beyond m on the same side.
bool allOneSide(const Eigen::Vector3d& s, double m) { return (s.array() > m).all() || (s.array() < -m).all(); }

// A body face at least this far (m) from a garment face's plane, on one side, crosses it in neither
// direction; the margin is far above the rounding of the predicate, so the shortcut never hides a
// crossing that the predicate would report (watertightness at shared edges included).
constexpr double kPlaneMargin = 1e-9;

// What testFacePair() needs of one garment face, taken once per face: its corners, its normal
// gn = (x1 - x0) x (x2 - x0), gm = kPlaneMargin |gn|, and the body's edge lists.
struct GarmentFaceContext {
  int gf = -1;
  Eigen::Vector3d x[3];
  Eigen::Vector3d gn;
  double gm = 0;
  const MatrixX2i* body_edges = nullptr;
  const MatrixX3i* body_face_edges = nullptr;
  const std::vector<int>* body_edge_first_face = nullptr;
};

// The crossings of garment face g.gf's three edges with body face bf, and of bf's three edges with
// g.gf. An edge is tested only when its end-points lie on opposite sides of the other face's plane
// (the predicate's own first test, done once per pair instead of once per edge); a body face
// wholly on one side of gf's plane (by kPlaneMargin) crosses nothing. Side k of a face (face_edges
// column k, uniqueEdges()) joins its corners k and k + 1.
void testFacePair(const Body& body, const TriMesh& garment, const GarmentTopology& topo, int bf,
                  const GarmentFaceContext& g, CrossingSet& out) {
  const MatrixX3d& BV = body.mesh().V;
  const MatrixX3i& BF = body.mesh().F;
  const Eigen::Vector3d y[3] = {row(BV, BF(bf, 0)), row(BV, BF(bf, 1)), row(BV, BF(bf, 2))};
  const Eigen::Vector3d sy = planeSides(g.gn, g.x[0], y[0], y[1], y[2]);  // body corners to gf
  if (allOneSide(sy, g.gm)) return;
  const Eigen::Vector3d bn = crossProduct(y[1] - y[0], y[2] - y[0]);
  const Eigen::Vector3d sx = planeSides(bn, y[0], g.x[0], g.x[1], g.x[2]);  // garment corners to bf
  const MatrixX3d& GV = garment.V;
  const MatrixX2i& BE = *g.body_edges;
  const MatrixX3i& BFE = *g.body_face_edges;
  EdgeFaceHit hit;
  for (int k = 0; k < 3; ++k) {
    const int next = k == 2 ? 0 : k + 1;
    if (crossesPlane(sx[k], sx[next])) {
      const int ge = topo.face_edges(g.gf, k);
      const int ga = topo.edges(ge, 0), gb = topo.edges(ge, 1);
      if (segmentCrossesTriangle(row(GV, ga), row(GV, gb), y[0], y[1], y[2], &hit))
        out.garment_edges.push_back({ge, bf, hit.t, hit.bary, hit.sa, hit.sb});
    }
    // A body edge through gf passes through both of its faces' boxes, and so through gf's: both
    // pairs are visited, and the edge is tested from its first face alone (the same crossings).
    const int be = BFE(bf, k);
    if ((*g.body_edge_first_face)[static_cast<std::size_t>(be)] == bf && crossesPlane(sy[k], sy[next])) {
      const int ba = BE(be, 0), bb = BE(be, 1);
      if (segmentCrossesTriangle(row(BV, ba), row(BV, bb), g.x[0], g.x[1], g.x[2], &hit))
        out.body_edges.push_back({be, g.gf, hit.t, hit.bary, hit.sa, hit.sb});
    }
  }
}

}  // namespace

namespace {

// The body's edge lists, taken once for many faces (faceContext).
GarmentFaceContext bodyContext(const Body& body) {
  GarmentFaceContext g;
  g.body_edges = &body.edges();
  g.body_face_edges = &body.faceEdges();
  g.body_edge_first_face = &body.edgeFirstFaces();
  return g;
}

// What testFacePair() needs of garment face gf, over `body` (bodyContext()).
GarmentFaceContext faceContext(const GarmentFaceContext& body, const TriMesh& garment, int gf) {
  GarmentFaceContext g = body;
  g.gf = gf;
  for (int k = 0; k < 3; ++k) g.x[k] = row(garment.V, garment.F(gf, k));
  g.gn = crossProduct(g.x[1] - g.x[0], g.x[2] - g.x[0]);
  g.gm = kPlaneMargin * g.gn.norm();
  return g;
}

// Face gf's bounding box.
void faceBounds(const TriMesh& garment, int gf, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  lo = hi = row(garment.V, garment.F(gf, 0));
  for (int k = 1; k < 3; ++k) {
    lo = lo.cwiseMin(row(garment.V, garment.F(gf, k)));
    hi = hi.cwiseMax(row(garment.V, garment.F(gf, k)));
  }
}

// Garment faces taken a run at a time by detectRuns(), and how much larger than its largest face
// a run's joint box may be (a longer run's faces do not lie side by side: each face asks alone).
constexpr int kRunFaces = 4;
constexpr double kRunSpread = 2.5;

// The crossings of the garment faces first .. last with the body, without a cache. Consecutive
// faces of a mesh mostly lie side by side, so the tree is asked once for a run of them (their
// joint box), and each face's own box is tested against the run's body faces: the same pairs as a
// query per face, in a quarter of the tree's walks.
void detectRuns(const Body& body, const TriMesh& garment, const GarmentTopology& topo, const FaceBoxTree& tree,
                int first, int last, CrossingSet& out) {
  const GarmentFaceContext lists = bodyContext(body);
  std::vector<int> candidates;
  Eigen::Vector3d lo[kRunFaces], hi[kRunFaces];
  for (int start = first; start < last; start += kRunFaces) {
    const int n = std::min(kRunFaces, last - start);
    Eigen::Vector3d runLo, runHi;
    double largest = 0;
    for (int j = 0; j < n; ++j) {
      faceBounds(garment, start + j, lo[j], hi[j]);
      runLo = j == 0 ? lo[j] : Eigen::Vector3d(runLo.cwiseMin(lo[j]));
      runHi = j == 0 ? hi[j] : Eigen::Vector3d(runHi.cwiseMax(hi[j]));
      largest = std::max(largest, (hi[j] - lo[j]).maxCoeff());
    }
    const bool together = (runHi - runLo).maxCoeff() <= kRunSpread * largest;
    if (together) {
      candidates.clear();
      tree.overlapping(runLo, runHi, [&](int bf) { candidates.push_back(bf); });
    }
    for (int j = 0; j < n; ++j) {
      const GarmentFaceContext g = faceContext(lists, garment, start + j);
      auto test = [&](int bf) { testFacePair(body, garment, topo, bf, g, out); };
      if (!together) {
        tree.overlapping(lo[j], hi[j], test);
        continue;
      }
      for (int bf : candidates)
        if (tree.faceOverlaps(bf, lo[j], hi[j])) test(bf);
    }
  }
}

// The crossings of the garment faces faces[first .. last) (or faces first .. last) with the body;
// with a cache, each face's candidates come from it where still valid (and are refreshed in it
// where not: each face's entry is written by the one thread that owns the face).
void detectRange(const Body& body, const TriMesh& garment, const GarmentTopology& topo, const FaceBoxTree& tree,
                 const std::vector<int>* faces, int first, int last, CrossingSet& out,
                 CandidateCache* cache = nullptr, std::size_t* reused = nullptr) {
  if (!faces && !cache) {
    detectRuns(body, garment, topo, tree, first, last, out);
    return;
  }
  const GarmentFaceContext lists = bodyContext(body);
  for (int i = first; i < last; ++i) {
    const int gf = faces ? (*faces)[static_cast<std::size_t>(i)] : i;
    Eigen::Vector3d lo, hi;
    faceBounds(garment, gf, lo, hi);
    const GarmentFaceContext g = faceContext(lists, garment, gf);
    auto test = [&](int bf) { testFacePair(body, garment, topo, bf, g, out); };
    if (!cache) {
      tree.overlapping(lo, hi, test);
      continue;
    }
    const std::size_t c = static_cast<std::size_t>(gf);
    if (cache->valid[c] && (lo.array() >= cache->lo[c].array()).all() && (hi.array() <= cache->hi[c].array()).all()) {
      ++*reused;
    } else {
      cache->lo[c] = lo.array() - cache->margin;
      cache->hi[c] = hi.array() + cache->margin;
      cache->faces[c].clear();
      tree.overlapping(cache->lo[c], cache->hi[c], [&](int bf) { cache->faces[c].push_back(bf); });
      cache->valid[c] = 1;
    }
    // The same pairs as the tree gives for the face's own box: every candidate whose box (the
    // tree's own) overlaps it.
    for (int bf : cache->faces[c])
      if (tree.faceOverlaps(bf, lo, hi)) test(bf);
  }
}

// Below this many garment faces one thread does the detection (starting a thread costs more than
// it saves); at most this many threads.
constexpr int kParallelFaces = 384;
constexpr unsigned kMaxThreads = 8;

int detectionThreads(int faces) {
  if (faces < kParallelFaces) return 1;
  const unsigned hw = std::max(1u, std::min(std::thread::hardware_concurrency(), kMaxThreads));
  return static_cast<int>(std::min<unsigned>(hw, static_cast<unsigned>(faces / (kParallelFaces / 2))));
}

}  // namespace

// Candidate pairs are the (body face, garment face) pairs whose bounding boxes overlap, from the
// body's box tree (built once with the body) and one box query per garment face; every crossing
// lies in such a pair, and the segment tests decide. Many faces are shared out among threads
// started for this call (one per hardware thread, at most 8; none outlives the call, so a process
// may fork at any time), each with its own list; the lists are joined, sorted and made unique, so
// the result does not depend on the number of threads.
namespace {
void detectCrossingsWith(const Body& body, const TriMesh& garment, const GarmentTopology& topo,
                         CrossingSet& out, const std::vector<int>* faces, CandidateCache* cache);
}  // namespace

void detectCrossings(const Body& body, const TriMesh& garment, const GarmentTopology& topo,
                     CrossingSet& out, const std::vector<int>* faces) {
  detectCrossingsWith(body, garment, topo, out, faces, nullptr);
}

void detectCrossings(const Body& body, const TriMesh& garment, const GarmentTopology& topo,
                     CrossingSet& out, const std::vector<int>* faces, CandidateCache& cache) {
  const std::size_t nf = static_cast<std::size_t>(garment.F.rows());
  if (cache.valid.size() != nf) {
    cache.lo.assign(nf, Eigen::Vector3d::Zero());
    cache.hi.assign(nf, Eigen::Vector3d::Zero());
    cache.faces.assign(nf, {});
    cache.valid.assign(nf, 0);
  }
  detectCrossingsWith(body, garment, topo, out, faces, &cache);
}

namespace {
void detectCrossingsWith(const Body& body, const TriMesh& garment, const GarmentTopology& topo,
                         CrossingSet& out, const std::vector<int>* faces, CandidateCache* cache) {
  out.garment_edges.clear();
  out.body_edges.clear();
  if (garment.F.rows() == 0 || body.mesh().F.rows() == 0) return;
  if (faces && faces->empty()) return;
  const FaceBoxTree& tree = body.bvh().faceTree();
  body.edges();  // the body's adjacency, built before any thread reads it
  const int n = faces ? static_cast<int>(faces->size()) : static_cast<int>(garment.F.rows());
  const int threads = detectionThreads(n);
  std::vector<std::size_t> reused(static_cast<std::size_t>(threads), 0);
  if (threads == 1) {
    detectRange(body, garment, topo, tree, faces, 0, n, out, cache, &reused[0]);
  } else {
    std::vector<CrossingSet> part(static_cast<std::size_t>(threads));
    auto range = [&](int t) {
      detectRange(body, garment, topo, tree, faces, static_cast<int>(static_cast<long long>(n) * t / threads),
                  static_cast<int>(static_cast<long long>(n) * (t + 1) / threads), part[static_cast<std::size_t>(t)],
                  cache, &reused[static_cast<std::size_t>(t)]);
    };
    std::vector<std::thread> workers;
    for (int t = 1; t < threads; ++t) workers.emplace_back(range, t);
    range(0);
    for (auto& w : workers) w.join();
    for (const CrossingSet& c : part) {
      out.garment_edges.insert(out.garment_edges.end(), c.garment_edges.begin(), c.garment_edges.end());
      out.body_edges.insert(out.body_edges.end(), c.body_edges.begin(), c.body_edges.end());
    }
  }
  if (cache) {
    std::size_t r = 0;
    for (std::size_t x : reused) r += x;
    cache->reused += r;
    cache->queried += static_cast<std::size_t>(n) - r;
  }
  sortUnique(out.garment_edges);
  sortUnique(out.body_edges);
}
}  // namespace

}  // namespace virtual_tryon
