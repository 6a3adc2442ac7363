// rostest: the demo bag (a raw scan of the procedural body, a garment mesh placed with
// penetrations, a skirt pattern) is replayed into tryon_node with auto_fit on and no service
// call. The node must mesh the scan into a closed, outward body, resolve the garment mesh and drape
// the pattern, and publish both fits, latched, with zero crossings by the referee, plus
// the markers.
#include "fixtures.h"
#include "marker_wait.h"
#include "virtual_tryon/core/geometry/mesh.h"
#include "virtual_tryon/core/scenes/procedural_body.h"
#include "virtual_tryon/testing/reference_bvh.h"
#include "virtual_tryon/testing/reference_check.h"
#include "virtual_tryon/ros/conversions.h"

#include <gtest/gtest.h>
#include <pcl_msgs/PolygonMesh.h>
#include <ros/ros.h>
#include <virtual_tryon/BodyReport.h>
#include <virtual_tryon/FitReport.h>

#include <cmath>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace vt = virtual_tryon;
using virtual_tryon_test::meshFromMsg;
using virtual_tryon_test::waitUntil;

namespace {

// Everything the node publishes, collected from the start of the replay.
struct Collector {
  std::mutex m;
  pcl_msgs::PolygonMesh::ConstPtr body;
  vt::BodyReport::ConstPtr body_report;
  std::vector<pcl_msgs::PolygonMesh::ConstPtr> garments;
  std::map<std::string, vt::FitReport::ConstPtr> reports;  // by kind
  std::vector<ros::Subscriber> subs;

  Collector() {
    ros::NodeHandle nh;
    subs.push_back(nh.subscribe<pcl_msgs::PolygonMesh>("/tryon_node/body", 2, [this](const auto& b) {
      std::lock_guard<std::mutex> l(m);
      body = b;
    }));
    subs.push_back(nh.subscribe<vt::BodyReport>("/tryon_node/body_report", 2, [this](const auto& r) {
      std::lock_guard<std::mutex> l(m);
      body_report = r;
    }));
    subs.push_back(nh.subscribe<pcl_msgs::PolygonMesh>("/tryon_node/fitted_garment", 10,
                                                       [this](const auto& g) {
                                                         std::lock_guard<std::mutex> l(m);
                                                         garments.push_back(g);
                                                       }));
    subs.push_back(nh.subscribe<vt::FitReport>("/tryon_node/fit_report", 10, [this](const auto& r) {
      std::lock_guard<std::mutex> l(m);
      reports[r->kind] = r;
    }));
  }

  // Waits (wall clock) until the body and a report of both kinds arrived.
  bool waitForAll(double seconds) {
    return waitUntil(
        [this] {
          std::lock_guard<std::mutex> l(m);
          return body && body_report && reports.count("resolve") && reports.count("drape");
        },
        seconds, 0.1);
  }

  // The garment published with the report of `kind` (same stamp). The two topics arrive in
  // either order, so it waits a little for the garment.
  pcl_msgs::PolygonMesh::ConstPtr garmentOf(const std::string& kind) {
    pcl_msgs::PolygonMesh::ConstPtr found;
    waitUntil(
        [&] {
          std::lock_guard<std::mutex> l(m);
          const auto r = reports.at(kind);
          for (const auto& g : garments)
            if (g->header.stamp == r->header.stamp) {
              found = g;
              return true;
            }
          return false;
        },
        10);
    return found;
  }
};

Collector* collector = nullptr;

}  // namespace

TEST(DemoReplay, AllFitsArriveWithoutAServiceCall) {
  ASSERT_TRUE(collector->waitForAll(200.0)) << "the body and both fits did not arrive in time";
}

TEST(DemoReplay, TheScanWasMeshedIntoAClosedOutwardBody) {
  ASSERT_TRUE(collector->body && collector->body_report);
  const vt::BodyReport& r = *collector->body_report;
  EXPECT_EQ(r.source, "scan");
  EXPECT_TRUE(r.normals_estimated);  // the demo scan has no normals, as a scanner gives it
  EXPECT_GT(r.scan_points, 10000u);
  // The scan's error bar: the demo scan has 2 mm noise; the mesh follows the points to within
  // 1.5x what that noise alone gives; fits clear the mesh by their clearance plus the 95% error.
  EXPECT_GE(r.poisson_depth, 6u);
  EXPECT_NEAR(r.noise_sigma, 0.002, 0.0005);
  EXPECT_GT(r.scan_error_median, 0.0);
  EXPECT_LE(r.scan_error_median, r.scan_error_p95);
  EXPECT_LE(r.scan_error_p95, r.scan_error_max);
  EXPECT_LE(r.scan_error_p95, 1.5 * 1.96 * r.noise_sigma);
  EXPECT_GT(r.scan_error_share_over_2mm, 0.0);
  EXPECT_DOUBLE_EQ(r.uncertainty, r.scan_error_p95);
  // Checked here on the mesh itself, not only from the node's report.
  const vt::TriMesh body = meshFromMsg(*collector->body);
  EXPECT_GT(body.numFaces(), 10000);
  EXPECT_TRUE(vt::edgeTopology(body).closed());
  // The procedural body encloses about 0.063 m^3; outward means a positive signed volume.
  EXPECT_GT(vt::signedVolume(body), 0.05);
  EXPECT_LT(vt::signedVolume(body), 0.08);
  EXPECT_EQ(collector->body->header.frame_id, "body");
}

TEST(DemoReplay, BothFittedGarmentsHaveNoCrossingsByTheReferee) {
  ASSERT_TRUE(collector->body);
  const vt::TriMesh body = meshFromMsg(*collector->body);
  // The referee's box tree (the brute-force count's own predicates): the meshed scan has ~87k
  // faces, and the brute-force pass over every edge-face pair took 346 s under the sanitizers.
  const vt::ReferenceReferee referee(body);
  for (const std::string kind : {"resolve", "drape"}) {
    SCOPED_TRACE(kind);
    const auto report = collector->reports.at(kind);
    EXPECT_TRUE(report->success) << report->message;
    EXPECT_EQ(report->body.source, "scan");
    const auto g = collector->garmentOf(kind);
    ASSERT_TRUE(g) << "no garment published with the " << kind << " report";
    EXPECT_EQ(g->header.frame_id, "body");
    const vt::TriMesh garment = meshFromMsg(*g);
    ASSERT_GT(garment.numFaces(), 100);
    const vt::ReferenceCounts c = referee.count(garment);
    EXPECT_EQ(c.garment_edge_crossings, 0u);
    EXPECT_EQ(c.body_edge_crossings, 0u);
    EXPECT_EQ(c.vertices_inside, 0u);
  }
  // The garment mesh came with penetrations: the resolver had work to do.
  const auto r = collector->reports.at("resolve")->resolve;
  EXPECT_DOUBLE_EQ(r.body_uncertainty, collector->body_report->uncertainty);
  EXPECT_GT(r.clearance, r.body_uncertainty);
  EXPECT_TRUE(r.converged) << r.reason;
  EXPECT_GT(r.garment_edge_crossings_before + r.body_edge_crossings_before, 10u);
  EXPECT_GT(r.moved_vertices, 10u);
  const auto d = collector->reports.at("drape")->drape;
  EXPECT_EQ(d.seams_open, 0u);
  EXPECT_GT(d.iterations, 10u);
}

TEST(DemoReplay, BothFittedGarmentsClearTheTrueBodyThatWasScanned) {
  // The bag's scan is of the procedural body: count against that truth, not against the mesh
  // (the referee's box tree, same predicates as the brute-force count: the sanitized run has a
  // time limit).
  const vt::ReferenceReferee truth(vt::makeProceduralBody());
  for (const std::string kind : {"resolve", "drape"}) {
    SCOPED_TRACE(kind);
    const auto g = collector->garmentOf(kind);
    ASSERT_TRUE(g);
    const vt::ReferenceCounts c = truth.count(meshFromMsg(*g));
    EXPECT_EQ(c.garment_edge_crossings, 0u);
    EXPECT_EQ(c.body_edge_crossings, 0u);
    EXPECT_EQ(c.vertices_inside, 0u);
  }
}

TEST(DemoReplay, MarkersShowTheBodyTheGarmentAndTheMovedVertices) {
  const virtual_tryon_test::NodeMarkers markers = virtual_tryon_test::waitForNodeMarkers();
  ASSERT_TRUE(markers.received);
  const auto *body = markers.body(), *garment = markers.garment(), *moved = markers.moved();
  ASSERT_TRUE(body && garment && moved);
  EXPECT_EQ(body->type, visualization_msgs::Marker::TRIANGLE_LIST);
  EXPECT_LT(body->color.a, 1.0f);  // semi-transparent
  EXPECT_EQ(garment->type, visualization_msgs::Marker::TRIANGLE_LIST);
  EXPECT_GT(garment->points.size(), 300u);
  // The fit map: a colour per triangle corner, by strain, not one colour for all.
  ASSERT_EQ(garment->colors.size(), garment->points.size());
  bool varies = false;
  for (const auto& c : garment->colors)
    varies = varies || std::abs(c.r - garment->colors[0].r) > 0.05f || std::abs(c.b - garment->colors[0].b) > 0.05f;
  EXPECT_TRUE(varies) << "every corner has the same colour";
  // The points are the vertices the last fit's resolver moved, one each, coloured by distance.
  const auto resolve = collector->reports.at("resolve"), drape = collector->reports.at("drape");
  const auto last = resolve->header.stamp > drape->header.stamp ? resolve : drape;
  const std::uint32_t movedCount = last->kind == "resolve" ? last->resolve.moved_vertices
                                                           : last->drape.resolver.moved_vertices;
  SCOPED_TRACE("last fit: " + last->kind);
  if (movedCount == 0) {
    EXPECT_EQ(moved->action, visualization_msgs::Marker::DELETE);
  } else {
    EXPECT_EQ(moved->type, visualization_msgs::Marker::POINTS);
    EXPECT_EQ(moved->points.size(), movedCount);
    EXPECT_EQ(moved->points.size(), moved->colors.size());
  }
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "demo_replay_test");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  Collector c;
  collector = &c;
  const int rc = RUN_ALL_TESTS();
  collector = nullptr;
  return rc;
}
