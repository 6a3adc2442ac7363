// Internal to the core: one call of resolvePenetrations() (penetration_resolver.h) as an object whose
// methods are the run's stages, so that a stage can be added without threading the run's shared
// state (garment graph, crossings, inside flags, undo log, report) through one long function.
//
// resolvePenetrations() calls them in this order:
//   detect()                      the first full detection and, for a closed body, the inside flags
//   then, step by step until one of them says stop:
//     with no crossing left:      decideStopCrossingFree(), else pushOutInsidePieces()
//     otherwise:                  decideStop(), else solveRound() (which stops when nothing moved)
//   relaxShape()                  converged, smooth objective: the shape relaxation
//   finish()                      the final counts, displacement and strain statistics; the report
// A stage after the loop (say, for a converged garment) goes between the loop and finish(): every
// move goes through moveVertex() and redetect(), which keep the crossings, the inside flags and
// the displacement statistics up to date.
#pragma once

#include "core/resolve/face_clearance.h"
#include "virtual_tryon/core/geometry/point_queries.h"
#include "virtual_tryon/core/resolve/impact_zones.h"
#include "virtual_tryon/core/resolve/intersections.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/resolve/stencils.h"

#include <chrono>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <unordered_map>
#include <vector>

namespace virtual_tryon {
namespace resolver_run {

using Clock = std::chrono::steady_clock;

// Wall clock of the call without the time spent in the observer.
class Stopwatch {
 public:
  Stopwatch() : start_(Clock::now()) {}
  double now() const { return std::chrono::duration<double>(Clock::now() - start_).count() - excluded_; }
  template <class F>
  void exclude(F&& f) {
    const auto t0 = Clock::now();
    f();
    excluded_ += std::chrono::duration<double>(Clock::now() - t0).count();
  }

 private:
  Clock::time_point start_;
  double excluded_ = 0;
};

// |l / l0 - 1| of edge (a, b) at positions `at` (#V by 3) against `input` (#V by 3); 0 for an edge
// of length 0 in `input`.
inline double edgeStrain(const MatrixX3d& input, const MatrixX3d& at, int a, int b) {
  const double l0 = (input.row(a) - input.row(b)).norm();
  return l0 > 0 ? std::abs((at.row(a) - at.row(b)).norm() / l0 - 1) : 0.0;
}

// Garment connectivity a run needs, built once per call: the faces round each vertex, the
// neighbours over edges, and the connected pieces.
struct GarmentGraph {
  std::vector<int> vf_start, vf;              // faces of vertex v: vf[vf_start[v] .. vf_start[v+1])
  std::vector<int> adj_start, adj_v, adj_e;   // neighbours of v and the edge to each
  std::vector<int> piece;                     // per vertex; -1 for a vertex on no edge
  std::vector<int> piece_start, piece_members;
  int pieces = 0;

  GarmentGraph(const TriMesh& garment, const GarmentTopology& topo);
  int pieceSize(int p) const { return piece_start[p + 1] - piece_start[p]; }
};

}  // namespace resolver_run

struct GarmentConnectivity {
  explicit GarmentConnectivity(const TriMesh& garment)
      : vertices(garment.V.rows()), faces(garment.F.rows()), topo(garment), graph(garment, topo) {}
  Eigen::Index vertices, faces;
  GarmentTopology topo;
  resolver_run::GarmentGraph graph;
};

namespace resolver_run {

// `given` when it was built for a garment of this one's vertex and face counts, else built here.
std::shared_ptr<const GarmentConnectivity> connectivityFor(const TriMesh& garment,
                                                           const std::shared_ptr<const GarmentConnectivity>& given);

// The shape relaxation (shape_relaxation.h) over a run's garment graph, so the run does not build
// the graph a second time.
// `candidates`, when given: the run's candidate cache (the faces' body faces found by the rounds'
// detections, reused by the relaxation's checks while a face stays in its box).
ShapeRelaxationReport relaxShape(const Body& body, const TriMesh& input, TriMesh& garment,
                                 const GarmentTopology& topo, const GarmentGraph& graph, double clearance,
                                 const ShapeRelaxationParams& params, CandidateCache* candidates = nullptr);

class ResolverRun {
 public:
  // `clock` was started when the call began (the run's times count from there). Builds the
  // garment's topology and graph and fixes the clearance; detects nothing yet. The body must not
  // be inside out (resolvePenetrations() refuses that before a run exists).
  ResolverRun(const Body& body, TriMesh& garment, const ResolverParams& params, const Stopwatch& clock);
  // A warm start: `garment` starts elsewhere than the garment's own `input` (same faces and vertex
  // order), which the shape relaxation, strain and displacement are measured against.
  ResolverRun(const Body& body, const TriMesh& input, TriMesh& garment, const ResolverParams& params,
              const Stopwatch& clock);

  void detect();
  // Every vertex found inside, to its nearest body point plus the clearance (the rounds then clear
  // what a vertex move cannot see: edges through the body, body edges through the garment).
  void pushOutInsideVertices();
  bool crossingFree() const { return crossings_.size() == 0; }
  // The stop checks of a step with no crossing left (converged, pieces wholly inside that may not
  // or cannot be pushed out, budget); true to stop. Else pushOutInsidePieces() is next.
  bool decideStopCrossingFree();
  void pushOutInsidePieces();
  // body_uncertainty > 0: every vertex inside the body or nearer to it than the clearance goes to
  // its nearest body point plus the clearance (before the rounds).
  void pushOutNearVertices();
  void liftFaceMiddles(const std::vector<double>& distance);
  // The stop checks before a round (iteration limit, stall, budget); true to stop, in the best state.
  bool decideStop();
  // One round; false when it moved nothing (the run stops, in the best state).
  bool solveRound();
  // For a converged run with the smooth objective: the shape relaxation (shape_relaxation.h),
  // which keeps the garment free of crossings; false when it does not apply.
  bool relaxShape();
  std::vector<int> movedByRounds() const;
  // The last stage: the report, moved out of the run.
  ResolverReport finish();

 private:
  // An entry of the undo log: a vertex's position and inside flag before its first move since
  // the last new best.
  struct Undo {
    int v;
    Eigen::RowVector3d x;
    char inside;
  };

  // The error the run drives down, and judges progress and the best state by: crossings plus
  // garment vertices inside (the crossings alone can stay level while a deep region shrinks).
  std::size_t error() const { return crossings_.size() + insideCount_; }
  bool budgetSpent() const { return params_.time_budget > 0 && clock_.now() >= params_.time_budget; }
  void record(ResolverIteration it);
  void newBest();
  void restoreBest();
  void describeBest();
  void moveVertex(int v, const Eigen::RowVector3d& to);
  // The nearest body point of each listed vertex, on the hardware threads.
  std::vector<ClosestPoint> nearestBodyPoints(const std::vector<int>& vertices) const;
  void pushTo(int v, const ClosestPoint& cp);  // to cp.point plus the clearance along its face normal
  void finishPushOut(double t0, bool alwaysNewBest);
  void redetect();
  void redetectFaces();
  void reclassifyMoved();
  void spread(const std::unordered_map<int, int>& flips);
  std::size_t insideNow(std::vector<int>& insidePieces);
  std::vector<Stencil> roundStencils(ResolverIteration& it);
  void solveZones(const std::vector<Stencil>& stencils, ResolverIteration& it);
  void apply(const ZoneSolution& sol);
  void stopNothingMoved();
  void displacementStats();
  void shapeStats();

  const Body& body_;
  TriMesh& garment_;
  const TriMesh input_;  // the garment as it came in (or its own input, for a warm start)
  const ResolverParams& params_;
  Stopwatch clock_;
  ResolverReport rep_;
  std::ostringstream reason_;
  const int nv_;
  const std::shared_ptr<const GarmentConnectivity> connectivity_;  // given, or built for this call
  const GarmentTopology& topo_;
  const GarmentGraph& graph_;
  const double d_;  // the clearance
  const bool insideTest_;
  const bool warm_;  // started from a garment other than the input (resolvePenetrationsFrom)

  CrossingSet crossings_;
  // Each garment face's candidate body faces, kept by every detection of the run and the
  // relaxation's checks (intersections.h): the same crossings, fewer box-tree queries.
  CandidateCache candidates_;
  // Inside flags before any move, and per piece how many of its vertices are inside. A vertex that
  // never moves keeps its flag; after a round only the moved vertices are classified again, from
  // a neighbour across the crossings of the edge between them (or one ray test for a region
  // with no known neighbour).
  std::vector<char> insideBefore_, inside_;
  std::vector<int> pieceInsideBefore_;
  std::size_t insideCount_ = 0;

  // Per-vertex and per-face flags for the rounds (allocated with the first pass).
  std::vector<char> touched_, logged_, faceMark_, dirtyFace_, dirtyEdge_, unknown_, everIllegal_, pieceMark_;

  // Every vertex that moved, with its start position (for the displacement statistics and the
  // inside test), and an undo log back to the state with the smallest error.
  std::vector<int> touchedList_;
  std::vector<Eigen::RowVector3d> startPos_;
  std::vector<Undo> undo_;
  CrossingSet bestCrossings_;
  std::size_t best_ = 0, bestInside_ = 0;
  int sinceBest_ = 0;

  std::vector<int> movedList_;  // this step
  std::vector<int> dirty_, queue_;
  std::vector<int> insidePieces_;
  bool pushedOut_ = false;
  std::size_t infeasibleLastRound_ = 0;
};

}  // namespace resolver_run
}  // namespace virtual_tryon
