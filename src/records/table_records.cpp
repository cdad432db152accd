// The records of `chatter map` and `chatter frf` (chatter/records/lobes.hpp):
// the Floquet stability map and the receptance table, computed and written
// once for the CLI and Python.
#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/number_text.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/records/lobes.hpp"
#include "chatter/semi_discretization.hpp"

namespace chatter {

using nlohmann::json;

namespace {

// The largest map: speeds x depths (memory and time: ~1e6 sdm solves is hours).
constexpr long long kMaxMapPoints = 4'000'000;

}  // namespace

// ------------------------------------------------------------------ map

std::string map_method(const std::string& requested, ArgStyle style) {
  std::string floquet;
  for (const auto& m : solver_registry())
    if (m.kind == SolverKind::kFloquet && floquet.empty()) floquet = m.name;
  const std::string method = requested == kAutoMethod ? floquet : requested;
  if (floquet.empty() || method != floquet)
    throw InputError(arg_name(style, "method") + " " + requested + ": map needs " + arg_name(style, "method") + " " +
                     floquet);
  return method;
}

std::vector<double> map_depths_m(double depth_max_mm, int depth_points, std::size_t speeds, ArgStyle style) {
  if (depth_points < 2)
    throw InputError(arg_name(style, "depth_points") + " = " + std::to_string(depth_points) + ": must be >= 2");
  if (static_cast<long long>(speeds) * depth_points > kMaxMapPoints)
    throw InputError(arg_name(style, "rpm_points") + " x " + arg_name(style, "depth_points") + " = " +
                     std::to_string(speeds) + " x " + std::to_string(depth_points) + ": at most " +
                     std::to_string(kMaxMapPoints) + " grid points (memory and time); use fewer points or a smaller range");
  std::vector<double> depths(static_cast<std::size_t>(depth_points));
  for (int k = 0; k < depth_points; ++k) depths[static_cast<std::size_t>(k)] = depth_max_mm * 1e-3 * k / (depth_points - 1);
  return depths;
}

StabilityMapGrid stability_map(const SemiDiscretizationSolver& sdm, const std::vector<double>& speeds,
                               const std::vector<double>& depths, bool multiplier_types, unsigned threads,
                               const std::function<void(std::size_t, std::size_t)>& progress) {
  StabilityMapGrid grid;
  grid.spindle_rpm = speeds;
  grid.depth_m = depths;
  grid.spectral_radius.resize(speeds.size() * depths.size());
  const std::size_t total = multiplier_types ? 2 * speeds.size() : speeds.size();
  parallel_for(
      speeds.size(), threads,
      [&](std::size_t i) {
        const auto row = sdm.spectral_radius_map({speeds[i]}, depths);
        std::copy(row.begin(), row.end(), grid.spectral_radius.begin() + static_cast<std::ptrdiff_t>(i * depths.size()));
      },
      [&](std::size_t done) {
        if (progress) progress(done, total);
      });
  if (!multiplier_types) return grid;
  // Hopf or flip: the type of the dominant multiplier at every unstable point
  // (the stable points' types are never read).
  grid.multiplier_type.assign(grid.spectral_radius.size(), MultiplierType::kHopf);
  parallel_for(
      speeds.size(), threads,
      [&](std::size_t i) {
        for (std::size_t k = 0; k < depths.size(); ++k)
          if (grid.spectral_radius[i * depths.size() + k] >= 1.0)
            grid.multiplier_type[i * depths.size() + k] = sdm.analyse(speeds[i], depths[k]).type;
      },
      [&](std::size_t done) {
        if (progress) progress(speeds.size() + done, total);
      });
  return grid;
}

std::string stability_map_csv(const StabilityMapGrid& grid) {
  std::ostringstream os;
  os << "spindle_rpm,depth_mm,spectral_radius\n";
  const std::size_t nd = grid.depth_m.size();
  for (std::size_t i = 0; i < grid.spindle_rpm.size(); ++i)
    for (std::size_t k = 0; k < nd; ++k)
      os << table_number(grid.spindle_rpm[i]) << ',' << table_number(grid.depth_m[k] * 1e3) << ','
         << table_number(grid.spectral_radius[i * nd + k]) << '\n';
  return os.str();
}

std::size_t unstable_points(const StabilityMapGrid& grid) {
  std::size_t n = 0;
  for (double r : grid.spectral_radius) n += r >= 1.0;
  return n;
}

json stability_map_record(const StabilityMapGrid& grid, const SolverValues& solver_options,
                          const RecordSource& source) {
  json options = json::object();
  for (const auto& [k, v] : solver_options) options[k] = value_json(v);
  json j = {{"method", "sdm"},
            {"axes", "speed-axial"},
            {"config", source.config_path},
            {"name", source.config_name},
            {"warnings", source.warnings},
            {"notes", source.notes},
            {"rpm_min", grid.spindle_rpm.front()},
            {"rpm_max", grid.spindle_rpm.back()},
            {"rpm_points", grid.spindle_rpm.size()},
            {"depth_max_mm", grid.depth_m.back() * 1e3},
            {"depth_points", grid.depth_m.size()},
            {"grid_points", grid.spectral_radius.size()},
            {"unstable_points", unstable_points(grid)},
            {"solver_options", options}};
  double worst = 0.0;
  for (double r : grid.spectral_radius) worst = std::max(worst, r);
  j["max_spectral_radius"] = finite_or_null(worst);
  if (!grid.multiplier_type.empty()) {
    std::size_t flips = 0;
    for (std::size_t i = 0; i < grid.spectral_radius.size(); ++i)
      flips += grid.spectral_radius[i] >= 1.0 && grid.multiplier_type[i] == MultiplierType::kFlip;
    j["unstable_flip_points"] = flips;
  }
  if (source.position_mm) j["position_mm"] = *source.position_mm;
  return j;
}

// ------------------------------------------------------- radial x axial map

MapAxes parse_map_axes(const std::string& text, ArgStyle style) {
  if (text == "speed-axial") return MapAxes::kSpeedAxial;
  if (text == "radial-axial") return MapAxes::kRadialAxial;
  throw InputError(arg_name(style, "axes") + " '" + text +
                   "': unknown; use speed-axial (spindle speed x axial depth, the default) or radial-axial "
                   "(radial immersion x axial depth at one speed)");
}

std::vector<double> map_immersions(double min, double max, int points, std::size_t depths, ArgStyle style) {
  const std::string lo = arg_name(style, "immersion_min"), hi = arg_name(style, "immersion_max");
  if (!(std::isfinite(min) && min > 0.0 && min <= 1.0))
    throw InputError(lo + " = " + number_text(min) + ": must be in (0, 1] (radial immersion a_e/D)");
  if (!(std::isfinite(max) && max > 0.0 && max <= 1.0))
    throw InputError(hi + " = " + number_text(max) + ": must be in (0, 1] (radial immersion a_e/D; 1 = slot)");
  if (!(max > min)) throw InputError(hi + " = " + number_text(max) + ": must be > " + lo + " (" + number_text(min) + ")");
  if (points < 2)
    throw InputError(arg_name(style, "immersion_points") + " = " + std::to_string(points) + ": must be >= 2");
  if (static_cast<long long>(points) * static_cast<long long>(depths) > kMaxMapPoints)
    throw InputError(arg_name(style, "immersion_points") + " x " + arg_name(style, "depth_points") + " = " +
                     std::to_string(points) + " x " + std::to_string(depths) + ": at most " +
                     std::to_string(kMaxMapPoints) + " grid points (memory and time); use fewer points");
  std::vector<double> v(static_cast<std::size_t>(points));
  for (int i = 0; i < points; ++i) v[static_cast<std::size_t>(i)] = min + (max - min) * i / (points - 1);
  v.back() = max;
  return v;
}

RadialStabilityMapGrid radial_stability_map(const Process& process, double spindle_rpm,
                                            const std::vector<double>& immersions, const std::vector<double>& depths,
                                            const ProcessSolverFactory& make_solver, bool multiplier_types,
                                            unsigned threads,
                                            const std::function<void(std::size_t, std::size_t)>& progress) {
  if (!process.rotating_edges())
    throw InputError("the radial x axial map needs a milling process (turning has no radial immersion)");
  RadialStabilityMapGrid grid;
  grid.spindle_rpm = spindle_rpm;
  grid.radial_immersion = immersions;
  grid.tool_diameter_m = process.milling_parameters().tool_diameter_m;
  grid.depth_m = depths;
  const std::size_t ni = immersions.size(), nd = depths.size();
  grid.spectral_radius.resize(ni * nd);
  grid.limit.resize(ni);
  if (multiplier_types) grid.multiplier_type.assign(ni * nd, MultiplierType::kHopf);
  std::vector<std::string> errors(ni);
  parallel_for(
      ni, threads,
      [&](std::size_t i) {
        MillingParameters p = process.milling_parameters();
        p.radial_immersion = immersions[i];
        Process at = Process::milling(p);
        at.set_speed_variation(process.speed_variation());  // the config's modulation, if any
        const std::unique_ptr<LobeSolver> solver = make_solver(at);
        const auto* sdm = dynamic_cast<const SemiDiscretizationSolver*>(solver.get());
        if (!sdm) {
          errors[i] = "the radial x axial map needs the Floquet (sdm) solver";
          return;
        }
        const auto col = sdm->spectral_radius_map({spindle_rpm}, depths);
        std::copy(col.begin(), col.end(), grid.spectral_radius.begin() + static_cast<std::ptrdiff_t>(i * nd));
        grid.limit[i] = sdm->limit_at(SpindleSpeed(spindle_rpm));
        if (multiplier_types)
          for (std::size_t k = 0; k < nd; ++k)
            if (grid.spectral_radius[i * nd + k] >= 1.0)
              grid.multiplier_type[i * nd + k] = sdm->analyse(spindle_rpm, depths[k]).type;
      },
      [&](std::size_t done) {
        if (progress) progress(done, ni);
      });
  for (const std::string& e : errors)
    if (!e.empty()) throw InputError(e);
  return grid;
}

std::string radial_map_csv(const RadialStabilityMapGrid& grid) {
  std::ostringstream os;
  const bool mm = grid.tool_diameter_m > 0.0;
  os << "radial_immersion," << (mm ? "radial_depth_mm," : "") << "depth_mm,spectral_radius,depth_limit_mm\n";
  const std::size_t nd = grid.depth_m.size();
  for (std::size_t i = 0; i < grid.radial_immersion.size(); ++i) {
    const double e = grid.radial_immersion[i];
    for (std::size_t k = 0; k < nd; ++k) {
      os << table_number(e) << ',';
      if (mm) os << table_number(e * grid.tool_diameter_m * 1e3) << ',';
      os << table_number(grid.depth_m[k] * 1e3) << ',' << table_number(grid.spectral_radius[i * nd + k]) << ','
         << table_number(grid.limit[i].depth_limit_m * 1e3) << '\n';
    }
  }
  return os.str();
}

json radial_map_record(const RadialStabilityMapGrid& grid, const SolverValues& solver_options,
                       const RecordSource& source) {
  json options = json::object();
  for (const auto& [k, v] : solver_options) options[k] = value_json(v);
  std::size_t unstable = 0;
  double worst = 0.0;
  for (double r : grid.spectral_radius) {
    unstable += r >= 1.0;
    worst = std::max(worst, r);
  }
  const bool mm = grid.tool_diameter_m > 0.0;
  json boundary = json::array();
  for (std::size_t i = 0; i < grid.radial_immersion.size(); ++i) {
    const StabilityLimit& l = grid.limit[i];
    const double e = grid.radial_immersion[i];
    boundary.push_back({{"radial_immersion", e},
                        {"radial_depth_mm", mm ? json(e * grid.tool_diameter_m * 1e3) : json(nullptr)},
                        {"depth_limit_mm", finite_or_null(l.depth_limit_m * 1e3)},
                        {"chatter_frequency_hz", finite_or_null(l.chatter_frequency_hz)},
                        {"lobe", l.lobe}});
  }
  json j = {{"method", "sdm"},
            {"axes", "radial-axial"},
            {"config", source.config_path},
            {"name", source.config_name},
            {"warnings", source.warnings},
            {"notes", source.notes},
            {"spindle_rpm", grid.spindle_rpm},
            {"immersion_min", grid.radial_immersion.front()},
            {"immersion_max", grid.radial_immersion.back()},
            {"immersion_points", grid.radial_immersion.size()},
            {"tool_diameter_mm", mm ? json(grid.tool_diameter_m * 1e3) : json(nullptr)},
            {"depth_max_mm", grid.depth_m.back() * 1e3},
            {"depth_points", grid.depth_m.size()},
            {"grid_points", grid.spectral_radius.size()},
            {"unstable_points", unstable},
            {"max_spectral_radius", finite_or_null(worst)},
            {"boundary", boundary},
            {"solver_options", options}};
  if (!grid.multiplier_type.empty()) {
    std::size_t flips = 0;
    for (std::size_t i = 0; i < grid.spectral_radius.size(); ++i)
      flips += grid.spectral_radius[i] >= 1.0 && grid.multiplier_type[i] == MultiplierType::kFlip;
    j["unstable_flip_points"] = flips;
  }
  if (source.position_mm) j["position_mm"] = *source.position_mm;
  return j;
}

// ------------------------------------------------------------------ frf

std::vector<double> FrfGrid::frequencies_hz() const {
  std::vector<double> f(static_cast<std::size_t>(points));
  for (int i = 0; i < points; ++i) {
    const double t = static_cast<double>(i) / (points - 1);
    f[static_cast<std::size_t>(i)] = log ? fmin_hz * std::pow(fmax_hz / fmin_hz, t) : fmin_hz + (fmax_hz - fmin_hz) * t;
  }
  return f;
}

FrfGrid frf_grid(const StructuralModel& model, std::optional<double> fmin_hz, std::optional<double> fmax_hz,
                 int points, bool log, ArgStyle style) {
  FrfGrid g;
  g.fmin_hz = fmin_hz.value_or(0.5 * model.min_omega() / (2 * std::numbers::pi));
  g.fmax_hz = fmax_hz.value_or(2.0 * model.max_omega() / (2 * std::numbers::pi));
  g.points = points;
  g.log = log;
  const std::string lo = arg_name(style, "fmin"), hi = arg_name(style, "fmax");
  if (!(std::isfinite(g.fmin_hz) && (log ? g.fmin_hz > 0.0 : g.fmin_hz >= 0.0)))
    throw InputError(lo + " = " + number_text(g.fmin_hz) +
                     (log ? ": must be > 0 Hz with " + arg_name(style, "log") : std::string(": must be >= 0 Hz")));
  if (!(std::isfinite(g.fmax_hz) && g.fmax_hz > g.fmin_hz))
    throw InputError(hi + " = " + number_text(g.fmax_hz) + ": must be > " + lo + " (" + number_text(g.fmin_hz) + ")");
  if (points < 2) throw InputError(arg_name(style, "points") + " = " + std::to_string(points) + ": must be >= 2");
  return g;
}

NamedColumns receptance_table(const StructuralModel& model, const FrfGrid& grid) {
  NamedColumns t;
  t.names.push_back("frequency_hz");
  for (const char* body : {"tool", "workpiece", "relative"})
    for (const char* term : {"xx", "xy", "yy"})
      for (const char* part : {"real", "imag"})
        t.names.push_back(std::string(body) + "_" + term + "_" + part + "_m_per_n");
  t.columns.assign(t.names.size(), {});
  const std::vector<double> f = grid.frequencies_hz();
  for (auto& c : t.columns) c.reserve(f.size());
  for (const double hz : f) {
    const double w = 2 * std::numbers::pi * hz;
    std::size_t c = 0;
    t.columns[c++].push_back(hz);
    const Matrix2c gt = model.tool.receptance(w), gw = model.workpiece.receptance(w);
    const Matrix2c gr = gt + gw;
    for (const Matrix2c* g : {&gt, &gw, &gr})
      for (auto [r, k] : {std::pair{0, 0}, std::pair{0, 1}, std::pair{1, 1}}) {
        t.columns[c++].push_back((*g)(r, k).real());
        t.columns[c++].push_back((*g)(r, k).imag());
      }
  }
  return t;
}

std::string named_columns_csv(const NamedColumns& t) {
  std::ostringstream os;
  for (std::size_t c = 0; c < t.names.size(); ++c) os << (c ? "," : "") << t.names[c];
  os << '\n';
  const std::size_t n = t.columns.empty() ? 0 : t.columns.front().size();
  char buf[40];
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t c = 0; c < t.columns.size(); ++c) {
      // "%.10g" (to_chars with a precision is that conversion), faster.
      char* p = buf;
      if (c) *p++ = ',';
      p = std::to_chars(p, buf + sizeof buf, t.columns[c][i], std::chars_format::general, 10).ptr;
      os.write(buf, p - buf);
    }
    os << '\n';
  }
  return os.str();
}

// ------------------------------------------------- the tables as columns (Python)

namespace {

// The grids of a map: spectral_radius and, when asked, multiplier_type
// ("" where ρ < 1: the type of a stable point is not computed).
void add_map_grids(ColumnRecord& out, const std::vector<double>& rho, const std::vector<MultiplierType>& types,
                   std::size_t cols, bool multiplier_types) {
  out.columns.emplace_back("spectral_radius", rho, cols);
  if (!multiplier_types) return;
  std::vector<std::string> cells;
  cells.reserve(rho.size());
  for (std::size_t i = 0; i < rho.size(); ++i) cells.push_back(rho[i] >= 1.0 ? to_string(types.at(i)) : std::string());
  out.columns.emplace_back("multiplier_type", std::move(cells), cols);
}

}  // namespace

ColumnRecord stability_map_columns(const StabilityMapGrid& grid, const SolverValues& solver_options,
                                   const RecordSource& source, bool multiplier_types) {
  ColumnRecord out;
  out.fields = stability_map_record(grid, solver_options, source);
  out.columns = {{"spindle_rpm", grid.spindle_rpm}, {"depth_mm", scaled(grid.depth_m, 1e3)}};
  add_map_grids(out, grid.spectral_radius, grid.multiplier_type, grid.depth_m.size(), multiplier_types);
  return out;
}

ColumnRecord radial_map_columns(const RadialStabilityMapGrid& grid, const SolverValues& solver_options,
                                const RecordSource& source, bool multiplier_types) {
  ColumnRecord out;
  out.fields = radial_map_record(grid, solver_options, source);
  out.columns.emplace_back("radial_immersion", grid.radial_immersion);
  if (grid.tool_diameter_m > 0.0) {
    std::vector<double> ae;
    for (const double e : grid.radial_immersion) ae.push_back(e * grid.tool_diameter_m * 1e3);
    out.columns.emplace_back("radial_depth_mm", std::move(ae));
  }
  std::vector<double> limit_mm, freq;
  for (const StabilityLimit& l : grid.limit) {
    limit_mm.push_back(l.depth_limit_m * 1e3);  // +inf where unbounded
    freq.push_back(l.chatter_frequency_hz);     // NaN there
  }
  out.columns.emplace_back("depth_mm", scaled(grid.depth_m, 1e3));
  out.columns.emplace_back("depth_limit_mm", std::move(limit_mm));
  out.columns.emplace_back("chatter_frequency_hz", std::move(freq));
  add_map_grids(out, grid.spectral_radius, grid.multiplier_type, grid.depth_m.size(), multiplier_types);
  return out;
}

ColumnRecord receptance_columns(const NamedColumns& t, const RecordSource& source) {
  ColumnRecord out;
  out.fields = {{"name", source.config_name}, {"warnings", source.warnings}};
  if (source.position_mm) out.fields["position_mm"] = *source.position_mm;
  for (std::size_t c = 0; c < t.names.size(); ++c) out.columns.emplace_back(t.names[c], t.columns[c]);
  return out;
}

}  // namespace chatter
