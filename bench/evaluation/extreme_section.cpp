// Section 4: extreme cases. Each runs in a forked child with a watchdog, so a crash or a hang is
// reported as such (and the rest of the suite still runs); the resolver's own time budget should
// stop it long before the watchdog.
#include "common.h"

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/scenes/procedural.h"
#include "virtual_tryon/core/scenes/procedural_body.h"
#include "virtual_tryon/testing/reference_bvh.h"

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>

namespace eval {
namespace {

using V3 = Eigen::Vector3d;

struct Case {
  std::string name, what;
  std::function<NamedScene()> make;
};

vt::TriMesh cube(double side, const V3& c = V3::Zero()) {
  vt::TriMesh m;
  m.V.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    m.V.row(i) << c.x() + ((i & 1) ? 0.5 : -0.5) * side, c.y() + ((i & 2) ? 0.5 : -0.5) * side,
        c.z() + ((i & 4) ? 0.5 : -0.5) * side;
  m.F.resize(12, 3);
  // Outward, counter-clockwise seen from outside.
  m.F << 0, 2, 3, 0, 3, 1,  // -z
      4, 5, 7, 4, 7, 6,     // +z
      0, 1, 5, 0, 5, 4,     // -y
      2, 6, 7, 2, 7, 3,     // +y
      0, 4, 6, 0, 6, 2,     // -x
      1, 3, 7, 1, 7, 5;     // +x
  return m;
}

vt::TriMesh fingers(int n, double radius, double length, double gap, const V3& centre) {
  vt::TriMesh all;
  for (int i = 0; i < n; ++i) {
    const V3 c = centre + V3((i - 0.5 * (n - 1)) * gap, 0, 0.37 * radius * (i % 2 ? 1 : -1));
    const vt::TriMesh f = vt::makeCylinder(radius, length, c, 16, 3, true);
    all = all.V.rows() ? vt::concatenate(all, f) : f;
  }
  return all;
}

std::vector<Case> cases(const Options& o) {
  std::vector<Case> cs;
  cs.push_back({"fig5_band_through_arm",
                "Fig. 5: a cloth band (0.2 m, 20x20) through the axis of a cylinder arm (r 4 cm): the arm's "
                "normals on either side of the band point opposite ways", [] {
                  NamedScene s;
                  s.body = vt::makeCylinder(0.04, 0.4, V3::Zero(), 32, 8, true);
                  s.garment = vt::transformed(vt::makePatch(0.2, 0.2, 20, 20), V3::UnitX(), M_PI / 2, V3(0, 0, 0.0007));
                  return s;
                }});
  cs.push_back({"fig5_sleeve_wall_through_arm",
                "Fig. 5b: a sleeve (open tube r 6 cm) round an arm (r 4 cm) tilted 20 degrees, so the arm "
                "leaves through the sleeve's wall near both ends", [] {
                  NamedScene s;
                  s.body = vt::transformed(vt::makeCylinder(0.04, 0.5, V3::Zero(), 32, 10, true), V3::UnitZ(),
                                           20 * M_PI / 180, V3::Zero());
                  s.garment = vt::makeCylinder(0.06, 0.3, V3::Zero(), 36, 15, false);
                  return s;
                }});
  cs.push_back({"fig5_sleeve_wholly_inside_arm",
                "a sleeve (r 3.5 cm) wrapped round the axis of a thicker arm (r 4 cm): wholly inside, no crossing", [] {
                  NamedScene s;
                  s.body = vt::makeCylinder(0.04, 0.4, V3::Zero(), 40, 10, true);
                  s.garment = vt::makeCylinder(0.035, 0.2, V3::Zero(), 30, 12, false);
                  return s;
                }});
  cs.push_back({"fig5_cloth_trapped_in_sphere",
                "Fig. 5c/d: a patch (0.3 m, 30x30) through the middle of a closed sphere (r 0.1 m): the disc "
                "inside is pushed along the sphere's normals, in the cloth's own plane", [] {
                  NamedScene s;
                  s.body = vt::makeSphere(0.1, V3::Zero(), 4);
                  s.garment = vt::makePatch(0.3, 0.3, 30, 30, V3(0.0013, 0.0007, -0.0011));
                  return s;
                }});
  cs.push_back({"garment_wholly_inside_body",
                "a tube (r 5 cm, 0.2 m) wholly inside the procedural body's chest", [&o] {
                  NamedScene s;
                  vt::ProceduralBodyParams bp;
                  bp.resolution = o.quick ? 0.025 : 0.015;
                  s.body = vt::makeProceduralBody(bp);
                  const vt::ProceduralBodyLandmarks lm = vt::proceduralBodyLandmarks(bp);
                  s.garment = vt::makeCylinder(0.05, 0.2, V3(0, lm.waist_y + 0.05, lm.waist_z), 30, 12, false);
                  return s;
                }});
  cs.push_back({"deep_penetration_half_width",
                "a 0.4 x 0.2 m patch whose middle lies 0.1 m (half its 0.2 m height) inside a capsule torso", [] {
                  NamedScene s;
                  s.body = vt::makeCapsule(0.15, 0.6, V3::Zero(), 48, 24);
                  vt::TriMesh p = vt::makePatch(0.4, 0.2, 40, 20);
                  s.garment = vt::transformed(p, V3::UnitX(), M_PI / 2, V3(0, 0, 0.05));
                  return s;
                }});
  cs.push_back({"fingers_through_coarse_garment",
                "five fingers (cylinders r 1 cm) through a 3x3-quad patch (6.7 cm quads): each pierces a "
                "triangle, no garment vertex inside", [] {
                  NamedScene s;
                  s.body = fingers(5, 0.01, 0.15, 0.03, V3(0.011, 0, 0.013));
                  s.garment = vt::makePatch(0.2, 0.2, 3, 3);
                  return s;
                }});
  cs.push_back({"fingers_through_fine_garment",
                "the same five fingers through a 40x40-quad patch (5 mm quads)", [] {
                  NamedScene s;
                  s.body = fingers(5, 0.01, 0.15, 0.03, V3(0.011, 0, 0.013));
                  s.garment = vt::makePatch(0.2, 0.2, 40, 40, V3(0.0011, 0.0003, 0.0007));
                  return s;
                }});
  for (double off : {0.0, 1e-12, -1e-12, 1e-9, -1e-9, -1e-6}) {
    char name[64], what[128];
    std::snprintf(name, sizeof name, "coplanar_offset_%+.0e", off);
    std::snprintf(what, sizeof what, "a 10x10 patch in the plane of a 0.2 m box's top face, offset %+g m along its normal", off);
    cs.push_back({off == 0 ? std::string("coplanar_touching") : std::string(name), what, [off] {
                    NamedScene s;
                    s.body = cube(0.2);
                    s.garment = vt::makePatch(0.1, 0.1, 10, 10, V3(0.013, 0.1 + off, -0.021));
                    return s;
                  }});
  }
  cs.push_back({"touching_vertex",
                "a horizontal patch whose centre vertex sits exactly on the top vertex of an icosphere", [] {
                  NamedScene s;
                  s.body = vt::makeSphere(0.1, V3::Zero(), 3);
                  Eigen::Index top = 0;
                  s.body.V.col(1).maxCoeff(&top);
                  s.garment = vt::makePatch(0.1, 0.1, 10, 10, s.body.V.row(top).transpose());
                  return s;
                }});
  cs.push_back({"very_coarse_garment", "a wrinkled tube of 8 x 5 = 40 vertices round the capsule torso", [] {
                  vt::ResolveScene r = vt::makeWrinkledTubeScene(8, 4);
                  NamedScene s;
                  s.body = r.body;
                  s.garment = r.garment;
                  return s;
                }});
  cs.push_back({"dense_garment_50k", "the wrinkled tube at 256 x 196 = 50,176 vertices round the capsule torso", [] {
                  vt::ResolveScene r = vt::makeWrinkledTubeScene(256, 195);
                  NamedScene s;
                  s.body = r.body;
                  s.garment = r.garment;
                  return s;
                }});
  cs.push_back({"inverted_body", "a sphere wound inside out (inward normals) with a patch through its cap", [] {
                  NamedScene s;
                  s.body = vt::makeSphere(0.1, V3::Zero(), 4);
                  for (Eigen::Index f = 0; f < s.body.F.rows(); ++f) std::swap(s.body.F(f, 1), s.body.F(f, 2));
                  s.garment = vt::makePatch(0.12, 0.12, 24, 24, V3(0.003, 0.08, -0.002));
                  return s;
                }});
  cs.push_back({"open_body_with_holes",
                "a sphere with three holes (faces within 2.5 cm of three points) and a patch through its cap "
                "next to them; no inside test (open body)", [] {
                  NamedScene s;
                  const vt::TriMesh sphere = vt::makeSphere(0.1, V3::Zero(), 4);
                  const V3 holes[3] = {V3(0.03, 0.095, 0.0), V3(-0.05, 0.085, 0.02), V3(0.0, 0.0, 0.1)};
                  std::vector<int> keep;
                  for (Eigen::Index f = 0; f < sphere.F.rows(); ++f) {
                    const V3 c = (sphere.V.row(sphere.F(f, 0)) + sphere.V.row(sphere.F(f, 1)) +
                                  sphere.V.row(sphere.F(f, 2))).transpose() / 3;
                    bool hole = false;
                    for (const V3& h : holes) hole = hole || (c - h).norm() < 0.025;
                    if (!hole) keep.push_back(static_cast<int>(f));
                  }
                  s.body.V = sphere.V;
                  s.body.F.resize(static_cast<Eigen::Index>(keep.size()), 3);
                  for (std::size_t i = 0; i < keep.size(); ++i) s.body.F.row(static_cast<Eigen::Index>(i)) = sphere.F.row(keep[i]);
                  s.garment = vt::makePatch(0.12, 0.12, 24, 24, V3(0.003, 0.08, -0.002));
                  return s;
                }});
  cs.push_back({"degenerate_garment_faces",
                "a patch through a sphere's cap with one row of vertices collapsed onto the next (zero-area faces)", [] {
                  NamedScene s;
                  s.body = vt::makeSphere(0.1, V3::Zero(), 4);
                  s.garment = vt::makePatch(0.12, 0.12, 24, 24, V3(0.003, 0.08, -0.002));
                  for (int i = 0; i <= 24; ++i) s.garment.V.row(12 * 25 + i) = s.garment.V.row(13 * 25 + i);
                  return s;
                }});
  return cs;
}

// What the child reports, one tab-separated line.
struct Outcome {
  std::string status = "ok";  // ok, crash (signal N), hang (killed after T s), error
  bool converged = false;
  std::string reason;
  int iterations = 0;
  double seconds = 0;
  long garment_vertices = 0, body_faces = 0;
  bool body_closed = false, finite = true;
  std::size_t before[3] = {0, 0, 0}, after[3] = {0, 0, 0};
  double depth_before = 0, depth_after = 0, max_displacement = 0;
};

std::string serialize(const Outcome& r) {
  std::string reason = r.reason;
  for (char& c : reason)
    if (c == '\t' || c == '\n') c = ' ';
  char buf[512];
  std::snprintf(buf, sizeof buf, "%d\t%d\t%.9g\t%ld\t%ld\t%d\t%d\t%zu\t%zu\t%zu\t%zu\t%zu\t%zu\t%.9g\t%.9g\t%.9g\t",
                r.converged, r.iterations, r.seconds, r.garment_vertices, r.body_faces, r.body_closed, r.finite,
                r.before[0], r.before[1], r.before[2], r.after[0], r.after[1], r.after[2], r.depth_before,
                r.depth_after, r.max_displacement);
  return std::string(buf) + reason + "\n";
}

bool parse(const std::string& line, Outcome& r) {
  int conv = 0, closed = 0, finite = 0;
  int used = 0;
  if (std::sscanf(line.c_str(), "%d\t%d\t%lg\t%ld\t%ld\t%d\t%d\t%zu\t%zu\t%zu\t%zu\t%zu\t%zu\t%lg\t%lg\t%lg\t%n", &conv,
                  &r.iterations, &r.seconds, &r.garment_vertices, &r.body_faces, &closed, &finite, &r.before[0],
                  &r.before[1], &r.before[2], &r.after[0], &r.after[1], &r.after[2], &r.depth_before, &r.depth_after,
                  &r.max_displacement, &used) < 16)
    return false;
  r.converged = conv != 0;
  r.body_closed = closed != 0;
  r.finite = finite != 0;
  r.reason = line.substr(static_cast<std::size_t>(used));
  while (!r.reason.empty() && r.reason.back() == '\n') r.reason.pop_back();
  return true;
}

Outcome runChild(const Case& c, double budget) {
  Outcome r;
  NamedScene s = c.make();
  vt::Body body(s.body);
  r.garment_vertices = static_cast<long>(s.garment.V.rows());
  r.body_faces = static_cast<long>(s.body.F.rows());
  r.body_closed = body.closed();
  const vt::ReferenceReferee ref(s.body);
  const bool inside = body.closed();
  const vt::ReferenceCounts b = ref.count(s.garment, inside);
  const vt::TriMesh start = s.garment;
  vt::ResolverParams p;
  p.time_budget = budget;
  const vt::ResolverReport rep = vt::resolvePenetrations(body, s.garment, p);
  const vt::ReferenceCounts a = ref.count(s.garment, inside);
  r.converged = rep.converged;
  r.reason = rep.reason;
  r.iterations = rep.iterations;
  r.seconds = rep.seconds_total;
  r.finite = s.garment.V.allFinite();
  r.before[0] = b.garment_edge_crossings;
  r.before[1] = b.body_edge_crossings;
  r.before[2] = b.vertices_inside;
  r.after[0] = a.garment_edge_crossings;
  r.after[1] = a.body_edge_crossings;
  r.after[2] = a.vertices_inside;
  r.depth_before = b.max_depth;
  r.depth_after = a.max_depth;
  r.max_displacement = rep.max_displacement;
  return r;
}

Outcome runForked(const Case& c, double budget, double timeout) {
  Outcome r;
  int fd[2];
  if (pipe(fd) != 0) {
    r.status = "error: pipe";
    return r;
  }
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) {
    r.status = "error: fork";
    return r;
  }
  if (pid == 0) {
    close(fd[0]);
    const std::string line = serialize(runChild(c, budget));
    const char* p = line.data();
    std::size_t left = line.size();
    while (left > 0) {
      const ssize_t n = write(fd[1], p, left);
      if (n <= 0) break;
      p += n;
      left -= static_cast<std::size_t>(n);
    }
    close(fd[1]);
    _exit(0);
  }
  close(fd[1]);
  std::string text;
  const double t0 = now();
  bool timedOut = false;
  for (;;) {
    const double left = timeout - (now() - t0);
    if (left <= 0) {
      timedOut = true;
      break;
    }
    pollfd pf{fd[0], POLLIN, 0};
    const int k = poll(&pf, 1, static_cast<int>(std::min(left, 1.0) * 1000) + 1);
    if (k <= 0) continue;
    char buf[1024];
    const ssize_t n = read(fd[0], buf, sizeof buf);
    if (n <= 0) break;  // EOF: the child closed its end (finished or died)
    text.append(buf, static_cast<std::size_t>(n));
  }
  close(fd[0]);
  if (timedOut) kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  if (timedOut) {
    r.status = "hang (killed after " + std::to_string(static_cast<int>(timeout)) + " s)";
  } else if (WIFSIGNALED(status)) {
    r.status = std::string("crash (signal ") + std::to_string(WTERMSIG(status)) + ", " + strsignal(WTERMSIG(status)) + ")";
  } else if (!parse(text, r)) {
    r.status = "error: no result from the child (exit " + std::to_string(WEXITSTATUS(status)) + ")";
  }
  return r;
}

}  // namespace

void extremeSection(const Options& o) {
  Csv csv(o.out + "/extreme.csv",
          {"case", "what", "status", "converged", "reason", "iterations", "seconds", "garment_vertices",
           "body_faces", "body_closed", "finite", "garment_edge_before", "body_edge_before", "inside_before",
           "max_depth_before_m", "garment_edge_after", "body_edge_after", "inside_after", "max_depth_after_m",
           "max_displacement_m"});
  const double budget = o.quick ? 10 : 30;
  bool noCrashNoHang = true;
  int converged = 0, total = 0;
  for (const Case& c : cases(o)) {
    if (o.quick && c.name == "dense_garment_50k") continue;  // seconds, not part of the quick run
    progress("extreme: %s", c.name.c_str());
    const Outcome r = runForked(c, budget, o.extreme_timeout);
    noCrashNoHang = noCrashNoHang && r.status == "ok" && r.finite;
    converged += r.converged;
    ++total;
    csv.row({c.name, c.what, r.status, r.converged, r.reason, r.iterations, r.seconds, r.garment_vertices,
             r.body_faces, r.body_closed, r.finite, r.before[0], r.before[1], r.before[2], r.depth_before, r.after[0],
             r.after[1], r.after[2], r.depth_after, r.max_displacement});
  }
  summary().set("extreme.cases", total);
  summary().set("extreme.converged", converged);
  summary().set("extreme.no_crash_no_hang", noCrashNoHang);
}

}  // namespace eval
