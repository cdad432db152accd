// The seeds' grinding cases (docs/grinding.md), shared by the grinding tests.
#pragma once

#include "chatter/grinding.hpp"

namespace chatter::grinding::cases {

/// Seed 001 ch. 4 (Tahvilian 2015): R = 115 mm, E = 6.8 mm, 6000 rev/min,
/// 80 mm/s, k_e = 75 N/mm, k_c = 10 020 N/mm^2, mu = 0.26, the n_c table of
/// §4.7, Malkin's modified energy partition with u_ch = 13.8 J/mm^3.
inline Process seed001_ch4() {
  Process p;
  p.wheel.diameter_m = 0.230;
  p.wheel.width_m = 6.8e-3;
  p.wheel.speed_rev_per_s = 6000.0 / 60.0;
  p.feed_m_per_s = 0.080;
  p.force_ratio = 0.26;
  p.density_kg_per_m3 = 7900.0;
  MechanisticModel m;
  m.edge_coefficient_n_per_m = 75e3;
  m.cutting_coefficient_n_per_m2 = 10020e6;
  m.impacts = ImpactsPerTurn({500, 1000, 1500, 2000}, {0.75, 1.29, 1.56, 2.25});
  p.mechanistic = m;
  EnergyPartitionModel e;
  e.model = PartitionModel::kModified;
  e.chip_energy_j_per_m3 = 13.8e9;
  p.partition = e;
  return p;
}

/// Seed 000 annex VI's screen (Thuot 2010): a 155 mm wheel at 2000 rev/min of
/// the motor x 1.125 (2250 rev/min), 25 mm wide, 50 mm/s, the annex IV
/// underwater poly11 removal and normal force (MATLAB term order). The
/// diameter is the one that gives the cutting speed the screen prints,
/// 18.3 m/s (its "about 155 mm").
constexpr double kAnnexCuttingSpeed = 18.3;   // m/s, as printed (3 significant digits)
constexpr double kAnnexWheelRpm = 2000.0 * 1.125;
constexpr double kAnnexPower = 2021.0;        // W, useful power at the wheel
inline Process seed000_annex6() {
  Process p;
  p.wheel.speed_rev_per_s = kAnnexWheelRpm / 60.0;
  p.wheel.diameter_m = kAnnexCuttingSpeed / (3.14159265358979323846 * p.wheel.speed_rev_per_s);
  p.wheel.width_m = 25e-3;
  p.feed_m_per_s = 0.050;
  p.force_ratio = 0.5;  // seed 000 table 6.2, "coefficient de friction"
  EmpiricalModel removal;
  removal.form = EmpiricalForm::kPoly11;
  removal.coefficients = {63.1, -5.05, 0.0439};
  p.empirical.removal = removal;
  EmpiricalModel force;
  force.form = EmpiricalForm::kPoly11;
  force.coefficients = {162.0, -9.38, 0.123};
  p.empirical.normal_force = force;
  return p;
}

}  // namespace chatter::grinding::cases
