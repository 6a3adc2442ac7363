// The core library must build without ROS: no file under include/virtual_tryon/core or src/core
// may include a ROS header.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

namespace fs = std::filesystem;

namespace {
bool isRosInclude(const std::string& line) {
  static const std::regex rosInclude(
      R"(^\s*#\s*include\s*[<"](ros|roscpp|rosbag|tf2_ros|tf2_eigen|tf2_msgs|pcl_conversions|pcl_ros|sensor_msgs|pcl_msgs|visualization_msgs|std_msgs|geometry_msgs|shape_msgs|actionlib|actionlib_msgs|virtual_tryon/ros|virtual_tryon/[A-Z][A-Za-z]*\.h)[/">])");
  return std::regex_search(line, rosInclude);
}
}  // namespace

TEST(CoreIsRosFree, NoCoreFileIncludesARosHeader) {
  const fs::path root = VIRTUAL_TRYON_SOURCE_DIR;
  int files = 0;
  for (const char* dir : {"include/virtual_tryon/core", "src/core", "include/virtual_tryon/testing", "src/testing"}) {
    ASSERT_TRUE(fs::is_directory(root / dir)) << (root / dir);
    for (const auto& entry : fs::recursive_directory_iterator(root / dir)) {
      if (!entry.is_regular_file()) continue;
      ++files;
      std::ifstream in(entry.path());
      std::string line;
      int lineNo = 0;
      while (std::getline(in, line)) {
        ++lineNo;
        EXPECT_FALSE(isRosInclude(line))
            << entry.path() << ":" << lineNo << " includes a ROS header: " << line;
      }
    }
  }
  EXPECT_GT(files, 10);
}

TEST(CoreIsRosFree, TheCheckRecognisesARosInclude) {
  // The pattern above must actually catch the includes it is meant to catch.
  EXPECT_TRUE(isRosInclude("#include <ros/ros.h>"));
  EXPECT_TRUE(isRosInclude("#include \"pcl_msgs/PolygonMesh.h\""));
  EXPECT_TRUE(isRosInclude("  #  include <tf2_ros/buffer.h>"));
  EXPECT_TRUE(isRosInclude("#include <virtual_tryon/PenetrationReport.h>"));
  EXPECT_TRUE(isRosInclude("#include \"virtual_tryon/ros/conversions.h\""));
  EXPECT_FALSE(isRosInclude("#include <pcl/io/ply_io.h>"));
  EXPECT_FALSE(isRosInclude("#include \"virtual_tryon/core/mesh.h\""));
  EXPECT_FALSE(isRosInclude("// #include <ros/ros.h> mentioned in a comment"));
}
