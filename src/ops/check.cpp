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

namespace {

// One solver and one speed search per distinct process (the rows' radial
// immersion, teeth and direction).
struct Group {
  Process process = Process::turning({1.0});
  std::string method;
  double depth_max_m = 0.0;
  std::vector<std::size_t> rows;
};

// One run of check_operations, in its steps: group the rows by process,
// solve each group's speed search (in parallel), then the per-row additions
// (unit-slip warnings, forced vibration, cutting load).
class CheckRun {
 public:
  CheckRun(const StructuralModel& model, const Process& process, const std::vector<OperationRow>& rows,
           const CheckOptions& options)
      : model_(model), process_(process), rows_(rows), options_(options), judged_(rows.size(), 1),
        checks_(rows.size()) {}

  // Rows grouped by process; a row without a cutter or without a chip is
  // not judged; the per-row plausibility warnings.
  void group_rows() {
    using Key = std::tuple<double, int, int>;
    auto key_of = [&](const OperationRow& r) -> Key {
      if (!process_.rotating_edges()) return {0.0, 0, 0};
      const auto& m = process_.milling_parameters();
      return {r.radial_immersion.value_or(m.radial_immersion), r.teeth.value_or(m.teeth),
              static_cast<int>(r.direction.value_or(m.direction))};
    };
    for (std::size_t i = 0; i < rows_.size(); ++i) {
      const OperationRow& r = rows_[i];
      if (!by_key_.count(key_of(r))) {
        // A row whose overrides make no cutter (e.g. teeth that contradict
        // the config's pitch angles) is that row's error, not the file's.
        try {
          (void)process_for(process_, r);
        } catch (const InputError& e) {
          not_judged(i, e.what());
          continue;
        }
      }
      Group& g = by_key_[key_of(r)];
      if (g.method.empty()) start_group(g, r);
      if (const std::string why = g.process.no_chip_reason(r.depth_m); !why.empty()) {
        not_judged(i, why);  // no chip: refused, never judged (docs/results.md "No cut")
        continue;
      }
      g.depth_max_m = std::max(g.depth_max_m, search_depth(r));
      g.rows.push_back(i);
      warn_row(r);
    }
    for (auto& [key, g] : by_key_)
      if (!g.rows.empty()) groups_.push_back(&g);
    group_of_.assign(rows_.size(), groups_.size());
    for (std::size_t gi = 0; gi < groups_.size(); ++gi)
      for (const std::size_t i : groups_[gi]->rows) group_of_[i] = gi;
  }

  // Groups are independent: solved in parallel (each deterministic, so the
  // report does not depend on the thread count); a lone group scans in
  // parallel. A solver that fails on a process fails that group's rows only.
  void solve_groups() {
    const unsigned scan_threads = groups_.size() == 1 ? options_.threads : 1;
    // Progress: exact solves against a rough estimate of the total (a scan
    // of a few lobes plus the refinements), never reaching 1 before the end.
    std::atomic<std::size_t> solves{0};
    const double expected = static_cast<double>(kProgressSolvesPerProcess * groups_.size() +
                                                kProgressSolvesPerRow * rows_.size());
    auto tick = [&] {
      const double f = static_cast<double>(++solves) / expected;
      if (options_.progress) options_.progress(std::min(f, kProgressCeiling));
    };
    std::vector<std::vector<std::pair<std::size_t, std::string>>> failed(groups_.size());  // in row order
    solvers_.resize(groups_.size());
    searches_.resize(groups_.size());
    parallel_for(groups_.size(), options_.threads, [&](std::size_t gi) {
      const Group& g = *groups_[gi];
      try {
        solvers_[gi] = make_lobe_solver(g.method, model_, g.process, g.depth_max_m);
        searches_[gi] = std::make_unique<SpeedSearch>(*solvers_[gi], options_.machine.rpm_min,
                                                      options_.machine.rpm_max, options_.speed_tolerance, scan_threads);
        searches_[gi]->on_solve = tick;
        searches_[gi]->scan(true);
      } catch (const std::exception& e) {
        for (const std::size_t i : g.rows)
          failed[gi].emplace_back(i, std::string("the ") + g.method + " solver failed on this row's process: " +
                                         e.what());
        searches_[gi].reset();
        return;
      }
      for (const std::size_t i : g.rows) {
        try {
          checks_[i] = check_row(*searches_[gi], g.method, rows_[i], search_depth(rows_[i]));
        } catch (const std::exception& e) {
          failed[gi].emplace_back(i, std::string("the ") + g.method + " solver failed at this row: " + e.what());
        }
      }
    });
    // The progress counter is this step's: later questions (the tolerance
    // search of a suggestion) must not call it.
    for (auto& search : searches_)
      if (search) search->on_solve = nullptr;
    for (const auto& f : failed)
      for (const auto& [i, why] : f) not_judged(i, why);
    std::sort(report_.not_judged.begin(), report_.not_judged.end(),
              [](const RejectedRow& a, const RejectedRow& b) { return a.line < b.line; });
  }

  // Depths far beyond the limit are probably typed in the wrong unit.
  void warn_implausible_depths() {
    for (std::size_t i = 0; i < rows_.size(); ++i) {
      const OperationCheck& c = checks_[i];
      if (judged_[i] && c.limit.bounded() && rows_[i].depth_m > kImplausibleMarginFactor * c.limit.depth_limit_m)
        report_.warnings.push_back(at(rows_[i]) + "depth " + num(rows_[i].depth_m * 1e3) + " mm is over " +
                                   num(kImplausibleMarginFactor) + " times the stability limit " +
                                   num(c.limit.depth_limit_m * 1e3) + " mm at its speed: a depth in um?");
    }
  }

  // The forced vibration of every judged row with a feed (issue 27): its
  // surface location or diametral error and the part's tolerance, also at
  // the suggested speed (moved when it breaks the tolerance). A solver that
  // cannot give it (e.g. measured FRFs) leaves the row without it, said once.
  void add_forced() {
    for (std::size_t i = 0; i < rows_.size(); ++i) {
      if (!judged_[i]) continue;
      OperationCheck& c = checks_[i];
      try {
        c.forced = forced_check(model_, process_, rows_[i]);
        if (!c.suggestion || !c.forced) continue;
        OperationRow at = rows_[i];
        at.spindle_rpm = c.suggestion->spindle_rpm;
        c.suggestion_forced = forced_check(model_, process_, at);
        SpeedSearch* s = group_of_[i] < groups_.size() ? searches_[group_of_[i]].get() : nullptr;
        if (c.suggestion_forced && c.suggestion_forced->within_tolerance == false && rows_[i].max_error_m && s)
          suggest_within_tolerance(*s, model_, process_, rows_[i], c);
      } catch (const std::exception& e) {
        warn_once(std::string("forced vibration not computed: ") + e.what());
      }
    }
  }

  // The mean cutting load of every judged row with a feed, on its process,
  // against the machine's power and torque (docs/cutting_law.md). (Turning's
  // K_f-as-K_c warning only where power and torque are reported: with a
  // diameter.)
  void add_loads() {
    std::vector<std::string> unreported;
    for (std::size_t i = 0; i < rows_.size(); ++i) {
      if (!judged_[i] || !rows_[i].feed_per_tooth_m) continue;
      const Process p = process_for(process_, rows_[i]);
      const CuttingLawOptions lo = cutting_law_options(p, options_.cutting_coefficient_n_per_m2,
                                                       options_.diameter_m > 0.0 ? report_.warnings : unreported);
      const double d = options_.diameter_m > 0.0 ? options_.diameter_m : kNaN;
      const MeanCut m =
          CuttingLaw::of(p, lo)->mean({rows_[i].spindle_rpm, rows_[i].depth_m, *rows_[i].feed_per_tooth_m, d});
      OperationLoad load;
      load.mean_force_n = m.tangential_force_n;
      load.torque_n_m = m.torque_n_m;
      load.power_w = m.power_w;
      load.removal_rate_m3_per_s = m.removal_rate_m3_per_s;
      load.within_power = !(m.power_w > options_.machine.max_power_w);
      load.within_torque = !(m.torque_n_m > options_.machine.max_torque_n_m);
      checks_[i].load = load;
    }
  }

  // The judged rows' checks, in file order.
  CheckReport finish() {
    if (options_.progress) options_.progress(1.0);
    for (std::size_t i = 0; i < rows_.size(); ++i)
      if (judged_[i]) report_.checks.push_back(std::move(checks_[i]));
    return std::move(report_);
  }

 private:
  double search_depth(const OperationRow& r) const {
    return std::max(options_.search_depth_factor * r.depth_m, options_.search_depth_min_m);
  }
  void not_judged(std::size_t i, const std::string& why) {
    judged_[i] = 0;
    report_.not_judged.push_back({rows_[i].line, rows_[i].id, why});
  }
  void warn_once(const std::string& w) {
    if (std::find(report_.warnings.begin(), report_.warnings.end(), w) == report_.warnings.end())
      report_.warnings.push_back(w);
  }
  static std::string at(const OperationRow& r) {
    return "operation '" + r.id + "' (line " + std::to_string(r.line) + "): ";
  }
  // A group's process, its method, and what the method does not see (once).
  void start_group(Group& g, const OperationRow& r) {
    g.process = process_for(process_, r);
    std::string warning;
    g.method = resolve_lobe_method(options_.method, model_, g.process, &warning);
    std::vector<std::string> notes = ignored_feature_notes(find_lobe_method(g.method), g.process);
    if (!warning.empty()) notes.insert(notes.begin(), warning);
    for (const std::string& n : notes) warn_once(n);
  }
  // A row deeper than the flutes, a depth or a feed in another unit.
  void warn_row(const OperationRow& r) {
    if (options_.flute_length_m && r.depth_m > *options_.flute_length_m)
      report_.warnings.push_back(at(r) + "depth " + num(r.depth_m * 1e3) + " mm exceeds the usable flute length " +
                                 num(*options_.flute_length_m * 1e3) + " mm");
    if (const std::string hint = depth_unit_hint(r.depth_m * 1e3); !hint.empty())
      report_.warnings.push_back(at(r) + hint);
    if (r.feed_per_tooth_m && *r.feed_per_tooth_m > kPlausibleFeedM)
      report_.warnings.push_back(at(r) + "feed " + num(*r.feed_per_tooth_m * 1e3) + " mm per " +
                                 std::string(process_.feed_basis()) +
                                 " is above 1 mm: a feed in um, or per revolution?");
  }

  const StructuralModel& model_;
  const Process& process_;
  const std::vector<OperationRow>& rows_;
  const CheckOptions& options_;
  CheckReport report_;
  std::vector<char> judged_;  // 0: the row could not be judged (report_.not_judged says why)
  std::vector<OperationCheck> checks_;
  std::map<std::tuple<double, int, int>, Group> by_key_;
  std::vector<Group*> groups_;
  std::vector<std::size_t> group_of_;  // row -> its group (groups_.size(): none)
  // Each group's solver and speed search outlive the parallel solve: the
  // tolerance search of a suggestion asks them again.
  std::vector<std::unique_ptr<LobeSolver>> solvers_;
  std::vector<std::unique_ptr<SpeedSearch>> searches_;
};

}  // namespace

CheckReport check_operations(const StructuralModel& model, const Process& process,
                             const std::vector<OperationRow>& rows, const CheckOptions& options) {
  if (const std::string e = options.validate(); !e.empty()) throw InputError("check: " + e);
  CheckRun run(model, process, rows, options);
  run.group_rows();
  run.solve_groups();
  run.warn_implausible_depths();
  run.add_forced();
  run.add_loads();
  return run.finish();
}

}  // namespace chatter
