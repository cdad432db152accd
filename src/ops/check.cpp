// check_operations(): the verdict on every row of an operations file
// (include/chatter/operations.hpp, docs/operations.md "chatter check").
// One solver and one speed search per distinct process; check_row() judges
// one row.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/operations.hpp"
#include "chatter/report.hpp"
#include "chatter/solvers.hpp"
#include "ops_internal.hpp"
#include "speed_search.hpp"

namespace chatter {

using namespace detail::ops;

std::string CheckOptions::validate() const {
  std::ostringstream os;
  if (const std::string e = machine.validate(); !e.empty()) os << e;
  else if (!(std::isfinite(search_depth_factor) && search_depth_factor > 1.0))
    os << "CheckOptions::search_depth_factor = " << search_depth_factor << ": must be > 1";
  else if (!(std::isfinite(search_depth_min_m) && search_depth_min_m > 0.0))
    os << "CheckOptions::search_depth_min_m = " << search_depth_min_m << ": must be > 0 m";
  else if (const std::string t = validate_speed_tolerance(speed_tolerance, "CheckOptions::speed_tolerance x 100"); !t.empty())
    os << t;
  else if (flute_length_m && !(std::isfinite(*flute_length_m) && *flute_length_m > 0.0))
    os << "CheckOptions::flute_length_m = " << *flute_length_m << ": must be > 0 m";
  else if (!(std::isfinite(diameter_m) && diameter_m >= 0.0))
    os << "CheckOptions::diameter_m = " << diameter_m << ": must be >= 0 m (0 = not known)";
  else if (cutting_coefficient_n_per_m2 && !(std::isfinite(*cutting_coefficient_n_per_m2) && *cutting_coefficient_n_per_m2 > 0.0))
    os << "CheckOptions::cutting_coefficient_n_per_m2 = " << *cutting_coefficient_n_per_m2 << ": must be > 0";
  else if ((std::isfinite(machine.max_power_w) || std::isfinite(machine.max_torque_n_m)) && !(diameter_m > 0.0))
    os << "CheckOptions: a power or torque limit needs diameter_m > 0 (the tool's in milling, the workpiece's in "
          "turning)";
  return os.str();
}

std::size_t CheckReport::out_of_tolerance() const {
  return static_cast<std::size_t>(std::count_if(checks.begin(), checks.end(), [](const OperationCheck& c) {
    return c.forced && c.op.max_error_m && c.forced->within_tolerance == false;  // unstable rows: no verdict
  }));
}

std::size_t CheckReport::overloaded() const {
  return static_cast<std::size_t>(std::count_if(checks.begin(), checks.end(), [](const OperationCheck& c) {
    return c.load && (!c.load->within_power || !c.load->within_torque);
  }));
}

std::size_t CheckReport::unstable() const {
  return static_cast<std::size_t>(std::count_if(checks.begin(), checks.end(), [](const auto& c) { return !c.stable; }));
}

namespace {

// A row deeper than this many times its own limit is probably typed in the
// wrong unit (um for mm): warned, naming the row. Feeds above 1 mm per tooth
// (or per revolution in turning) likewise.
constexpr double kImplausibleMarginFactor = 10.0;
constexpr double kPlausibleFeedM = 1e-3;

// The verdict on one row (OperationCheck): its exact limit and margins, and
// the suggested speed with its pocket. `s` is the speed search of the row's
// process (it caches the solves the rows of a process share); `ds` the depth
// searched for the row. Each per-row judgement is one step here.
// Sets c's suggestion to speed n: its exact limit, margin and pocket at the
// row's depth, when its band's worst limit clears the depth.
void suggest(SpeedSearch& s, const OperationRow& r, double ds, double n, OperationCheck& c) {
  const double w = s.band_min(n);
  const double worst = w > ds ? kInf : w;
  if (!(worst > r.depth_m)) return;
  c.suggestion = clip(s.at(n), ds);
  c.suggestion_margin = c.suggestion->depth_limit_m / r.depth_m;
  SpeedPocket p = make_pocket(s, n, r.depth_m, r.depth_m);
  p.limit = *c.suggestion;
  p.worst_limit_m = worst;
  p.worst_margin = worst / r.depth_m;
  c.suggestion_pocket = p;
}

OperationCheck check_row(SpeedSearch& s, const std::string& method, const OperationRow& r, double ds) {
  auto clipped = [&](double w) { return w > ds ? kInf : w; };
  OperationCheck c;
  c.op = r;
  c.method = method;
  c.search_depth_m = ds;
  // The verdict: the exact limit at the row's own speed.
  c.limit = clip(s.at(r.spindle_rpm), ds);
  c.stable = r.depth_m < c.limit.depth_limit_m;
  c.margin = c.limit.depth_limit_m / r.depth_m;
  // The worst limit over the row's own speed band.
  const double own_worst = clipped(s.band_min(r.spindle_rpm));
  c.worst_margin = own_worst / r.depth_m;
  // The suggestion: the speed whose band has the largest worst limit
  // (unbounded for this row's searched depth: the nearest such speed); the
  // row's own speed when it is as good.
  double n = r.spindle_rpm;
  if (std::isfinite(own_worst)) {
    const double best = s.best(ds, r.spindle_rpm);
    if (clipped(s.band_min(best)) > own_worst) n = best;
  }
  suggest(s, r, ds, n, c);
  return c;
}

// Candidates tried for a suggestion within the part's tolerance: forced
// responses (~1-10 ms each) at the stable scanned speeds, best worst margin
// first.
constexpr std::size_t kToleranceTries = 24;

// When the suggested speed breaks the row's part tolerance (its forced part
// error above row.max_error_m), the stable speed with the largest worst
// margin whose part error holds the tolerance replaces it; without one the
// suggestion stays and the note says no scanned speed holds the tolerance.
// Cost: up to kToleranceTries forced responses and their exact band solves.
void suggest_within_tolerance(SpeedSearch& s, const StructuralModel& model, const Process& process,
                              const OperationRow& r, OperationCheck& c) {
  const OperationForced& broken = *c.suggestion_forced;
  const double ds = c.search_depth_m;
  auto clipped = [&](double w) { return w > ds ? kInf : w; };
  std::vector<std::pair<double, double>> ranked;  // (estimated worst limit, rpm)
  for (const double n : s.scan_speeds())
    if (const double w = s.band_min_scan(n, ds); w > r.depth_m && n != c.suggestion->spindle_rpm) ranked.emplace_back(w, n);
  std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  auto um = [](double m) {
    std::ostringstream os;
    os.precision(3);
    os << m * 1e6 << " um";
    return os.str();
  };
  const std::string was = num(std::round(c.suggestion->spindle_rpm)) + " rev/min (part error " +
                          um(broken.part_error_m) + ", tolerance " + um(*r.max_error_m) + ")";
  for (std::size_t k = 0; k < ranked.size() && k < kToleranceTries; ++k) {
    const double n = ranked[k].second;
    if (!(clipped(s.band_min(n)) > r.depth_m)) continue;  // the estimate was optimistic
    OperationRow at = r;
    at.spindle_rpm = n;
    const std::optional<OperationForced> f = forced_check(model, process, at);
    if (!f || f->within_tolerance != true) continue;
    suggest(s, r, ds, n, c);
    c.suggestion_forced = f;
    c.suggestion_note = "moved from " + was + " to " + num(std::round(n)) + " rev/min (part error " +
                        um(f->part_error_m) + "), the stable speed with the largest margin within the tolerance";
    return;
  }
  c.suggestion_note = "the best-margin speed " + was + " breaks the tolerance, and no other stable scanned speed "
                      "holds it at this depth and feed: reduce the feed or the depth";
}

}  // namespace

CheckReport check_operations(const StructuralModel& model, const Process& process,
                             const std::vector<OperationRow>& rows, const CheckOptions& options) {
  if (const std::string e = options.validate(); !e.empty()) throw InputError("check: " + e);
  CheckReport report;
  auto search_depth = [&](const OperationRow& r) {
    return std::max(options.search_depth_factor * r.depth_m, options.search_depth_min_m);
  };

  // One solver and one speed search per distinct process.
  struct Group {
    Process process = Process::turning({1.0});
    std::string method;
    double depth_max_m = 0.0;
    std::vector<std::size_t> rows;
  };
  using Key = std::tuple<double, int, int>;
  auto key_of = [&](const OperationRow& r) -> Key {
    if (!process.rotating_edges()) return {0.0, 0, 0};
    const auto& m = process.milling_parameters();
    return {r.radial_immersion.value_or(m.radial_immersion), r.teeth.value_or(m.teeth),
            static_cast<int>(r.direction.value_or(m.direction))};
  };
  std::map<Key, Group> by_key;
  std::vector<char> judged(rows.size(), 1);  // 0: the row could not be judged (report.not_judged says why)
  auto not_judged = [&](std::size_t i, const std::string& why) {
    judged[i] = 0;
    report.not_judged.push_back({rows[i].line, rows[i].id, why});
  };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const OperationRow& r = rows[i];
    if (!by_key.count(key_of(r))) {
      // A row whose overrides make no cutter (e.g. teeth that contradict
      // the config's pitch angles) is that row's error, not the file's.
      try {
        (void)process_for(process, r);
      } catch (const InputError& e) {
        not_judged(i, e.what());
        continue;
      }
    }
    Group& g = by_key[key_of(r)];
    if (g.method.empty()) {
      g.process = process_for(process, r);
      std::string warning;
      g.method = resolve_lobe_method(options.method, model, g.process, &warning);
      std::vector<std::string> notes = ignored_feature_notes(find_lobe_method(g.method), g.process);
      if (!warning.empty()) notes.insert(notes.begin(), warning);
      for (const std::string& n : notes)
        if (std::find(report.warnings.begin(), report.warnings.end(), n) == report.warnings.end())
          report.warnings.push_back(n);
    }
    if (const std::string why = g.process.no_chip_reason(r.depth_m); !why.empty()) {
      not_judged(i, why);  // no chip: refused, never judged (docs/results.md "No cut")
      continue;
    }
    g.depth_max_m = std::max(g.depth_max_m, search_depth(r));
    g.rows.push_back(i);
    if (options.flute_length_m && r.depth_m > *options.flute_length_m)
      report.warnings.push_back("operation '" + r.id + "' (line " + std::to_string(r.line) + "): depth " +
                                num(r.depth_m * 1e3) + " mm exceeds the usable flute length " +
                                num(*options.flute_length_m * 1e3) + " mm");
    if (const std::string hint = depth_unit_hint(r.depth_m * 1e3); !hint.empty())
      report.warnings.push_back("operation '" + r.id + "' (line " + std::to_string(r.line) + "): " + hint);
    if (r.feed_per_tooth_m && *r.feed_per_tooth_m > kPlausibleFeedM)
      report.warnings.push_back("operation '" + r.id + "' (line " + std::to_string(r.line) + "): feed " +
                                num(*r.feed_per_tooth_m * 1e3) + " mm per " +
                                std::string(process.feed_basis()) +
                                " is above 1 mm: a feed in um, or per revolution?");
  }
  std::vector<Group*> groups;
  for (auto& [key, g] : by_key)
    if (!g.rows.empty()) groups.push_back(&g);

  // Groups are independent: solved in parallel (each deterministic, so the
  // report does not depend on the thread count); a lone group scans in parallel.
  std::vector<OperationCheck> checks(rows.size());
  const unsigned scan_threads = groups.size() == 1 ? options.threads : 1;
  // Progress: exact solves against a rough estimate of the total (a scan of
  // a few lobes plus the refinements), never reaching 1 before the end.
  std::atomic<std::size_t> solves{0};
  const double expected = static_cast<double>(kProgressSolvesPerProcess * groups.size() +
                                              kProgressSolvesPerRow * rows.size());
  auto tick = [&] {
    const double f = static_cast<double>(++solves) / expected;
    if (options.progress) options.progress(std::min(f, kProgressCeiling));
  };
  const double tol = options.speed_tolerance;
  std::vector<std::vector<std::pair<std::size_t, std::string>>> failed(groups.size());  // per group, in row order
  // Each group's solver and speed search outlive the loop: the tolerance
  // search of a suggestion (below) asks them again.
  std::vector<std::unique_ptr<LobeSolver>> solvers(groups.size());
  std::vector<std::unique_ptr<SpeedSearch>> searches(groups.size());
  std::vector<std::size_t> group_of(rows.size(), groups.size());
  for (std::size_t gi = 0; gi < groups.size(); ++gi)
    for (const std::size_t i : groups[gi]->rows) group_of[i] = gi;
  parallel_for(groups.size(), options.threads, [&](std::size_t gi) {
    const Group& g = *groups[gi];
    std::unique_ptr<LobeSolver>& solver = solvers[gi];
    std::unique_ptr<SpeedSearch>& search = searches[gi];
    try {
      solver = make_lobe_solver(g.method, model, g.process, g.depth_max_m);
      search = std::make_unique<SpeedSearch>(*solver, options.machine.rpm_min, options.machine.rpm_max, tol,
                                             scan_threads);
      search->on_solve = tick;
      search->scan(true);
    } catch (const std::exception& e) {
      // A solver that fails on this process fails every row of it; the
      // other processes' rows are still checked.
      for (const std::size_t i : g.rows)
        failed[gi].emplace_back(i, std::string("the ") + g.method + " solver failed on this row's process: " +
                                       e.what());
      return;
    }
    SpeedSearch& s = *search;
    for (const std::size_t i : g.rows) {
      try {
        checks[i] = check_row(s, g.method, rows[i], search_depth(rows[i]));
      } catch (const std::exception& e) {
        failed[gi].emplace_back(i, std::string("the ") + g.method + " solver failed at this row: " + e.what());
      }
    }
  });
  for (const auto& f : failed)
    for (const auto& [i, why] : f) not_judged(i, why);
  std::sort(report.not_judged.begin(), report.not_judged.end(),
            [](const RejectedRow& a, const RejectedRow& b) { return a.line < b.line; });
  // Depths far beyond the limit are probably typed in the wrong unit.
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const OperationCheck& c = checks[i];
    if (judged[i] && c.limit.bounded() && rows[i].depth_m > kImplausibleMarginFactor * c.limit.depth_limit_m)
      report.warnings.push_back("operation '" + rows[i].id + "' (line " + std::to_string(rows[i].line) + "): depth " +
                                num(rows[i].depth_m * 1e3) + " mm is over " + num(kImplausibleMarginFactor) +
                                " times the stability limit " + num(c.limit.depth_limit_m * 1e3) +
                                " mm at its speed: a depth in um?");
  }
  // The forced vibration of every judged row with a feed (issue 27): its
  // surface location or diametral error and the part's tolerance. A solver
  // that cannot give it (e.g. measured FRFs) leaves the row without it, said
  // once in the warnings.
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!judged[i]) continue;
    try {
      checks[i].forced = forced_check(model, process, rows[i]);
      if (checks[i].suggestion && checks[i].forced) {
        OperationRow at = rows[i];
        at.spindle_rpm = checks[i].suggestion->spindle_rpm;
        checks[i].suggestion_forced = forced_check(model, process, at);
        if (checks[i].suggestion_forced && checks[i].suggestion_forced->within_tolerance == false &&
            rows[i].max_error_m && group_of[i] < groups.size() && searches[group_of[i]])
          suggest_within_tolerance(*searches[group_of[i]], model, process, rows[i], checks[i]);
      }
    } catch (const std::exception& e) {
      const std::string w = std::string("forced vibration not computed: ") + e.what();
      if (std::find(report.warnings.begin(), report.warnings.end(), w) == report.warnings.end())
        report.warnings.push_back(w);
    }
  }
  // The mean cutting load of every judged row with a feed, on its process,
  // against the machine's power and torque (docs/cutting_law.md).
  // (Turning's K_f-as-K_c warning only where power and torque are reported:
  // with a diameter.)
  std::vector<std::string> unreported;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!judged[i] || !rows[i].feed_per_tooth_m) continue;
    const Process p = process_for(process, rows[i]);
    const CuttingLawOptions lo = cutting_law_options(p, options.cutting_coefficient_n_per_m2,
                                                     options.diameter_m > 0.0 ? report.warnings : unreported);
    const double d = options.diameter_m > 0.0 ? options.diameter_m : kNaN;
    const MeanCut m = CuttingLaw::of(p, lo)->mean({rows[i].spindle_rpm, rows[i].depth_m, *rows[i].feed_per_tooth_m, d});
    OperationLoad load;
    load.mean_force_n = m.tangential_force_n;
    load.torque_n_m = m.torque_n_m;
    load.power_w = m.power_w;
    load.removal_rate_m3_per_s = m.removal_rate_m3_per_s;
    load.within_power = !(m.power_w > options.machine.max_power_w);
    load.within_torque = !(m.torque_n_m > options.machine.max_torque_n_m);
    checks[i].load = load;
  }
  if (options.progress) options.progress(1.0);
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (judged[i]) report.checks.push_back(std::move(checks[i]));
  return report;
}

}  // namespace chatter
