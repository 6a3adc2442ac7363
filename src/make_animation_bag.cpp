// make_animation_bag: writes a moving body (and optionally its garment animation) into a bag that
// replays it into tryon_node, one message per frame:
//   ~body_mesh     pcl_msgs/PolygonMesh  every frame of the body (same faces, new vertices)
//   ~garment_mesh  pcl_msgs/PolygonMesh  every frame of the garment, when one is given
// Usage:
//   make_animation_bag OUT.bag --procedural [--frames N]
//   make_animation_bag OUT.bag --body B.obj --body-cache B.pc2 [--garment G.obj --garment-cache G.pc2]
//                      [--frames N] [--rate HZ] [--node NAME]
// --procedural: the project's own animation (core/scenes/procedural_animation.h: the procedural
// body swaying, the demo's waist tube skinned with it). Frame i is stamped t0 + i / rate (t0 fixed,
// so the same input writes the same bag); its garment goes first, then its body, both with the
// frame's stamp. Exit 2 on bad input, naming it.
#include "virtual_tryon/core/io/mesh_io.h"
#include "virtual_tryon/core/io/point_cache.h"
#include "virtual_tryon/core/scenes/procedural_animation.h"
#include "virtual_tryon/ros/conversions.h"

#include <rosbag/bag.h>

#include <algorithm>
#include <exception>
#include <iostream>
#include <map>
#include <string>
#include <vector>

namespace vt = virtual_tryon;

namespace {

struct Animation {
  vt::TriMesh body, garment;
  std::vector<vt::MatrixX3d> body_frames, garment_frames;
  double rate = 30;
};

bool loadCached(const std::string& meshPath, const std::string& cachePath, vt::TriMesh& mesh,
                std::vector<vt::MatrixX3d>& frames, std::string& error) {
  if (!vt::readMesh(meshPath, mesh, error)) return false;
  vt::PointCache cache;
  if (!vt::readPointCache(cachePath, cache, error, static_cast<int>(mesh.V.rows()))) return false;
  frames = std::move(cache.samples);
  return true;
}

int usage(const std::string& why) {
  std::cerr << "make_animation_bag: " << why << "\n"
            << "usage: make_animation_bag OUT.bag --procedural [--frames N]\n"
            << "       make_animation_bag OUT.bag --body B.obj --body-cache B.pc2 [--garment G.obj --garment-cache G.pc2]\n"
            << "                          [--frames N] [--rate HZ] [--node NAME]\n";
  return 2;
}

// The animation the options name: the procedural one, or OBJ + PC2 (frames cut to --frames).
bool loadAnimation(std::map<std::string, std::string>& opt, int frames, Animation& anim, std::string& error) {
  if (opt.count("procedural")) {
    vt::ProceduralAnimationParams p;
    if (frames > 0) p.frames = frames;
    vt::ProceduralAnimation a = vt::makeProceduralAnimation(p);
    anim = {std::move(a.body), std::move(a.garment), std::move(a.body_frames), std::move(a.garment_frames), a.rate};
    return true;
  }
  if (!opt.count("body") || !opt.count("body-cache")) return error = "--body and --body-cache (or --procedural)", false;
  if (!loadCached(opt["body"], opt["body-cache"], anim.body, anim.body_frames, error)) return false;
  if (opt.count("garment") != opt.count("garment-cache")) return error = "--garment and --garment-cache go together", false;
  if (opt.count("garment") && !loadCached(opt["garment"], opt["garment-cache"], anim.garment, anim.garment_frames, error))
    return false;
  if (opt.count("rate")) anim.rate = std::stod(opt["rate"]);
  if (!(anim.rate > 0)) return error = "--rate must be > 0 (frames per second)", false;
  if (frames > 0) {
    anim.body_frames.resize(std::min<std::size_t>(anim.body_frames.size(), static_cast<std::size_t>(frames)));
    if (!anim.garment_frames.empty())
      anim.garment_frames.resize(std::min(anim.garment_frames.size(), anim.body_frames.size()));
  }
  return true;
}

// Frame f at t0 + f / rate: its garment (when there is one), then its body, both with that stamp.
void writeBag(const std::string& out, const std::string& node, const Animation& anim) {
  const ros::Time t0(1700000000, 0);
  std_msgs::Header header;
  header.frame_id = "body";
  rosbag::Bag bag(out, rosbag::bagmode::Write);
  auto write = [&](const std::string& topic, const vt::TriMesh& rest, const vt::MatrixX3d& V, const ros::Time& t) {
    vt::TriMesh m = rest;
    m.V = V;
    pcl_msgs::PolygonMesh msg;
    vt::ros_conversions::toMsg(m, header, msg);
    bag.write(node + topic, t, msg);
  };
  for (std::size_t f = 0; f < anim.body_frames.size(); ++f) {
    header.stamp = t0 + ros::Duration(static_cast<double>(f) / anim.rate);
    if (f < anim.garment_frames.size()) write("/garment_mesh", anim.garment, anim.garment_frames[f], header.stamp);
    write("/body_mesh", anim.body, anim.body_frames[f], header.stamp + ros::Duration(1e-4));
  }
  bag.close();
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 3) return usage("an output bag and an animation are needed");
    const std::string out = argv[1];
    std::map<std::string, std::string> opt;
    for (int i = 2; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--procedural") {
        opt["procedural"] = "1";
      } else if (a.rfind("--", 0) == 0 && i + 1 < argc) {
        opt[a.substr(2)] = argv[++i];
      } else {
        return usage("unexpected argument '" + a + "'");
      }
    }
    const int frames = opt.count("frames") ? std::stoi(opt["frames"]) : -1;
    if (opt.count("frames") && frames < 1) return usage("--frames must be >= 1");
    Animation anim;
    std::string error;
    if (!loadAnimation(opt, frames, anim, error)) return usage(error);
    writeBag(out, opt.count("node") ? opt["node"] : "/tryon_node", anim);
    std::cout << "make_animation_bag: wrote " << out << ": " << anim.body_frames.size() << " body frames ("
              << anim.body.V.rows() << " vertices) at " << anim.rate << " Hz, " << anim.garment_frames.size()
              << " garment frames\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "make_animation_bag: " << e.what() << "\n";
    return 2;
  }
}
