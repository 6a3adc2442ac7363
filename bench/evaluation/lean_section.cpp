// Section 5: leaving out what a scene does not need. The cost of a second call on an unchanged
// body, of a garment with no penetration, and of a frame with only a few penetrating vertices
// against their number, for several garment and body sizes.
#include "common.h"

#include "virtual_tryon/core/io/pattern_yaml.h"
#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/drape/drape.h"
#include "virtual_tryon/core/resolve/intersections.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/geometry/point_queries.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/core/scenes/procedural_body.h"
#include "virtual_tryon/testing/reference_bvh.h"

#include <algorithm>

namespace eval {

void leanSection(const Options& o) {
  const int runs = o.quick ? 3 : 15;
  // (a) First and second call on one body: the second builds no BVH and renders no map. Each the
  // fastest of `runs` fresh bodies.
  Csv calls(o.out + "/lean_calls.csv",
            {"what", "first_call_s", "second_call_s", "built_on_first_call_s", "builds_after_two_calls"});
  {
    vt::ResolveScene s = vt::makeWrinkledTubeScene(64, 40);
    double first = 1e30, second = 1e30, build = 1e30;
    for (int r = 0; r < runs; ++r) {
      vt::Body body(s.body);
      vt::TriMesh g1 = s.garment, g2 = s.garment;
      const double t0 = now();
      vt::resolvePenetrations(body, g1);
      first = std::min(first, now() - t0);
      const double t1 = now();
      vt::resolvePenetrations(body, g2);
      second = std::min(second, now() - t1);
      build = std::min(build, body.bvhBuildSeconds());
    }
    calls.row({"resolve: the wrinkled tube on a new capsule Body, then again (BVH)", first, second, build, 1});
    summary().set("lean.resolve_first_call_s", first);
    summary().set("lean.resolve_second_call_s", second);
    summary().set("lean.resolve_bvh_build_s", build);
  }
  {
    vt::ProceduralBodyParams bp;
    bp.resolution = o.quick ? 0.025 : 0.015;
    const vt::TriMesh mesh = vt::makeProceduralBody(bp);
    vt::Pattern pattern;
    std::string err;
    if (vt::readPatternYaml(o.patterns + "/procedural/skirt.yaml", pattern, err)) {
      vt::DrapeParams p;
      p.spacing = 0.05;
      p.max_iterations = 50;  // the setup is the point here, not the drape
      p.resolve = false;
      double first = 1e30, second = 1e30, render = 1e30;
      int renders = 0;
      for (int r = 0; r < std::min(runs, 5); ++r) {
        vt::Body body(mesh);
        vt::TriMesh out;
        const vt::DrapeResult a = vt::drape(body, pattern, p, out);
        const vt::DrapeResult b = vt::drape(body, pattern, p, out);
        first = std::min(first, a.seconds_setup);
        second = std::min(second, b.seconds_setup);
        render = std::min(render, body.depthMaps(p.collision)->buildSeconds());
        renders = body.depthMapRenders();
      }
      calls.row({"drape setup: the skirt on a new procedural Body, then again (depth maps)", first, second, render,
                 renders});
      summary().set("lean.drape_map_renders_after_two_drapes", renders);
      summary().set("lean.drape_setup_first_s", first);
      summary().set("lean.drape_setup_second_s", second);
    } else {
      summary().note("lean: " + err);
    }
  }

  // (b) + (c) A clean garment, then k of its vertices pushed 5 mm inside, for several sizes.
  Csv few(o.out + "/lean_few.csv",
          {"garment_vertices", "body_faces", "penetrating_vertices", "time_median_s", "time_min_s",
           "first_pass_min_s", "after_first_pass_min_s", "iterations", "trace_entries", "crossings_before",
           "crossings_after_independent", "inside_after_independent", "detection_pass_s"});
  struct Size {
    int segments, rings;
    bool body4x;
  };
  const std::vector<Size> sizes = o.quick ? std::vector<Size>{{64, 40, false}, {64, 40, true}}
                                          : std::vector<Size>{{64, 40, false}, {128, 80, false}, {128, 80, true},
                                                              {256, 160, false}, {362, 137, false}};
  bool cleanZeroIterations = true;
  for (const Size& sz : sizes) {
    vt::ResolveScene s = vt::makeWrinkledTubeScene(sz.segments, sz.rings);
    if (sz.body4x) s.body = vt::subdivideMidpoint(vt::subdivideMidpoint(s.body));
    vt::Body body(s.body);
    body.bvh();
    vt::resolvePenetrations(body, s.garment);  // now clean
    const vt::ReferenceReferee ref(s.body);
    progress("lean: %ld garment vertices, %ld body faces", static_cast<long>(s.garment.V.rows()),
             static_cast<long>(s.body.F.rows()));
    // One bare detection pass on the clean garment, for reference.
    const vt::GarmentTopology topo(s.garment);
    const Timing detect = timeRuns(runs, [&] {
      vt::CrossingSet cs;
      vt::detectCrossings(body, s.garment, topo, cs);
    });
    const std::vector<int> ks = o.quick ? std::vector<int>{0, 1, 4, 16}
                                        : std::vector<int>{0, 1, 2, 4, 8, 16, 32, 64, 128, 256, 512};
    for (int k : ks) {
      vt::TriMesh g = s.garment;
      // k vertices spread over the garment, each moved 5 mm behind its nearest body face.
      const Eigen::Index n = g.V.rows();
      for (int i = 0; i < k; ++i) {
        const Eigen::Index v = (static_cast<Eigen::Index>(i) * n) / k + (n / (2 * k));
        const vt::ClosestPoint cp = vt::closestPointOnBody(body, g.V.row(v).transpose());
        g.V.row(v) = (cp.point - 0.005 * body.faceNormals().row(cp.face).transpose()).transpose();
      }
      // The resolver's own split of each call: the first pass (detection over the whole garment and
      // the inside test) and everything after it (stencils, solves, re-detection round the moved
      // faces); each the fastest of the runs, the least disturbed by other load.
      vt::ResolverReport rep;
      vt::TriMesh out;
      double firstPass = 1e30, after = 1e30;
      const Timing t = timeRuns(runs, [&] {
        vt::TriMesh h = g;
        rep = vt::resolvePenetrations(body, h);
        firstPass = std::min(firstPass, rep.trace.front().seconds);
        after = std::min(after, rep.seconds_total - rep.trace.front().seconds);
        out = std::move(h);
      });
      const vt::ReferenceCounts c = ref.count(out);
      if (k == 0 && (rep.iterations != 0 || rep.trace.size() != 1)) cleanZeroIterations = false;
      few.row({static_cast<long>(n), static_cast<long>(s.body.F.rows()), k, t.median, t.min, firstPass, after,
               rep.iterations, rep.trace.size(), rep.garment_edge_crossings_before + rep.body_edge_crossings_before,
               c.garment_edge_crossings + c.body_edge_crossings, c.vertices_inside, detect.min});
    }
  }
  summary().set("lean.clean_garment_zero_iterations", cleanZeroIterations);
}

}  // namespace eval
