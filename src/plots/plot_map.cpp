// Plots through gnuplot: Floquet stability maps (speed x depth and radial x axial) with the rho = 1 contour.
// The shared plumbing is plot_kit.hpp (plot.cpp); docs/plots.md shows each plot.
#include "chatter/io/plot.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <iterator>
#include <numbers>
#include <sstream>
#include <system_error>
#include <utility>

#include "chatter/io/table_writer.hpp"
#include "chatter/solvers.hpp"
#include "plot_kit.hpp"

namespace chatter {

namespace fs = std::filesystem;
using namespace plot_kit;

// ---------------------------------------------------------------------------
// Floquet stability map

namespace {

// The colour scale of the map (the contour colours: plot_kit.hpp).
constexpr const char* kStableKey = "#6fa3d2";   // a stable colour of the palette, for the key
constexpr const char* kChatterKey = "#f0804a";  // an unstable one

// One piece of the ρ = 1 contour: a polyline along which the dominant
// multiplier on the unstable side has one type (-1 = not known).
struct ContourPiece {
  std::vector<std::pair<double, double>> points;  // (rev/min, mm)
  int type = -1;
};

// A segment of the contour inside one cell: between the crossings on edges
// e0 and e1, with the multiplier type on its unstable side.
struct Segment {
  std::size_t e0, e1;
  int type;
};

// Chain the segments into polylines through their shared edges (point:
// each edge's crossing, at_edge: the two segments at each edge, -1 if none):
// open chains from their ends first, then loops; a piece ends where the
// type changes.
std::vector<ContourPiece> chain(const std::vector<Segment>& segs, const std::vector<std::pair<double, double>>& point,
                                const std::vector<std::array<int, 2>>& at_edge) {
  std::vector<char> used(segs.size(), 0);
  std::vector<ContourPiece> pieces;
  auto walk = [&](int s, std::size_t start_edge) {
    ContourPiece piece;
    piece.type = segs[static_cast<std::size_t>(s)].type;
    piece.points.push_back(point[start_edge]);
    std::size_t edge = start_edge;
    while (s >= 0 && !used[static_cast<std::size_t>(s)]) {
      const Segment& g = segs[static_cast<std::size_t>(s)];
      used[static_cast<std::size_t>(s)] = 1;
      if (g.type != piece.type) {  // a new piece from the shared point
        const auto last = piece.points.back();
        pieces.push_back(std::move(piece));
        piece = ContourPiece{{last}, g.type};
      }
      edge = g.e0 == edge ? g.e1 : g.e0;
      piece.points.push_back(point[edge]);
      const auto& both = at_edge[edge];
      s = both[0] == s ? both[1] : both[0];
    }
    pieces.push_back(std::move(piece));
  };
  for (std::size_t s = 0; s < segs.size(); ++s)
    for (std::size_t e : {segs[s].e0, segs[s].e1})
      if (!used[s] && at_edge[e][1] < 0) walk(static_cast<int>(s), e);
  for (std::size_t s = 0; s < segs.size(); ++s)
    if (!used[s]) walk(static_cast<int>(s), segs[s].e0);
  return pieces;
}

// The ρ = 1 contour of the grid by marching squares on ln ρ (linear
// interpolation along each cell edge; saddle cells resolved by the mean of
// the four corners), chained into polylines and split where the type of the
// dominant multiplier on the unstable side changes.
std::vector<ContourPiece> unit_contour(const StabilityMapGrid& m) {
  const std::size_t n = m.spindle_rpm.size(), k = m.depth_m.size();
  const bool typed = !m.multiplier_type.empty();
  auto at = [&](std::size_t i, std::size_t j) { return i * k + j; };
  auto f = [&](std::size_t p) { return std::log(std::max(m.spectral_radius[p], 1e-300)); };
  auto unstable = [&](std::size_t p) { return m.spectral_radius[p] >= 1.0; };

  // Edge ids: horizontal (i,j)-(i+1,j) first, then vertical (i,j)-(i,j+1).
  const std::size_t n_h = (n - 1) * k;
  auto h_edge = [&](std::size_t i, std::size_t j) { return i * k + j; };
  auto v_edge = [&](std::size_t i, std::size_t j) { return n_h + i * (k - 1) + j; };
  const std::size_t n_edges = n_h + n * (k - 1);
  // Crossing point of an edge (between grid points a and b, one unstable).
  auto crossing = [&](std::size_t a, std::size_t b) {
    const double fa = f(a), fb = f(b);
    const double t = std::clamp(fa / (fa - fb), 0.0, 1.0);
    const double xa = m.spindle_rpm[a / k], xb = m.spindle_rpm[b / k];
    const double ya = m.depth_m[a % k] * 1e3, yb = m.depth_m[b % k] * 1e3;
    return std::make_pair(xa + t * (xb - xa), ya + t * (yb - ya));
  };

  std::vector<Segment> segs;
  std::vector<std::pair<double, double>> point(n_edges);
  std::vector<std::array<int, 2>> at_edge(n_edges, {-1, -1});
  auto add_segment = [&](std::size_t e0, std::size_t e1, int type) {
    const int id = static_cast<int>(segs.size());
    segs.push_back({e0, e1, type});
    for (std::size_t e : {e0, e1}) (at_edge[e][0] < 0 ? at_edge[e][0] : at_edge[e][1]) = id;
  };
  for (std::size_t i = 0; i + 1 < n; ++i)
    for (std::size_t j = 0; j + 1 < k; ++j) {
      const std::size_t c[4] = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
      // Edge q joins corners q and q+1 (mod 4).
      const std::size_t e[4] = {h_edge(i, j), v_edge(i + 1, j), h_edge(i, j + 1), v_edge(i, j)};
      bool u[4];
      for (int q = 0; q < 4; ++q) u[q] = unstable(c[q]);
      int crossings = 0;
      for (int q = 0; q < 4; ++q)
        if (u[q] != u[(q + 1) % 4]) {
          point[e[q]] = crossing(c[q], c[(q + 1) % 4]);
          ++crossings;
        }
      if (crossings == 0) continue;
      // The type on the unstable side: that of the least unstable of the
      // given corners (the one nearest the crossing).
      auto type_of = [&](std::initializer_list<int> corners) {
        if (!typed) return -1;
        int best = -1;
        for (int q : corners)
          if (u[q] && (best < 0 || m.spectral_radius[c[q]] < m.spectral_radius[c[best]])) best = q;
        return best < 0 ? -1 : static_cast<int>(m.multiplier_type[c[best]]);
      };
      if (crossings == 2) {
        int a = -1, b = -1;
        for (int q = 0; q < 4; ++q)
          if (u[q] != u[(q + 1) % 4]) (a < 0 ? a : b) = q;
        add_segment(e[a], e[b], type_of({0, 1, 2, 3}));
      } else {  // saddle: the mean of the corners decides which pairs connect
        const double centre = (f(c[0]) + f(c[1]) + f(c[2]) + f(c[3])) / 4.0;
        const bool centre_unstable = centre >= 0.0;
        for (int q = 0; q < 4; ++q) {
          if (u[q] == centre_unstable) continue;  // cut off the corners unlike the centre
          const int prev = (q + 3) % 4, next = (q + 1) % 4;
          add_segment(e[prev], e[q], u[q] ? type_of({q}) : type_of({prev, next}));
        }
      }
    }

  return chain(segs, point, at_edge);
}

// Colour-box tics for the clip value R (a round list inside (1/R, R)).
std::vector<double> map_tics(double r) {
  if (r <= 1.5) return {0.8, 0.9, 1.0, 1.1, 1.25};
  if (r <= 2.0) return {0.7, 0.8, 1.0, 1.25, 1.5};
  if (r <= 3.0) return {0.5, 0.7, 1.0, 1.5, 2.0};
  if (r <= 5.0) return {0.3, 0.5, 1.0, 2.0, 3.0};
  return {0.2, 0.5, 1.0, 2.0, 5.0};
}

bool strictly_increasing(const std::vector<double>& v) {
  for (std::size_t i = 1; i < v.size(); ++i)
    if (!(v[i] > v[i - 1])) return false;
  return true;
}

}  // namespace

namespace {

// What the map's x values are (map.spindle_rpm holds them): spindle speed
// for the speed x depth map, radial depth for the radial x axial one.
struct MapXAxis {
  std::string label = "spindle speed (rev/min)";  // axis title, with the unit
  std::string column = "spindle_rpm";             // .dat column name, with the unit
  std::string plural = "spindle speeds";          // in messages and the .dat header
  std::string y_label = "depth of cut (mm)";
  int digits = 10;                                 // of the range in the script
};

// Refuses a grid the map cannot draw, naming the plot and the rule.
void check_map(const Target& t, const StabilityMapGrid& map, const MapXAxis& xaxis,
               const std::vector<double>& limit_depth_m) {
  const std::size_t n = map.spindle_rpm.size(), k = map.depth_m.size();
  const std::string where = t.label + ": stability map: ";
  if (n < 2 || k < 2)
    throw InputError(where + "needs >= 2 " + xaxis.plural + " and >= 2 depths (got " + std::to_string(n) + " x " +
                     std::to_string(k) + ")");
  for (double r : map.spindle_rpm)
    if (!(std::isfinite(r) && r > 0.0)) throw InputError(where + xaxis.plural + " must be finite and > 0");
  for (double d : map.depth_m)
    if (!(std::isfinite(d) && d >= 0.0)) throw InputError(where + "depths must be finite and >= 0");
  if (!strictly_increasing(map.spindle_rpm) || !strictly_increasing(map.depth_m))
    throw InputError(where + xaxis.plural + " and depths must be strictly increasing");
  if (!limit_depth_m.empty() && limit_depth_m.size() != n)
    throw InputError(where + std::to_string(limit_depth_m.size()) + " depth limits for " + std::to_string(n) + " " +
                     xaxis.plural);
  if (map.spectral_radius.size() != n * k)
    throw InputError(where + std::to_string(map.spectral_radius.size()) + " spectral radii for " +
                     std::to_string(n) + " x " + std::to_string(k) + " grid points");
  for (double r : map.spectral_radius)
    if (!(std::isfinite(r) && r >= 0.0)) throw InputError(where + "spectral radii must be finite and >= 0");
  const bool typed = !map.multiplier_type.empty();
  if (typed && map.multiplier_type.size() != n * k)
    throw InputError(where + std::to_string(map.multiplier_type.size()) + " multiplier types for " +
                     std::to_string(n * k) + " grid points");
}

// Colour clip R (ρ from 1/R to R, centred on 1): the smallest of a few
// round values covering 90 % of |ln ρ|.
double colour_clip(const StabilityMapGrid& map) {
  std::vector<double> spread;
  spread.reserve(map.spectral_radius.size());
  for (double r : map.spectral_radius) spread.push_back(std::abs(std::log(std::max(r, 1e-300))));
  const auto q90 = spread.begin() + static_cast<std::ptrdiff_t>((spread.size() - 1) * 9 / 10);
  std::nth_element(spread.begin(), q90, spread.end());
  for (double r : {1.5, 2.0, 3.0, 5.0, 10.0})
    if (std::log(r) >= *q90) return r;
  return 10.0;
}

// The .dat file of the map: the grid (index 0), the ρ = 1 contour (1), the
// flip/fold marks (2) and the searched limits (3); with the counts the
// script needs.
struct MapData {
  std::string text;
  std::size_t marks[3] = {0, 0, 0};  // per multiplier type
  std::size_t limit_points = 0;
};

MapData map_data(const std::string& title, const StabilityMapGrid& map, const MapXAxis& xaxis,
                 const std::vector<ContourPiece>& contour, const std::vector<double>& limit_depth_m) {
  const std::size_t n = map.spindle_rpm.size(), k = map.depth_m.size();
  const bool typed = !map.multiplier_type.empty();
  MapData d;
  std::ostringstream dat;
  dat << "# " << one_line(title) << ": Floquet spectral radius map (chatter " << version() << ")\n"
      << "# " << n << " " << xaxis.plural << " x " << k << " depths; rho < 1 stable, rho >= 1 chatter.\n"
      << "# Missing values are '?' (gnuplot: set datafile missing '?').\n\n"
      << "# index 0: the grid, one block per " << xaxis.column << " value (blocks separated by one blank line);\n"
      << "# 7 significant digits.\n"
      << "# multiplier_type: type of the dominant multiplier (hopf, flip, fold) where rho >= 1, else '?'.\n"
      << "# " << xaxis.column << " depth_mm spectral_radius multiplier_type\n";
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) dat << '\n';
    for (std::size_t j = 0; j < k; ++j) {
      const std::size_t p = i * k + j;
      const double r = map.spectral_radius[p];
      dat << num(map.spindle_rpm[i], 7) << ' ' << num(map.depth_m[j] * 1e3, 7) << ' ' << num(r, 7) << ' '
          << (typed && r >= 1.0 ? type_word(map.multiplier_type[p]) : "?") << '\n';
    }
  }
  dat << "\n\n# index 1: the rho = 1 contour (linear interpolation of ln rho along the grid edges), one block\n"
      << "# per piece; multiplier_type: the type on the unstable side (hopf, flip, fold; '?' if not given).\n"
      << "# " << xaxis.column << " depth_mm multiplier_type\n";
  for (std::size_t c = 0; c < contour.size(); ++c) {
    if (c > 0) dat << '\n';
    const char* word = contour[c].type < 0 ? "?" : type_word(static_cast<MultiplierType>(contour[c].type));
    for (const auto& [x, y] : contour[c].points) dat << num(x, 7) << ' ' << num(y, 7) << ' ' << word << '\n';
  }
  // Marks on the unstable points where flip or fold dominates, thinned to a
  // regular subset so that they read as a hatch.
  const std::size_t si = std::max<std::size_t>(1, (n + 39) / 40), sj = std::max<std::size_t>(1, (k + 24) / 25);
  dat << "\n\n# index 2: marks on unstable grid points where the dominant multiplier is flip or fold\n"
      << "# (every " << si << " speed(s) and " << sj << " depth(s))\n"
      << "# " << xaxis.column << " depth_mm multiplier_type\n";
    if (typed)
    for (std::size_t i = si / 2; i < n; i += si)
      for (std::size_t j = sj / 2; j < k; j += sj) {
        const std::size_t p = i * k + j;
        if (map.spectral_radius[p] < 1.0 || map.multiplier_type[p] == MultiplierType::kHopf) continue;
        dat << num(map.spindle_rpm[i]) << ' ' << num(map.depth_m[j] * 1e3) << ' '
            << type_word(map.multiplier_type[p]) << '\n';
        ++d.marks[static_cast<int>(map.multiplier_type[p])];
      }

  if (!limit_depth_m.empty()) {
    dat << "\n\n# index 3: the depth limit searched at each " << xaxis.column
        << " (the limit search of the lobe table; none where no limit below the depths searched)\n"
        << "# " << xaxis.column << " depth_limit_mm\n";
    for (std::size_t i = 0; i < n; ++i)
      if (std::isfinite(limit_depth_m[i]) && limit_depth_m[i] * 1e3 <= map.depth_m.back() * 1e3) {
        dat << num(map.spindle_rpm[i], 7) << ' ' << num(limit_depth_m[i] * 1e3, 7) << '\n';
        ++d.limit_points;
      }
    if (d.limit_points == 0) dat << "? ?\n";  // gnuplot needs a block to read
  }
  d.text = dat.str();
  return d;
}

// The plot's clauses after the map and its key: each contour piece by type
// (a white casing under the coloured line, so that it reads on every colour
// of the map), the flip/fold marks and the searched limits.
void plot_clauses(std::ostringstream& gp, const bool (&contour_type)[4], const MapData& data) {
  struct Kind {
    int index;
    const char* word;
    const char* colour;
    const char* dash;
    const char* line_title;
    const char* mark_title;
    int point_type;
  };
  const Kind kinds[3] = {
      {0, "hopf", "c_hopf", "", "ρ = 1, Hopf (complex μ)", "", 0},
      {1, "flip", "c_flip", " dt (5,3)", "ρ = 1, flip (μ = −1)", "flip dominates (μ ≈ −1)", 2},
      {2, "fold", "c_fold", " dt (2,2)", "ρ = 1, fold (μ = +1)", "fold dominates (μ ≈ +1)", 6},
  };
  auto contour_clause = [&](const std::string& filter, const std::string& colour, const std::string& dash,
                            const std::string& line_title) {
    gp << ", \\\n  data index 1 using 1:" << filter << " with lines lw 5.5 lc rgb '#50ffffff' notitle"
       << ", \\\n  data index 1 using 1:" << filter << " with lines lw 2.6" << dash << " lc rgb " << colour
       << " title " << quote(line_title);
  };
  if (contour_type[3]) contour_clause("2", "c_hopf", "", "ρ = 1 (stability boundary)");
  for (const Kind& kd : kinds)
    if (contour_type[kd.index])
      contour_clause("(strcol(3) eq '" + std::string(kd.word) + "' ? $2 : NaN)", kd.colour, kd.dash, kd.line_title);
  for (const Kind& kd : kinds)
    if (kd.index > 0 && data.marks[kd.index] > 0)
      gp << ", \\\n  data index 2 using 1:(strcol(3) eq '" << kd.word << "' ? $2 : NaN) with points pt "
         << kd.point_type << " ps 0.7 lw 1.5 lc rgb " << kd.colour << " title " << quote(kd.mark_title);
  if (data.limit_points > 0)
    gp << ", \\\n  data index 3 using 1:2 with points pt 7 ps 0.9 lc rgb '#ffffff' notitle"
       << ", \\\n  data index 3 using 1:2 with points pt 7 ps 0.55 lc rgb '#000000' title "
       << quote("limit search");
}

// `limit_depth_m` (empty, or one per x value: m, +inf = none) is drawn as
// points over the map: the depth limit searched at each x.
void draw_stability_map(const Target& t, const std::string& title, const StabilityMapGrid& map,
                        const PlotOptions& options, const MapXAxis& xaxis = {},
                        const std::vector<double>& limit_depth_m = {}) {
  check_map(t, map, xaxis, limit_depth_m);
  const double rho_clip = colour_clip(map);

  std::size_t unstable = 0;
  for (double r : map.spectral_radius) unstable += r >= 1.0;
  const std::vector<ContourPiece> contour = unit_contour(map);
  bool contour_type[4] = {false, false, false, false};  // hopf, flip, fold, unknown
  for (const auto& c : contour) contour_type[c.type < 0 ? 3 : c.type] = true;

  const MapData data = map_data(title, map, xaxis, contour, limit_depth_m);

  // --- script ---
  std::ostringstream gp;
  gp << script_preamble(t, options, "Floquet stability map (spectral radius)")
     << "# Colour scale: spectral radius from 1/rho_clip to rho_clip on a log axis, centred on 1\n"
     << "# (values beyond are drawn in the end colours).\n"
     << "rho_clip = " << short_num(rho_clip) << "\n"
     << "clip(r) = r < 1.0/rho_clip ? 1.0/rho_clip : (r > rho_clip ? rho_clip : r)\n\n"
     << "# Colours: contour pieces by multiplier type, key swatches\n"
     << "c_hopf = " << quote(kHopfLine) << "; c_flip = " << quote(kFlipLine) << "; c_fold = " << quote(kFoldLine)
     << "\n"
     << "c_stable = " << quote(kStableKey) << "; c_chatter = " << quote(kChatterKey) << "\n"
     << "# Blues below rho = 1, oranges to reds above, with a step at 1.\n"
     << "set palette defined (0 '#0b3a6e', 0.25 '#3f7fbf', 0.5 '#bcd7ee', 0.5 '#fdc793', 0.75 '#ee7640', "
        "1 '#7a0c0c')\n\n"
     << "set multiplot title " << quote(title) << " noenhanced font ','.(fs+3)\n"
     << "set lmargin at screen 0.085; set rmargin at screen 0.855\n"
     << "set tmargin at screen 0.83; set bmargin at screen 0.11\n"
     << "set key at screen 0.47, screen 0.885 center center horizontal reverse Left samplen 2 width -1 "
        "font ','.(fs-1)\n"
     << "set border lw 1 lc rgb '#404040' front\n"
     << "set tics front\n"
     << "set mxtics 2; set mytics 2\n"
     << "set xrange [" << short_num(map.spindle_rpm.front(), xaxis.digits) << ":"
     << short_num(map.spindle_rpm.back(), xaxis.digits) << "]\n"
     << "set yrange [" << short_num(map.depth_m.front() * 1e3, 10) << ":" << short_num(map.depth_m.back() * 1e3, 10)
     << "]\n"
     << "set xlabel " << quote(xaxis.label) << "\n"
     << "set ylabel " << quote(xaxis.y_label) << "\n"
     << "set logscale cb\n"
     << "set cbrange [1.0/rho_clip:rho_clip]\n"
     << "set colorbox user origin screen 0.875, screen 0.11 size screen 0.022, screen 0.72 front border\n"
     << "set cblabel 'spectral radius ρ' offset 0.5,0\n"
     << "set cbtics (";
  gp << "sprintf('≤ %g', 1.0/rho_clip) 1.0/rho_clip";
  for (double v : map_tics(rho_clip)) gp << ", '" << short_num(v) << "' " << short_num(v);
  gp << ", sprintf('≥ %g', rho_clip) rho_clip) out nomirror\n"
     << "set mcbtics 1\n";
  if (contour.empty())
    gp << "set label 3 " << quote(unstable == 0 ? "ρ < 1 on the whole grid: stable everywhere"
                                                : "ρ ≥ 1 on the whole grid: chatter everywhere")
       << " at graph 0.5, graph 0.5 center front\n";
  gp << "plot \\\n"
     << "  data index 0 using 1:2:(clip($3)) with image notitle, \\\n"
     << "  keyentry with boxes fs solid 1.0 noborder fc rgb c_stable title 'stable (ρ < 1)', \\\n"
     << "  keyentry with boxes fs solid 1.0 noborder fc rgb c_chatter title 'chatter (ρ > 1)'";
  plot_clauses(gp, contour_type, data);
  gp << "\nunset multiplot\n";
  write_and_render(t, data.text, gp.str());
}

}  // namespace

PlotFiles plot_stability_map(const fs::path& image, const std::string& title, const StabilityMapGrid& map,
                             const PlotOptions& options) {
  const Target t = make_target(image, options);
  draw_stability_map(t, title, map, options);
  return {t.image, t.script, t.data};
}

void plot_stability_map(PlotWindow& window, const std::string& title, const StabilityMapGrid& map,
                        const PlotOptions& options) {
  draw_stability_map(live_target(window, options), title, map, options);
}

namespace {

// The radial map as a StabilityMapGrid whose x values are a_e in mm (or
// a_e/D without a diameter), and the axis that says so.
std::pair<StabilityMapGrid, MapXAxis> radial_view(const RadialStabilityMapGrid& r) {
  StabilityMapGrid g;
  const bool mm = r.tool_diameter_m > 0.0;
  for (double e : r.radial_immersion) g.spindle_rpm.push_back(mm ? e * r.tool_diameter_m * 1e3 : e);
  g.depth_m = r.depth_m;
  g.spectral_radius = r.spectral_radius;
  g.multiplier_type = r.multiplier_type;
  MapXAxis x;
  x.label = mm ? "radial depth of cut a_e (mm)" : "radial immersion a_e/D (-)";
  x.column = mm ? "radial_depth_mm" : "radial_immersion";
  x.plural = mm ? "radial depths" : "radial immersions";
  x.digits = 6;
  x.y_label = "axial depth of cut a_p (mm)";
  return {g, x};
}

std::vector<double> radial_limits(const RadialStabilityMapGrid& r) {
  std::vector<double> v;
  for (const StabilityLimit& l : r.limit) v.push_back(l.depth_limit_m);
  return v;
}

}  // namespace

PlotFiles plot_radial_stability_map(const fs::path& image, const std::string& title, const RadialStabilityMapGrid& map,
                                    const PlotOptions& options) {
  const Target t = make_target(image, options);
  const auto [grid, x] = radial_view(map);
  draw_stability_map(t, title, grid, options, x, radial_limits(map));
  return {t.image, t.script, t.data};
}

void plot_radial_stability_map(PlotWindow& window, const std::string& title, const RadialStabilityMapGrid& map,
                               const PlotOptions& options) {
  const auto [grid, x] = radial_view(map);
  draw_stability_map(live_target(window, options), title, grid, options, x, radial_limits(map));
}

}  // namespace chatter
