// config/params.yaml documents the drape defaults: its drape/ values must be the core's defaults
// (DrapeParams, ClothParams, CollisionParams), so that the node and the `tryon` command behave
// alike unless someone changes a parameter on purpose.
#include "virtual_tryon/core/drape/drape.h"
#include "virtual_tryon/core/body/scan_meshing.h"
#include "virtual_tryon/ros/report_conversions.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <set>
#include <string>

namespace vt = virtual_tryon;
namespace rc = virtual_tryon::ros_conversions;

TEST(Params, DrapeDefaultsInParamsYamlAreTheCoreDefaults) {
  const YAML::Node root = YAML::LoadFile(std::string(VIRTUAL_TRYON_SOURCE_DIR) + "/config/params.yaml");
  const YAML::Node d = root["drape"];
  ASSERT_TRUE(d && d.IsMap()) << "no drape: section";
  const vt::DrapeParams p;
  ASSERT_EQ(vt::validateDrapeParams(p), "");
  std::set<std::string> seen;
  auto num = [&](const char* key) {
    seen.insert(key);
    EXPECT_TRUE(d[key]) << "drape/" << key << " missing";
    return d[key] ? d[key].as<double>() : -12345.0;
  };
  EXPECT_DOUBLE_EQ(num("spacing"), p.spacing);
  EXPECT_DOUBLE_EQ(num("tol"), p.collision.tol);
  EXPECT_DOUBLE_EQ(num("map_size"), p.collision.map_size);
  EXPECT_DOUBLE_EQ(num("friction"), p.collision.friction);
  EXPECT_DOUBLE_EQ(num("reflection"), p.collision.reflection);
  EXPECT_DOUBLE_EQ(num("density"), p.cloth.density);
  EXPECT_DOUBLE_EQ(num("k_structural"), p.cloth.k_structural);
  EXPECT_DOUBLE_EQ(num("k_shear"), p.cloth.k_shear);
  EXPECT_DOUBLE_EQ(num("k_flexion"), p.cloth.k_flexion);
  EXPECT_DOUBLE_EQ(num("k_seam"), p.cloth.k_seam);
  EXPECT_DOUBLE_EQ(num("damping_rate"), p.cloth.damping_rate);
  EXPECT_DOUBLE_EQ(num("stretch_threshold"), p.cloth.stretch_threshold);
  EXPECT_DOUBLE_EQ(num("dt"), p.dt);
  EXPECT_DOUBLE_EQ(num("max_iterations"), p.max_iterations);
  EXPECT_DOUBLE_EQ(num("settle_speed"), p.settle_speed);
  EXPECT_DOUBLE_EQ(num("time_budget"), p.time_budget);
  EXPECT_DOUBLE_EQ(num("max_strain"), p.max_strain);
  EXPECT_DOUBLE_EQ(num("weld_relax_passes"), p.cloth.weld_relax_passes);
  EXPECT_DOUBLE_EQ(num("resolve_rest_strain"), p.resolve_rest_strain);
  for (const char* key : {"clamp_dt", "resolve", "collision_mode"}) seen.insert(key);
  ASSERT_TRUE(d["clamp_dt"] && d["resolve"] && d["collision_mode"]);
  EXPECT_EQ(d["clamp_dt"].as<bool>(), p.clamp_dt);
  EXPECT_EQ(d["resolve"].as<bool>(), p.resolve);
  EXPECT_EQ(d["collision_mode"].as<std::string>(), rc::collisionModeName(p.mode));
  // Nothing in the file that the node does not read.
  for (const auto& kv : d) EXPECT_TRUE(seen.count(kv.first.as<std::string>())) << kv.first.as<std::string>();
}

TEST(Params, ScanDefaultsInParamsYamlAreTheCoreDefaults) {
  const YAML::Node root = YAML::LoadFile(std::string(VIRTUAL_TRYON_SOURCE_DIR) + "/config/params.yaml");
  const YAML::Node s = root["scan"];
  ASSERT_TRUE(s && s.IsMap()) << "no scan: section";
  const vt::ScanMeshingParams p;
  ASSERT_EQ(vt::validateScanMeshingParams(p), "");
  EXPECT_DOUBLE_EQ(s["voxel_size"].as<double>(), p.voxel_size);
  EXPECT_EQ(s["normal_neighbours"].as<int>(), p.normal_neighbours);
  EXPECT_EQ(s["depth"].as<int>(), p.depth);
  EXPECT_EQ(s["max_auto_depth"].as<int>(), p.max_auto_depth);
  EXPECT_DOUBLE_EQ(s["uncertainty"].as<double>(), -1.0);  // the scan's own error
  EXPECT_EQ(s.size(), 5u) << "a scan/ key the node does not read";
  ASSERT_TRUE(root["auto_fit"]);
  EXPECT_FALSE(root["auto_fit"].as<bool>());
}
