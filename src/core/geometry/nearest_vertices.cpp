#include "virtual_tryon/core/geometry/point_queries.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <vector>

namespace virtual_tryon {

// PCL's k-d tree (FLANN) over V, in single precision: the nearest vertex up to float rounding.
std::vector<int> nearestVertices(const MatrixX3d& V, const MatrixX3d& P) {
  std::vector<int> out(static_cast<std::size_t>(P.rows()), -1);
  if (V.rows() == 0) return out;
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->resize(static_cast<std::size_t>(V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    (*cloud)[static_cast<std::size_t>(i)] = pcl::PointXYZ(static_cast<float>(V(i, 0)), static_cast<float>(V(i, 1)),
                                                          static_cast<float>(V(i, 2)));
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  pcl::Indices index(1);
  std::vector<float> distance(1);
  for (Eigen::Index p = 0; p < P.rows(); ++p) {
    const pcl::PointXYZ q(static_cast<float>(P(p, 0)), static_cast<float>(P(p, 1)), static_cast<float>(P(p, 2)));
    if (tree.nearestKSearch(q, 1, index, distance) == 1) out[static_cast<std::size_t>(p)] = index[0];
  }
  return out;
}

}  // namespace virtual_tryon
