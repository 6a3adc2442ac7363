#include "virtual_tryon/core/resolve/penetration_resolver.h"

#include "core/resolve/resolver_run.h"

#include <sstream>

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

}  // namespace

// The stages of a run are the methods of resolver_run::ResolverRun (core/resolve/resolver_run.h).
ResolverReport resolvePenetrations(const Body& body, TriMesh& garment, const ResolverParams& params) {
  const resolver_run::Stopwatch clock;
  if (body.closed() && body.signedVolume() < 0) return refuseInsideOut(body, clock);
  resolver_run::ResolverRun run(body, garment, params, clock);
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

}  // namespace virtual_tryon
