#include "virtual_tryon/core/resolve/penetration_resolver.h"

#include "core/resolve/resolver_run.h"

#include <sstream>
#include <string>

namespace virtual_tryon {
namespace {

// A closed body wound inside out: its inside tests and normals would push the garment the wrong
// way, so nothing moves.
ResolverReport refuseInsideOut(const Body& body, const resolver_run::Stopwatch& clock) {
  ResolverReport rep;
  rep.body_closed = body.closed();
  std::ostringstream reason;
  reason << "the body is inside out (closed, signed volume " << body.signedVolume()
         << " m^3 < 0): its faces must wind counter-clockwise seen from outside; nothing moved";
  rep.reason = reason.str();
  rep.seconds_total = clock.now();
  return rep;
}

// The stages of a run, in order (core/resolve/resolver_run.h).
ResolverReport runStages(resolver_run::ResolverRun& run, const ResolverParams& params) {
  run.detect();
  if (params.body_uncertainty > 0)
    run.pushOutNearVertices();
  else if (params.objective == ResolverObjective::Smooth && params.push_out_first && params.push_out_inside)
    run.pushOutInsideVertices();
  for (;;) {
    if (run.crossingFree()) {
      if (run.decideStopCrossingFree()) break;
      run.pushOutInsidePieces();
    } else if (run.decideStop() || !run.solveRound()) {
      break;
    }
  }
  run.relaxShape();
  return run.finish();
}

}  // namespace

ResolverReport resolvePenetrations(const Body& body, TriMesh& garment, const ResolverParams& params) {
  const resolver_run::Stopwatch clock;
  if (body.closed() && body.signedVolume() < 0) return refuseInsideOut(body, clock);
  resolver_run::ResolverRun run(body, garment, params, clock);
  return runStages(run, params);
}

ResolverReport resolvePenetrationsFrom(const Body& body, const TriMesh& input, TriMesh& garment,
                                       const ResolverParams& params) {
  const resolver_run::Stopwatch clock;
  if (body.closed() && body.signedVolume() < 0) return refuseInsideOut(body, clock);
  if (input.V.rows() != garment.V.rows() || input.F.rows() != garment.F.rows() || input.F != garment.F) {
    ResolverReport rep;
    rep.reason = "the warm start has " + std::to_string(garment.V.rows()) + " vertices and " +
                 std::to_string(garment.F.rows()) + " faces, its input " + std::to_string(input.V.rows()) +
                 " and " + std::to_string(input.F.rows()) + ": they must share faces and vertex order; nothing moved";
    rep.seconds_total = clock.now();
    return rep;
  }
  resolver_run::ResolverRun run(body, input, garment, params, clock);
  return runStages(run, params);
}

MatrixX3d warmStart(const MatrixX3d& input, const MatrixX3d& correction, double minCarried) {
  MatrixX3d start = input;
  if (correction.rows() != input.rows() || correction.cols() != input.cols()) return start;
  for (Eigen::Index v = 0; v < input.rows(); ++v)
    if (correction.row(v).norm() >= minCarried) start.row(v) += correction.row(v);
  return start;
}

double defaultWarmStartMin(const ResolverParams& params) {
  return params.warm_local_relaxation ? 0.0 : kWarmStartMinCorrection;
}

ResolverReport resolveFrame(const Body& body, TriMesh& garment, const PreviousFrame& previous,
                            const ResolverParams& params, double minCarried, FrameStart* start) {
  if (minCarried < 0) minCarried = defaultWarmStartMin(params);
  FrameStart how = FrameStart::Cold;
  ResolverReport rep;
  const MatrixX3d& correction = previous.correction;
  if (correction.rows() == garment.V.rows() && correction.cols() == 3) {
    TriMesh warm{warmStart(garment.V, correction, minCarried), garment.F};
    ResolverParams warmParams = params;
    if (params.warm_local_relaxation && previous.input.rows() == garment.V.rows() && previous.input.cols() == 3) {
      warmParams.relaxation.local_previous_input = previous.input;
      warmParams.relaxation.local_previous_result = previous.input + correction;
    }
    rep = resolvePenetrationsFrom(body, garment, warm, warmParams);
    if (rep.converged) {
      garment = std::move(warm);
      how = FrameStart::Warm;
    } else {
      const double warmSeconds = rep.seconds_total;
      rep = resolvePenetrations(body, garment, params);
      rep.seconds_total += warmSeconds;
      how = FrameStart::WarmFailedResolvedCold;
    }
  } else {
    rep = resolvePenetrations(body, garment, params);
  }
  if (start) *start = how;
  return rep;
}

}  // namespace virtual_tryon
