// Pattern message <-> core conversions and DrapeResult -> message.
#include "virtual_tryon/ros/pattern_conversions.h"
#include "virtual_tryon/ros/report_conversions.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace vt = virtual_tryon;
namespace rc = virtual_tryon::ros_conversions;

namespace {

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// A valid two-panel skirt with non-trivial poses (rotation about a tilted axis, translation).
vt::Pattern skirt() {
  vt::Pattern p;
  p.name = "skirt";
  for (int i = 0; i < 2; ++i) {
    vt::PatternPanel panel;
    panel.name = i == 0 ? "front" : "back";
    panel.outline.resize(4, 2);
    panel.outline << -0.33, 0.0, 0.33, 0.0, 0.29, 0.5, -0.29, 0.5;
    panel.placement.pose = Eigen::Translation3d(0.01 * i, 0.55, -0.02) *
                           Eigen::AngleAxisd(M_PI * i + 0.1, Eigen::Vector3d(0.1, 1, 0.2).normalized());
    panel.placement.wrap_radius = 0.2;
    p.panels.push_back(panel);
  }
  vt::PatternSeam s1, s2;
  s1.a = {0, 1, 2};
  s1.b = {1, 0, 3};
  s2.a = {0, 0, 3};
  s2.b = {1, 1, 2};
  p.seams = {s1, s2};
  return p;
}

vt::GarmentPattern skirtMsg() {
  std_msgs::Header h;
  h.frame_id = "body";
  return rc::toMsg(skirt(), h);
}

}  // namespace

TEST(PatternConversions, RoundTripIsExact) {
  const vt::Pattern in = skirt();
  ASSERT_EQ(vt::validatePattern(in), "");
  std_msgs::Header h;
  h.frame_id = "torso";
  const vt::GarmentPattern msg = rc::toMsg(in, h);
  EXPECT_EQ(msg.header.frame_id, "torso");
  EXPECT_EQ(msg.name, "skirt");
  ASSERT_EQ(msg.panels.size(), 2u);
  ASSERT_EQ(msg.seams.size(), 2u);
  EXPECT_EQ(msg.panels[1].name, "back");
  ASSERT_EQ(msg.panels[0].outline_u.size(), 4u);
  EXPECT_EQ(msg.panels[0].outline_u[2], 0.29);
  EXPECT_EQ(msg.panels[0].outline_v[2], 0.5);
  EXPECT_EQ(msg.panels[1].wrap_radius, 0.2);
  EXPECT_EQ(msg.seams[0].panel_b, 1u);
  EXPECT_EQ(msg.seams[0].b_to, 3u);
  EXPECT_EQ(msg.seams[1].a_to, 3u);
  // Unit quaternion with w >= 0.
  const auto& q = msg.panels[1].pose.orientation;
  EXPECT_NEAR(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w, 1.0, 1e-12);
  EXPECT_GE(q.w, 0.0);

  vt::Pattern out;
  std::string error;
  ASSERT_TRUE(rc::fromMsg(msg, out, error)) << error;
  EXPECT_EQ(out.name, in.name);
  ASSERT_EQ(out.panels.size(), in.panels.size());
  for (std::size_t i = 0; i < in.panels.size(); ++i) {
    EXPECT_EQ(out.panels[i].name, in.panels[i].name);
    EXPECT_TRUE(out.panels[i].outline == in.panels[i].outline);  // exact
    EXPECT_EQ(out.panels[i].placement.wrap_radius, in.panels[i].placement.wrap_radius);
    EXPECT_TRUE(out.panels[i].placement.pose.matrix().isApprox(in.panels[i].placement.pose.matrix(), 1e-12))
        << out.panels[i].placement.pose.matrix() << "\nvs\n" << in.panels[i].placement.pose.matrix();
  }
  ASSERT_EQ(out.seams.size(), in.seams.size());
  for (std::size_t i = 0; i < in.seams.size(); ++i) {
    EXPECT_EQ(out.seams[i].a.panel, in.seams[i].a.panel);
    EXPECT_EQ(out.seams[i].a.from, in.seams[i].a.from);
    EXPECT_EQ(out.seams[i].a.to, in.seams[i].a.to);
    EXPECT_EQ(out.seams[i].b.panel, in.seams[i].b.panel);
    EXPECT_EQ(out.seams[i].b.from, in.seams[i].b.from);
    EXPECT_EQ(out.seams[i].b.to, in.seams[i].b.to);
  }
  EXPECT_EQ(vt::validatePattern(out), "");
  // And the places the panels land are the same.
  for (std::size_t i = 0; i < in.panels.size(); ++i) {
    const Eigen::Vector2d uv(0.1, 0.3);
    EXPECT_LT((out.panels[i].placement.place(uv) - in.panels[i].placement.place(uv)).norm(), 1e-12);
  }
}

TEST(PatternConversions, QuaternionIsNormalized) {
  vt::GarmentPattern msg = skirtMsg();
  auto& q = msg.panels[0].pose.orientation;
  q.x = 0;
  q.y = 0;
  q.z = 3;  // 180 degrees about z, not unit
  q.w = 0;
  msg.panels[0].pose.position.x = 1.5;
  vt::Pattern out;
  std::string error;
  ASSERT_TRUE(rc::fromMsg(msg, out, error)) << error;
  const Eigen::Matrix3d R = out.panels[0].placement.pose.linear();
  EXPECT_TRUE(R.isApprox(Eigen::Vector3d(-1, -1, 1).asDiagonal().toDenseMatrix(), 1e-12)) << R;
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
  EXPECT_EQ(out.panels[0].placement.pose.translation().x(), 1.5);
  EXPECT_EQ(vt::validatePattern(out), "");
}

TEST(PatternConversions, MismatchedOutlineLengthsFailNamingThePanel) {
  vt::GarmentPattern msg = skirtMsg();
  msg.panels[1].outline_v.pop_back();
  vt::Pattern out = skirt();
  out.name = "untouched";
  std::string error;
  EXPECT_FALSE(rc::fromMsg(msg, out, error));
  EXPECT_TRUE(contains(error, "panel 'back' (index 1)")) << error;
  EXPECT_TRUE(contains(error, "outline_u has 4")) << error;
  EXPECT_TRUE(contains(error, "outline_v has 3")) << error;
  EXPECT_EQ(out.name, "untouched");  // left unchanged
}

TEST(PatternConversions, ZeroOrNonFiniteQuaternionFails) {
  {
    vt::GarmentPattern msg = skirtMsg();
    msg.panels[0].pose.orientation = geometry_msgs::Quaternion();  // all zero: an unset pose
    vt::Pattern out;
    std::string error;
    EXPECT_FALSE(rc::fromMsg(msg, out, error));
    EXPECT_TRUE(contains(error, "panel 'front' (index 0)")) << error;
    EXPECT_TRUE(contains(error, "orientation")) << error;
    EXPECT_TRUE(out.panels.empty());
  }
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    vt::GarmentPattern msg = skirtMsg();
    msg.panels[1].pose.orientation.y = bad;
    vt::Pattern out;
    std::string error;
    EXPECT_FALSE(rc::fromMsg(msg, out, error)) << bad;
    EXPECT_TRUE(contains(error, "panel 'back' (index 1)")) << error;
    EXPECT_TRUE(contains(error, "not a finite quaternion")) << error;
  }
  {
    vt::GarmentPattern msg = skirtMsg();
    msg.panels[1].pose.position.z = std::numeric_limits<double>::quiet_NaN();
    vt::Pattern out;
    std::string error;
    EXPECT_FALSE(rc::fromMsg(msg, out, error));
    EXPECT_TRUE(contains(error, "position")) << error;
  }
}

TEST(PatternConversions, SeamIndexBeyondIntFails) {
  vt::GarmentPattern msg = skirtMsg();
  msg.seams[1].b_from = 4000000000u;
  vt::Pattern out;
  std::string error;
  EXPECT_FALSE(rc::fromMsg(msg, out, error));
  EXPECT_TRUE(contains(error, "seam 1")) << error;
  EXPECT_TRUE(contains(error, "b_from")) << error;
}

TEST(ReportConversions, DrapeReportFieldByField) {
  vt::DrapeResult r;
  r.success = true;
  r.converged = true;
  r.cancelled = false;
  r.message = "draped";
  r.warnings = {"w1", "w2"};
  r.vertices = 421;
  r.triangles = 800;
  r.iterations = 1049;
  r.sew_iterations = 65;
  r.dt = 0.0018;
  r.dt_bound = 0.002;
  r.dt_bound_paper = 0.0046;
  r.map_size = 182;
  r.seconds_total = 0.06;
  r.seams_total = 3;
  r.seams_open = 1;
  r.seam_gap_max = 0.01;
  r.strain_max = 0.1;
  r.max_speed = 0.12;
  r.kinetic_energy = 1e-5;
  r.penetrating_before_resolve = 7;
  r.penetrating_after = 2;
  r.resolver_run = true;
  r.resolver.iterations = 4;
  r.resolver.reason = "done";
  const vt::DrapeReport m = rc::toMsg(r, vt::CollisionMode::ImageSpace);
  EXPECT_TRUE(m.converged);
  EXPECT_EQ(m.message, "draped");
  ASSERT_EQ(m.warnings.size(), 2u);
  EXPECT_EQ(m.warnings[1], "w2");
  EXPECT_EQ(m.vertices, 421u);
  EXPECT_EQ(m.iterations, 1049u);
  EXPECT_EQ(m.sew_iterations, 65u);
  EXPECT_EQ(m.dt, 0.0018);
  EXPECT_EQ(m.dt_bound, 0.002);
  EXPECT_EQ(m.collision_mode, "image");
  EXPECT_EQ(m.map_size, 182u);
  EXPECT_EQ(m.seams_total, 3u);
  EXPECT_EQ(m.seams_open, 1u);
  EXPECT_EQ(m.penetrating_before_resolve, 7u);
  EXPECT_EQ(m.penetrating_after, 2u);
  EXPECT_TRUE(m.resolver_run);
  EXPECT_EQ(m.resolver.iterations, 4u);
  EXPECT_EQ(m.resolver.reason, "done");
  EXPECT_EQ(rc::toMsg(r, vt::CollisionMode::ObjectSpace).collision_mode, "object");
  r.iterations = -3;  // clamped, not wrapped
  EXPECT_EQ(rc::toMsg(r, vt::CollisionMode::ImageSpace).iterations, 0u);
}

TEST(ReportConversions, CollisionModeNames) {
  vt::CollisionMode m = vt::CollisionMode::ImageSpace;
  EXPECT_TRUE(rc::parseCollisionMode("object", m));
  EXPECT_EQ(m, vt::CollisionMode::ObjectSpace);
  EXPECT_TRUE(rc::parseCollisionMode("image", m));
  EXPECT_EQ(m, vt::CollisionMode::ImageSpace);
  EXPECT_FALSE(rc::parseCollisionMode("Object", m));
  EXPECT_FALSE(rc::parseCollisionMode("", m));
  EXPECT_EQ(m, vt::CollisionMode::ImageSpace);
  EXPECT_EQ(rc::collisionModeName(vt::CollisionMode::ObjectSpace), "object");
}
