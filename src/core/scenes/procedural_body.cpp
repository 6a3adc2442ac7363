// Procedural human-like body: smooth union of capsules, ellipsoids and a lofted elliptical torso,
// meshed by marching tetrahedra. See procedural_body.h.
#include "virtual_tryon/core/scenes/procedural_body.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace virtual_tryon {

namespace {

// ------------------------------------------------------------------------------------------------
// Primitives
// ------------------------------------------------------------------------------------------------

// Polynomial smooth minimum (Quilez): equals min(a, b) when |a - b| >= k, at most k/4 below it.
inline double smin(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}

// Capsule with a linearly tapering radius (segment distance minus the interpolated radius).
struct Capsule {
  Eigen::Vector3d a, b;
  double ra, rb;
  double eval(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d ba = b - a, pa = p - a;
    const double h = std::clamp(pa.dot(ba) / ba.squaredNorm(), 0.0, 1.0);
    return (pa - h * ba).norm() - (ra + h * (rb - ra));
  }
  void bounds(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const {
    const double r = std::max(ra, rb);
    lo = a.cwiseMin(b).array() - r;
    hi = a.cwiseMax(b).array() + r;
  }
};

// Ellipsoid with semi-axes r along the columns of R (approximate SDF, exact on the surface).
struct Ellipsoid {
  Eigen::Vector3d c;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d r;
  double eval(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d q = R.transpose() * (p - c);
    const double k0 = q.cwiseQuotient(r).norm();
    const double k1 = q.cwiseQuotient(r.cwiseProduct(r)).norm();
    if (k1 < 1e-12) return -r.minCoeff();
    return k0 * (k0 - 1.0) / k1;
  }
  void bounds(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const {
    Eigen::Vector3d e;
    for (int j = 0; j < 3; ++j)
      e(j) = std::sqrt(std::pow(R(j, 0) * r(0), 2) + std::pow(R(j, 1) * r(1), 2) + std::pow(R(j, 2) * r(2), 2));
    lo = c - e;
    hi = c + e;
  }
};

// Approximate signed distance to the ellipse x^2/a^2 + z^2/b^2 = 1 in the plane.
inline double ellipse2d(double x, double z, double a, double b) {
  const double k0 = std::sqrt(x * x / (a * a) + z * z / (b * b));
  const double k1 = std::sqrt(x * x / (a * a * a * a) + z * z / (b * b * b * b));
  if (k1 < 1e-12) return -std::min(a, b);
  return k0 * (k0 - 1.0) / k1;
}

// Torso: elliptical cross-sections (half-widths rx, rz, centre z = cz, centred at x = 0) lofted
// along y through stations with Catmull-Rom interpolation; the bottom and top caps are rounded with
// radius `round` (the station radii describe the outer surface).
struct Loft {
  std::vector<double> y, rx, rz, cz;
  double round = 0.03;

  static double catmullRom(const std::vector<double>& ys, const std::vector<double>& v, double t) {
    const int n = static_cast<int>(ys.size());
    if (t <= ys.front()) return v.front();
    if (t >= ys.back()) return v.back();
    int i = 0;
    while (i + 1 < n - 1 && t > ys[i + 1]) ++i;
    const double h = ys[i + 1] - ys[i];
    const double s = (t - ys[i]) / h;
    // Tangents (finite differences over the neighbouring stations, per unit y), scaled to h.
    auto slope = [&](int j) {
      if (j <= 0) return (v[1] - v[0]) / (ys[1] - ys[0]);
      if (j >= n - 1) return (v[n - 1] - v[n - 2]) / (ys[n - 1] - ys[n - 2]);
      return (v[j + 1] - v[j - 1]) / (ys[j + 1] - ys[j - 1]);
    };
    const double m0 = slope(i) * h, m1 = slope(i + 1) * h;
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * v[i] + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * v[i + 1] +
           (s3 - s2) * m1;
  }
  double eval(const Eigen::Vector3d& p) const {
    const double y0 = y.front() + round, y1 = y.back() - round;
    const double yc = std::clamp(p.y(), y0, y1);
    const double a = catmullRom(y, rx, yc) - round, b = catmullRom(y, rz, yc) - round;
    const double d2 = ellipse2d(p.x(), p.z() - catmullRom(y, cz, yc), a, b);
    const double dy = std::max(y0 - p.y(), p.y() - y1);
    const double ox = std::max(d2, 0.0), oy = std::max(dy, 0.0);
    return std::sqrt(ox * ox + oy * oy) + std::min(std::max(d2, dy), 0.0) - round;
  }
  void bounds(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const {
    // Catmull-Rom may overshoot the stations slightly: pad by 10%.
    const double mx = *std::max_element(rx.begin(), rx.end()) * 1.1;
    const double mz = *std::max_element(rz.begin(), rz.end()) * 1.1;
    const double zlo = *std::min_element(cz.begin(), cz.end()), zhi = *std::max_element(cz.begin(), cz.end());
    lo = Eigen::Vector3d(-mx, y.front(), zlo - mz);
    hi = Eigen::Vector3d(mx, y.back(), zhi + mz);
  }
};

// ------------------------------------------------------------------------------------------------
// The body model
// ------------------------------------------------------------------------------------------------

struct BodyModel {
  double height = 1.70, girth = 1.0;
  double blend = 0.025;  // smooth-union radius
  Loft torso;
  std::vector<Capsule> capsules;
  std::vector<Ellipsoid> ellipsoids;

  // Joints and key heights (for landmarks).
  double waist_y = 0, hip_y = 0, chest_y = 0;
  Eigen::Vector3d shoulder[2], elbow[2], wrist[2], hand[2], hip[2], knee[2], ankle[2];
  double arm_radius = 0, thigh_radius = 0, neck_y = 0, neck_radius = 0;

  double eval(const Eigen::Vector3d& p) const {
    double d = torso.eval(p);
    for (const Capsule& c : capsules) d = smin(d, c.eval(p), blend);
    for (const Ellipsoid& e : ellipsoids) d = smin(d, e.eval(p), blend);
    return d;
  }

  void bounds(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const {
    torso.bounds(lo, hi);
    Eigen::Vector3d l, h;
    for (const Capsule& c : capsules) {
      c.bounds(l, h);
      lo = lo.cwiseMin(l);
      hi = hi.cwiseMax(h);
    }
    for (const Ellipsoid& e : ellipsoids) {
      e.bounds(l, h);
      lo = lo.cwiseMin(l);
      hi = hi.cwiseMax(h);
    }
    // The smooth union can bulge by at most blend/4 beyond the primitives.
    lo.array() -= 0.25 * blend;
    hi.array() += 0.25 * blend;
  }
};

// Rotation whose columns are (u, v, w) with u along `axis` and v in the plane of axis and `hint`.
Eigen::Matrix3d frameAlong(const Eigen::Vector3d& axis, const Eigen::Vector3d& hint) {
  const Eigen::Vector3d u = axis.normalized();
  const Eigen::Vector3d v = (hint - hint.dot(u) * u).normalized();
  Eigen::Matrix3d R;
  R.col(0) = u;
  R.col(1) = v;
  R.col(2) = u.cross(v);
  return R;
}

// Positions given for a 1.70 m body, scaled by s = height / 1.70.
struct Scaled {
  double s;
  Eigen::Vector3d operator()(double x, double y, double z) const {
    return Eigen::Vector3d(s * x, s * y, s * z);
  }
};

// Torso: (y, half-width x, half-depth z, centre z) stations of the loft, and the key heights.
void addTorso(BodyModel& m, double s, double g) {
  struct Station { double y, rx, rz, cz; };
  const Station stations[] = {
      {0.755, 0.050, 0.050, -0.010},  // crotch (bottom cap)
      {0.840, 0.160, 0.108, -0.020},
      {0.890, 0.168, 0.112, -0.018},  // hips / seat
      {0.970, 0.158, 0.104, -0.010},
      {1.050, 0.138, 0.094, 0.000},   // waist
      {1.150, 0.150, 0.102, 0.008},
      {1.240, 0.166, 0.110, 0.012},   // chest
      {1.330, 0.170, 0.102, 0.004},
      {1.390, 0.164, 0.088, -0.010},  // shoulder line
      {1.430, 0.128, 0.074, -0.016},
      {1.470, 0.080, 0.060, -0.020},  // base of the neck (top cap)
  };
  for (const Station& st : stations) {
    m.torso.y.push_back(s * st.y);
    m.torso.rx.push_back(s * g * st.rx);
    m.torso.rz.push_back(s * g * st.rz);
    m.torso.cz.push_back(s * st.cz);
  }
  m.torso.round = 0.035 * s * g;
  m.waist_y = s * 1.05;
  m.hip_y = s * 0.88;
  m.chest_y = s * 1.24;
}

// Neck, head and trapezius.
void addNeckAndHead(BodyModel& m, double s, double g, double shoulderX) {
  const Scaled P{s};
  m.neck_y = s * 1.47;
  m.neck_radius = s * g * 0.056;
  m.capsules.push_back({P(0, 1.40, -0.018), P(0, 1.54, -0.004), m.neck_radius, m.neck_radius});
  {
    Ellipsoid head;
    head.c = P(0, 1.597, 0.008);
    head.r = Eigen::Vector3d(0.078, 0.103, 0.096) * s;  // head size does not follow the girth
    m.ellipsoids.push_back(head);
  }
  // Trapezius: slope from the neck down to the shoulders.
  for (int side = 0; side < 2; ++side) {
    const double sx = side == 0 ? 1.0 : -1.0;  // 0: left (+x), 1: right (-x)
    m.capsules.push_back({P(0, 1.435, -0.02), P(sx * (shoulderX - 0.02), 1.40, -0.014), s * g * 0.045,
                          s * g * 0.045});
  }
}

// Arms in an A-pose, 45 degrees below the horizontal.
void addArms(BodyModel& m, double s, double g, double shoulderX) {
  const Scaled P{s};
  const double armAngle = 45.0 * 3.14159265358979323846 / 180.0;
  m.arm_radius = s * g * 0.050;
  for (int side = 0; side < 2; ++side) {
    const double sx = side == 0 ? 1.0 : -1.0;
    const Eigen::Vector3d dir(sx * std::cos(armAngle), -std::sin(armAngle), 0.0);
    m.shoulder[side] = P(sx * shoulderX, 1.385, -0.012);
    m.elbow[side] = m.shoulder[side] + s * 0.285 * dir;
    m.wrist[side] = m.elbow[side] + s * 0.250 * dir;
    m.hand[side] = m.wrist[side] + s * 0.080 * dir;
    m.capsules.push_back({m.shoulder[side], m.elbow[side], m.arm_radius, s * g * 0.038});
    m.capsules.push_back({m.elbow[side], m.wrist[side], s * g * 0.039, s * g * 0.027});
    // Deltoid.
    m.ellipsoids.push_back({m.shoulder[side] + s * 0.045 * dir + P(0, 0.005, 0),
                            frameAlong(dir, Eigen::Vector3d(0, 0, 1)),
                            Eigen::Vector3d(0.085, 0.052, 0.050) * s * g});
    // Hand (a mitten): flattened, palm facing the thigh (thin along the in-plane normal of the arm),
    // thick enough to survive coarse meshing.
    m.ellipsoids.push_back({m.hand[side], frameAlong(dir, Eigen::Vector3d(0, 0, 1)),
                            Eigen::Vector3d(0.088 * s, 0.044 * s * g, 0.027 * s * g)});
  }
}

// Legs, slightly apart.
void addLegs(BodyModel& m, double s, double g) {
  const Scaled P{s};
  m.thigh_radius = s * g * 0.088;
  const double hipX = 0.094 * g;
  for (int side = 0; side < 2; ++side) {
    const double sx = side == 0 ? 1.0 : -1.0;
    m.hip[side] = P(sx * hipX, 0.875, -0.004);
    m.knee[side] = P(sx * (hipX + 0.024), 0.480, 0.006);
    m.ankle[side] = P(sx * (hipX + 0.034), 0.080, -0.022);
    m.capsules.push_back({m.hip[side], m.knee[side], m.thigh_radius, s * g * 0.050});
    m.capsules.push_back({m.knee[side], m.ankle[side], s * g * 0.049, s * g * 0.035});
    // Calf.
    m.ellipsoids.push_back({m.knee[side] + 0.32 * (m.ankle[side] - m.knee[side]) + P(0, 0, -0.018),
                            Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.052, 0.120, 0.054) * s * g});
    // Foot: bottom at y = 0.
    m.ellipsoids.push_back({P(sx * (hipX + 0.040), 0.036, 0.045), Eigen::Matrix3d::Identity(),
                            Eigen::Vector3d(0.045, 0.036, 0.128) * s});
  }
}

// All dimensions are for a 1.70 m body (metres) and scaled by s = height / 1.70; radii (and the
// lateral offsets that must follow them) are also scaled by the girth factor g.
BodyModel buildModel(const ProceduralBodyParams& params) {
  BodyModel m;
  const double s = params.height / 1.70;
  const double g = params.girth_scale;
  m.height = params.height;
  m.girth = g;
  m.blend = 0.025 * s;
  addTorso(m, s, g);
  const double shoulderX = 0.178 + 0.165 * (g - 1.0);  // follows the torso width
  addNeckAndHead(m, s, g, shoulderX);
  addArms(m, s, g, shoulderX);
  addLegs(m, s, g);
  return m;
}

// The model for `params`, cached per thread (proceduralBodySdf is called per point).
const BodyModel& cachedModel(const ProceduralBodyParams& params) {
  thread_local BodyModel model;
  thread_local bool valid = false;
  thread_local double h = 0, g = 0;
  if (!valid || h != params.height || g != params.girth_scale) {
    model = buildModel(params);
    h = params.height;
    g = params.girth_scale;
    valid = true;
  }
  return model;
}

// First zero crossing of the model's SDF along origin + t * dir, t in (0, tmax], starting inside.
double crossing(const BodyModel& m, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double tmax) {
  const double step = 0.002 * m.height / 1.70;
  double t0 = 0.0;
  if (m.eval(origin) >= 0) return 0.0;
  for (double t = step; t <= tmax; t += step) {
    if (m.eval(origin + t * dir) >= 0) {
      double a = t0, b = t;
      for (int it = 0; it < 40; ++it) {
        const double c = 0.5 * (a + b);
        (m.eval(origin + c * dir) < 0 ? a : b) = c;
      }
      return 0.5 * (a + b);
    }
    t0 = t;
  }
  return tmax;
}

// The connected component with the most faces (the mesh itself when it is in one piece).
TriMesh largestComponent(const TriMesh& mesh) {
  std::vector<int> label;
  const int n = connectedComponents(mesh, label);
  if (n <= 1) return mesh;
  std::vector<Eigen::Index> faces(static_cast<std::size_t>(n), 0);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) ++faces[static_cast<std::size_t>(label[mesh.F(f, 0)])];
  const int keep = static_cast<int>(std::max_element(faces.begin(), faces.end()) - faces.begin());
  std::vector<int> remap(static_cast<std::size_t>(mesh.V.rows()), -1);
  int nv = 0;
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v)
    if (label[static_cast<std::size_t>(v)] == keep) remap[static_cast<std::size_t>(v)] = nv++;
  TriMesh out;
  out.V.resize(nv, 3);
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v)
    if (remap[static_cast<std::size_t>(v)] >= 0) out.V.row(remap[static_cast<std::size_t>(v)]) = mesh.V.row(v);
  out.F.resize(faces[static_cast<std::size_t>(keep)], 3);
  Eigen::Index nf = 0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    if (label[static_cast<std::size_t>(mesh.F(f, 0))] == keep)
      out.F.row(nf++) << remap[static_cast<std::size_t>(mesh.F(f, 0))], remap[static_cast<std::size_t>(mesh.F(f, 1))],
          remap[static_cast<std::size_t>(mesh.F(f, 2))];
  return out;
}

}  // namespace

double proceduralBodySdf(const Eigen::Vector3d& p, const ProceduralBodyParams& params) {
  return cachedModel(params).eval(p);
}

TriMesh makeProceduralBody(const ProceduralBodyParams& params) {
  const BodyModel m = buildModel(params);
  Eigen::Vector3d lo, hi;
  m.bounds(lo, hi);
  const double cell = params.resolution;
  lo.array() -= 2.0 * cell;
  hi.array() += 2.0 * cell;
  TriMesh mesh = meshImplicit([&m](const Eigen::Vector3d& p) { return m.eval(p); }, lo, hi, cell);
  // At coarse resolutions a fingertip can come out as a separate sliver: keep the largest piece.
  return largestComponent(mesh);
}

ProceduralBodyLandmarks proceduralBodyLandmarks(const ProceduralBodyParams& params) {
  const BodyModel m = buildModel(params);
  ProceduralBodyLandmarks L;
  L.waist_y = m.waist_y;
  L.hip_y = m.hip_y;
  L.chest_y = m.chest_y;
  L.shoulder_y = m.shoulder[0].y();
  L.knee_y = m.knee[0].y();
  L.neck_y = m.neck_y;
  L.neck_radius = m.neck_radius;
  const double reach = m.height;  // longer than any half-width
  auto section = [&](double y, double& rx, double& rz, double& cz) {
    // Centre in z from the torso loft, then the extents measured on the actual shape.
    const double zc = Loft::catmullRom(m.torso.y, m.torso.cz, y);
    const Eigen::Vector3d o(0.0, y, zc);
    const double front = crossing(m, o, Eigen::Vector3d::UnitZ(), reach);
    const double back = crossing(m, o, -Eigen::Vector3d::UnitZ(), reach);
    rz = 0.5 * (front + back);
    cz = zc + 0.5 * (front - back);
    const Eigen::Vector3d oc(0.0, y, cz);
    rx = 0.5 * (crossing(m, oc, Eigen::Vector3d::UnitX(), reach) + crossing(m, oc, -Eigen::Vector3d::UnitX(), reach));
  };
  section(L.waist_y, L.waist_radius_x, L.waist_radius_z, L.waist_z);
  section(L.hip_y, L.hip_radius_x, L.hip_radius_z, L.hip_z);
  section(L.chest_y, L.chest_radius_x, L.chest_radius_z, L.chest_z);
  // Crotch: lowest point of the torso between the legs (going down from the hip section centre).
  L.crotch_y = L.hip_y - crossing(m, Eigen::Vector3d(0.0, L.hip_y, L.hip_z), -Eigen::Vector3d::UnitY(), L.hip_y);
  L.left_shoulder = m.shoulder[0];
  L.right_shoulder = m.shoulder[1];
  L.left_elbow = m.elbow[0];
  L.right_elbow = m.elbow[1];
  L.left_wrist = m.wrist[0];
  L.right_wrist = m.wrist[1];
  L.left_hand = m.hand[0];
  L.right_hand = m.hand[1];
  L.left_hip_joint = m.hip[0];
  L.right_hip_joint = m.hip[1];
  L.left_knee = m.knee[0];
  L.right_knee = m.knee[1];
  L.left_ankle = m.ankle[0];
  L.right_ankle = m.ankle[1];
  L.arm_radius = m.arm_radius;
  L.thigh_radius = m.thigh_radius;
  return L;
}

// ------------------------------------------------------------------------------------------------
// Marching tetrahedra
// ------------------------------------------------------------------------------------------------

namespace {

// The grid of meshImplicit: nodes lo + cell * (i, j, k) for i < nx, j < ny, k < nz, and f at each.
struct Grid {
  Eigen::Vector3d lo;
  double cell = 0;
  std::int64_t nx = 0, ny = 0, nz = 0;
  std::vector<double> val;  // f per node, NaN replaced by 1 (outside)

  std::int64_t node(std::int64_t i, std::int64_t j, std::int64_t k) const { return i + nx * (j + ny * k); }
  Eigen::Vector3d pos(std::int64_t idx) const {
    const std::int64_t i = idx % nx, j = (idx / nx) % ny, k = idx / (nx * ny);
    return Eigen::Vector3d(lo.x() + cell * i, lo.y() + cell * j, lo.z() + cell * k);
  }
  bool inside(std::int64_t idx) const { return val[static_cast<std::size_t>(idx)] < 0.0; }
};

// Enough nodes from lo to cover hi; f once per node.
Grid sampleGrid(const std::function<double(const Eigen::Vector3d&)>& f, const Eigen::Vector3d& lo,
                const Eigen::Vector3d& hi, double cell) {
  Grid g;
  g.lo = lo;
  g.cell = cell;
  const Eigen::Array3d ext = (hi - lo).array() / cell;
  g.nx = static_cast<std::int64_t>(std::ceil(ext(0))) + 1;
  g.ny = static_cast<std::int64_t>(std::ceil(ext(1))) + 1;
  g.nz = static_cast<std::int64_t>(std::ceil(ext(2))) + 1;
  const std::int64_t nNodes = g.nx * g.ny * g.nz;
  g.val.resize(static_cast<std::size_t>(nNodes));
  for (std::int64_t k = 0; k < g.nz; ++k)
    for (std::int64_t j = 0; j < g.ny; ++j)
      for (std::int64_t i = 0; i < g.nx; ++i) {
        const double v = f(Eigen::Vector3d(lo.x() + cell * i, lo.y() + cell * j, lo.z() + cell * k));
        g.val[static_cast<std::size_t>(g.node(i, j, k))] = std::isnan(v) ? 1.0 : v;
      }
  return g;
}

// Six tetrahedra sharing the diagonal 0-7 of a cube (corners: bit 0 = +x, bit 1 = +y, bit 2 = +z)
// (Kuhn / Freudenthal split): 0, e_a, e_a + e_b, 7 for each permutation (a, b, c) of the axes. All
// cubes split the same way, so faces match between cubes.
std::array<std::array<int, 4>, 6> kuhnTetrahedra() {
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  std::array<std::array<int, 4>, 6> tets;
  for (int t = 0; t < 6; ++t) {
    tets[t][0] = 0;
    tets[t][1] = 1 << perms[t][0];
    tets[t][2] = (1 << perms[t][0]) | (1 << perms[t][1]);
    tets[t][3] = 7;
  }
  return tets;
}

// The surface as it is built cube by cube: vertices on grid edges, shared, and faces.
struct TetSurface {
  const Grid& grid;
  std::array<std::int64_t, 8> cornerOffset;  // of each cube corner, in node indices
  const std::array<std::array<int, 4>, 6> tets = kuhnTetrahedra();
  // Vertices on grid edges: key = (node of the lower corner) * 8 + offset bits. Every tet edge joins
  // corners u < v with u's bits a subset of v's, so the key is unique per grid edge.
  std::unordered_map<std::uint64_t, int> edgeVertex;
  std::vector<double> verts;  // xyz
  std::vector<int> faces;     // abc

  explicit TetSurface(const Grid& g) : grid(g) {
    for (int c = 0; c < 8; ++c) cornerOffset[c] = grid.node(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    edgeVertex.reserve(1 << 16);
  }

  // Vertex on the edge between cube corners cu and cv of the cube at base node `base`.
  int edgeVertexId(std::int64_t base, int cu, int cv) {
    constexpr double tMin = 1e-3, tMax = 1.0 - 1e-3;
    if (cu > cv) std::swap(cu, cv);  // chains are monotone: the smaller corner is the lower one
    const std::int64_t a = base + cornerOffset[cu], b = base + cornerOffset[cv];
    const std::uint64_t key = static_cast<std::uint64_t>(a) * 8u + static_cast<std::uint64_t>(cu ^ cv);
    auto it = edgeVertex.find(key);
    if (it != edgeVertex.end()) return it->second;
    const double fa = grid.val[static_cast<std::size_t>(a)], fb = grid.val[static_cast<std::size_t>(b)];
    const double t = std::clamp(fa / (fa - fb), tMin, tMax);
    const Eigen::Vector3d p = grid.pos(a) + t * (grid.pos(b) - grid.pos(a));
    const int id = static_cast<int>(verts.size() / 3);
    verts.insert(verts.end(), {p.x(), p.y(), p.z()});
    edgeVertex.emplace(key, id);
    return id;
  }

  Eigen::Vector3d vertexPos(int id) const {
    return Eigen::Vector3d(verts[3 * id], verts[3 * id + 1], verts[3 * id + 2]);
  }

  // Adds the triangle (i0, i1, i2), oriented so that node `ref` (at position pr) is on the inner
  // side if refInside, else on the outer side. `ref` is the common endpoint of two of the three
  // grid edges, so the triangle's plane separates it from those edges' other ends.
  void addTri(int i0, int i1, int i2, const Eigen::Vector3d& pr, bool refInside) {
    const Eigen::Vector3d p0 = vertexPos(i0), p1 = vertexPos(i1), p2 = vertexPos(i2);
    const double side = (p1 - p0).cross(p2 - p0).dot(pr - p0);
    if ((side < 0) != refInside) std::swap(i1, i2);
    if (i0 == i1 || i1 == i2 || i0 == i2) return;
    faces.insert(faces.end(), {i0, i1, i2});
  }

  // The surface in the cube at base node `base`, tetrahedron by tetrahedron.
  void addCube(std::int64_t base) {
    int mask = 0;
    for (int c = 0; c < 8; ++c)
      if (grid.inside(base + cornerOffset[c])) mask |= 1 << c;
    if (mask == 0 || mask == 255) return;
    const Eigen::Vector3d basePos = grid.pos(base);
    for (const auto& tet : tets) addTet(base, basePos, mask, tet);
  }

  // The surface in one tetrahedron of the cube at `base` (at basePos) whose inside corners are `mask`:
  // a triangle round a lone corner, or a quad split in two.
  void addTet(std::int64_t base, const Eigen::Vector3d& basePos, int mask, const std::array<int, 4>& tet) {
    const double cell = grid.cell;
    auto cornerPos = [&](int c) {
      return Eigen::Vector3d(basePos.x() + cell * (c & 1), basePos.y() + cell * ((c >> 1) & 1),
                             basePos.z() + cell * ((c >> 2) & 1));
    };
    int in[4], outs[4], nIn = 0, nOut = 0;
    for (int q = 0; q < 4; ++q) {
      if (mask & (1 << tet[q]))
        in[nIn++] = tet[q];
      else
        outs[nOut++] = tet[q];
    }
    if (nIn == 0 || nOut == 0) return;
    if (nIn == 1 || nOut == 1) {
      const bool loneInside = nIn == 1;
      const int lone = loneInside ? in[0] : outs[0];
      const int* others = loneInside ? outs : in;
      addTri(edgeVertexId(base, lone, others[0]), edgeVertexId(base, lone, others[1]),
             edgeVertexId(base, lone, others[2]), cornerPos(lone), loneInside);
    } else {
      // Quad ac, ad, bd, bc (a, b inside; c, d outside); split along the shorter diagonal.
      const int a = in[0], b = in[1], c = outs[0], d = outs[1];
      const int ac = edgeVertexId(base, a, c), ad = edgeVertexId(base, a, d);
      const int bc = edgeVertexId(base, b, c), bd = edgeVertexId(base, b, d);
      if ((vertexPos(ac) - vertexPos(bd)).squaredNorm() <= (vertexPos(ad) - vertexPos(bc)).squaredNorm()) {
        addTri(ac, ad, bd, cornerPos(a), true);   // ac, ad share a
        addTri(ac, bd, bc, cornerPos(c), false);  // ac, bc share c
      } else {
        addTri(ac, ad, bc, cornerPos(a), true);   // ac, ad share a
        addTri(ad, bd, bc, cornerPos(b), true);   // bd, bc share b
      }
    }
  }

  // Compacted (only matters if a face was dropped) and copied out.
  TriMesh mesh() const {
    TriMesh out;
    const int nv = static_cast<int>(verts.size() / 3);
    std::vector<int> remap(static_cast<std::size_t>(nv), -1);
    int used = 0;
    for (int id : faces)
      if (remap[static_cast<std::size_t>(id)] < 0) remap[static_cast<std::size_t>(id)] = 0;
    for (int v = 0; v < nv; ++v)
      if (remap[static_cast<std::size_t>(v)] == 0) remap[static_cast<std::size_t>(v)] = used++;
    out.V.resize(used, 3);
    for (int v = 0; v < nv; ++v) {
      const int r = remap[static_cast<std::size_t>(v)];
      if (r >= 0) out.V.row(r) << verts[3 * v], verts[3 * v + 1], verts[3 * v + 2];
    }
    out.F.resize(static_cast<Eigen::Index>(faces.size() / 3), 3);
    for (std::size_t q = 0; q < faces.size(); ++q)
      out.F(static_cast<Eigen::Index>(q / 3), static_cast<Eigen::Index>(q % 3)) =
          remap[static_cast<std::size_t>(faces[q])];
    return out;
  }
};

}  // namespace

TriMesh meshImplicit(const std::function<double(const Eigen::Vector3d&)>& f, const Eigen::Vector3d& lo,
                     const Eigen::Vector3d& hi, double cell) {
  if (!(cell > 0) || !(hi.array() > lo.array()).all()) return TriMesh();
  const Grid grid = sampleGrid(f, lo, hi, cell);
  TetSurface surface(grid);
  for (std::int64_t k = 0; k + 1 < grid.nz; ++k)
    for (std::int64_t j = 0; j + 1 < grid.ny; ++j)
      for (std::int64_t i = 0; i + 1 < grid.nx; ++i) surface.addCube(grid.node(i, j, k));
  return surface.mesh();
}

TriMesh subdivideMidpoint(const TriMesh& mesh) {
  MatrixX3i FE;
  const MatrixX2i E = uniqueEdges(mesh, &FE);
  const Eigen::Index nv = mesh.V.rows(), nf = mesh.F.rows();
  TriMesh out;
  out.V.resize(nv + E.rows(), 3);
  out.V.topRows(nv) = mesh.V;
  for (Eigen::Index e = 0; e < E.rows(); ++e)
    out.V.row(nv + e) = 0.5 * (mesh.V.row(E(e, 0)) + mesh.V.row(E(e, 1)));
  out.F.resize(4 * nf, 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const int v0 = mesh.F(f, 0), v1 = mesh.F(f, 1), v2 = mesh.F(f, 2);
    const int m01 = static_cast<int>(nv + FE(f, 0)), m12 = static_cast<int>(nv + FE(f, 1)),
              m20 = static_cast<int>(nv + FE(f, 2));
    out.F.row(4 * f + 0) << v0, m01, m20;
    out.F.row(4 * f + 1) << v1, m12, m01;
    out.F.row(4 * f + 2) << v2, m20, m12;
    out.F.row(4 * f + 3) << m01, m12, m20;
  }
  return out;
}

}  // namespace virtual_tryon
