// The energy partition into the part (include/chatter/grinding.hpp; seed 001
// ch. 2 eqs. 2.2, 2.17, 2.18 and its table 2.2 of beta by power and feed).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/grinding.hpp"
#include "grinding_internal.hpp"
#include "grinding_text.hpp"

namespace chatter::grinding {

namespace {

std::string row_name(std::size_t i) { return "beta_table[" + std::to_string(i) + "]"; }

// Linear interpolation in power along one row, held at its end values.
double row_at(const BetaTable::Row& r, double power_w, bool& held) {
  held = r.power_w.size() > 1 && (power_w < r.power_w.front() || power_w > r.power_w.back());
  if (r.power_w.size() == 1) {
    held = power_w != r.power_w.front();
    return r.beta.front();
  }
  if (power_w <= r.power_w.front()) return r.beta.front();
  if (power_w >= r.power_w.back()) return r.beta.back();
  const auto it = std::upper_bound(r.power_w.begin(), r.power_w.end(), power_w);
  const std::size_t i = static_cast<std::size_t>(it - r.power_w.begin()) - 1;
  const double t = (power_w - r.power_w[i]) / (r.power_w[i + 1] - r.power_w[i]);
  return r.beta[i] + t * (r.beta[i + 1] - r.beta[i]);
}

std::string mm_per_s(double v) { return detail::num(v * 1e3) + " mm/s"; }

}  // namespace

BetaTable::BetaTable(std::vector<Row> rows) : rows_(std::move(rows)) {
  if (rows_.empty()) throw InputError("beta_table: needs at least one row (a feed with its powers and betas)");
  for (std::size_t i = 0; i < rows_.size(); ++i) {
    const Row& r = rows_[i];
    if (!(std::isfinite(r.feed_m_per_s) && r.feed_m_per_s > 0.0))
      throw InputError(row_name(i) + ".feed_mm_per_s = " + detail::num(r.feed_m_per_s * 1e3) + ": must be > 0");
    if (i > 0 && !(r.feed_m_per_s > rows_[i - 1].feed_m_per_s))
      throw InputError(row_name(i) + ".feed_mm_per_s = " + detail::num(r.feed_m_per_s * 1e3) +
                       ": the feeds must increase from row to row (previous row " + mm_per_s(rows_[i - 1].feed_m_per_s) +
                       ")");
    if (r.power_w.empty() || r.power_w.size() != r.beta.size())
      throw InputError(row_name(i) + ": needs one beta per power_w (at least one)");
    for (std::size_t k = 0; k < r.power_w.size(); ++k) {
      if (!(std::isfinite(r.power_w[k]) && r.power_w[k] > 0.0))
        throw InputError(row_name(i) + ".power_w[" + std::to_string(k) + "] = " + detail::num(r.power_w[k]) +
                         ": must be > 0 W");
      if (k > 0 && !(r.power_w[k] > r.power_w[k - 1]))
        throw InputError(row_name(i) + ".power_w[" + std::to_string(k) + "] = " + detail::num(r.power_w[k]) +
                         ": the powers must increase along the row");
      if (!(r.beta[k] >= 0.0 && r.beta[k] <= 1.0))
        throw InputError(row_name(i) + ".beta[" + std::to_string(k) + "] = " + detail::num(r.beta[k]) +
                         ": must be in [0, 1]");
    }
  }
}

double BetaTable::at(double power_w, double feed_m_per_s, std::vector<std::string>* notes) const {
  auto note_row = [&](const Row& r, bool held) {
    if (held && notes)
      notes->push_back("power " + detail::num(power_w) + " W is outside the beta table's row at " +
                       mm_per_s(r.feed_m_per_s) + " (" + detail::num(r.power_w.front()) + " to " +
                       detail::num(r.power_w.back()) + " W): its beta held at the end value");
  };
  bool held = false;
  if (rows_.size() == 1 || feed_m_per_s <= rows_.front().feed_m_per_s || feed_m_per_s >= rows_.back().feed_m_per_s) {
    const Row& r = rows_.size() == 1 || feed_m_per_s <= rows_.front().feed_m_per_s ? rows_.front() : rows_.back();
    const double b = row_at(r, power_w, held);
    note_row(r, held);
    if (notes && feed_m_per_s != r.feed_m_per_s)
      notes->push_back("feed " + mm_per_s(feed_m_per_s) + " is outside the beta table's feeds (" +
                       mm_per_s(rows_.front().feed_m_per_s) + " to " + mm_per_s(rows_.back().feed_m_per_s) +
                       "): the row at " + mm_per_s(r.feed_m_per_s) + " used");
    return b;
  }
  const auto it = std::upper_bound(rows_.begin(), rows_.end(), feed_m_per_s,
                                   [](double v, const Row& r) { return v < r.feed_m_per_s; });
  const Row& hi = *it;
  const Row& lo = *(it - 1);
  bool held_lo = false, held_hi = false;
  const double b_lo = row_at(lo, power_w, held_lo), b_hi = row_at(hi, power_w, held_hi);
  note_row(lo, held_lo);
  note_row(hi, held_hi);
  const double t = (feed_m_per_s - lo.feed_m_per_s) / (hi.feed_m_per_s - lo.feed_m_per_s);
  return b_lo + t * (b_hi - b_lo);
}

const char* partition_model_name(PartitionModel m) {
  switch (m) {
    case PartitionModel::kMalkin: return "malkin";
    case PartitionModel::kModified: return "modified";
    case PartitionModel::kPower: return "power";
  }
  return "?";
}

namespace detail {

EnergyPartition energy_partition(const Process& p, const Prediction& r, std::vector<std::string>& warnings) {
  const EnergyPartitionModel& m = *p.partition;
  EnergyPartition e;
  e.model = m.model;
  double eps = 0.0;
  const double u = r.specific_energy_j_per_m3;
  switch (e.model) {
    case PartitionModel::kMalkin: eps = (u - 0.45 * m.chip_energy_j_per_m3) / u; break;
    case PartitionModel::kModified: eps = (u - 0.6 * m.chip_energy_j_per_m3) / u; break;
    case PartitionModel::kPower:
      e.alpha = m.alpha;
      e.beta = m.beta_at(r.power_w, p.feed_m_per_s, &warnings);
      eps = (m.alpha * r.friction_power_w.value_or(0.0) + *e.beta * r.chip_power_w.value_or(0.0)) / r.power_w;
      break;
  }
  e.fraction = std::clamp(eps, 0.0, 1.0);
  e.clamped = eps != e.fraction;
  if (e.clamped)
    warnings.push_back(std::string("energy partition (") + partition_model_name(e.model) + ") gives " + num(eps) +
                       ", outside [0, 1] (specific energy " + num(u * 1e-9) + " J/mm^3): clamped to " +
                       num(e.fraction));
  e.heat_into_part_w = e.fraction * r.power_w;
  return e;
}

}  // namespace detail

}  // namespace chatter::grinding
