// Edge-face crossings between a garment and a body, in both directions: the body's box tree hands
// over the (body face, garment face) pairs whose bounding boxes overlap; each pair's edges are then
// tested against the other triangle with segmentCrossesTriangle() (edge_face_crossing.h).
#pragma once

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/geometry/mesh.h"

#include <vector>

namespace virtual_tryon {

struct EdgeFaceCrossing {
  int edge = -1;  // unique-edge index of the mesh the edge belongs to
  int face = -1;  // face index of the other mesh
  double t = 0;   // crossing point = E(edge,0) + t (E(edge,1) - E(edge,0))
  Eigen::Vector3d bary{0, 0, 0};  // crossing point in barycentric coordinates of `face`
  double s0 = 0, s1 = 0;  // signed distances of E(edge,0), E(edge,1) from the face's plane
};

struct CrossingSet {
  std::vector<EdgeFaceCrossing> garment_edges;  // garment edge x body face
  std::vector<EdgeFaceCrossing> body_edges;     // body edge x garment face
  std::size_t size() const { return garment_edges.size() + body_edges.size(); }
};

// The garment's connectivity, computed once per garment and reused every round.
struct GarmentTopology {
  MatrixX2i edges;       // #E by 2
  MatrixX3i face_edges;  // #F by 3
  explicit GarmentTopology(const TriMesh& garment);
};

// Finds every crossing between `garment` (positions as they are now) and `body`.
// If `faces` is non-null only those garment faces (and their edges) are tested: the result then
// holds the crossings that involve one of those faces or one of their edges.
// Results are sorted (edge, face) and free of duplicates.
void detectCrossings(const Body& body, const TriMesh& garment, const GarmentTopology& topo,
                     CrossingSet& out, const std::vector<int>* faces = nullptr);

// Each garment face's candidate body faces, kept between detections of a garment that moves a
// little at a time (the shape relaxation checks the same faces some 20 times): a face's body faces
// are those whose boxes overlap its own box grown by `margin` on every side, and while the face's
// box stays inside that grown box they are reused instead of asking the body's tree again. Valid
// for one body and one garment's faces; the body must not move while it is in use.
struct CandidateCache {
  explicit CandidateCache(double margin_m = 0.002) : margin(margin_m) {}
  double margin;                              // m
  std::vector<Eigen::Vector3d> lo, hi;        // per garment face: the grown box (empty: none yet)
  std::vector<std::vector<int>> faces;        // per garment face: its candidate body faces
  std::vector<char> valid;                    // per garment face
  std::size_t reused = 0, queried = 0;        // faces answered from the cache / by the tree
};

// As detectCrossings(), with the candidates taken from (and kept in) `cache`; the same result.
// The faces in `faces` must be distinct (threads share the work by face).
void detectCrossings(const Body& body, const TriMesh& garment, const GarmentTopology& topo,
                     CrossingSet& out, const std::vector<int>* faces, CandidateCache& cache);

}  // namespace virtual_tryon
