// Section 3: stability on stiff cases. (a) The explicit cloth step over stiffness K/m and dt as a
// fraction of the paper's eq. 4 bound 0.4 pi sqrt(m / K); (b) the resolver's zone solves on
// nearly parallel and duplicate stencils, and on the zones of the section 1 scenes.
#include "common.h"

#include "virtual_tryon/core/body/body.h"
#include "virtual_tryon/core/drape/cloth.h"
#include "virtual_tryon/core/resolve/impact_zones.h"
#include "virtual_tryon/core/resolve/intersections.h"
#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/resolve/penetration_resolver.h"
#include "virtual_tryon/core/resolve/stencils.h"

#include <algorithm>
#include <random>

namespace eval {
namespace {

// A square of cloth hanging from its top row (the rail), every node nudged by up to 1e-4 of the
// spacing so that every mode starts excited.
struct Hanging {
  vt::ClothMesh mesh;
  std::vector<int> rail;
};
Hanging hangingCloth(double side, double spacing) {
  vt::Pattern p;
  vt::PatternPanel panel;
  panel.name = "sheet";
  panel.outline.resize(4, 2);
  panel.outline << 0, 0, side, 0, side, side, 0, side;
  p.panels.push_back(panel);
  Hanging h;
  std::string err;
  vt::meshPattern(p, spacing, h.mesh, err);
  const double top = h.mesh.X.col(1).maxCoeff();
  for (Eigen::Index i = 0; i < h.mesh.X.rows(); ++i)
    if (h.mesh.X(i, 1) > top - 1e-9) h.rail.push_back(static_cast<int>(i));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1e-4 * spacing, 1e-4 * spacing);
  for (Eigen::Index i = 0; i < h.mesh.X.rows(); ++i)
    for (int k = 0; k < 3; ++k) h.mesh.X(i, k) += u(rng);
  return h;
}

struct CellResult {
  bool stable = true;
  std::string why = "stable";
  double max_strain = 0;
  double energy_growth = 0;  // (max E - E0) / (m g side): > 0.001 counts as growth
  int steps_done = 0;
};

CellResult runCell(const Hanging& h, const vt::ClothParams& params, double dt, int steps, double side) {
  CellResult c;
  vt::ClothState cloth(h.mesh, params);
  vt::MatrixX3d railX(static_cast<Eigen::Index>(h.rail.size()), 3);
  for (std::size_t i = 0; i < h.rail.size(); ++i) railX.row(static_cast<Eigen::Index>(i)) = cloth.positions().row(h.rail[i]);
  double totalMass = 0;
  for (double m : cloth.masses()) totalMass += m;
  const double scale = totalMass * params.gravity.norm() * side;  // J
  const double e0 = cloth.kineticEnergy() + cloth.potentialEnergy();
  double eMax = e0;
  for (int s = 0; s < steps; ++s) {
    if (!cloth.step(dt, false)) {
      c.stable = false;
      c.why = "blew up (non-finite or > 50 m/s) at step " + std::to_string(s + 1);
      break;
    }
    for (std::size_t i = 0; i < h.rail.size(); ++i) {
      cloth.positions().row(h.rail[i]) = railX.row(static_cast<Eigen::Index>(i));
      cloth.velocities().row(h.rail[i]).setZero();
    }
    c.steps_done = s + 1;
    if (s % 10 == 9 || s == steps - 1) {
      double mx, mean;
      cloth.strain(mx, mean);
      c.max_strain = std::max(c.max_strain, mx);
      eMax = std::max(eMax, cloth.kineticEnergy() + cloth.potentialEnergy());
      if (!std::isfinite(eMax)) {
        c.stable = false;
        c.why = "non-finite energy at step " + std::to_string(s + 1);
        break;
      }
    }
  }
  c.energy_growth = (eMax - e0) / scale;
  if (c.stable && c.energy_growth > 1e-3) {
    c.stable = false;
    c.why = "energy grew by " + std::to_string(c.energy_growth) + " m g side";
  }
  return c;
}

vt::ClothParams stiffParams(double kOverM, double mass) {
  vt::ClothParams p;
  const double k = kOverM * mass;  // the stiffest spring (structural); shear and flexion keep the default ratios
  p.k_structural = k;
  p.k_shear = 0.2 * k;
  p.k_flexion = 0.1 * k;
  return p;
}

vt::Stencil vertexStencil(int v, const Eigen::Vector3d& n, double D) {
  vt::Stencil s;
  s.count = 1;
  s.vertex = {{v, -1, -1}};
  s.normal = n.normalized();
  s.D = D;
  return s;
}
vt::Stencil faceStencil(const std::array<int, 3>& v, const std::array<double, 3>& w, const Eigen::Vector3d& n,
                        double D) {
  vt::Stencil s;
  s.count = 3;
  s.vertex = v;
  s.weight = w;
  s.normal = n.normalized();
  s.D = D;
  return s;
}

}  // namespace

void stabilitySection(const Options& o) {
  // (a) Cloth: K/m against dt / dt_paper.
  const double side = 0.3, spacing = 0.03;
  const Hanging h = hangingCloth(side, spacing);
  const vt::ClothParams defaults;
  const double mass = defaults.density * spacing * spacing;
  const std::vector<double> kOverM = o.quick ? std::vector<double>{1e2, 1e4, 1e6}
                                             : std::vector<double>{1e2, 3.16e2, 1e3, 3.16e3, 1e4, 3.16e4, 1e5, 3.16e5, 1e6};
  std::vector<double> factors;
  if (o.quick)
    factors = {0.2, 0.5, 1.0, 2.0};
  else
    for (int i = 1; i <= 20; ++i) factors.push_back(0.1 * i);
  const int steps = o.quick ? 600 : 3000;
  Csv cells(o.out + "/stability_cloth.csv",
            {"k_over_m_per_s2", "dt_factor", "dt_s", "dt_paper_s", "automatic", "stable", "why", "max_strain",
             "energy_growth", "steps"});
  Csv edges(o.out + "/stability_edges.csv",
            {"k_over_m_per_s2", "dt_paper_s", "measured_edge_factor", "per_node_bound_factor", "automatic_factor"});
  bool autoStableAll = true, paperUnstableSomewhere = false;
  double edgeMin = 1e9, edgeMax = 0, autoMax = 0;
  for (double km : kOverM) {
    const vt::ClothParams p = stiffParams(km, mass);
    vt::ClothState probe(h.mesh, p);
    const double dtPaper = probe.paperTimeStep();
    const double dtAuto = 0.9 * probe.stableTimeStep();  // DrapeParams::dt_safety * the per-node bound
    progress("stability: K/m %.3g (dt_paper %.3g s, automatic %.3g s)", km, dtPaper, dtAuto);
    for (double f : factors) {
      const CellResult c = runCell(h, p, f * dtPaper, steps, side);
      cells.row({km, f, f * dtPaper, dtPaper, false, c.stable, c.why, c.max_strain, c.energy_growth, c.steps_done});
      if (!c.stable && f <= 1.0 + 1e-9) paperUnstableSomewhere = true;
    }
    const CellResult a = runCell(h, p, dtAuto, steps, side);
    cells.row({km, dtAuto / dtPaper, dtAuto, dtPaper, true, a.stable, a.why, a.max_strain, a.energy_growth, a.steps_done});
    autoStableAll = autoStableAll && a.stable;
    autoMax = std::max(autoMax, dtAuto / dtPaper);
    // The measured edge: bisection between a stable and an unstable factor.
    double lo = 0.05, hi = 4.0;
    if (!runCell(h, p, hi * dtPaper, steps, side).stable && runCell(h, p, lo * dtPaper, steps, side).stable) {
      for (int i = 0; i < (o.quick ? 6 : 12); ++i) {
        const double mid = 0.5 * (lo + hi);
        (runCell(h, p, mid * dtPaper, steps, side).stable ? lo : hi) = mid;
      }
    } else {
      lo = std::nan("");
    }
    edges.row({km, dtPaper, lo, probe.stableTimeStep() / dtPaper, dtAuto / dtPaper});
    if (std::isfinite(lo)) {
      edgeMin = std::min(edgeMin, lo);
      edgeMax = std::max(edgeMax, lo);
    }
  }
  summary().set("stability.automatic_dt_stable_in_every_cell", autoStableAll);
  summary().set("stability.paper_bound_unstable_somewhere", paperUnstableSomewhere);
  summary().set("stability.measured_edge_factor_min", edgeMin);
  summary().set("stability.measured_edge_factor_max", edgeMax);
  summary().set("stability.automatic_factor_max", autoMax);

  // (b) Zone solves: constructed ill-conditioned zones.
  Csv zones(o.out + "/stability_zones.csv",
            {"case", "parameter", "stencils", "condition", "regularized_condition", "solver_pivot_ratio", "method",
             "feasible", "finite", "max_violation_m", "max_displacement_m", "single_stencil_m", "displacement_ratio"});
  const double d = 0.001;
  bool finiteBounded = true;
  double worstRatio = 0;
  auto solve = [&](const std::string& name, double param, const std::vector<vt::Stencil>& st) {
    std::vector<int> zone(st.size());
    for (std::size_t i = 0; i < st.size(); ++i) zone[i] = static_cast<int>(i);
    const vt::ZoneConditioning c = vt::zoneConditioning(st, zone);
    const vt::ZoneSolution s = vt::solveImpactZone(st, zone, d);
    bool finite = true;
    double maxDx = 0;
    for (const auto& v : s.displacement) {
      finite = finite && v.allFinite();
      maxDx = std::max(maxDx, v.norm());
    }
    for (double l : s.lambda) finite = finite && std::isfinite(l);
    double single = 0;  // the largest move one stencil alone asks for: (d - D) / |grad|
    for (const auto& x : st) {
      double g2 = 0;
      for (int j = 0; j < x.count; ++j) g2 += x.weight[j] * x.weight[j];
      single = std::max(single, (d - x.D) / std::sqrt(g2));
    }
    const double ratio = single > 0 ? maxDx / single : 0.0;
    const std::string method = s.sweeps > 0 ? "hildreth" : "active-set LDLT";
    zones.row({name, param, static_cast<int>(st.size()), c.computed ? c.condition : std::nan(""),
               c.computed ? c.regularized_condition : std::nan(""), s.condition_estimate, method, s.feasible, finite,
               s.max_violation, maxDx, single, ratio});
    finiteBounded = finiteBounded && finite && ratio <= 10;
    worstRatio = std::max(worstRatio, ratio);
  };
  const Eigen::Vector3d z(0, 0, 1);
  for (int k : {2, 4, 16, 64, 65, 200}) {
    std::vector<vt::Stencil> st;
    for (int i = 0; i < k; ++i) st.push_back(vertexStencil(0, z, -0.01));
    solve("duplicate vertex stencils", k, st);
  }
  for (double th : {1e-1, 1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14}) {
    solve("two nearly parallel vertex stencils", th,
          {vertexStencil(0, z, -0.01), vertexStencil(0, Eigen::Vector3d(std::sin(th), 0, std::cos(th)), -0.012)});
    // Ten stencils on one vertex, normals in a cone of half-angle th.
    std::vector<vt::Stencil> fan;
    for (int i = 0; i < 10; ++i) {
      const double a = 2 * M_PI * i / 10;
      fan.push_back(vertexStencil(0, Eigen::Vector3d(th * std::cos(a), th * std::sin(a), 1), -0.01 - 0.0005 * i));
    }
    solve("fan of 10 vertex stencils in a cone", th, fan);
    // Two face stencils on the same garment triangle, weights and normals differing by th.
    solve("two nearly equal face stencils", th,
          {faceStencil({{0, 1, 2}}, {{0.3, 0.3, 0.4}}, z, 0.0),
           faceStencil({{0, 1, 2}}, {{0.3 + th, 0.3, 0.4 - th}}, Eigen::Vector3d(th, 0, 1), 0.0)});
    // Opposing normals (a vertex inside a thin slab, the paper's Fig. 5): infeasible, must stay bounded.
    solve("opposing vertex stencils", th,
          {vertexStencil(0, z, -0.004), vertexStencil(0, Eigen::Vector3d(th, 0, -1), -0.006)});
  }
  // A chain of face stencils sharing edges along a strip, nearly dependent.
  for (double th : {1e-2, 1e-6, 1e-10}) {
    std::vector<vt::Stencil> chain;
    for (int i = 0; i < 80; ++i)
      chain.push_back(faceStencil({{i, i + 1, i + 2}}, {{1.0 / 3, 1.0 / 3, 1.0 / 3}},
                                  Eigen::Vector3d(th * std::sin(i), th * std::cos(i), 1), -0.002));
    solve("chain of 80 face stencils (Hildreth)", th, chain);
  }
  summary().set("stability.zone_solves_finite_and_bounded", finiteBounded);
  summary().set("stability.zone_worst_displacement_ratio", worstRatio);

  // (c) The zones the resolver meets on the section 1 scenes (first round): their conditioning.
  Csv real(o.out + "/stability_scene_zones.csv",
           {"scene", "round", "stencils", "condition", "regularized_condition", "solver_pivot_ratio", "feasible",
            "max_displacement_m"});
  for (const NamedScene& sc : resolverScenes(o)) {
    vt::Body body(sc.body);
    vt::TriMesh g = sc.garment;
    const vt::GarmentTopology topo(g);
    const double dd = 0.05 * vt::meanEdgeLength(g);
    for (int round = 1; round <= 3; ++round) {
      vt::CrossingSet cs;
      vt::detectCrossings(body, g, topo, cs);
      if (cs.size() == 0) break;
      const auto st = vt::buildStencils(body, g, topo, cs);
      const auto zs = vt::groupImpactZones(st, static_cast<int>(g.V.rows()));
      for (const auto& zone : zs) {
        const vt::ZoneConditioning c = vt::zoneConditioning(st, zone);
        const vt::ZoneSolution s = vt::solveImpactZone(st, zone, dd);
        double maxDx = 0;
        for (const auto& v : s.displacement) maxDx = std::max(maxDx, v.norm());
        real.row({sc.name, round, static_cast<int>(zone.size()), c.computed ? c.condition : std::nan(""),
                  c.computed ? c.regularized_condition : std::nan(""), s.condition_estimate, s.feasible, maxDx});
        if (s.feasible)
          for (std::size_t i = 0; i < s.vertices.size(); ++i) g.V.row(s.vertices[i]) += s.displacement[i].transpose();
      }
    }
  }
}

}  // namespace eval
