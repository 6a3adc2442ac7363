#include "virtual_tryon/ros/tryon_node.h"
#include "virtual_tryon/heap_settings.h"

#include <ros/ros.h>

int main(int argc, char** argv) {
  virtual_tryon::keepHeapForFrames();
  ros::init(argc, argv, "tryon_node");
  virtual_tryon::TryonNode node(ros::NodeHandle(), ros::NodeHandle("~"));
  // Callbacks and services on four threads; long topic work runs on the node's worker (see
  // tryon_node.h), so two service calls run at once while topics keep arriving.
  ros::AsyncSpinner spinner(4);
  spinner.start();
  ros::waitForShutdown();
  return 0;
}
