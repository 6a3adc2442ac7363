// Load and concurrency test of tryon_node (load.test runs it for a few seconds; scripts/load_test.sh
// runs it longer): several clients call ~resolve_penetration and ~drape at once while bodies and
// garments stream in at 10 Hz. Every answer is checked (success, and zero crossings by the
// brute-force referee on the request's own body), nothing may deadlock (every call must return
// within a deadline), and the node's resident memory must stay flat after a warm-up. Prints
// throughput, latency and memory. Private parameters: ~duration (s, default 5), ~clients
// (default 3), ~max_rss_growth_mb (default 64).
#include "fixtures.h"
#include "virtual_tryon/testing/reference_check.h"

#include <gtest/gtest.h>
#include <pcl_msgs/PolygonMesh.h>
#include <ros/network.h>
#include <ros/ros.h>
#include <virtual_tryon/Drape.h>
#include <virtual_tryon/ResolvePenetration.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace vt = virtual_tryon;
using virtual_tryon_test::bag;
using virtual_tryon_test::capsule;
using virtual_tryon_test::meshFromMsg;
using virtual_tryon_test::patternMsg;
using virtual_tryon_test::toMsg;

namespace {

// The node's process id, through the master and the node's own XML-RPC getPid; -1 if unknown.
int nodePid(const std::string& node) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = node;
  if (!ros::master::execute("lookupNode", args, result, payload, true)) return -1;
  std::string host;
  uint32_t port = 0;
  if (!ros::network::splitURI(static_cast<std::string>(payload), host, port)) return -1;
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue a, r;
  a[0] = ros::this_node::getName();
  if (!client.execute("getPid", a, r) || r.getType() != XmlRpc::XmlRpcValue::TypeArray || r.size() < 3)
    return -1;
  return static_cast<int>(r[2]);
}

// Resident set size of `pid` in MiB (from /proc), or -1.
double rssMb(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string key;
  while (in >> key) {
    if (key == "VmRSS:") {
      double kb = 0;
      in >> kb;
      return kb / 1024.0;
    }
    std::getline(in, key);
  }
  return -1;
}

struct Stats {
  std::mutex m;
  std::vector<double> resolve_s, drape_s;
  std::atomic<int> wrong{0}, failed_calls{0};
};

}  // namespace

TEST(Load, ClientsAndStreamsAtOnceGiveCorrectAnswersAndFlatMemory) {
  ros::NodeHandle pnh("~");
  double duration = 5, maxGrowth = 64;
  int clients = 3;
  pnh.param("duration", duration, duration);
  pnh.param("clients", clients, clients);
  pnh.param("max_rss_growth_mb", maxGrowth, maxGrowth);
#if defined(__SANITIZE_ADDRESS__)
  // Under AddressSanitizer freed memory waits in a quarantine (256 MB by default) before reuse,
  // so the node's RSS grows under load whatever the code does: only a gross growth is checked.
  maxGrowth = std::max(maxGrowth, 1024.0);
#endif
  ASSERT_TRUE(ros::service::waitForService("/tryon_node/resolve_penetration", ros::Duration(30)));
  ASSERT_TRUE(ros::service::waitForService("/tryon_node/drape", ros::Duration(30)));
  const int pid = nodePid("/tryon_node");
  ASSERT_GT(pid, 0) << "cannot find tryon_node's process";

  const vt::ResolveScene scene = vt::makeWrinkledTubeScene();
  const vt::TriMesh drapeBody = capsule();
  const pcl_msgs::PolygonMesh sceneBodyMsg = toMsg(scene.body, "body");
  const pcl_msgs::PolygonMesh garmentMsg = toMsg(scene.garment, "body");
  const pcl_msgs::PolygonMesh drapeBodyMsg = toMsg(drapeBody, "body");
  const vt::GarmentPattern patternMessage = patternMsg(bag(), "body");

  // Streams at 10 Hz: bodies alternating between two shapes (each one new), garments.
  ros::NodeHandle nh;
  ros::Publisher bodies = nh.advertise<pcl_msgs::PolygonMesh>("/tryon_node/body_mesh", 2);
  ros::Publisher garments = nh.advertise<pcl_msgs::PolygonMesh>("/tryon_node/garment_mesh", 2);
  std::atomic<bool> running{true};
  std::atomic<int> streamed{0};
  std::thread streamer([&] {
    const pcl_msgs::PolygonMesh sphere = toMsg(vt::makeSphere(0.3), "body");
    for (int i = 0; running; ++i) {
      bodies.publish(i % 2 ? sceneBodyMsg : sphere);
      garments.publish(garmentMsg);
      ++streamed;
      ros::WallDuration(0.1).sleep();
    }
  });

  Stats stats;
  const ros::WallTime start = ros::WallTime::now();
  const ros::WallTime end = start + ros::WallDuration(duration);
  double rssWarm = -1;
  std::mutex rssMutex;
  // Each client holds persistent connections, one per service, as a front end calling at this
  // rate would: a call without one opens and closes a TCP connection, and roscpp's non-persistent
  // calls fail now and then under load by a known race of its own (ros/ros_comm#1976: the
  // connection is closed on POLLRDHUP before the client has read the response; seen here once in
  // 174 calls), which says nothing about the node.
  auto client = [&](int id) {
    ros::ServiceClient resolver = nh.serviceClient<vt::ResolvePenetration>("/tryon_node/resolve_penetration", true);
    ros::ServiceClient draper = nh.serviceClient<vt::Drape>("/tryon_node/drape", true);
    for (int k = 0; ros::WallTime::now() < end; ++k) {
      const bool doResolve = (k + id) % 2 == 0;
      const ros::WallTime t0 = ros::WallTime::now();
      if (doResolve) {
        vt::ResolvePenetration srv;
        srv.request.body = sceneBodyMsg;
        srv.request.garment = garmentMsg;
        if (!resolver.call(srv)) {
          ++stats.failed_calls;
          continue;
        }
        const vt::ReferenceCounts c = vt::referenceCounts(scene.body, meshFromMsg(srv.response.garment), false);
        if (!srv.response.success || c.garment_edge_crossings + c.body_edge_crossings != 0) ++stats.wrong;
        std::lock_guard<std::mutex> l(stats.m);
        stats.resolve_s.push_back((ros::WallTime::now() - t0).toSec());
      } else {
        vt::Drape srv;
        srv.request.body = drapeBodyMsg;
        srv.request.pattern = patternMessage;
        srv.request.spacing = 0.04;
        if (!draper.call(srv)) {
          ++stats.failed_calls;
          continue;
        }
        const vt::ReferenceCounts c = vt::referenceCounts(drapeBody, meshFromMsg(srv.response.garment), false);
        if (!srv.response.success || srv.response.report.seams_open != 0 ||
            c.garment_edge_crossings + c.body_edge_crossings != 0)
          ++stats.wrong;
        std::lock_guard<std::mutex> l(stats.m);
        stats.drape_s.push_back((ros::WallTime::now() - t0).toSec());
      }
      // Memory after the warm-up third: every code path has run and every cache is filled.
      std::lock_guard<std::mutex> l(rssMutex);
      if (rssWarm < 0 && ros::WallTime::now() > start + ros::WallDuration(duration / 3)) rssWarm = rssMb(pid);
    }
  };
  std::vector<std::thread> threads;
  for (int i = 0; i < clients; ++i) threads.emplace_back(client, i);
  for (auto& t : threads) t.join();
  running = false;
  streamer.join();
  const double seconds = (ros::WallTime::now() - start).toSec();
  const double rssEnd = rssMb(pid);

  auto summary = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    char buf[128];
    std::snprintf(buf, sizeof buf, "%zu calls, median %.3f s, max %.3f s", v.size(),
                  v.empty() ? 0.0 : v[v.size() / 2], v.empty() ? 0.0 : v.back());
    return std::string(buf);
  };
  std::printf("load: %.1f s, %d clients, %d bodies + %d garments streamed\n", seconds, clients,
              streamed.load(), streamed.load());
  std::printf("load: resolve: %s; drape: %s; throughput %.1f calls/s\n",
              summary(stats.resolve_s).c_str(), summary(stats.drape_s).c_str(),
              (stats.resolve_s.size() + stats.drape_s.size()) / seconds);
  std::printf("load: node RSS %.1f MiB after warm-up, %.1f MiB at the end (growth %.1f MiB)\n", rssWarm,
              rssEnd, rssEnd - rssWarm);
  std::fflush(stdout);

  EXPECT_EQ(stats.failed_calls.load(), 0);
  EXPECT_EQ(stats.wrong.load(), 0);
  EXPECT_GT(stats.resolve_s.size(), 0u);
  EXPECT_GT(stats.drape_s.size(), 0u);
  // No call may hang: the slowest one returns well within the run (a deadlock would stop it).
  for (const auto* v : {&stats.resolve_s, &stats.drape_s})
    for (double s : *v) EXPECT_LT(s, 30.0);
  ASSERT_GT(rssWarm, 0);
  EXPECT_LT(rssEnd - rssWarm, maxGrowth) << "the node's memory grew under a steady load";
}

int main(int argc, char** argv) { return virtual_tryon_test::runClientTests(argc, argv, "load_test"); }
