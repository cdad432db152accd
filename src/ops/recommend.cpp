// recommend() and explain(): the speed and depth that remove the most
// material within stability, power, torque and the tool
// (include/chatter/operations.hpp, docs/operations.md "chatter recommend").
#include <algorithm>
#include <atomic>
#include <map>
#include <memory>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/cutting_law.hpp"
#include "chatter/error.hpp"
#include "chatter/forced.hpp"
#include "chatter/operations.hpp"
#include "chatter/solvers.hpp"
#include "ops_internal.hpp"
#include "speed_search.hpp"

namespace chatter {

using namespace detail::ops;

namespace {

constexpr double kPi = std::numbers::pi;

}  // namespace

namespace {

// Two MRR values this close (relative) are a tie: power-bound MRR is the same
// at every speed up to round-off.
constexpr double kTieRelative = 1e-9;
// Speeds of the grid on which the refinement's floor is placed (no solves:
// the depth caps only).
constexpr int kFloorGridPoints = 2000;
// A depth cap within this relative distance of the chosen depth binds too.
// The speed search locates the optimum to 1e-8 of the speed; on a
// steep lobe flank (d ln limit / d ln N up to ~10³) two caps that cross at the
// optimum then differ by up to ~1e-5.
constexpr double kBindingRelative = 1e-5;
// With a speed tolerance the optimum is bracketed to kRobustRelativeWidth
// (1e-4 of the speed): on a flank of log-slope up to 10 crossing caps then
// differ by up to 1e-3.
constexpr double kRobustBindingRelative = 1e-3;
// The recommendation searches limits up to this multiple of depth_max/safety,
// so a limit near the tool's depth cap is still reported (and can co-bind).
constexpr double kRecommendSearchFactor = 2.0;
// The part-error cap is located to this fraction of the depth.
constexpr double kPartErrorDepthRel = 1e-4;
constexpr int kPartErrorMaxResponses = 60;

}  // namespace

std::string RecommendOptions::validate() const {
  std::ostringstream os;
  if (const std::string e = machine.validate(); !e.empty()) os << e;
  else if (!(safety > 0.0 && safety <= 1.0))
    os << "safety = " << safety << ": must be in (0, 1] (fraction of the depth limit)";
  else if (!(std::isfinite(feed_per_tooth_m) && feed_per_tooth_m > 0.0))
    os << "feed_per_tooth = " << feed_per_tooth_m * 1e3 << " mm: must be > 0";
  else if (!(std::isfinite(diameter_m) && diameter_m >= 0.0))
    os << "diameter = " << diameter_m * 1e3 << " mm: must be > 0 (or 0 = unknown)";
  else if (!(std::isfinite(depth_max_m) && depth_max_m > 0.0))
    os << "depth_max = " << depth_max_m * 1e3 << " mm: must be > 0";
  else if (cutting_coefficient_n_per_m2 && !(std::isfinite(*cutting_coefficient_n_per_m2) && *cutting_coefficient_n_per_m2 > 0.0))
    os << "cutting coefficient = " << *cutting_coefficient_n_per_m2 << " N/m²: must be > 0";
  else if (flute_length_m && !(std::isfinite(*flute_length_m) && *flute_length_m > 0.0))
    os << "flute_length = " << *flute_length_m * 1e3 << " mm: must be > 0";
  else if (const std::string t = validate_speed_tolerance(speed_tolerance, "speed tolerance x 100"); !t.empty())
    os << t;
  else if (max_part_error_m && !(std::isfinite(*max_part_error_m) && *max_part_error_m > 0.0))
    os << "max part error = " << *max_part_error_m * 1e6 << " um: must be > 0";
  return os.str();
}

std::string to_string(Binding b) {
  switch (b) {
    case Binding::kStability: return "stability";
    case Binding::kPower: return "power";
    case Binding::kTorque: return "torque";
    case Binding::kDepthMax: return "depth_max";
    case Binding::kSpeedRange: return "speed_range";
    case Binding::kFluteLength: return "flute_length";
    case Binding::kSurfaceError: return "surface_error";
  }
  return "?";
}

namespace {

// The cutting law (chatter/cutting_law.hpp) as recommend reads it: its means
// at a speed and depth, and the deepest depth within a power or torque cap.
// A flat cutter's (and an insert's) means are linear in the depth, so a cap
// is a quotient; a ball-end, bull-nose or general cutter's are not (its
// section grows faster than the depth near the tip), so its cap is the root
// of the law's own power (torque) against the cap.
class CutModel {
 public:
  CutModel(const Process& p, const RecommendOptions& o, std::vector<std::string>& warnings)
      : law_(CuttingLaw::of(p, cutting_law_options(p, o.cutting_coefficient_n_per_m2, warnings))),
        feed_m_(o.feed_per_tooth_m),
        diameter_m_(o.diameter_m > 0.0 ? o.diameter_m : kNaN),
        linear_(!p.has_profile()) {
    const MeanCut unit = at(1.0, 1.0);
    power_per_depth_rpm_ = unit.power_w;
    torque_per_depth_ = unit.torque_n_m;
    mrr_per_depth_rpm_ = unit.removal_rate_m3_per_s;
  }

  /// The law's means at `rpm` and depth a (m), with the options' diameter.
  MeanCut at(double rpm, double depth_m) const { return law_->mean(CutPoint{rpm, depth_m, feed_m_, diameter_m_}); }
  /// The same per unit tool (workpiece) diameter: the removal rate per mm of D.
  MeanCut per_unit_diameter(double rpm, double depth_m) const {
    return law_->mean(CutPoint{rpm, depth_m, feed_m_, 1.0});
  }
  /// The deepest depth (m) whose mean power stays within `max_w` at `rpm`;
  /// +inf when none is given. At most `d_hi` is searched for a profile
  /// (+inf when the cap holds there).
  double depth_within_power(double rpm, double max_w, double d_hi) const {
    if (!std::isfinite(max_w)) return kInf;
    if (linear_) return max_w / (power_per_depth_rpm_ * rpm);
    return root(max_w, d_hi, [&](double a) { return at(rpm, a).power_w; });
  }
  double depth_within_torque(double max_n_m, double d_hi) const {
    if (!std::isfinite(max_n_m)) return kInf;
    if (linear_) return max_n_m / torque_per_depth_;
    return root(max_n_m, d_hi, [&](double a) { return at(1.0, a).torque_n_m; });
  }
  /// What the search maximises, in m·rev/min: N a for a law linear in the
  /// depth (the removal rate over its value at 1 m and 1 rev/min), the
  /// removal rate over that same value for a profile.
  double objective(double rpm, double depth_m) const {
    if (linear_ || !std::isfinite(depth_m)) return rpm * depth_m;
    return at(rpm, depth_m).removal_rate_m3_per_s / mrr_per_depth_rpm_;
  }

 private:
  // The depth where the increasing g(a) meets `cap` in [0, d_hi], by
  // bisection to kCapDepthRelative of d_hi; +inf when g(d_hi) <= cap.
  template <class G>
  static double root(double cap, double d_hi, G g) {
    if (!(std::isfinite(d_hi) && d_hi > 0.0) || g(d_hi) <= cap) return kInf;
    double lo = 0.0, hi = d_hi;
    while (hi - lo > kCapDepthRelative * d_hi) {
      const double mid = 0.5 * (lo + hi);
      (g(mid) <= cap ? lo : hi) = mid;
    }
    return lo;
  }
  static constexpr double kCapDepthRelative = 1e-10;

  std::shared_ptr<const CuttingLaw> law_;
  double feed_m_, diameter_m_;
  bool linear_;
  double power_per_depth_rpm_ = 0.0, torque_per_depth_ = 0.0, mrr_per_depth_rpm_ = 0.0;
};

// The deepest depth in (0, d_hi] whose part error (forced_check's: |SLE| in
// milling, the diametral error in turning) stays within `tol`; +inf when it
// holds at d_hi. The error grows with depth (the force does): Illinois
// regula falsi on err(d) − tol over [0, d_hi], the lower end kept feasible;
// an unstable point counts as out of tolerance (bisection there).
class PartErrorCap {
 public:
  PartErrorCap(const StructuralModel& model, const Process& process, double feed_m, double tol)
      : solver_(model, process), feed_m_(feed_m), tol_(tol) {}

  double error(double rpm, double depth_m) const {
    ForcedSettings st;
    st.spindle_rpm = rpm;
    st.depth_m = depth_m;
    st.feed_m = feed_m_;
    st.record_path = false;
    const ForcedResponse r = solver_.response(st);
    return r.stable ? part_error_m(r) : kInf;  // unstable: out of any tolerance
  }

  double cap(double rpm, double d_hi) {
    if (!(std::isfinite(d_hi) && d_hi > 0.0)) return kInf;
    const auto key = std::make_pair(rpm, d_hi);
    if (const auto it = cache_.find(key); it != cache_.end()) return it->second;
    double lo = 0.0, g_lo = -tol_, hi = d_hi, g_hi = error(rpm, d_hi) - tol_;
    double result = kInf;
    if (g_hi > 0.0) {
      int side = 0;
      for (int i = 0; i < kPartErrorMaxResponses && hi - lo > kPartErrorDepthRel * hi; ++i) {
        const double x = std::isfinite(g_hi) ? lo + (hi - lo) * g_lo / (g_lo - g_hi) : 0.5 * (lo + hi);
        const double gx = error(rpm, x) - tol_;
        if (gx <= 0.0) {
          lo = x, g_lo = gx;
          if (side == -1 && std::isfinite(g_hi)) g_hi *= 0.5;
          side = -1;
        } else {
          hi = x, g_hi = gx;
          if (side == 1) g_lo *= 0.5;
          side = 1;
        }
        if (gx <= 0.0 && gx > -kPartErrorDepthRel * tol_) break;  // on the tolerance
      }
      result = lo;
    }
    cache_.emplace(key, result);
    return result;
  }

 private:
  ForcedResponseSolver solver_;
  double feed_m_, tol_;
  std::map<std::pair<double, double>, double> cache_;
};

// The refinement's floor (SpeedSearch::refinement_floor): on a fine
// geometric grid of the range, the last speed below the first whose `bound`
// reaches `target` (every speed below it removes less than target whatever
// its limit), lowered by a band's width (1 + tol)^2 so that the bands of the
// speeds kept are scanned whole; rpm_min (nothing skipped) when the bound
// reaches the target at once.
template <class Bound>
double pruning_floor(Bound&& bound, double target, double rpm_min, double rpm_max, double tol) {
  if (!(target > 0.0) || !std::isfinite(target)) return rpm_min;
  double floor = rpm_min;
  for (int k = 0; k <= kFloorGridPoints; ++k) {
    const double n = rpm_min * std::pow(rpm_max / rpm_min, static_cast<double>(k) / kFloorGridPoints);
    if (!(bound(n) < target)) break;
    floor = n;
  }
  return floor == rpm_min ? rpm_min : floor / ((1.0 + tol) * (1.0 + tol));
}

// One candidate speed: its depth caps (m), the depth they allow, what it
// removes (the objective) and its worst margin.
struct Cand {
  double rpm, worst, stab, power, torque, cap, flute, part, depth, objective, margin;
};

// recommend()'s search on a SpeedSearch: each candidate's caps and objective,
// the ranking of the scan and the refinement of its best local maxima
// (docs/operations.md, "Search").
class Ranking {
 public:
  Ranking(SpeedSearch& s, const CutModel& cm, const RecommendOptions& o, double search_depth_m,
          double solver_depth_max_m, PartErrorCap* part_error)
      : s_(s), cm_(cm), o_(o), search_depth_m_(search_depth_m), solver_depth_max_m_(solver_depth_max_m),
        flute_(o.flute_length_m.value_or(kInf)), part_error_(part_error) {}

  /// `exact`: the worst limit over the band from exact solves, else the scan's estimate.
  Cand evaluate(double n, bool exact) {
    const MachineLimits& mc = o_.machine;
    Cand c;
    c.rpm = n;
    const double w = exact ? s_.band_min(n) : s_.band_min_scan(n, kInf);
    c.worst = w > search_depth_m_ || w >= solver_depth_max_m_ ? kInf : w;
    c.stab = o_.safety * c.worst;
    c.power = cm_.depth_within_power(n, mc.max_power_w, search_depth_m_);
    c.torque = cm_.depth_within_torque(mc.max_torque_n_m, search_depth_m_);
    c.cap = o_.depth_max_m;
    c.flute = flute_;
    const double others = std::min({c.stab, c.power, c.torque, c.cap, c.flute});
    c.part = part_error_ ? part_error_->cap(n, others) : kInf;
    c.depth = std::min(others, c.part);
    c.objective = cm_.objective(n, c.depth);  // MRR / (MRR at 1 m and 1 rev/min)
    c.margin = c.worst / c.depth;
    return c;
  }
  /// x strictly better than y: more removed, or as much with a larger margin.
  static bool better(const Cand& x, const Cand& y) {
    if (x.objective > y.objective * (1.0 + kTieRelative)) return true;
    if (x.objective < y.objective * (1.0 - kTieRelative)) return false;
    return x.margin > y.margin;
  }
  /// The deepest cut at `n` whatever its limit: the depth caps other than
  /// stability and the part error (each only lowers it).
  double caps(double n) const {
    const MachineLimits& mc = o_.machine;
    return std::min({cm_.depth_within_power(n, mc.max_power_w, search_depth_m_),
                     cm_.depth_within_torque(mc.max_torque_n_m, search_depth_m_), o_.depth_max_m, flute_,
                     search_depth_m_});
  }
  /// What that cut removes: no speed removes more (a bound without a solve).
  double bound(double n) const { return cm_.objective(n, caps(n)); }
  /// SpeedSearch::refinement_floor: below it no speed reaches what the
  /// speeds solved so far promise (their best, less the candidate spread).
  double floor(const std::vector<double>& solved) {
    double promise = 0.0;
    for (const double n : solved) promise = std::max(promise, cm_.objective(n, std::min(o_.safety * s_.g(n), caps(n))));
    return pruning_floor([&](double n) { return bound(n); }, (1.0 - kCandidateSpread) * promise, o_.machine.rpm_min,
                         o_.machine.rpm_max, o_.speed_tolerance);
  }
  /// Whether a skipped speed of the scan could remove as much as `best`.
  bool skipped_could_beat(const Cand& best) const {
    double b = 0.0;
    for (const double n : s_.skipped()) b = std::max(b, bound(n));
    return !s_.skipped().empty() && !(best.objective * (1.0 - kTieRelative) > b);
  }
  /// Ranks the scanned speeds and refines the best local maxima with exact
  /// solves: the best candidate and the index of its scan speed.
  std::pair<Cand, std::size_t> search();

 private:
  SpeedSearch& s_;
  const CutModel& cm_;
  const RecommendOptions& o_;
  double search_depth_m_, solver_depth_max_m_, flute_;
  PartErrorCap* part_error_;
};

std::pair<Cand, std::size_t> Ranking::search() {
  const std::vector<double>& pts = s_.scan_speeds();
  std::vector<Cand> scanned;
  for (double n : pts) scanned.push_back(evaluate(n, false));
  std::vector<std::size_t> cand;
  double top = 0.0;
  for (const auto& c : scanned) top = std::max(top, c.objective);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const bool local = (i == 0 || !better(scanned[i - 1], scanned[i])) &&
                       (i + 1 == pts.size() || !better(scanned[i + 1], scanned[i]));
    if (local && scanned[i].objective >= (1.0 - kCandidateSpread) * top) cand.push_back(i);
  }
  if (cand.empty()) cand.push_back(0);  // only with NaN objectives
  std::sort(cand.begin(), cand.end(), [&](std::size_t x, std::size_t y) { return better(scanned[x], scanned[y]); });
  if (cand.size() > kMaxCandidates) cand.resize(kMaxCandidates);
  const double rel = o_.speed_tolerance > 0.0 ? kRobustRelativeWidth : kGoldenRelativeWidth;
  Cand best = evaluate(pts[cand.front()], true);
  std::size_t ib = cand.front();
  for (const std::size_t i : cand) {
    const Cand at_point = evaluate(pts[i], true);
    if (better(at_point, best)) best = at_point, ib = i;
    const double a = pts[i == 0 ? 0 : i - 1], b = pts[std::min(i + 1, pts.size() - 1)];
    // Power-bound MRR is flat in speed: then the largest worst margin.
    const bool power_bound = at_point.depth == at_point.power;
    auto f = [&](double n) {
      const Cand c = evaluate(n, true);
      if (better(c, best)) best = c, ib = i;
      return power_bound ? c.margin : c.objective;
    };
    // Bound by stability or power near a cusp, the optimum is where the band's
    // two ends balance (MRR ∝ N·worst limit has its kink there; beyond it the
    // lobe flank falls faster than 1/N); bound by a fixed depth cap, MRR grows
    // with N up to where stability takes over: Brent's minimiser.
    const bool stability_bound = at_point.depth == at_point.stab;
    const double x = (power_bound || stability_bound) && o_.speed_tolerance > 0.0 ? s_.balance(a, b, rel) : 0.0;
    if (x > 0.0) f(x);
    else s_.maximize(f, a, b, rel);
  }
  return {best, ib};
}

// Part quality beside the suggestion (docs/results.md), with or without a
// tolerance: the forced response at the recommended cut (modal models).
void add_part_quality(Recommendation& rec, const StructuralModel& model, const Process& process, double feed_m) {
  if (model.has_measured()) return;
  ForcedSettings st;
  st.spindle_rpm = rec.spindle_rpm;
  st.depth_m = rec.depth_m;
  st.feed_m = feed_m;
  st.record_path = false;
  try {
    const ForcedResponse fr = ForcedResponseSolver(model, process).response(st);
    if (fr.stable) {
      rec.part_error_m = part_error_m(fr);
      rec.peak_to_peak_m = std::max(fr.peak_to_peak_x_m, fr.peak_to_peak_y_m);
    }
  } catch (const InputError& e) {
    rec.warnings.push_back(std::string("part error not computed: ") + e.what());
  }
}

// What binds the recommended cut: each cap within the binding tolerance of
// the depth, and the speed range when the optimum sits on an end of the scan
// and MRR still grows towards it (a power-bound MRR is flat in speed: it
// does not).
void add_bindings(Recommendation& rec, const Cand& best, std::size_t ib, Ranking& rk, const std::vector<double>& pts,
                  const RecommendOptions& options) {
  const double bind_rel = options.speed_tolerance > 0.0 ? kRobustBindingRelative : kBindingRelative;
  auto binds = [&](double cap) { return std::isfinite(cap) && cap <= rec.depth_m * (1.0 + bind_rel); };
  if (binds(best.stab)) rec.binding.push_back(Binding::kStability);
  if (binds(best.power)) rec.binding.push_back(Binding::kPower);
  if (binds(best.torque)) rec.binding.push_back(Binding::kTorque);
  if (binds(best.cap)) rec.binding.push_back(Binding::kDepthMax);
  if (binds(best.flute)) rec.binding.push_back(Binding::kFluteLength);
  if (binds(best.part)) rec.binding.push_back(Binding::kSurfaceError);
  if (!binds(best.power) && (ib == 0 || ib + 1 == pts.size()) && best.rpm == pts[ib]) {
    const Cand inner = rk.evaluate(pts[ib == 0 ? 1 : ib - 1], true);
    if (best.objective > inner.objective * (1.0 + kTieRelative)) rec.binding.push_back(Binding::kSpeedRange);
  }
}

}  // namespace

Recommendation recommend(const StructuralModel& model, const Process& given, const RecommendOptions& options) {
  if (const std::string e = options.validate(); !e.empty()) throw InputError("recommend: " + e);
  // Kienzle's law: the regenerative coefficient at the plan's own feed.
  const Process process = given.at_feed(options.feed_per_tooth_m);
  const MachineLimits& mc = options.machine;
  const bool limits = std::isfinite(mc.max_power_w) || std::isfinite(mc.max_torque_n_m);
  if (limits && !(options.diameter_m > 0.0))
    throw InputError(std::string("recommend: a power or torque limit needs the ") +
                     (process.rotating_edges() ? "tool diameter (RecommendOptions::diameter_m)"
                                                                 : "workpiece diameter (RecommendOptions::diameter_m)"));
  Recommendation rec;
  std::string warning;
  rec.method = resolve_lobe_method(options.method, model, process, &warning);
  if (!warning.empty()) rec.warnings.push_back(warning);
  for (const std::string& n : ignored_feature_notes(find_lobe_method(rec.method), process)) rec.warnings.push_back(n);
  std::vector<std::string> model_warnings;
  const CutModel cm(process, options, model_warnings);
  if (options.diameter_m > 0.0)
    rec.warnings.insert(rec.warnings.end(), model_warnings.begin(), model_warnings.end());

  const double flute = options.flute_length_m.value_or(kInf);
  rec.search_depth_m = kRecommendSearchFactor * std::min(options.depth_max_m, flute) / options.safety;
  const auto solver = make_lobe_solver(rec.method, model, process, rec.search_depth_m);
  SpeedSearch s(*solver, mc.rpm_min, mc.rpm_max, options.speed_tolerance, options.threads);
  std::atomic<std::size_t> solves{0};
  s.on_solve = [&] {
    const double f = static_cast<double>(++solves) / static_cast<double>(kProgressSolvesPerProcess);
    if (options.progress) options.progress(std::min(f, kProgressCeiling));
  };

  std::optional<PartErrorCap> part_error;
  if (options.max_part_error_m)
    part_error.emplace(model, process, options.feed_per_tooth_m, *options.max_part_error_m);
  Ranking rk(s, cm, options, rec.search_depth_m, solver->depth_max_m(), part_error ? &*part_error : nullptr);
  // At low speed the lobes crowd (most of the scan's speeds, the dearest
  // solves) and remove little: the refinement, solved from the top down,
  // skips the speeds whose bound is below what the speeds solved so far
  // promise, and the optimum found is kept only if no skipped speed's bound
  // reaches it (else they are solved and the scan ranked again).
  if (options.skip_out_of_reach)
    s.refinement_floor = [&](const std::vector<double>& solved) { return rk.floor(solved); };
  s.scan();
  auto [best, ib] = rk.search();
  if (rk.skipped_could_beat(best)) {
    s.fill_skipped();
    std::tie(best, ib) = rk.search();
  }
  rec.skipped_solves = s.skipped().size();

  rec.spindle_rpm = best.rpm;
  rec.depth_m = best.depth;
  rec.limit = clip(s.at(best.rpm), rec.search_depth_m);
  rec.margin = rec.limit.depth_limit_m / rec.depth_m;
  rec.depth_stability_m = best.stab;
  rec.depth_power_m = best.power;
  rec.depth_torque_m = best.torque;
  rec.depth_cap_m = best.cap;
  rec.depth_flute_m = best.flute;
  rec.depth_part_error_m = best.part;
  add_part_quality(rec, model, process, options.feed_per_tooth_m);
  rec.pocket = make_pocket(s, best.rpm, rec.depth_m, rec.depth_m / options.safety);
  rec.pocket.limit = rec.limit;
  rec.pocket.worst_limit_m = best.worst;
  rec.pocket.worst_margin = best.margin;
  // The law at the recommended point itself (the numbers `check` and
  // `performance` give there).
  const MeanCut at = cm.at(rec.spindle_rpm, rec.depth_m);
  rec.force_n = at.tangential_force_n;  // F_c = K_c b f; milling the teeth's tangential forces
  rec.torque_n_m = at.torque_n_m;
  rec.power_w = at.power_w;
  rec.mrr_m3_per_s = at.removal_rate_m3_per_s;
  // Per unit diameter: turning b f π N/60; milling the section per unit D.
  rec.mrr_per_diameter_m2_per_s = cm.per_unit_diameter(rec.spindle_rpm, rec.depth_m).removal_rate_m3_per_s;
  add_bindings(rec, best, ib, rk, s.scan_speeds(), options);
  if (options.progress) options.progress(1.0);
  return rec;
}

std::string explain(const Recommendation& r, const RecommendOptions& o) {
  std::ostringstream os;
  os.setf(std::ios::fixed);
  auto f = [](double x, int d) {
    std::ostringstream s;
    s.setf(std::ios::fixed);
    s.precision(d);
    s << x;
    return s.str();
  };
  const double d_mm = r.depth_m * 1e3;
  os << "Recommended: " << f(r.spindle_rpm, 0) << " rev/min, depth " << f(d_mm, 3) << " mm (" << r.method
     << " lobes, feed " << f(o.feed_per_tooth_m * 1e3, 3) << " mm)\n";
  os << "Binding: ";
  for (std::size_t i = 0; i < r.binding.size(); ++i) {
    if (i) os << "; ";
    switch (r.binding[i]) {
      case Binding::kStability:
        // The cap is safety x the worst limit over the speed band (the limit
        // at the speed itself when the tolerance is 0).
        if (o.speed_tolerance > 0.0)
          os << "stability (depth = " << f(o.safety, 3) << " x the worst limit "
             << f(r.pocket.worst_limit_m * 1e3, 3) << " mm over the speed band +/-"
             << f(o.speed_tolerance * 100.0, 1) << " %; " << f(r.limit.depth_limit_m * 1e3, 3)
             << " mm at this speed)";
        else
          os << "stability (depth = " << f(o.safety, 3) << " x limit " << f(r.limit.depth_limit_m * 1e3, 3)
             << " mm at this speed)";
        break;
      case Binding::kPower:
        os << "spindle power (mean cutting power = " << f(o.machine.max_power_w * 1e-3, 3) << " kW limit)";
        break;
      case Binding::kTorque:
        os << "spindle torque (mean cutting torque = " << f(o.machine.max_torque_n_m, 2) << " N*m limit)";
        break;
      case Binding::kDepthMax: os << "the tool's maximum depth " << f(r.depth_cap_m * 1e3, 3) << " mm"; break;
      case Binding::kFluteLength:
        os << "the cutter's usable flute length " << f(r.depth_flute_m * 1e3, 3) << " mm";
        break;
      case Binding::kSurfaceError:
        os << "the part's tolerance (forced vibration: "
           << "part error " << f(r.part_error_m * 1e6, 2) << " um = "
           << f(*o.max_part_error_m * 1e6, 2) << " um limit)";
        break;
      case Binding::kSpeedRange:
        os << "speed range (at the machine's "
           << (r.spindle_rpm >= o.machine.rpm_max ? "maximum " : "minimum ") << f(r.spindle_rpm, 0)
           << " rev/min; more MRR lies beyond it)";
        break;
    }
  }
  os << "\n";
  const SpeedPocket& p = r.pocket;
  os << "Speed band +/-" << f(p.speed_tolerance * 100.0, 1) << " %: ";
  if (std::isfinite(p.worst_limit_m))
    os << "worst limit " << f(p.worst_limit_m * 1e3, 3) << " mm, worst margin " << f(p.worst_margin, 3);
  else
    os << "no chatter below " << f(r.search_depth_m * 1e3, 3) << " mm";
  os << "; stable pocket " << f(p.pocket_min_rpm, 0) << "-" << f(p.pocket_max_rpm, 0)
     << " rev/min (safety x limit >= depth)\n";
  if (r.limit.bounded())
    os << "Stability margin: " << f(r.margin, 3) << " (limit " << f(r.limit.depth_limit_m * 1e3, 3)
       << " mm / depth; chatter would start at " << f(r.limit.chatter_frequency_hz, 1) << " Hz, lobe "
       << r.limit.lobe << ")\n";
  else
    os << "Stability margin: no chatter below " << f(r.search_depth_m * 1e3, 3) << " mm at this speed\n";
  if (std::isfinite(r.mrr_m3_per_s)) {
    os << "MRR: " << f(r.mrr_m3_per_s * 6e7, 2) << " cm^3/min; mean power " << f(r.power_w * 1e-3, 3) << " kW";
    if (std::isfinite(o.machine.max_power_w)) os << " of " << f(o.machine.max_power_w * 1e-3, 3) << " kW";
    os << ", torque " << f(r.torque_n_m, 2) << " N*m";
    if (std::isfinite(o.machine.max_torque_n_m)) os << " of " << f(o.machine.max_torque_n_m, 2) << " N*m";
    os << "\n";
  } else {
    os << "MRR: " << f(r.mrr_per_diameter_m2_per_s * 6e7 * 1e-3, 4)
       << " cm^3/min per mm of diameter (give the diameter for MRR, power and torque)\n";
  }
  if (std::isfinite(r.part_error_m)) {
    os << "Part error (forced vibration, linear model): " << f(r.part_error_m * 1e6, 2) << " um";
    if (o.max_part_error_m) os << " of " << f(*o.max_part_error_m * 1e6, 2) << " um allowed";
    os << " (milling: |surface location error|; turning: diametral error), vibration "
       << f(r.peak_to_peak_m * 1e6, 2) << " um peak to peak\n";
  }
  for (const auto& w : r.warnings) os << "warning: " << w << "\n";
  return os.str();
}

}  // namespace chatter
