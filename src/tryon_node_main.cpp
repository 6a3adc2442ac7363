#include "virtual_tryon/ros/tryon_node.h"

#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "tryon_node");
  virtual_tryon::TryonNode node(ros::NodeHandle(), ros::NodeHandle("~"));
  // Two threads: topics keep being received while a resolve runs. TryonNode guards its shared
  // state with a mutex and works on copies, so this is safe (see tryon_node.h).
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ros::waitForShutdown();
  return 0;
}
