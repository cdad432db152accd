// The cutting law's regenerative side (docs/cutting_law.md): the cut at one
// spindle speed and one depth as a set of cutting edges, each with its delay
// and the exact integral of its share of the directional matrix over any
// time step. What a general solver path needs of any operation, so a new
// operation or cutter geometry is one more implementation here, not an edit
// of the solver (the static side — mean force, torque, power, removal rate —
// is chatter/cutting_law.hpp).
//
// The regenerative force of §3/§8, written per edge e:
//   F(t) = −Σ_e H_e(t) (r(t) − r(t − τ_e)) − (C_pd / V) D(t) ṙ(t),
// H_e (N/m) the edge's directional matrix already integrated over its part
// of the depth, τ_e its delay, D (m) the process-damping direction times the
// engaged length. Implementations:
//  - milling (src/model/cutting/milling_law.cpp): an edge is a tooth, or an
//    axial slice of a tooth when the delays vary along it (variable helix) or
//    the cutter has a profile; H_e is tooth_matrix summed over the slice
//    (Process::tooth_force_integral, slice_force_integral), zero out of the
//    arc; the engagement events are the tooth tips and the top of the cut
//    entering and leaving the arc.
//  - turning (src/model/cutting/turning_law.cpp): one edge, the insert, one
//    revolution back; H_e = a H(a) = b d nᵀ constant in time
//    (Process::turning_force_matrix), D = b n nᵀ; no events.
// The `sdm` solver's general step grid (src/solvers/sdm_grid.cpp,
// cutter_grid) reads the cut only through this interface; its fast paths
// (straight uniform milling, constant turning) are specialisations tested
// equal to it (tests/test_regenerative_cut.cpp).
//
// Units: SI; integrals over time in N/m·s (force) and m·s (damping).
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "chatter/process.hpp"

namespace chatter {

class RegenerativeCut {
 public:
  virtual ~RegenerativeCut() = default;

  /// The cut of `process` at spindle speed `rpm` (rev/min, > 0) and depth
  /// a (m, >= 0). `helix_slices` (>= 1): axial slices of a tooth whose delay
  /// varies along it (a variable helix; a profile has its own slices).
  /// @throws InputError if rpm <= 0 or a < 0 (or not finite), helix_slices < 1.
  static std::unique_ptr<const RegenerativeCut> of(const Process& process, double rpm, double depth_m,
                                                   int helix_slices);

  /// The period (s) of the cut's pattern of edges: the engagement events
  /// repeat after it (one revolution for a cutter that is not uniform, one
  /// tooth period for a uniform one, a revolution for turning).
  virtual double pattern_period_s() const = 0;
  /// The times in [0, pattern_period_s()) at which the force law changes
  /// form (an edge enters or leaves the cut), sorted; empty when it never
  /// does (turning). A step grid puts a boundary at each.
  virtual std::vector<double> engagement_events_s() const = 0;
  /// The times in [0, pattern_period_s()) at which the summed H_e of any
  /// set of edges with one delay changes form, sorted: engagement_events_s()
  /// and, when a tooth's slices have different delays (a variable helix),
  /// each slice's own top and bottom entering and leaving (where the tooth's
  /// sum stays smooth but a slice's share has a kink). What a method
  /// sampling H per delay (collocation) steps on.
  virtual std::vector<double> edge_events_s() const { return engagement_events_s(); }
  /// τ_e (s) of every edge, in the order of force_integrals.
  virtual const std::vector<double>& edge_delays_s() const = 0;
  /// ∫_{t_a}^{t_b} H_e(t) dt of every edge (N/m·s), written to `per_edge`
  /// (resized to the number of edges). @pre t_b >= t_a.
  virtual void force_integrals(double t_a, double t_b, std::vector<Eigen::Matrix2d>& per_edge) const = 0;
  /// H_e(t) of every edge at one instant t (N/m): the integrand of
  /// force_integrals, for methods that sample H (collocation). At an
  /// engagement event H may jump; a caller samples between events.
  virtual void force_rates(double t, std::vector<Eigen::Matrix2d>& per_edge) const = 0;
  /// Σ_e ∫ H_e dt (N/m·s), summed the way the law sums it (the step grid's
  /// free-flight test reads it). @pre t_b >= t_a.
  virtual Eigen::Matrix2d total_force_integral(double t_a, double t_b) const = 0;
  /// ∫_{t_a}^{t_b} D(t) dt (m·s): zero without process damping.
  virtual Eigen::Matrix2d damping_integral(double t_a, double t_b) const = 0;
  /// D(t) at one instant (m): the integrand of damping_integral, for
  /// methods that sample it (collocation); zero without process damping.
  virtual Eigen::Matrix2d damping_rate(double t) const = 0;
  /// A scale of the cutting coefficients (N/m²: K_t + K_r in milling, K_f +
  /// K_r in turning) against which an integral is called zero (free flight).
  virtual double force_scale_n_per_m2() const = 0;
};

}  // namespace chatter
