// `chatter compare` as a record (chatter/records/lobes.hpp): several methods
// at the same spindle speeds, the largest difference between each pair and
// why the methods differ: the cross-check people use to trust the numbers
// (issue 5). The CLI and Python run this; neither builds it again.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/number_text.hpp"
#include "chatter/forced.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/records/lobes.hpp"

namespace chatter {

using nlohmann::json;

namespace {

bool has(const std::vector<std::string>& v, const std::string& x) { return std::find(v.begin(), v.end(), x) != v.end(); }

std::string methods_rule() {
  std::string known;
  const auto names = lobe_methods();
  for (std::size_t i = 0; i < names.size(); ++i) known += (i == 0 ? "" : ", ") + names[i];
  return "a comma-separated list of distinct methods from " + known + ", or 'all'";
}

}  // namespace

std::vector<std::string> parse_compare_methods(const std::optional<std::string>& given_list, ArgStyle style) {
  if (!given_list || *given_list == "all") return {};
  const std::string& list = *given_list;
  const std::string given = arg_name(style, "methods") + " '" + list + "': ";
  if (list.empty()) throw InputError(given + "empty list; must be " + methods_rule());
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = list.find(',', start);
    const std::string name = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (name.empty()) throw InputError(given + "empty name; must be " + methods_rule());
    if (name == "all") throw InputError(given + "'all' must stand alone; must be " + methods_rule());
    if (!has_lobe_method(name)) throw InputError(given + "unknown method '" + name + "'; must be " + methods_rule());
    if (has(out, name)) throw InputError(given + "'" + name + "' given twice; must be " + methods_rule());
    out.push_back(name);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::vector<std::string> choose_compare_methods(const std::optional<std::string>& list, const Config& cfg,
                                                ArgStyle style) {
  std::vector<std::string> methods = parse_compare_methods(list, style);
  const bool all = list && *list == "all";
  const FeatureSet needed = needed_features(cfg.model, cfg.process);
  const auto applies = [&](const SolverDescriptor& d) { return d.accepts.missing(needed).empty(); };
  if (all || methods.empty()) {
    for (const auto& d : solver_registry())
      if (applies(d) && (all || d.in_default_compare)) methods.push_back(d.name);
    return methods;
  }
  std::string able;
  for (const auto& d : solver_registry())
    if (applies(d)) able += (able.empty() ? "" : ", ") + d.name;
  const std::string given = arg_name(style, "methods") + " '" + *list + "': ";
  for (const auto& m : methods) {
    const SolverDescriptor& d = find_lobe_method(m);
    if (applies(d)) continue;
    const auto missing = d.accepts.missing(needed);
    if (missing.front() == SolverFeature::kMeasuredFrf)
      throw InputError(given + m + " does not apply to " + cfg.source.string() + ": it has measured FRFs, and only " +
                       able + " works from measured data (fit modes with chatter fit for the others)");
    throw InputError(given + m + " does not apply to " + cfg.source.string() + ": it does not handle " +
                     to_string(missing.front()) + " (methods that do: " + able + ")");
  }
  return methods;
}

SolverValue ComparedMethod::value(const std::string& name, std::size_t i) const {
  for (std::size_t c = 0; c < columns.size(); ++c)
    if (columns[c].name == name && i < values.size() && c < values[i].size()) return values[i][c];
  return std::monostate{};
}

bool ComparedMethod::is_flip(std::size_t i) const {
  const SolverValue v = value("multiplier_type", i);
  return rows[i].bounded() && std::holds_alternative<std::string>(v) &&
         std::get<std::string>(v) == to_string(MultiplierType::kFlip);
}

namespace {

// Largest relative difference per pair, over speeds where both are bounded;
// speeds where only one of them finds a limit are counted apart.
std::vector<ComparedPair> compare_pairs(const Comparison& c) {
  std::vector<ComparedPair> pairs;
  const auto& runs = c.methods;
  for (std::size_t a = 0; a < runs.size(); ++a)
    for (std::size_t b = a + 1; b < runs.size(); ++b) {
      ComparedPair p;
      p.first = runs[a].descriptor->name;
      p.second = runs[b].descriptor->name;
      for (std::size_t i = 0; i < c.speeds_rpm.size(); ++i) {
        const auto &la = runs[a].rows[i], &lb = runs[b].rows[i];
        if (la.bounded() && lb.bounded()) {
          const double r = std::abs(lb.depth_limit_m / la.depth_limit_m - 1.0);
          if (r > p.largest_relative_difference) {
            p.largest_relative_difference = r;
            p.at_spindle_rpm = c.speeds_rpm[i];
          }
        } else if (la.bounded()) {
          ++p.bounded_only_by_first;
        } else if (lb.bounded()) {
          ++p.bounded_only_by_second;
        }
      }
      pairs.push_back(p);
    }
  return pairs;
}

// Below this radial immersion a_e/D the cut is intermittent enough for flip
// (period-doubling) lobes to be wide and set the limit over whole speed
// ranges (Insperger & Stepan 2004; case C at 0.05); above it they are few
// and narrow, so "low radial immersion" is not said as the reason.
constexpr double kLowImmersion = 0.25;
// A flip-limited speed counts as missed by the averaged method when the
// averaged limit there is this much deeper.
constexpr double kFlipMissedRel = 0.05;

std::string speeds_word(std::size_t n) { return std::to_string(n) + (n == 1 ? " speed" : " speeds"); }

// The radial immersion a_e/D of a milling config (1 for turning).
double immersion(const Config& cfg) {
  return cfg.process.rotating_edges() ? cfg.process.milling_parameters().radial_immersion : 1.0;
}

// Milling speeds where both limits are Hopf (no flip at the Floquet one)
// and differ by more than this (relative) are explained by the averaging.
constexpr double kAveragingGapRel = 0.05;
// A lobe number from which the averaging's dropped harmonics are named as a
// cause (many vibration cycles per tooth period).
constexpr int kHighLobe = 10;

// Where the averaged limit differs from the Floquet one without a flip lobe
// (issue 44: analytic 18 % below sdm at 500 rev/min, with no word): the
// zeroth-order approximation keeps only the mean of the directional matrix
// over the tooth period. The difference is the pair's (ComparedPair:
// |second / first − 1|, `first` and `second` as the pair lists them); the
// largest is reported with its lobe number and the immersion.
void explain_averaging(const ComparedMethod& first, const ComparedMethod& second, const ComparedMethod& f,
                       const ComparedMethod& averaged, double ae_d, std::size_t speeds, std::ostream& report) {
  std::size_t count = 0, at = speeds;
  double worst = 0.0;
  for (std::size_t i = 0; i < speeds; ++i) {
    const StabilityLimit &a = first.rows[i], &b = second.rows[i];
    if (!a.bounded() || !b.bounded() || f.is_flip(i)) continue;
    const double rel = std::abs(b.depth_limit_m / a.depth_limit_m - 1.0);
    if (rel <= kAveragingGapRel) continue;
    ++count;
    if (rel > worst) worst = rel, at = i;
  }
  if (count == 0) return;
  const StabilityLimit& b = f.rows[at];
  const bool below = averaged.rows[at].depth_limit_m < b.depth_limit_m;
  report << "  at " << speeds_word(count) << " where " << f.descriptor->name << "'s limit is a Hopf one, "
         << first.descriptor->name << " and " << second.descriptor->name << " differ by more than "
         << number_text(100.0 * kAveragingGapRel, 3) << " % (largest " << number_text(worst, 3) << ", " << averaged.descriptor->name
         << (below ? " below " : " above ") << f.descriptor->name << ", at " << number_text(b.spindle_rpm) << " rev/min, lobe "
         << b.lobe << "):\n"
         << "  the averaged method keeps only the mean of the cutting force's directional matrix over the tooth\n"
         << "  period (the zeroth-order approximation); the harmonics it drops shift the Hopf lobes";
  std::vector<std::string> where;
  if (b.lobe >= kHighLobe) where.push_back("the lobe number is high (low speed: many vibration cycles per tooth period)");
  if (ae_d < kLowImmersion) where.push_back("the arc is short (a_e/D = " + number_text(ae_d, 3) + ")");
  for (std::size_t i = 0; i < where.size(); ++i) report << (i == 0 ? ",\n  most where " : " and ") << where[i];
  report << ". " << f.descriptor->name << " keeps them (so does a simulation: chatter simulate --linear).\n";
}

// What a Floquet method finds that the averaged (zeroth-order) one cannot;
// each sentence only where the compared numbers (or the config) support it.
// Returns the number of flip-limited speeds.
std::size_t explain_floquet(const ComparedMethod& f, const ComparedMethod* averaged, const Config& cfg,
                            std::size_t speeds, std::ostream& report) {
  const std::string& name = f.descriptor->name;
  const bool turning = !cfg.process.rotating_edges();
  std::size_t flips = 0, flips_deeper_tf = 0;
  for (std::size_t i = 0; i < speeds; ++i)
    if (f.is_flip(i)) {
      ++flips;
      if (averaged && averaged->rows[i].depth_limit_m > (1.0 + kFlipMissedRel) * f.rows[i].depth_limit_m)
        ++flips_deeper_tf;
    }
  const double ae_d = immersion(cfg);
  const std::string why_flip = ae_d < kLowImmersion ? " (low radial immersion, a_e/D = " + number_text(ae_d, 3) + ")" : "";
  if (flips > 0 && averaged && flips_deeper_tf > 0) {
    report << "  " << name << " finds period-doubling (flip) chatter at " << speeds_word(flips) << "; at "
           << flips_deeper_tf << " of them the " << averaged->descriptor->name
           << " limit is more than 5 % deeper: the transfer-function method averages\n"
              "  the cutting force over the tooth period and cannot see flip lobes"
           << why_flip << ".\n";
  } else if (flips > 0 && averaged) {
    report << "  " << name << " finds period-doubling (flip) chatter at " << speeds_word(flips) << "; there the "
           << averaged->descriptor->name << " limit is within 5 %: no flip lobe cuts below the averaged\n"
              "  lobes in this sweep.\n";
  } else if (flips > 0) {
    std::string averaged_names;
    for (const auto& d : solver_registry())
      if (d.kind == SolverKind::kAveraged) averaged_names += (averaged_names.empty() ? "" : ", ") + d.name;
    report << "  " << name << " finds period-doubling (flip) chatter at " << speeds_word(flips)
           << ": the transfer-function methods (" << averaged_names << ") cannot see flip lobes" << why_flip
           << ".\n";
  } else if (turning && averaged) {
    report << "  turning has constant coefficients: " << name << " differs from the exact "
           << averaged->descriptor->name << " limit only by its\n  discretisation error.\n";
  }
  return flips;
}

// How a simulation method's limits are found, from its effective options.
// `flips`: flip-limited speeds found by the Floquet methods compared (0 if none ran).
void explain_simulation(const ComparedMethod& r, bool turning, std::size_t flips, std::ostream& report) {
  const auto get = [&](const char* k) { return r.options.at(k); };
  const double tol = std::get<double>(get("depth_tolerance"));
  const int periods = std::get<int>(get("periods"));
  const bool linear = std::get<bool>(get("linear"));
  report << "  " << r.descriptor->name << ": each limit is the middle of a depth bracket " << number_text(tol * 100, 3)
         << " % wide, every depth judged by simulating\n  " << periods << " delay periods"
         << (linear ? " of the linear equation" : " with the nonlinear chip (the tool may leave the cut)");
  if (turning)
    report << "; turning has constant\n  coefficients: " << r.descriptor->name
           << " should match the exact limit to about the bracket width.\n";
  else if (flips > 0)
    report << "; like sdm it sees the\n  intermittent cut of milling (the flip lobes sdm finds at " << speeds_word(flips)
           << ") that the averaged methods miss.\n";
  else
    report << "; it follows the\n  intermittent cut of milling tooth by tooth, which the averaged methods "
              "average out.\n";
}

// A simulation deeper than the linear methods by more than this (relative)
// at some speed is checked for teeth leaving the cut below the linear limit.
constexpr double kForcedExplainRel = 0.05;
// The forced response is read this far below the linear limit (a stable
// cut: a forced response exists).
constexpr double kBelowLinearLimit = 0.95;

// The simulation with the real chip finds a cut stable deeper than the
// linear methods when the forced vibration below the linear limit already
// throws the teeth out of the cut (the linear limit does not hold there). At
// the speed where the simulation is deepest relative to the linear reference
// (sdm, else the averaged method), the forced response at 0.95 x that limit
// says whether this is the cause.
void explain_forced(const Config& cfg, const Comparison& c, std::ostream& report) {
  const std::vector<double>& speeds = c.speeds_rpm;
  const ComparedMethod *sim = nullptr, *lin = nullptr;
  for (const auto& r : c.methods) {
    if (r.descriptor->kind == SolverKind::kSimulation && !sim) sim = &r;
    if (r.descriptor->kind == SolverKind::kFloquet && !lin) lin = &r;
  }
  for (const auto& r : c.methods)
    if (!lin && r.descriptor->kind == SolverKind::kAveraged) lin = &r;
  if (!sim || !lin || !cfg.process.rotating_edges()) return;
  if (const auto it = sim->options.find("linear"); it != sim->options.end() && std::get<bool>(it->second)) return;
  std::size_t at = speeds.size();
  double worst = kForcedExplainRel;
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    const StabilityLimit &a = sim->rows[i], &b = lin->rows[i];
    if (!b.bounded()) continue;
    const double rel = a.bounded() ? a.depth_limit_m / b.depth_limit_m - 1.0 : 1.0;
    if (rel > worst) {
      worst = rel;
      at = i;
    }
  }
  if (at == speeds.size()) return;
  const double feed_m = std::get<double>(sim->options.at("feed_m"));
  ForcedResponse f;
  try {
    ForcedSettings st;
    st.spindle_rpm = speeds[at];
    st.depth_m = kBelowLinearLimit * lin->rows[at].depth_limit_m;
    st.feed_m = feed_m;
    st.record_path = false;
    f = ForcedResponseSolver(cfg.model, cfg.process).response(st);
  } catch (const InputError&) {
    return;  // e.g. measured FRFs: no forced response to explain with
  }
  if (!f.stable) return;
  report << "  " << sim->descriptor->name << " is " << number_text(100.0 * worst, 3) << " % deeper than "
         << lin->descriptor->name << " at " << number_text(speeds[at]) << " rev/min. ";
  if (f.teeth_leave_cut)
    report << "There the forced vibration at " << number_text(100.0 * kBelowLinearLimit, 3) << " % of the\n  "
           << lin->descriptor->name << " limit (" << number_text(f.depth_m * 1e3, 4) << " mm, feed " << number_text(feed_m * 1e3, 4)
           << " mm) is " << number_text(1e6 * std::max(f.peak_to_peak_x_m, f.peak_to_peak_y_m), 3)
           << " um peak to peak and the teeth leave the cut (linear chip negative over "
           << number_text(f.negative_chip_arc_deg, 3) << " deg,\n  " << number_text(100.0 * f.negative_chip_fraction, 3)
           << " % of the arc): below its limit the linear model no longer holds, and the simulation with the real "
              "chip\n  finds the cut stable deeper (check the part with chatter forced / chatter sle; "
              "docs/forced.md).\n";
  else
    report << "The forced vibration there stays inside the chip (no tooth leaves the cut at\n  "
           << number_text(100.0 * kBelowLinearLimit, 3) << " % of the " << lin->descriptor->name
           << " limit): the difference is not the forced vibration.\n";
}

std::string explanation(const Config& cfg, const Comparison& c) {
  std::ostringstream report;
  const std::vector<double>& speeds = c.speeds_rpm;
  report << cfg.name << ": " << speeds.size() << " speeds " << number_text(speeds.front()) << "-" << number_text(speeds.back())
         << " rev/min, depth searched to " << number_text(c.depth_max_mm) << " mm\n";
  for (const ComparedPair& p : c.pairs) {
    report << "  " << p.first << " vs " << p.second << ": largest relative difference "
           << number_text(p.largest_relative_difference, 3) << " (at " << number_text(p.at_spindle_rpm) << " rev/min)";
    if (p.bounded_only_by_first + p.bounded_only_by_second > 0)
      report << "; a limit below " << number_text(c.depth_max_mm) << " mm found only by " << p.first << " at "
             << p.bounded_only_by_first << " speeds, only by " << p.second << " at " << p.bounded_only_by_second;
    report << '\n';
  }
  // The zeroth-order (averaged) method the others are measured against: the
  // first of that kind in registry order.
  const ComparedMethod* averaged = nullptr;
  for (const auto& d : solver_registry())
    for (const auto& r : c.methods)
      if (!averaged && r.descriptor == &d && d.kind == SolverKind::kAveraged) averaged = &r;
  const bool turning = !cfg.process.rotating_edges();
  std::size_t flips = 0;
  for (const auto& r : c.methods)
    if (r.descriptor->kind == SolverKind::kFloquet)
      flips = std::max(flips, explain_floquet(r, averaged, cfg, speeds.size(), report));
  if (!turning && averaged)
    for (const auto& r : c.methods)
      if (r.descriptor->kind == SolverKind::kFloquet) {
        const bool averaged_first = averaged < &r;  // c.methods and c.pairs keep the asked order
        explain_averaging(averaged_first ? *averaged : r, averaged_first ? r : *averaged, r, *averaged, immersion(cfg),
                          speeds.size(), report);
      }
  for (const auto& r : c.methods)
    if (r.descriptor->kind == SolverKind::kSimulation) explain_simulation(r, turning, flips, report);
  explain_forced(cfg, c, report);
  return report.str();
}

}  // namespace

Comparison compare_methods(const Config& cfg, const CompareRequest& q) {
  if (q.speeds_rpm.empty()) throw InputError("compare: no spindle speeds");
  Comparison c;
  c.speeds_rpm = q.speeds_rpm;
  c.depth_max_mm = q.depth_max_mm;
  // Build every solver before running any: a bad option fails at once.
  c.methods.resize(q.methods.size());
  for (std::size_t m = 0; m < q.methods.size(); ++m) {
    ComparedMethod& r = c.methods[m];
    r.descriptor = &find_lobe_method(q.methods[m]);
    const SolverValues values = q.options ? q.options(*r.descriptor) : SolverValues{};
    r.solver = SolverRecipe{q.methods[m], values}.build(cfg.model, cfg.process, q.depth_max_mm * 1e-3);
    r.options = r.descriptor->effective_options(*r.solver);
    r.notes = method_notes(q.methods[m], *r.descriptor, cfg.process, values, "", q.style);
    r.columns = r.solver->diagnostic_columns();
  }
  const std::size_t n = q.speeds_rpm.size();
  for (ComparedMethod& r : c.methods) {
    if (q.progress) q.progress(r.descriptor->name, 0, n);
    const LobeSolver& solver = *r.solver;
    r.rows.resize(n);
    if (!r.columns.empty()) r.values.resize(n);
    parallel_for(
        n, q.threads,
        [&](std::size_t i) {
          if (r.columns.empty()) {
            r.rows[i] = solver.limit_at(SpindleSpeed(q.speeds_rpm[i]));
            return;
          }
          DiagnosedLimit d = solver.limit_with_diagnostics(SpindleSpeed(q.speeds_rpm[i]));
          r.rows[i] = d.limit;
          r.values[i] = std::move(d.values);
        },
        [&](std::size_t done) {
          if (q.progress) q.progress(r.descriptor->name, done, n);
        });
  }
  c.pairs = compare_pairs(c);
  c.explanation = explanation(cfg, c);
  return c;
}

std::string comparison_csv(const Comparison& c) {
  std::ostringstream csv;
  csv << "spindle_rpm";
  for (const auto& r : c.methods) csv << ",depth_limit_mm_" << r.descriptor->name;
  for (const auto& r : c.methods)
    for (const auto& col : r.descriptor->compare_columns) csv << ',' << col << '_' << r.descriptor->name;
  csv << '\n';
  for (std::size_t i = 0; i < c.speeds_rpm.size(); ++i) {
    csv << table_number(c.speeds_rpm[i]);
    for (const auto& r : c.methods) csv << ',' << table_number(r.rows[i].depth_limit_m * 1e3);
    for (const auto& r : c.methods)
      for (const auto& col : r.descriptor->compare_columns)
        csv << ',' << (r.rows[i].bounded() ? value_text(r.value(col, i)) : "");
    csv << '\n';
  }
  return csv.str();
}

json comparison_record(const Comparison& c, const RecordSource& source) {
  json methods = json::array(), options = json::object(), notes = source.notes, pairs = json::array();
  for (const auto& r : c.methods) {
    methods.push_back(r.descriptor->name);
    json o = json::object();
    for (const auto& [k, v] : r.options) o[k] = value_json(v);
    options[r.descriptor->name] = o;
    for (const std::string& n : r.notes) notes.push_back(r.descriptor->name + ": " + n);
  }
  for (const ComparedPair& p : c.pairs)
    pairs.push_back({{"methods", {p.first, p.second}},
                     {"largest_relative_difference", p.largest_relative_difference},
                     {"at_spindle_rpm", p.at_spindle_rpm},
                     {"bounded_only_by_first", p.bounded_only_by_first},
                     {"bounded_only_by_second", p.bounded_only_by_second}});
  json j = {{"config", source.config_path},
            {"name", source.config_name},
            {"methods", methods},
            {"rpm_min", c.speeds_rpm.front()},
            {"rpm_max", c.speeds_rpm.back()},
            {"rpm_points", c.speeds_rpm.size()},
            {"depth_max_mm", c.depth_max_mm},
            {"solver_options", options},
            {"warnings", source.warnings},
            {"notes", notes},
            {"pairs", pairs},
            {"explanation", c.explanation}};
  if (source.position_mm) j["position_mm"] = *source.position_mm;
  return j;
}

std::vector<MethodLimits> comparison_plot_lines(const Comparison& c) {
  std::vector<MethodLimits> lines(c.methods.size());
  for (std::size_t m = 0; m < c.methods.size(); ++m) {
    const ComparedMethod& r = c.methods[m];
    lines[m].method = r.descriptor->name;
    lines[m].limits = r.rows;
    const bool typed = std::any_of(r.columns.begin(), r.columns.end(),
                                   [](const DiagnosticColumn& col) { return col.name == "multiplier_type"; });
    if (!typed) continue;
    for (std::size_t i = 0; i < r.rows.size(); ++i) {
      // The text back to the type (rows without a limit are not marked).
      MultiplierType type = MultiplierType::kHopf;
      const SolverValue v = r.value("multiplier_type", i);
      if (const auto* t = std::get_if<std::string>(&v))
        for (MultiplierType k : {MultiplierType::kHopf, MultiplierType::kFlip, MultiplierType::kFold})
          if (*t == to_string(k)) type = k;
      lines[m].multiplier_type.push_back(type);
    }
  }
  return lines;
}

ColumnRecord comparison_columns(const Comparison& c, const RecordSource& source) {
  ColumnRecord out;
  out.fields = comparison_record(c, source);
  out.columns.emplace_back("spindle_rpm", c.speeds_rpm);
  for (const auto& m : c.methods) {
    std::vector<double> depth;
    for (const StabilityLimit& r : m.rows) depth.push_back(r.depth_limit_m * 1e3);  // +inf where unbounded
    out.columns.emplace_back("depth_limit_mm_" + m.descriptor->name, std::move(depth));
  }
  for (const auto& m : c.methods)
    for (const std::string& col : m.descriptor->compare_columns) {
      std::vector<std::string> cells;
      for (std::size_t i = 0; i < m.rows.size(); ++i)
        cells.push_back(m.rows[i].bounded() ? value_text(m.value(col, i)) : std::string());
      out.columns.emplace_back(col + "_" + m.descriptor->name, std::move(cells));
    }
  return out;
}

}  // namespace chatter
