// rostest: the animation bag (make_animation_bag --procedural --frames 12: the procedural body
// swaying, the demo's waist tube skinned with it, one ~body_mesh and one ~garment_mesh per frame at
// 30 Hz) is replayed into tryon_node with auto_fit on. Every body message after the first has the
// same faces: the node installs it as a frame of that body (refitted, not rebuilt) and fits the
// latest garment on it. Every fitted garment the node publishes is checked against its own frame's
// body (regenerated here, found by the stamp) by the referee; every frame is fitted or counted as
// dropped; the last one is fitted.
//
// The test also publishes a pattern (the procedural sleeveless shirt) on ~garment_pattern: the node
// drapes it on the first body frame it meets and then wears it, each later frame stepping that cloth
// to the frame (WornGarment::follow; its report says "worn garment stepped"). Each worn frame the
// node publishes is checked by the referee against its own body frame in the same way.
#include "fixtures.h"
#include "virtual_tryon/core/io/pattern_yaml.h"
#include "virtual_tryon/core/scenes/procedural_animation.h"
#include "virtual_tryon/testing/reference_bvh.h"
#include "virtual_tryon/testing/reference_check.h"

#include <gtest/gtest.h>
#include <pcl_msgs/PolygonMesh.h>
#include <ros/ros.h>
#include <virtual_tryon/FitReport.h>

#include <cmath>
#include <map>
#include <mutex>
#include <set>
#include <vector>

namespace vt = virtual_tryon;
using virtual_tryon_test::contains;
using virtual_tryon_test::meshFromMsg;
using virtual_tryon_test::patternMsg;
using virtual_tryon_test::waitUntil;

namespace {

constexpr int kFrames = 12;  // as CMake writes the bag
const ros::Time kStart(1700000000, 0);

int frameOf(const ros::Time& stamp) { return static_cast<int>(std::lround((stamp - kStart).toSec() * 30.0)); }

struct Collector {
  std::mutex m;
  std::vector<vt::FitReport::ConstPtr> reports;
  // By stamp, then vertex count: a frame's resolved tube and worn shirt share its stamp.
  std::map<std::pair<ros::Time, std::size_t>, pcl_msgs::PolygonMesh::ConstPtr> garments;
  std::vector<ros::Subscriber> subs;
  ros::Publisher pattern_pub;

  Collector() {
    ros::NodeHandle nh;
    subs.push_back(nh.subscribe<pcl_msgs::PolygonMesh>("/tryon_node/fitted_garment", 100, [this](const auto& g) {
      std::lock_guard<std::mutex> l(m);
      garments[{g->header.stamp, meshFromMsg(*g).V.rows()}] = g;
    }));
    subs.push_back(nh.subscribe<vt::FitReport>("/tryon_node/fit_report", 100, [this](const auto& r) {
      std::lock_guard<std::mutex> l(m);
      reports.push_back(r);
    }));
  }

  // Latched, so that the node has it whenever it starts.
  void publishPattern() {
    vt::Pattern p;
    std::string error;
    ASSERT_TRUE(vt::readPatternYaml(std::string(VIRTUAL_TRYON_SOURCE_DIR) +
                                        "/config/patterns/procedural/sleeveless_shirt.yaml", p, error))
        << error;
    ros::NodeHandle nh;
    pattern_pub = nh.advertise<vt::GarmentPattern>("/tryon_node/garment_pattern", 1, /*latch=*/true);
    pattern_pub.publish(patternMsg(p, "body"));
  }

  static std::size_t vertices(const vt::FitReport& r, std::size_t tube) {
    return r.kind == "drape" ? r.drape.vertices : tube;
  }

  bool lastFrameFitted(const std::string& kind, std::size_t tube) {
    std::lock_guard<std::mutex> l(m);
    for (const auto& r : reports)
      if (r->kind == kind && r->body_refitted && frameOf(r->header.stamp) == kFrames - 1 &&
          garments.count({r->header.stamp, vertices(*r, tube)}))
        return true;
    return false;
  }
};

Collector* collector = nullptr;

}  // namespace

// Every fit of `kind` ("resolve": the tube; "drape": the worn shirt) clean on its own body frame;
// returns the frames fitted and the node's count of frames dropped.
// carried: the fits that started from the frame before (resolve: a warm start; drape: the worn
// garment stepped).
void checkFits(const std::string& kind, std::set<int>& fitted, std::uint64_t& dropped, int& carried) {
  vt::ProceduralAnimationParams p;
  p.frames = kFrames;
  const vt::ProceduralAnimation anim = vt::makeProceduralAnimation(p);
  const std::size_t tube = static_cast<std::size_t>(anim.garment.V.rows());
  ASSERT_TRUE(waitUntil([&] { return collector->lastFrameFitted(kind, tube); }, 240.0, 0.1))
      << "the last frame's " << kind << " fit did not arrive";
  std::vector<vt::FitReport::ConstPtr> reports;
  std::map<std::pair<ros::Time, std::size_t>, pcl_msgs::PolygonMesh::ConstPtr> garments;
  {
    std::lock_guard<std::mutex> l(collector->m);
    reports = collector->reports;
    garments = collector->garments;
  }
  for (const auto& r : reports) {
    if (r->kind != kind) continue;
    // A refitted frame's fit carries that frame's stamp; the body as first installed (frame 0)
    // is fitted at the time of the fit.
    const int f = r->body_refitted ? frameOf(r->header.stamp) : 0;
    SCOPED_TRACE(kind + " of frame " + std::to_string(f));
    ASSERT_GE(f, 0);
    ASSERT_LT(f, kFrames);
    EXPECT_TRUE(r->success) << r->message;
    // The node's frame index counts the frames it installed (a dropped one is not counted), and
    // every one after the first is a refit.
    EXPECT_LE(r->body_frame_index, static_cast<std::uint64_t>(f));
    EXPECT_EQ(r->body_refitted, r->body_frame_index > 0);
    EXPECT_EQ(f == 0, r->body_frame_index == 0);
    if (kind == "drape" && contains(r->message, "worn garment stepped")) ++carried;
    if (kind == "resolve" && contains(r->message, "warm start from frame")) ++carried;
    dropped = std::max<std::uint64_t>(dropped, r->frames_dropped);
    std::printf("%s of frame %d: node's frame index %llu, dropped so far %llu: %s\n", kind.c_str(), f,
                static_cast<unsigned long long>(r->body_frame_index), static_cast<unsigned long long>(r->frames_dropped),
                r->message.substr(0, 120).c_str());
    const auto g = garments.find({r->header.stamp, Collector::vertices(*r, tube)});
    ASSERT_NE(g, garments.end()) << "no garment published with this report";
    vt::TriMesh body = anim.body;
    body.V = anim.body_frames[static_cast<std::size_t>(f)];
    const vt::ReferenceCounts c = vt::ReferenceReferee(body).count(meshFromMsg(*g->second));
    EXPECT_EQ(c.garment_edge_crossings, 0u);
    EXPECT_EQ(c.body_edge_crossings, 0u);
    EXPECT_EQ(c.vertices_inside, 0u);
    fitted.insert(f);
  }
}

TEST(AnimationReplay, EveryFittedFrameIsCleanOnItsOwnBodyFrame) {
  std::set<int> resolved, worn;
  std::uint64_t dropped = 0;
  int warmed = 0, stepped = 0;
  checkFits("resolve", resolved, dropped, warmed);
  // The pattern, draped once and worn: later frames step it (no fresh drape), and each is clean.
  checkFits("drape", worn, dropped, stepped);
  std::printf("frames resolved %zu (warm-started %d), worn %zu (stepped %d) of %d, dropped (node's count) %llu\n",
              resolved.size(), warmed, worn.size(), stepped, kFrames, static_cast<unsigned long long>(dropped));
  EXPECT_TRUE(resolved.count(kFrames - 1));
  EXPECT_TRUE(worn.count(kFrames - 1));
  EXPECT_GE(resolved.size(), 2u);  // at least one frame after the first: a refitted body was fitted
  EXPECT_GE(stepped, 1) << "no frame stepped the worn garment";
  EXPECT_GE(warmed, 1) << "no resolve started from the last fit's correction (~warm_start)";
  // No frame lost in silence, none counted twice: each is fitted (resolved, worn or both) or
  // counted as dropped.
  std::set<int> fitted = resolved;
  fitted.insert(worn.begin(), worn.end());
  EXPECT_EQ(fitted.size() + dropped, static_cast<std::size_t>(kFrames));
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "animation_replay_test");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  Collector c;
  c.publishPattern();
  collector = &c;
  const int result = RUN_ALL_TESTS();
  collector = nullptr;
  return result;
}
