#include "virtual_tryon/core/resolve/shape_relaxation.h"

#include "virtual_tryon/core/geometry/point_queries.h"

#include "core/geometry/parallel_ranges.h"
#include "core/resolve/face_clearance.h"
#include "core/resolve/resolver_run.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <unordered_set>
#include <vector>

namespace virtual_tryon {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kMaxRevertPasses = 64;
constexpr int kMaxWalkSteps = 16;
constexpr int kWalkMemory = 96;  // faces a walk remembers having measured
constexpr int kContactPasses = 3;
constexpr int kRotationIterations = 8;
constexpr int kRotationsPerThread = 256;  // fewer active vertices: one thread fits their rotations
constexpr int kPlanesPerThread = 128;     // fewer active vertices: one thread takes their first planes
constexpr double kRotationTolerance = 1e-6;  // rad: a rotation fit stops when its step is below this
constexpr int kPolishRounds = 3;
// A contact whose movable corners carry less weight than this is left to the step back (moving
// them would lever them far out).
constexpr double kMinContactWeight = 0.25;

class ShapeRelaxation {
 public:
  ShapeRelaxation(const Body& body, const TriMesh& input, TriMesh& garment, const GarmentTopology& topo,
                  const resolver_run::GarmentGraph& graph, double clearance, const ShapeRelaxationParams& params,
                  CandidateCache* candidates)
      : body_(body), in_(input), g_(garment), topo_(topo), d_(clearance), p_(params),
        nv_(static_cast<int>(garment.V.rows())), graph_(graph), candidates_(candidates ? *candidates : own_candidates_),
        reused_before_(candidates_.reused), queried_before_(candidates_.queried) {}

  ShapeRelaxationReport run() {
    const auto t0 = Clock::now();
    chooseActive();
    setFloors();
    for (int v : active_) start_[v] = checked_[v] = g_.V.row(v);
    turned_.resize(graph_.adj_v.size());
    turnEdges();
    rep_.seconds_setup = seconds(t0);
    const int perCheck = std::max(1, p_.sweeps_per_check);
    const int sweeps = p_.local && p_.local_max_sweeps > 0 ? p_.local_max_sweeps : p_.max_sweeps;
    for (int s = 0; s < sweeps && !active_.empty(); ++s) {
      if (p_.time_budget > 0 && seconds(t0) >= p_.time_budget) break;
      sweep_ = s;
      if (s % perCheck == 0) {
        for (int v : active_) clean_[v] = g_.V.row(v);
        if (p_.local_rotations) updateRotations();
      }
      rep_.last_step = sweep();
      if (p_.strain_limit > 0) limitStrain();
      projectContacts();
      ++rep_.sweeps;
      const bool settled = rep_.last_step < p_.tolerance;
      if ((s + 1) % perCheck == 0 || settled || s + 1 == sweeps) verify(p_.check_distance);
      if (settled) break;
    }
    // Every vertex that moved, checked once more however little it moved since its last check;
    // should that leave a crossing, the resolver's own clean state is kept. A step back in that
    // check can tear an edge again: then the polish and the check once more.
    // With a fine polish, its round comes first and the coarse polish always follows it: the
    // fine limit fights edges that must stretch (a hem round an arm), and what a step back tears
    // there goes back to polish_strain.
    const bool fine = p_.fine_polish_strain > 0 && p_.fine_polish_strain < p_.polish_strain;
    for (int round = 0; round < kPolishRounds + (fine ? 1 : 0) && !active_.empty(); ++round) {
      const bool fineRound = fine && round == 0;
      polish(fineRound ? p_.fine_polish_strain : p_.polish_strain);
      const std::size_t stepsBefore = rep_.steps_back, contactsBefore = contacts_.size();
      if (!verify(0)) {
        for (int v : active_) g_.V.row(v) = start_[v];
        rep_.clean = false;
        break;
      }
      const bool added = p_.face_clearance > 0 && addFaceClearanceContacts() > 0;
      if (!fineRound && rep_.steps_back == stepsBefore && contacts_.size() == contactsBefore && !added) break;
    }
    rep_.active_vertices = active_.size();
    rep_.contacts = contacts_.size();
    rep_.candidates_reused = candidates_.reused - reused_before_;
    rep_.faces_checked = rep_.candidates_reused + (candidates_.queried - queried_before_);
    rep_.seconds = seconds(t0);
    return rep_;
  }

 private:
  static double seconds(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
  }


  // The vertices the resolver moved, and `rings` rings of neighbours round them; with p_.local, the
  // seeds and the ends of strained edges, and local_rings rings (chooseSeeds).
  void chooseActive() {
    active_flag_.assign(static_cast<std::size_t>(nv_), 0);
    moved_.assign(static_cast<std::size_t>(nv_), 0);
    std::vector<int> front;
    for (int v = 0; v < nv_; ++v)
      if ((g_.V.row(v) - in_.V.row(v)).squaredNorm() > 0) {
        moved_[v] = 1;
        if (p_.local) continue;
        active_flag_[v] = 1;
        front.push_back(v);
      }
    if (p_.local) chooseSeeds(front);
    rep_.local = p_.local;
    const int rings = p_.local ? p_.local_rings : p_.rings;
    for (int r = 0; r < rings; ++r) {
      std::vector<int> next;
      for (int v : front)
        for (int i = graph_.adj_start[v]; i < graph_.adj_start[v + 1]; ++i)
          if (!active_flag_[graph_.adj_v[i]]) {
            active_flag_[graph_.adj_v[i]] = 1;
            next.push_back(graph_.adj_v[i]);
          }
      front.swap(next);
    }
    for (int v = 0; v < nv_; ++v)
      if (active_flag_[v]) active_.push_back(v);
    takeRestLengths();
    input_length_.assign(static_cast<std::size_t>(topo_.edges.rows()), 0.0);
    for (Eigen::Index e = 0; e < topo_.edges.rows(); ++e) {
      const int a = topo_.edges(e, 0), b = topo_.edges(e, 1);
      input_length_[static_cast<std::size_t>(e)] = (in_.V.row(a) - in_.V.row(b)).norm();
      if (active_flag_[a] || active_flag_[b]) active_edges_.push_back(e);
    }
    clean_.resize(static_cast<std::size_t>(nv_));
    start_.resize(clean_.size());
    checked_.resize(clean_.size());
    plane_point_.resize(clean_.size());
    plane_normal_.resize(clean_.size());
    plane_at_.resize(clean_.size());
    plane_face_.assign(clean_.size(), -1);
    exact_distance_.assign(clean_.size(), -1.0);
    exact_at_.resize(clean_.size());
    floor_.assign(clean_.size(), d_);
    held_.assign(clean_.size(), 0);
    quat_.assign(clean_.size(), Eigen::Quaterniond::Identity());
    rot_.assign(clean_.size(), Eigen::Matrix3d::Identity());
  }

  // p_.local: the seeds, and both ends of each edge with a moved end strained past
  // local_seed_strain against the input (and, given the frame before, past what it was there by
  // local_seed_growth), flagged active and put on the front.
  void chooseSeeds(std::vector<int>& front) {
    auto seed = [&](int v) {
      if (v < 0 || v >= nv_ || active_flag_[v]) return;
      active_flag_[v] = 1;
      front.push_back(v);
    };
    for (int v : p_.seeds) seed(v);
    const bool before = p_.local_previous_input.rows() == nv_ && p_.local_previous_result.rows() == nv_ &&
                        p_.local_previous_input.cols() == 3 && p_.local_previous_result.cols() == 3;
    for (Eigen::Index e = 0; e < topo_.edges.rows(); ++e) {
      const int a = topo_.edges(e, 0), b = topo_.edges(e, 1);
      if (!moved_[a] && !moved_[b]) continue;
      const double strain = resolver_run::edgeStrain(in_.V, g_.V, a, b);
      if (!(strain > p_.local_seed_strain)) continue;
      if (before &&
          !(strain > resolver_run::edgeStrain(p_.local_previous_input, p_.local_previous_result, a, b) + p_.local_seed_growth))
        continue;
      seed(a);
      seed(b);
    }
  }

  // edge_rest_: per garment edge, its listed rest length (0: none), when rest_strain > 0.
  void takeRestLengths() {
    if (!(p_.rest_strain > 0) || p_.rest_lengths.empty()) return;
    edge_rest_.assign(static_cast<std::size_t>(topo_.edges.rows()), 0.0);
    // The edge a-b found among a's neighbours in the graph (no table to build: this runs every
    // frame of an animation, with thousands of rest lengths).
    for (const EdgeRestLength& r : p_.rest_lengths) {
      if (r.a < 0 || r.b < 0 || r.a >= nv_ || r.b >= nv_ || !(r.rest > 0)) continue;
      const int e = edgeBetween(r.a, r.b);
      if (e < 0) continue;
      double& rest = edge_rest_[static_cast<std::size_t>(e)];
      rest = rest > 0 ? std::min(rest, r.rest) : r.rest;
    }
  }

  // The garment edge between vertices a and b, -1 when they share none.
  int edgeBetween(int a, int b) const {
    for (int i = graph_.adj_start[a]; i < graph_.adj_start[a + 1]; ++i)
      if (graph_.adj_v[i] == b) return graph_.adj_e[i];
    return -1;
  }

  // The tangent plane of the body at the nearest point to x; outside a ridge the direction from
  // that point to x is the better normal. The first query of a vertex goes through the body's BVH;
  // later ones, for a vertex that moved a little, walk from its last face over the faces that share
  // a corner with the nearest one so far (the nearest point moves little with the vertex).
  void takePlane(int v, const Eigen::Vector3d& x) {
    takePlaneOf(v, x);
    ++rep_.plane_queries;
  }
  // takePlane() without the count: touches vertex v's entries alone (threads may share vertices).
  void takePlaneOf(int v, const Eigen::Vector3d& x) {
    int face = plane_face_[v];
    Eigen::Vector3d point;
    if (face < 0) {
      const ClosestPoint cp = closestPointOnBody(body_, x);
      face = cp.face;
      point = cp.point;
      exact_distance_[v] = (x - point).norm();
      exact_at_[v] = x;
    } else {
      point = walkToNearest(x, face);
    }
    Eigen::Vector3d n = body_.faceNormal(face);
    const Eigen::Vector3d r = x - point;
    if (r.norm() > 1e-9 && r.dot(n) > 0) n = r.normalized();
    plane_face_[v] = face;
    plane_point_[v] = point;
    plane_normal_[v] = n;
    plane_at_[v] = x;
  }

  Eigen::Vector3d walkToNearest(const Eigen::Vector3d& x, int& face) const {
    const TriMesh& B = body_.mesh();
    const std::vector<int>& bvfStart = body_.vertexFaceStart();
    const std::vector<int>& bvf = body_.vertexFaces();
    auto nearestOn = [&](int f) {
      return closestPointOnTriangle(x, B.V.row(B.F(f, 0)).transpose(), B.V.row(B.F(f, 1)).transpose(),
                                    B.V.row(B.F(f, 2)).transpose());
    };
    Eigen::Vector3d best = nearestOn(face);
    double bestD = (best - x).squaredNorm();
    // Faces already measured in this walk are not measured again: none was nearer than the best
    // then, and the best only gets nearer (the same walk, for less).
    std::array<int, kWalkMemory> seen;
    int seenCount = 0;
    seen[seenCount++] = face;
    auto measured = [&](int f) {
      for (int i = 0; i < seenCount; ++i)
        if (seen[static_cast<std::size_t>(i)] == f) return true;
      if (seenCount < kWalkMemory) seen[static_cast<std::size_t>(seenCount++)] = f;
      return false;
    };
    for (int step = 0; step < kMaxWalkSteps; ++step) {
      const int from = face;
      for (int k = 0; k < 3; ++k) {
        const int c = B.F(from, k);
        for (int i = bvfStart[c]; i < bvfStart[c + 1]; ++i) {
          if (measured(bvf[i])) continue;
          const Eigen::Vector3d q = nearestOn(bvf[i]);
          const double dq = (q - x).squaredNorm();
          if (dq < bestD) {
            bestD = dq;
            best = q;
            face = bvf[i];
          }
        }
      }
      if (face == from) break;
    }
    return best;
  }

  // Each active vertex's first body plane (a query through the body's tree) and its floor; the
  // vertices are independent, so the hardware threads share them.
  void setFloors() {
    parallelRanges(static_cast<int>(active_.size()), kPlanesPerThread, [this](int first, int last) {
      for (int i = first; i < last; ++i) {
        const int v = active_[static_cast<std::size_t>(i)];
        const Eigen::Vector3d x = g_.V.row(v).transpose();
        takePlaneOf(v, x);
        if (!moved_[v]) floor_[v] = std::min(d_, std::max(0.0, (x - plane_point_[v]).dot(plane_normal_[v])));
      }
    });
    rep_.plane_queries += active_.size();
  }

  // One projected Gauss-Seidel sweep; returns the largest vertex move.
  double sweep() {
    double largest = 0;
    for (int v : active_) {
      if (held_[v] > sweep_) continue;
      Eigen::Vector3d x = target(v);
      x = g_.V.row(v).transpose() + p_.over_relaxation * (x - g_.V.row(v).transpose());
      if ((x - plane_at_[v]).norm() > p_.replane_distance) takePlane(v, x);
      const double sd = (x - plane_point_[v]).dot(plane_normal_[v]);
      if (sd < floor_[v]) x += (floor_[v] - sd) * plane_normal_[v];
      largest = std::max(largest, (x.transpose() - g_.V.row(v)).norm());
      g_.V.row(v) = x.transpose();
    }
    return largest;
  }

  // After the sweeps: edges strained beyond `polish_strain` are brought back to it, held vertices
  // too (a step back near the end leaves single edges torn between a vertex that stepped back and
  // one that did not), the contacts kept, each pass checked for crossings like a sweep.
  void polish(double strain) {
    sweep_ = std::numeric_limits<int>::max() / 2;
    for (int pass = 0; pass < std::max(1, p_.polish_passes) && !active_.empty(); ++pass) {
      for (int v : active_) {
        clean_[v] = g_.V.row(v);
        held_[v] = 0;  // nothing is held in a polish, not even what stepped back in the pass before
      }
      if (p_.polish_passes > 0) limitStrain(strain);
      projectContacts();
      verify(p_.check_distance);
    }
  }

  // Where vertex v's neighbours put it: the mean over neighbours j of x_j plus the input edge
  // vector (x0_v - x0_j), turned by the mean of both ends' rotations, and a pull mu to the input.
  Eigen::Vector3d target(int v) const {
    Eigen::Vector3d sum = p_.mu * in_.V.row(v).transpose();
    for (int i = graph_.adj_start[v]; i < graph_.adj_start[v + 1]; ++i)
      sum += g_.V.row(graph_.adj_v[i]).transpose() + turned_[static_cast<std::size_t>(i)];
    return sum / (static_cast<double>(graph_.adj_start[v + 1] - graph_.adj_start[v]) + p_.mu);
  }

  // turned_: for each active vertex v and neighbour j, the input edge vector x0_v - x0_j turned by
  // the mean of both ends' rotations (as it is, without local rotations); kept between rotation
  // fits, so that a sweep only adds.
  void turnEdges() {
    for (int v : active_) {
      const Eigen::Vector3d x0 = in_.V.row(v).transpose();
      for (int i = graph_.adj_start[v]; i < graph_.adj_start[v + 1]; ++i) {
        const int j = graph_.adj_v[i];
        const Eigen::Vector3d e0 = x0 - in_.V.row(j).transpose();
        turned_[static_cast<std::size_t>(i)] = p_.local_rotations ? Eigen::Vector3d(0.5 * (rot_[v] + rot_[j]) * e0) : e0;
      }
    }
  }

  // Each active vertex's rotation: the one that best turns its input edge vectors into the
  // current ones (ARAP's local step), by the warm-started iteration of Mueller et al. 2016 ("A
  // robust method to extract the rotational part of deformations").
  void updateRotations() {
    const auto t0 = Clock::now();
    parallelRanges(static_cast<int>(active_.size()), kRotationsPerThread, [this](int first, int last) {
      for (int i = first; i < last; ++i) fitRotation(active_[static_cast<std::size_t>(i)]);
    });
    turnEdges();
    rep_.seconds_rotations += seconds(t0);
  }

  // Vertex v's rotation, warm-started from its last (independent of every other vertex's).
  void fitRotation(int v) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    const Eigen::Vector3d x = g_.V.row(v).transpose(), x0 = in_.V.row(v).transpose();
    for (int i = graph_.adj_start[v]; i < graph_.adj_start[v + 1]; ++i) {
      const int j = graph_.adj_v[i];
      A += (x - g_.V.row(j).transpose()) * (x0 - in_.V.row(j).transpose()).transpose();
    }
    Eigen::Quaterniond& q = quat_[v];
    for (int it = 0; it < kRotationIterations; ++it) {
      const Eigen::Matrix3d R = q.toRotationMatrix();
      const Eigen::Vector3d omega = (R.col(0).cross(A.col(0)) + R.col(1).cross(A.col(1)) + R.col(2).cross(A.col(2))) /
                                    (std::abs(R.col(0).dot(A.col(0)) + R.col(1).dot(A.col(1)) + R.col(2).dot(A.col(2))) + 1e-12);
      const double w = omega.norm();
      if (!(w > kRotationTolerance)) break;
      // A small turn by its first-order quaternion (no sine or cosine), a large one exactly.
      const Eigen::Quaterniond dq = w < 0.1 ? Eigen::Quaterniond(1, 0.5 * omega.x(), 0.5 * omega.y(), 0.5 * omega.z())
                                            : Eigen::Quaterniond(Eigen::AngleAxisd(w, omega / w));
      q = dq * q;
      q.normalize();
    }
    rot_[v] = q.toRotationMatrix();
  }

  // Edges longer than (1 + strain_limit) or shorter than (1 - strain_limit) times their input length
  // are brought back to that bound, each end moving half (a held or inactive end not at all), then
  // each moved end goes back onto its half-space.
  void limitStrain() { limitStrain(p_.strain_limit); }
  void limitStrain(double s) {
    for (const Eigen::Index e : active_edges_) {
      const int a = topo_.edges(e, 0), b = topo_.edges(e, 1);
      const bool ma = active_flag_[a] && held_[a] <= sweep_, mb = active_flag_[b] && held_[b] <= sweep_;
      if (!ma && !mb) continue;
      const double l0 = input_length_[static_cast<std::size_t>(e)];
      Eigen::RowVector3d ab = g_.V.row(b) - g_.V.row(a);
      const double l = ab.norm();
      if (!(l0 > 0) || !(l > 0)) continue;
      double upper = (1 + s) * l0;
      if (!edge_rest_.empty() && edge_rest_[static_cast<std::size_t>(e)] > 0)
        upper = std::min(upper, std::max(l0, (1 + p_.rest_strain) * edge_rest_[static_cast<std::size_t>(e)]));
      const double target = std::clamp(l, (1 - s) * l0, upper);
      if (target == l) continue;
      const Eigen::RowVector3d corr = (l - target) / l * ab;
      const double wa = ma ? (mb ? 0.5 : 1.0) : 0.0;
      if (ma) project(a, g_.V.row(a) + wa * corr);
      if (mb) project(b, g_.V.row(b) - (1 - wa) * corr);
    }
  }

  void project(int v, const Eigen::RowVector3d& to) {
    Eigen::Vector3d x = to.transpose();
    const double sd = (x - plane_point_[v]).dot(plane_normal_[v]);
    if (sd < floor_[v]) x += (floor_[v] - sd) * plane_normal_[v];
    g_.V.row(v) = x.transpose();
  }

  // Detects again round the vertices that moved more than `distance` since their last check (all
  // that moved at all, for 0). Each vertex of a crossing steps back a level (stepBack()), and the
  // faces round the vertices that stepped are detected again, until no crossing is left: a face
  // whose corners are all back in the resolver's state is clean, so this ends. Returns false only
  // if it did not end within kMaxRevertPasses passes.
  bool verify(double distance) {
    const auto t0 = Clock::now();
    const bool clean = checkAndStepBack(distance);
    rep_.seconds_checks += seconds(t0);
    return clean;
  }
  bool checkAndStepBack(double distance) {
    std::vector<int> check, moved, all;
    for (int v : active_) {
      const double d = (g_.V.row(v) - checked_[v]).norm();
      if (d > distance || (distance == 0 && d > 0)) check.push_back(v);
    }
    level_.assign(static_cast<std::size_t>(nv_), 0);
    for (int pass = 0; pass <= kMaxRevertPasses; ++pass) {
      CrossingSet found;
      detectAround(pass == 0 ? check : moved, found);
      if (found.size() == 0) {
        for (int v : check) checked_[v] = g_.V.row(v);
        for (int v : all) checked_[v] = g_.V.row(v);
        return true;
      }
      if (pass == kMaxRevertPasses) return false;
      addContacts(found);
      moved.clear();
      markCrossed(found, moved);
      for (int v : moved) {
        if (level_[v] == 0) all.push_back(v);
        stepBack(v);
      }
    }
    return false;
  }

  // Vertex v of a crossing steps back one level: half way to where this sweep block started
  // (`bisections` times), then all the way there, then (a crossing that even that did not clear:
  // the block's start was not checked everywhere) to the resolver's state, which is clean for every
  // face whose corners are all there. Only the vertices of crossings step, each as far as its own
  // crossings ask.
  void stepBack(int v) {
    const int level = level_[v]++;
    if (level < p_.bisections) g_.V.row(v) = 0.5 * (g_.V.row(v) + clean_[v]);
    else if (level == p_.bisections) g_.V.row(v) = clean_[v];
    else g_.V.row(v) = start_[v];
    held_[v] = sweep_ + 1 + p_.hold_sweeps;
    ++rep_.steps_back;
  }

  // A crossing found after a sweep becomes a contact that every later sweep keeps, so that the
  // vertices that stepped back do not walk into the same crossing again once released:
  //   body edge e through garment face (x1, x2, x3) at weights w: the garment point sum w_i x_i
  //     must lie beyond the edge's outer end along the edge's normal n_e, by the clearance;
  //   garment edge (a, b) through body face f at t: the edge's point (1 - t) a + t b must lie
  //     outside f's plane by the clearance.
  void addContacts(const CrossingSet& found) {
    const MatrixX3d& BV = body_.mesh().V;
    for (const auto& c : found.body_edges) {
      if (!contact_keys_.insert(contactKey(1, c.edge, c.face)).second) continue;
      const Eigen::Vector3d n = body_.edgeNormal(c.edge);
      if (n.squaredNorm() == 0) continue;
      const double top = std::max(n.dot(BV.row(body_.edges()(c.edge, 0)).transpose()),
                                  n.dot(BV.row(body_.edges()(c.edge, 1)).transpose()));
      Contact k;
      k.count = 3;
      for (int i = 0; i < 3; ++i) {
        k.vertex[i] = g_.F(c.face, i);
        k.weight[i] = c.bary[i];
      }
      k.normal = n;
      k.bound = top + d_;
      contacts_.push_back(k);
    }
    for (const auto& c : found.garment_edges) {
      if (!contact_keys_.insert(contactKey(0, c.edge, c.face)).second) continue;
      const Eigen::Vector3d n = body_.faceNormal(c.face);
      Contact k;
      k.count = 2;
      k.vertex = {{topo_.edges(c.edge, 0), topo_.edges(c.edge, 1), -1}};
      k.weight = {{1 - c.t, c.t, 0}};
      k.normal = n;
      k.bound = n.dot(BV.row(body_.mesh().F(c.face, 0)).transpose()) + d_;
      contacts_.push_back(k);
    }
  }

  static long long contactKey(int kind, int edge, int face) {
    return (static_cast<long long>(edge) << 32 | static_cast<unsigned>(face)) * 3 + kind;
  }

  // Each contact short of its bound moves its movable vertices together along its normal, by the
  // same amount (the least common move that meets the bound): a contact near one corner does not
  // lever that corner out by the inverse of its small weight.
  void projectContacts() {
    for (int pass = 0; pass < kContactPasses; ++pass)
      for (const Contact& k : contacts_) {
        double value = 0, w = 0;
        for (int i = 0; i < k.count; ++i) {
          value += k.weight[i] * k.normal.dot(g_.V.row(k.vertex[i]).transpose());
          if (active_flag_[k.vertex[i]]) w += k.weight[i];
        }
        if (value >= k.bound || !(w > kMinContactWeight)) continue;
        const Eigen::RowVector3d step = ((k.bound - value) / w) * k.normal.transpose();
        for (int i = 0; i < k.count; ++i)
          if (active_flag_[k.vertex[i]]) g_.V.row(k.vertex[i]) += step;
      }
  }

  // Adds the movable vertices of every crossing in `found` to `stepped` (each once).
  void markCrossed(const CrossingSet& found, std::vector<int>& stepped) {
    stepping_.resize(static_cast<std::size_t>(nv_), 0);
    auto mark = [&](int v) {
      if (!active_flag_[v] || stepping_[v]) return;
      stepping_[v] = 1;
      stepped.push_back(v);
    };
    for (const auto& c : found.garment_edges) {
      mark(topo_.edges(c.edge, 0));
      mark(topo_.edges(c.edge, 1));
    }
    for (const auto& c : found.body_edges)
      for (int k = 0; k < 3; ++k) mark(g_.F(c.face, k));
    for (int v : stepped) stepping_[v] = 0;
  }

  void detectAround(const std::vector<int>& vertices, CrossingSet& found) {
    facesAround(vertices, 0.0);
    if (faces_.empty()) return;
    detectCrossings(body_, g_, topo_, found, &faces_, candidates_);
    ++rep_.detections;
  }

  // faces_: the faces round `vertices` that may come within `margin` of the body, sorted.
  void facesAround(const std::vector<int>& vertices, double margin) {
    faces_.clear();
    const std::size_t nf = static_cast<std::size_t>(g_.F.rows());
    face_mark_.resize(nf, 0);
    std::size_t marked = 0;
    for (int v : vertices)
      for (int i = graph_.vf_start[v]; i < graph_.vf_start[v + 1]; ++i)
        if (!face_mark_[graph_.vf[i]]) {
          face_mark_[graph_.vf[i]] = 1;
          ++marked;
        }
    // In face order: a scan of the marks when many are marked, else a sort of the few.
    if (marked * 16 > nf) {
      for (std::size_t f = 0; f < nf; ++f)
        if (face_mark_[f]) {
          face_mark_[f] = 0;
          faces_.push_back(static_cast<int>(f));
        }
    } else {
      for (int v : vertices)
        for (int i = graph_.vf_start[v]; i < graph_.vf_start[v + 1]; ++i)
          if (face_mark_[graph_.vf[i]]) {
            face_mark_[graph_.vf[i]] = 0;
            faces_.push_back(graph_.vf[i]);
          }
      std::sort(faces_.begin(), faces_.end());
    }
    faces_.erase(std::remove_if(faces_.begin(), faces_.end(), [&](int f) { return clearOfBody(f, margin); }), faces_.end());
  }

  // The face clearances (face_clearance.h) of the faces round the active vertices, each a contact
  // that every later pass keeps. Returns how many were added.
  std::size_t addFaceClearanceContacts() {
    const std::size_t before = contacts_.size();
    facesAround(active_, p_.face_clearance);
    std::vector<resolver_run::FaceClearance> found;
    for (int f : faces_) resolver_run::faceClearances(body_, g_, f, p_.face_clearance, found);
    for (const resolver_run::FaceClearance& c : found) {
      if (!contact_keys_.insert(contactKey(2, c.body_vertex, c.face)).second) continue;
      Contact k;
      k.count = 3;
      for (int i = 0; i < 3; ++i) {
        k.vertex[i] = g_.F(c.face, i);
        k.weight[i] = c.weight[i];
      }
      k.normal = c.normal;
      k.bound = c.bound;
      contacts_.push_back(k);
    }
    return contacts_.size() - before;
  }

  // A lower bound on vertex v's distance from the body: its distance at its last exact nearest-
  // point query less how far it moved since; -1 when unknown.
  double distanceBound(int v) const {
    if (!active_flag_[v] || exact_distance_[v] < 0) return -1;
    return exact_distance_[v] - (g_.V.row(v).transpose() - exact_at_[v]).norm();
  }

  // True when garment face f cannot touch the body: some corner is farther from the body than
  // from every point of the face (its two edges' lengths bound that; the distance to the body
  // changes by at most the distance moved).
  bool clearOfBody(int f, double margin) const {
    for (int k = 0; k < 3; ++k) {
      const double bound = distanceBound(g_.F(f, k));
      if (bound > margin && bound > resolver_run::cornerReach(g_, f, k) + margin) return true;  // reach >= 0
    }
    return false;
  }

  struct Contact {
    int count = 0;
    std::array<int, 3> vertex{{-1, -1, -1}};
    std::array<double, 3> weight{{0, 0, 0}};
    Eigen::Vector3d normal{0, 0, 0};
    double bound = 0;  // sum_i weight_i normal . x_i >= bound
  };
  std::vector<Contact> contacts_;
  std::unordered_set<long long> contact_keys_;

  const Body& body_;
  const TriMesh& in_;
  TriMesh& g_;
  const GarmentTopology& topo_;
  const double d_;
  const ShapeRelaxationParams& p_;
  const int nv_;
  ShapeRelaxationReport rep_;
  const resolver_run::GarmentGraph& graph_;  // faces round each vertex, neighbours over edges
  CandidateCache own_candidates_;  // used when the caller has no cache to lend
  CandidateCache& candidates_;     // each checked face's body faces, reused while it stays in its box
  const std::size_t reused_before_, queried_before_;  // the cache's counts when the stage began
  std::vector<int> active_, faces_;
  std::vector<char> active_flag_, moved_, stepping_, face_mark_;
  std::vector<double> floor_;
  std::vector<Eigen::Index> active_edges_;  // edges with an active end, in edge order
  std::vector<double> input_length_;        // per garment edge: its length in the input
  std::vector<double> edge_rest_;  // per garment edge: its rest length, 0: none (takeRestLengths)
  std::vector<int> held_;  // per vertex: the first sweep it may move again after a step back
  std::vector<int> level_;  // per vertex: how far it has stepped back in this check (stepBack)
  int sweep_ = 0;
  // Per vertex: at the start of this sweep, at the start of the stage (the resolver's clean state),
  // and where it was last checked for crossings.
  std::vector<Eigen::RowVector3d> clean_, start_, checked_;
  std::vector<Eigen::Vector3d> plane_point_, plane_normal_, plane_at_;
  std::vector<int> plane_face_;
  std::vector<double> exact_distance_;     // per vertex: at its last query through the body's tree
  std::vector<Eigen::Vector3d> exact_at_;  // and where it was then
  std::vector<Eigen::Quaterniond> quat_;  // per vertex: its local rotation (identity when inactive)
  std::vector<Eigen::Matrix3d> rot_;
  std::vector<Eigen::Vector3d> turned_;  // per neighbour entry of the graph (turnEdges)
};

}  // namespace

ShapeRelaxationReport relaxShape(const Body& body, const TriMesh& input, TriMesh& garment,
                                 const GarmentTopology& topo, double clearance,
                                 const ShapeRelaxationParams& params) {
  const resolver_run::GarmentGraph graph(garment, topo);
  return ShapeRelaxation(body, input, garment, topo, graph, clearance, params, nullptr).run();
}

namespace resolver_run {

ShapeRelaxationReport relaxShape(const Body& body, const TriMesh& input, TriMesh& garment,
                                 const GarmentTopology& topo, const GarmentGraph& graph, double clearance,
                                 const ShapeRelaxationParams& params, CandidateCache* candidates) {
  return ShapeRelaxation(body, input, garment, topo, graph, clearance, params, candidates).run();
}

}  // namespace resolver_run

}  // namespace virtual_tryon
