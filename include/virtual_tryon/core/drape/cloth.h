// The mass-spring cloth of Vassilev et al. 2001 (sec. 3-4): mass points joined by structural,
// shear and flexion springs, gravity and viscous damping, explicit Euler, and the velocity
// modification that stops super-elastic stretching.
//
//   spring force on a from b:  k (|x_b - x_a| - l0) (x_b - x_a) / |x_b - x_a|
//   gravity m g, damping -C_vd v with C_vd = damping_rate * m
//   Euler (eq. 3):  v(t+dt) = v(t) + dt f / m,   x(t+dt) = x(t) + dt v(t+dt)
//   stable when dt <= 0.4 pi sqrt(m / K_max)  (eq. 4; K_max read per node, see stableTimeStep)
//   velocity fix (sec. 4.3): for a spring longer than (1 + threshold) l0, the end velocities'
//   components along the spring that stretch it further are removed.
#pragma once

#include "virtual_tryon/core/drape/pattern.h"
#include "virtual_tryon/core/drape/spring_forces.h"

#include <functional>
#include <string>
#include <vector>

namespace virtual_tryon {

struct ClothParams {
  double density = 0.15;        // kg/m^2; a node's mass is density * spacing^2
  // N/m. Stiff enough to carry the garment's weight: a shirt of 150 g/m^2 hangs its whole weight
  // (about 0.7 N) on two shoulder seams, some 0.1 N per 2 cm column of springs; at 10 N/m those
  // springs stretched 30-58% (the velocity fix stops growth, it cannot hold a load), at 100 N/m
  // they stay under 15%. The stable time step shrinks with sqrt(k): about 3x the iterations.
  double k_structural = 100.0;
  // N/m. Against the cells' shear: at 2 N/m a worn pair of trousers let the walk's legs through
  // on 18 of 60 frames (the quads shear flat out of the way, 0.28-0.95 strain once corrected);
  // at 20, none (a fifth of the structural stiffness, as a woven cloth's in-plane shear).
  double k_shear = 20.0;
  double k_flexion = 1.0;       // N/m
  double k_seam = 4.0;          // N/m: seam points pull each other with the constant force
  double seam_max_stretch = 0.05;  // k_seam * seam_max_stretch (N) until their seam is welded
  double sewing_damping_rate = 6.0;  // 1/s, damping while any seam is open (when above damping_rate)
  bool gravity_while_sewing = false;  // off: panels do not slide down before they are closed
  double damping_rate = 6.0;  // 1/s; C_vd = damping_rate * m (heavy: a quasi-static dressing)
  Eigen::Vector3d gravity{0, -9.81, 0};
  double stretch_threshold = 0.10;  // super-elasticity threshold, 0.01 .. 0.15
  int velocity_fix_passes = 3;      // Gauss-Seidel passes of the velocity fix per step; 0: off
  // Beyond the paper: once the seams are welded, each spring longer than (1 + stretch_threshold)
  // rest also contracts, both ends moving towards each other so that this fraction of its excess
  // length goes in one step (Provot 1995's correction, as a velocity). The velocity fix alone only
  // stops an over-long spring from growing: what sewing stretched, and what the garment's weight
  // holds on its shoulders, stayed (springs 30-70% long). 0: off, 0 .. 1.
  double strain_restore = 0.0;
  // A weld moves the two nodes of each seam pair to their mean, up to half the weld tolerance
  // (7.5 mm at the default 1.5 cm) in one step: the springs at the welded nodes jumped to 0.4-0.9
  // over their rest length (GarmentCode's shirt at its shoulder points), and where the body held
  // the cloth the dynamics never took it back (0.39 at the end). After each weld this many
  // Gauss-Seidel passes move the ends of every structural spring longer than (1 + stretch_
  // threshold) rest back to that length (positions, each end by its inverse mass), so that the
  // jump spreads over the rings round the seam. 0: off.
  int weld_relax_passes = 30;
  double runaway_speed = 50.0;      // m/s: a faster node means the integration blew up
  // Spring forces four springs at a time with AVX2 + FMA when the processor has them (chosen at
  // run time; about half the time of the scalar loop). Off: the scalar loop everywhere. The two
  // agree to the last bits of a double, not bit for bit.
  bool vectorized = true;
};

// eq. 4: 0.4 pi sqrt(m / K_max).
double stableTimeStep(double mass, double kMax);

class ClothState {
 public:
  // Builds the particle system from a meshed pattern. Node masses: density * spacing^2.
  ClothState(const ClothMesh& mesh, const ClothParams& params);

  const ClothParams& params() const { return params_; }
  // The strain_restore of every later step (0 .. 1; see ClothParams), e.g. for a garment worn on a
  // moving body after its drape.
  void setStrainRestore(double restore) { params_.strain_restore = restore; }
  double nodeMass() const { return mass_; }  // of an unwelded node
  double maxStiffness(bool withSeams) const;  // of a single spring
  // The eq. 4 bound as the paper reads, K = the stiffest single spring. A node joined by several
  // springs feels their sum, and the explicit step overshoots at about 0.7-0.85 of this bound
  // (measured: see the stability section of the evaluation report), so it is reported, not used.
  double paperTimeStep() const;
  // The eq. 4 bound with K = the largest sum of stiffnesses meeting at one node (springs and open
  // seams) and m that node's mass: min over nodes of 0.4 pi sqrt(m_i / K_i). By Gershgorin the
  // stiffness matrix's largest eigenvalue is <= 2 K_i / m_i, so the explicit Euler limit
  // 2 / sqrt(lambda_max) >= sqrt(2) sqrt(m_i / K_i) > 0.4 pi sqrt(m_i / K_i): this bound is on
  // the stable side by construction.
  double stableTimeStep() const;
  // The symplectic Euler limit 2 / sqrt(lambda_max) of M^-1 H at the current positions
  // (core/drape/stiffness_spectrum.h; open seams not counted), lambda_max estimated by power
  // iteration (about 10 ms on the 3.8k-node dress). There, as draped, 1.73x stableTimeStep(): a
  // spring resists along itself, the per-node bound counts it along every axis. 0 without springs.
  double spectralTimeStep() const;

  // One explicit Euler step with the velocity fix; `sewing` adds the seam springs. Returns false
  // when a position or velocity became non-finite or a node exceeded runaway_speed (the state is
  // then put back to the last finite checkpoint, at most 32 steps old).
  bool step(double dt, bool sewing);

  // Collision response hook: called between the velocity update and the position update.
  // It receives positions and velocities and may change velocities.
  using VelocityHook = std::function<void(const MatrixX3d& x, MatrixX3d& v)>;
  void setVelocityHook(VelocityHook hook) { hook_ = std::move(hook); }

  // PatternSeam pairs still open, and the largest and mean gap between their ends (metres).
  double maxSeamGap() const;
  double meanSeamGap() const;
  // Welds every seam whose pairs are all closer than `tolerance`: their nodes merge into one
  // (mass summed, position and velocity averaged). Returns how many seams were welded.
  int weldClosedSeams(double tolerance);
  int openSeams() const { return open_seams_; }
  // The pattern seams not welded yet (indices into pattern.seams), ascending.
  std::vector<int> openSeamIndices() const;
  // The seam pairs still open (node indices of the current, possibly welded, state).
  const std::vector<SeamPair>& openSeamPairs() const { return seams_; }

  double kineticEnergy() const;
  double maxSpeed() const;
  double rmsSpeed() const;  // sqrt(2 KE / total mass)
  // max and mean |l / l0 - 1| over structural springs.
  void strain(double& maxStrain, double& meanStrain) const;
  // Per node, the largest |l / l0 - 1| of the structural springs at it, with the nodes at `x`
  // (#N by 3, e.g. the garment after the resolver moved it); 0 where no spring meets the node.
  std::vector<double> nodeStrain(const MatrixX3d& x) const;
  // Springs the velocity fix acted on in the last step.
  std::size_t fixedSprings() const { return fixed_springs_; }

  const MatrixX3d& positions() const { return x_; }
  MatrixX3d& positions() { return x_; }
  const MatrixX3d& velocities() const { return v_; }
  MatrixX3d& velocities() { return v_; }
  const std::vector<double>& masses() const { return m_; }
  const std::vector<Spring>& springs() const { return springs_; }
  const std::vector<std::array<int, 4>>& quads() const { return quads_; }

  // The cloth as a triangle mesh in its current state (welded nodes shared).
  TriMesh mesh() const;

  // Gauss-Seidel passes that move the ends of every structural spring longer than
  // (1 + stretch_threshold) rest back to that length (positions, each end by its inverse mass),
  // and, with `compressed` > 0, of every one shorter than (1 - compressed) rest out to that, at
  // most `passes`, fewer once none is over. Returns the passes that moved something. Used after a
  // weld (weld_relax_passes; stretched springs alone) and on a worn garment after the resolver's
  // correction.
  int relaxStrainedSprings(int passes, double compressed = 0);

  // Applies the velocity fix alone (exposed for tests).
  // `restore` (1/s): each over-long spring's ends also approach each other at restore x its excess
  // (strain_restore / dt); 0: the velocity fix alone.
  void fixVelocities(double restore = 0.0);

  // Forces at the current state (springs, gravity, damping; no seams), #N by 3, and the potential
  // energy they derive from (springs 1/2 k (l - l0)^2 plus gravity -m g.x), for derivative checks.
  const MatrixX3d& evaluateForces();
  double potentialEnergy() const;

 private:
  void computeForces(bool sewing);
  void rebuildAfterWeld(const std::vector<int>& rep);

  ClothParams params_;
  double mass_ = 0;
  MatrixX3d x_, v_, f_;
  MatrixX3d x_prev_, v_prev_;  // the last finite checkpoint (at most 32 steps old)
  long steps_ = 0;
  std::vector<double> m_;
  std::vector<Spring> springs_;
  SpringArrays packed_;    // springs_ as the force kernel reads them, with each spring's stiffness
  PaddedRows x4_, f4_;     // positions and forces in the kernel's layout (step reads f4_; f_ is
                           // filled for evaluateForces only)
  std::vector<int> over_index_;
  void packSprings();
  struct Stretched {
    int a, b;       // the spring's end nodes
    double u[3];    // unit vector from a to b
    double excess;  // m: its length beyond (1 + stretch_threshold) rest
  };
  std::vector<Stretched> over_;  // over-stretched springs at the current positions
  void addStretched(int spring);
  bool over_valid_ = false;
  std::vector<SeamPair> seams_;  // open seam pairs
  std::vector<char> seam_welded_;  // per pattern seam
  int open_seams_ = 0;             // distinct seams among seams_, counted when seams_ changes
  void countOpenSeams();
  std::vector<int> seam_stage_;    // per pattern seam
  std::vector<std::array<int, 4>> quads_;
  MatrixX3i F_;
  VelocityHook hook_;
  std::size_t fixed_springs_ = 0;
};

}  // namespace virtual_tryon
