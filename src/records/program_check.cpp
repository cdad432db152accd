// `chatter program`, the solves (chatter/records/program.hpp): every
// sample's limit by the registry's method for its tool (one solve per
// distinct cut key, or per sample with the cache off), the cutting law's
// load per sample, each block's worst sample judged as `chatter point`
// judges it (report_point) with its forced part error, then the fixes.
#include <algorithm>
#include <cmath>
#include <atomic>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <set>
#include <string>

#include "chatter/cutting_law.hpp"
#include "chatter/error.hpp"
#include "chatter/forced.hpp"
#include "chatter/io/nc_program.hpp"
#include "chatter/operations.hpp"
#include "chatter/records.hpp"
#include "chatter/report.hpp"
#include "program_internal.hpp"

namespace chatter {
using namespace program_detail;
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The feed (mm per revolution) a turning block's regenerative side is
// linearised at: its own with Kienzle's law (Process::at_feed), else none (0:
// the limit does not depend on it).
double linearising_feed_mm(const ToolSetup& t, const Engaged& eng, const Sample& s) {
  return t.turning && t.tool->config.process.has_size_effect() ? eng.rows[s.row].feed : 0.0;
}

// The config of one cut: the tool's, with the engaged arc (milling) or the
// structure at the position and the block's feed (turning).
Config cut_config(const ToolSetup& t, const Sample& s, double feed_mm) {
  const Config& base = t.tool->config;
  if (t.turning) {
    Config c = base.position.empty() ? base : config_at_position(base, s.position_mm, "position_mm");
    if (feed_mm > 0.0) c.process = c.process.at_feed(feed_mm * 1e-3);
    return c;
  }
  Config c = base;
  MillingParameters mp = base.process.milling_parameters();
  const double step = kArcStepDeg * kPi / 180.0;
  const double en = s.arc_en() * step, ex = s.arc_ex() * step;
  if (t.flat) {
    // Every arc as data: the solvers read them through the Process.
    mp.engaged_arcs_rad.clear();
    for (const auto& [a, b] : s.arcs) mp.engaged_arcs_rad.emplace_back(a * step, b * step);
  } else if (s.arc_en() == 0 && s.arc_ex() == static_cast<int>(std::lround(180.0 / kArcStepDeg))) {
    mp.radial_immersion = 1.0;
  } else if (s.arc_en() == 0) {
    mp.direction = MillingDirection::kUp;
    mp.radial_immersion = 0.5 * (1.0 - std::cos(ex));
  } else {
    mp.direction = MillingDirection::kDown;
    mp.radial_immersion = 0.5 * (1.0 + std::cos(en));
  }
  c.process = Process::milling(mp);
  return c;
}

struct RowVerdict {
  PointReport point;
  double part_error_m = kNaN;
  bool no_chip = false;  ///< the cut's slices miss the stock's arc: no chip, a block in air
};

// The solves: one per distinct cut key with the cache (one per sample
// without), each by the registry's method for its tool.
struct Solves {
  std::vector<std::size_t> key_of;        ///< per sample: its solve
  std::vector<std::size_t> first_sample;  ///< per solve: the sample it was made for
  std::vector<Solved> solved;
};

// The deepest cut searched per tool: as `point`'s default, at least twice the deepest sample.
std::map<int, double> search_depths_mm(const Engaged& eng, const std::map<int, ToolSetup>& tools) {
  std::map<int, double> depth_max_mm;
  for (const Sample& s : eng.samples) {
    const int tool = eng.rows[s.row].tool;
    const Config& c = tools.at(tool).tool->config;
    double& d = depth_max_mm.try_emplace(tool, c.sweep.depth_max_mm.value_or(kDefaultSearchDepthMm)).first->second;
    d = std::max(d, 2.0 * s.depth_mm);
  }
  return depth_max_mm;
}

Solves key_samples(const Engaged& eng, const std::map<int, ToolSetup>& tools, bool cache) {
  Solves out;
  out.key_of.resize(eng.samples.size());
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < eng.samples.size(); ++i) {
    const Sample& s = eng.samples[i];
    const int tool = eng.rows[s.row].tool;
    const double feed = linearising_feed_mm(tools.at(tool), eng, s);
    const std::string k = cut_key(tool, s.rpm, s.arcs, s.position_mm) + (feed > 0.0 ? "|f" + std::to_string(feed) : "");
    const auto [it, fresh] = cache ? index.try_emplace(k, out.first_sample.size()) : std::pair{index.end(), true};
    out.key_of[i] = fresh ? out.first_sample.size() : it->second;
    if (fresh) out.first_sample.push_back(i);
  }
  return out;
}

void solve_keys(Solves& out, const Engaged& eng, const std::map<int, ToolSetup>& tools,
                const std::map<int, double>& depth_max_mm, const ProgramOptions& options, const std::function<void()>& tick) {
  out.solved.resize(out.first_sample.size());
  parallel_for(out.first_sample.size(), options.threads, [&](std::size_t k) {
    const Sample& s = eng.samples[out.first_sample[k]];
    const ToolSetup& t = tools.at(eng.rows[s.row].tool);
    Solved& sv = out.solved[k];
    sv.config = cut_config(t, s, linearising_feed_mm(t, eng, s));
    ConfiguredSolver c =
        configure_solver(kAutoMethod, sv.config, depth_max_mm.at(t.tool->number) * 1e-3, {}, ArgStyle::kFlag);
    sv.method = c.method;
    sv.solver = std::move(c.solver);
    sv.limit_m = sv.solver->limit_at(SpindleSpeed(s.rpm)).depth_limit_m;
    tick();
  });
}

// The part error of a stable cut (SLE in milling, diametral error in
// turning), m; NaN for a measured FRF (no forced response) or an unstable cut.
double part_error_m(const Solved& sv, double rpm, double depth_mm, double feed_mm) {
  ForcedSettings st;
  st.spindle_rpm = rpm;
  st.depth_m = depth_mm * 1e-3;
  st.feed_m = feed_mm * 1e-3;
  st.record_path = false;
  try {
    const ForcedResponse fr = ForcedResponseSolver(sv.config.model, sv.config.process).response(st);
    if (fr.stable) return fr.milling ? fr.surface_location_error_m : fr.diametral_error_m;
  } catch (const InputError&) {
    // measured FRFs: no forced response; the column stays empty
  }
  return kNaN;
}

// Per sample: the row's feed and peak load, and each row's worst sample
// (smallest margin; the first of equals). Returns the worst sample per row
// (`kNone` for a move in the air).
constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
std::vector<std::size_t> load_rows(Engaged& eng, const Solves& sv, const std::map<int, ToolSetup>& tools,
                                   const Toolpath& path, const Job& job, std::vector<std::string>& warnings) {
  std::vector<std::size_t> worst(eng.rows.size(), kNone);
  std::vector<double> worst_margin(eng.rows.size(), kInf);
  for (std::size_t i = 0; i < eng.samples.size(); ++i) {
    const Sample& s = eng.samples[i];
    const Solved& cut = sv.solved[sv.key_of[i]];
    const ToolSetup& t = tools.at(eng.rows[s.row].tool);
    ProgramRow& r = eng.rows[s.row];
    const ToolpathMove& m = path.moves[s.row];
    const double feed_mm = m.feed_per_rev ? m.feed / t.teeth : m.feed / (s.rpm * t.teeth);
    r.feed = feed_mm;
    const double margin = cut.limit_m / (s.depth_mm * 1e-3);
    if (worst[s.row] == kNone || margin < worst_margin[s.row]) {
      worst[s.row] = i;
      worst_margin[s.row] = margin;
    }
    const CuttingLawOptions lo = cutting_law_options(cut.config.process, cutting_coefficient(t.tool->config), warnings);
    double diameter_m = t.turning ? s.diameter_mm * 1e-3 : 2.0 * t.shape.radius_mm * 1e-3;
    if (!(diameter_m > 0.0)) diameter_m = kNaN;  // the centre: no cutting speed
    const MeanCut mc = CuttingLaw::of(cut.config.process, lo)->mean({s.rpm, s.depth_mm * 1e-3, feed_mm * 1e-3, diameter_m});
    r.power_kw = std::max(r.power_kw, mc.power_w * 1e-3);
    r.torque_nm = std::max(r.torque_nm, mc.torque_n_m);
    r.force_n = std::max(r.force_n, mc.tangential_force_n);
    r.removal_rate_mm3_per_s = std::max(r.removal_rate_mm3_per_s, mc.removal_rate_m3_per_s * 1e9);
    auto note = [&](bool on, const char* text) {
      if (on && std::find(r.notes.begin(), r.notes.end(), text) == r.notes.end()) r.notes.emplace_back(text);
    };
    if ((job.machine.max_power_kw && mc.power_w * 1e-3 > *job.machine.max_power_kw) ||
        (job.machine.max_torque_nm && mc.torque_n_m > *job.machine.max_torque_nm))
      r.overloaded = true;
    if ((job.machine.rpm_max && s.rpm > *job.machine.rpm_max) || (job.machine.rpm_min && s.rpm < *job.machine.rpm_min)) {
      r.overloaded = true;
      note(true, "spindle speed outside the machine's range");
    }
    note(s.facing, "facing: the depth of cut is axial, checked in the tool config's frame");
    note(s.plunge, "plunge: moving along Z, checked as a slot");
    note(s.split, "two engaged arcs: each solved as an arc of the cut (no part error: the wall is not defined)");
    note(s.widened, "arc widened to a wall for the cutter's profile");
  }
  return worst;
}

// Each cutting row's worst sample judged as `point` judges it, with the part
// error: one verdict per distinct (cut, depth, feed) with the cache.
std::vector<RowVerdict> judge_rows(const Engaged& eng, const Solves& sv, const std::vector<std::size_t>& worst,
                                   bool cache, const ProgramOptions& options, std::vector<std::size_t>& verdict_of,
                                   const std::function<void()>& tick) {
  std::vector<std::size_t> verdict_row;
  verdict_of.assign(eng.rows.size(), kNone);
  std::map<std::string, std::size_t> index;
  for (std::size_t r = 0; r < eng.rows.size(); ++r) {
    if (worst[r] == kNone) continue;
    const Sample& s = eng.samples[worst[r]];
    char extra[96];
    std::snprintf(extra, sizeof extra, "|%.17g|%.17g", s.depth_mm, eng.rows[r].feed);
    const std::string k = std::to_string(sv.key_of[worst[r]]) + extra;
    const auto [it, fresh] = cache ? index.try_emplace(k, verdict_row.size()) : std::pair{index.end(), true};
    verdict_of[r] = fresh ? verdict_row.size() : it->second;
    if (fresh) verdict_row.push_back(r);
  }
  std::vector<RowVerdict> verdicts(verdict_row.size());
  parallel_for(verdict_row.size(), options.threads, [&](std::size_t v) {
    const std::size_t r = verdict_row[v];
    const Sample& s = eng.samples[worst[r]];
    const Solved& cut = sv.solved[sv.key_of[worst[r]]];
    RowVerdict& out = verdicts[v];
    out.no_chip = !cut.config.process.no_chip_reason(s.depth_mm * 1e-3).empty();
    if (out.no_chip) return tick();
    out.point = report_point(*cut.solver, cut.config.process, s.rpm, s.depth_mm);
    if (out.point.stable && eng.rows[r].feed > 0.0) out.part_error_m = part_error_m(cut, s.rpm, s.depth_mm, eng.rows[r].feed);
    tick();
  });
  return verdicts;
}

// Turning: every sample's margin and diametral error along the bar (the
// plot's lower panel). The error is the forced response's for turning
// (static_deflection_turning, its one definition) where the sample is below
// its limit; the row's own column comes from the full forced response.
void along_the_bar(Engaged& eng, const Solves& sv) {
  for (std::size_t i = 0; i < eng.samples.size(); ++i) {
    const Sample& s = eng.samples[i];
    const Solved& cut = sv.solved[sv.key_of[i]];
    const double margin = cut.limit_m / (s.depth_mm * 1e-3), feed = eng.rows[s.row].feed;
    double error_um = kNaN;
    if (margin > 1.0 && feed > 0.0 && !cut.config.model.has_measured()) {
      try {
        error_um = static_deflection_turning(cut.config.model, cut.config.process, s.depth_mm * 1e-3, feed * 1e-3)
                       .diametral_error_m * 1e6;
      } catch (const InputError&) {
        // an oblique insert: no turning deflection model; the plot leaves a gap
      }
    }
    eng.rows[s.row].along_bar.push_back({s.position_mm, margin, error_um});
  }
}

// A cutting row's columns from its worst sample and verdict, and the summary.
void fill_row(ProgramRow& row, const Sample& s, const RowVerdict& v, const ToolpathMove& m, bool turning, double radius_mm) {
  const PointReport& p = v.point;
  row.air = false;
  row.spindle_rpm = s.rpm;
  row.depth_mm = s.depth_mm;
  if (turning) {
    row.position_mm = s.position_mm;
    row.diameter_mm = s.diameter_mm;
  } else {
    const double step = kArcStepDeg * kPi / 180.0;
    row.axial_depth_mm = s.depth_mm;
    row.entry_angle_deg = s.arc_en() * kArcStepDeg;
    row.exit_angle_deg = s.arc_ex() * kArcStepDeg;
    row.radial_depth_mm = 0.0;
    row.arcs_deg.clear();
    for (const auto& [en, ex] : s.arcs) {
      row.radial_depth_mm += radius_mm * (std::cos(en * step) - std::cos(ex * step));
      row.arcs_deg.emplace_back(en * kArcStepDeg, ex * kArcStepDeg);
    }
  }
  row.depth_limit_mm = p.limit.limit.depth_limit_m * 1e3;
  row.margin = p.margin;
  row.stable = p.stable;
  row.chatter_frequency_hz = p.limit.limit.chatter_frequency_hz;
  row.part_error_um = v.part_error_m * 1e6;
  const double minutes = m.feed_per_rev ? row.length_mm / (m.feed * s.rpm) : row.length_mm / m.feed;
  row.time_s = 60.0 * minutes;
}

}  // namespace

ProgramReport check_program(const Job& job, const Toolpath& path, const ProgramOptions& options) {
  ProgramReport report;
  report.program = path.source;
  report.job = job.source.string();
  report.turning = job.turning();
  report.warnings = job.warnings;
  std::map<int, ToolSetup> tools;
  for (const JobTool& t : job.tools) tools[t.number] = tool_setup(t, job.turning());
  Engaged eng = simulate_stock(job, path, tools);
  if (tools.size() == 1 && std::any_of(path.moves.begin(), path.moves.end(), [](const ToolpathMove& m) { return m.tool == 0; }))
    report.warnings.push_back(path.source + ": moves with no tool selected (no T and M6) are checked with the job's only tool, " +
                              std::to_string(tools.begin()->first));
  if (eng.samples.empty())
    throw InputError(path.source + ": the program never cuts the stock (" + std::to_string(path.moves.size()) +
                     " feed moves, all in the air): check [stock] in " + job.source.string() +
                     " against the program's coordinates");
  const bool cache = options.cache.value_or(job.cache);
  const std::map<int, double> depth_max_mm = search_depths_mm(eng, tools);
  for (const auto& [tool, d] : depth_max_mm) report.depth_max_mm.emplace_back(tool, d);
  Solves sv = key_samples(eng, tools, cache);
  std::atomic<std::size_t> done{0};
  // The work: the solves, then at most one verdict per row.
  const double total_work = static_cast<double>(sv.first_sample.size() + eng.rows.size());
  auto tick = [&] {
    if (options.progress) options.progress(static_cast<double>(++done) / total_work);
  };
  solve_keys(sv, eng, tools, depth_max_mm, options, tick);
  report.summary.solves = sv.first_sample.size();
  report.summary.cache_hits = eng.samples.size() - sv.first_sample.size();
  std::set<int> listed;
  for (std::size_t k = 0; k < sv.solved.size(); ++k) {
    const int tool = eng.rows[eng.samples[sv.first_sample[k]].row].tool;
    if (listed.insert(tool).second) report.methods.emplace_back(tool, sv.solved[k].method);
  }
  const std::vector<std::size_t> worst = load_rows(eng, sv, tools, path, job, report.warnings);
  std::vector<std::size_t> verdict_of;
  const std::vector<RowVerdict> verdicts = judge_rows(eng, sv, worst, cache, options, verdict_of, tick);
  if (report.turning) along_the_bar(eng, sv);
  ProgramSummary& sum = report.summary;
  sum.worst_margin = kInf;
  std::vector<ProgramRow>& rows = eng.rows;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    ProgramRow& row = rows[r];
    ++sum.blocks;
    if (worst[r] == kNone || verdicts[verdict_of[r]].no_chip) {
      ++sum.air_blocks;
      row.air = true;
      row.overloaded = false;
      row.spindle_rpm = block_rpm(path.moves[r], 1.0, job);
      row.depth_limit_mm = row.margin = row.chatter_frequency_hz = row.part_error_um = kNaN;
      continue;
    }
    const Sample& s = eng.samples[worst[r]];
    fill_row(row, s, verdicts[verdict_of[r]], path.moves[r], report.turning, tools.at(row.tool).shape.radius_mm);
    ++sum.cutting_blocks;
    sum.cutting_time_s += row.time_s;
    if (!row.stable) ++sum.unstable_blocks;
    if (row.overloaded) ++sum.overloaded_blocks;
    if (row.margin < sum.worst_margin || sum.worst_line == 0) sum.worst_line = row.line;
    sum.worst_margin = std::min(sum.worst_margin, row.margin);
    const Solved& cut = sv.solved[sv.key_of[worst[r]]];
    if (options.fix_speed && !row.stable) fix_speed(row, path.moves[r], cut, job);
    if (options.fix_feed && row.overloaded) {
      const ToolSetup& t = tools.at(row.tool);
      fix_feed(row, path.moves[r], cut, job, t.teeth, t.turning ? s.diameter_mm : 2.0 * t.shape.radius_mm, report.warnings);
    }
  }
  sum.removed_volume_mm3 = eng.removed_mm3;
  report.rows = std::move(rows);
  return report;
}

ProgramReport run_program(const std::filesystem::path& program, const Job& job, const ProgramOptions& options) {
  NcReadOptions nc;
  for (const JobTool& t : job.tools) nc.tool_diameters_mm[t.number] = t.config.process.compensation_diameter_m() * 1e3;
  return check_program(job, read_nc_program(program, nc), options);
}

}  // namespace chatter
