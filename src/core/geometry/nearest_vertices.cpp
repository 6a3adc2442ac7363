#include "virtual_tryon/core/geometry/point_queries.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <vector>

namespace virtual_tryon {

// PCL's k-d tree (FLANN) over V, in single precision: the nearest vertex up to float rounding.
// PointNormal, as scan_error.cpp: a PointCloud<PointXYZ> instantiated here (with the core's Eigen
// alignment) is taken by libpcl_io's own code (vtk2mesh, STL reading) and freed there with another
// allocator (AddressSanitizer: bad-free).
std::vector<int> nearestVertices(const MatrixX3d& V, const MatrixX3d& P) {
  std::vector<int> out(static_cast<std::size_t>(P.rows()), -1);
  if (V.rows() == 0) return out;
  pcl::PointCloud<pcl::PointNormal>::Ptr cloud(new pcl::PointCloud<pcl::PointNormal>);
  cloud->reserve(static_cast<std::size_t>(V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    pcl::PointNormal q;
    q.x = static_cast<float>(V(i, 0)), q.y = static_cast<float>(V(i, 1)), q.z = static_cast<float>(V(i, 2));
    q.normal_x = q.normal_y = 0, q.normal_z = 1, q.curvature = 0;
    cloud->push_back(q);
  }
  pcl::KdTreeFLANN<pcl::PointNormal> tree;
  tree.setInputCloud(cloud);
  pcl::Indices index(1);
  std::vector<float> distance(1);
  for (Eigen::Index p = 0; p < P.rows(); ++p) {
    pcl::PointNormal q;
    q.x = static_cast<float>(P(p, 0)), q.y = static_cast<float>(P(p, 1)), q.z = static_cast<float>(P(p, 2));
    q.normal_x = q.normal_y = 0, q.normal_z = 1, q.curvature = 0;
    if (tree.nearestKSearch(q, 1, index, distance) == 1) out[static_cast<std::size_t>(p)] = index[0];
  }
  return out;
}

}  // namespace virtual_tryon
