// rostest: the animation bag (make_animation_bag --procedural --frames 12: the procedural body
// swaying, the demo's waist tube skinned with it, one ~body_mesh and one ~garment_mesh per frame at
// 30 Hz) is replayed into tryon_node with auto_fit on. Every body message after the first has the
// same faces: the node installs it as a frame of that body (refitted, not rebuilt) and fits the
// latest garment on it. Every fitted garment the node publishes is checked against its own frame's
// body (regenerated here, found by the stamp) by the referee; every frame is fitted or counted as
// dropped; the last one is fitted.
#include "fixtures.h"
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
using virtual_tryon_test::meshFromMsg;
using virtual_tryon_test::waitUntil;

namespace {

constexpr int kFrames = 12;  // as CMake writes the bag
const ros::Time kStart(1700000000, 0);

int frameOf(const ros::Time& stamp) { return static_cast<int>(std::lround((stamp - kStart).toSec() * 30.0)); }

struct Collector {
  std::mutex m;
  std::vector<vt::FitReport::ConstPtr> reports;
  std::map<ros::Time, pcl_msgs::PolygonMesh::ConstPtr> garments;  // by stamp
  std::vector<ros::Subscriber> subs;

  Collector() {
    ros::NodeHandle nh;
    subs.push_back(nh.subscribe<pcl_msgs::PolygonMesh>("/tryon_node/fitted_garment", 100, [this](const auto& g) {
      std::lock_guard<std::mutex> l(m);
      garments[g->header.stamp] = g;
    }));
    subs.push_back(nh.subscribe<vt::FitReport>("/tryon_node/fit_report", 100, [this](const auto& r) {
      std::lock_guard<std::mutex> l(m);
      reports.push_back(r);
    }));
  }

  bool lastFrameFitted() {
    std::lock_guard<std::mutex> l(m);
    for (const auto& r : reports)
      if (r->kind == "resolve" && r->body_refitted && frameOf(r->header.stamp) == kFrames - 1 &&
          garments.count(r->header.stamp))
        return true;
    return false;
  }
};

Collector* collector = nullptr;

}  // namespace

TEST(AnimationReplay, EveryFittedFrameIsCleanOnItsOwnBodyFrame) {
  ASSERT_TRUE(waitUntil([] { return collector->lastFrameFitted(); }, 240.0, 0.1))
      << "the last frame's fit did not arrive";
  std::vector<vt::FitReport::ConstPtr> reports;
  std::map<ros::Time, pcl_msgs::PolygonMesh::ConstPtr> garments;
  {
    std::lock_guard<std::mutex> l(collector->m);
    reports = collector->reports;
    garments = collector->garments;
  }
  vt::ProceduralAnimationParams p;
  p.frames = kFrames;
  const vt::ProceduralAnimation anim = vt::makeProceduralAnimation(p);
  std::set<int> fitted;
  std::uint64_t dropped = 0;
  for (const auto& r : reports) {
    if (r->kind != "resolve") continue;
    // A refitted frame's fit carries that frame's stamp; the body as first installed (frame 0)
    // is fitted at the time of the fit.
    const int f = r->body_refitted ? frameOf(r->header.stamp) : 0;
    SCOPED_TRACE("frame " + std::to_string(f));
    ASSERT_GE(f, 0);
    ASSERT_LT(f, kFrames);
    EXPECT_TRUE(r->success) << r->message;
    // The node's frame index counts the frames it installed (a dropped one is not counted), and
    // every one after the first is a refit.
    EXPECT_LE(r->body_frame_index, static_cast<std::uint64_t>(f));
    EXPECT_EQ(r->body_refitted, r->body_frame_index > 0);
    EXPECT_EQ(f == 0, r->body_frame_index == 0);
    dropped = std::max<std::uint64_t>(dropped, r->frames_dropped);
    std::printf("fit of frame %d: node's frame index %llu, dropped so far %llu\n", f,
                static_cast<unsigned long long>(r->body_frame_index), static_cast<unsigned long long>(r->frames_dropped));
    const auto g = garments.find(r->header.stamp);
    ASSERT_NE(g, garments.end()) << "no garment published with this report";
    vt::TriMesh body = anim.body;
    body.V = anim.body_frames[static_cast<std::size_t>(f)];
    const vt::ReferenceCounts c = vt::ReferenceReferee(body).count(meshFromMsg(*g->second));
    EXPECT_EQ(c.garment_edge_crossings, 0u);
    EXPECT_EQ(c.body_edge_crossings, 0u);
    EXPECT_EQ(c.vertices_inside, 0u);
    fitted.insert(f);
  }
  std::printf("frames fitted %zu of %d, dropped (node's count) %llu\n", fitted.size(), kFrames,
              static_cast<unsigned long long>(dropped));
  EXPECT_TRUE(fitted.count(kFrames - 1));
  EXPECT_GE(fitted.size(), 2u);  // at least one frame after the first: a refitted body was fitted
  // No frame lost in silence, none counted twice: each is fitted or counted as dropped.
  EXPECT_EQ(fitted.size() + dropped, static_cast<std::size_t>(kFrames));
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "animation_replay_test");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  Collector c;
  collector = &c;
  const int result = RUN_ALL_TESTS();
  collector = nullptr;
  return result;
}
