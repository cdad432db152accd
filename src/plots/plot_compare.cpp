// Plots through gnuplot: the comparison of methods on one speed axis.
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
// Method comparison

namespace {

// One style per method: every registered method has its own (solver registry,
// PlotStyle: a method looks the same on every chart), other names take the
// next unused one of kMethodStyles. The lines are drawn widest first, so that methods that agree
// (analytic and coupled to round-off, sdm in turning) all stay visible: a wide
// light band, a medium line on it, a thin dashed line on top. time-domain is
// drawn as open circles, one per simulated speed, on top of everything (the
// flip marks included): it lies on sdm's line where they agree, and a line on
// a line would hide one of them.
struct MethodStyle {
  const char* colour;
  double width;
  const char* dash;  // "" = solid
  int point_type;    // 0 = a line; else gnuplot's point type, drawn as points
};
// The styles of unregistered names, after those of the registry.
constexpr MethodStyle kExtraStyles[] = {
    {"#7570b3", 2.2, " dt (10,4,2,4)", 0}, {"#e7298a", 2.0, "", 0},
    {"#66a61e", 1.8, " dt (6,3,2,3)", 0}, {"#7a5a1d", 1.4, " dt (3,3)", 0},
};
// The registry's styles, in registry order, then kExtraStyles.
const std::vector<MethodStyle>& method_styles() {
  static const std::vector<MethodStyle> styles = [] {
    std::vector<MethodStyle> s;
    for (const auto& d : solver_registry()) s.push_back({d.plot.colour, d.plot.width, d.plot.dash, d.plot.point_type});
    for (const auto& e : kExtraStyles) s.push_back(e);
    return s;
  }();
  return styles;
}

// A method name as a column name: anything but letters, digits and _ becomes _.
std::string column_word(const std::string& s) {
  std::string out = s;
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
  return out;
}

}  // namespace

namespace {

// Refuses an empty, inconsistent or too long list of methods. @throws InputError.
void check_compare_input(const std::string& where, const std::vector<MethodLimits>& methods, double depth_max_m,
                         std::size_t kMaxMethods) {
  if (methods.empty() || methods.size() > kMaxMethods)
    throw InputError(where + std::to_string(methods.size()) + " methods: must be 1 to " +
                     std::to_string(kMaxMethods));
  if (!(std::isfinite(depth_max_m) && depth_max_m > 0.0))
    throw InputError(where + "depth_max = " + short_num(depth_max_m) + " m: must be > 0");
  const std::size_t rows = methods.front().limits.size();
  if (rows == 0) throw InputError(where + "no speeds to plot");
  for (std::size_t m = 0; m < methods.size(); ++m) {
    const MethodLimits& ml = methods[m];
    if (ml.method.empty()) throw InputError(where + "method " + std::to_string(m + 1) + " has no name");
    for (std::size_t o = 0; o < m; ++o)
      if (methods[o].method == ml.method) throw InputError(where + "method '" + ml.method + "' given twice");
    if (ml.limits.size() != rows)
      throw InputError(where + "method '" + ml.method + "' has " + std::to_string(ml.limits.size()) +
                       " speeds, '" + methods.front().method + "' has " + std::to_string(rows));
    if (!ml.multiplier_type.empty() && ml.multiplier_type.size() != rows)
      throw InputError(where + "method '" + ml.method + "': " + std::to_string(ml.multiplier_type.size()) +
                       " multiplier types for " + std::to_string(rows) + " speeds");
    for (std::size_t i = 0; i < rows; ++i) {
      const double a = methods.front().limits[i].spindle_rpm, b = ml.limits[i].spindle_rpm;
      if (!(std::isfinite(b) && b > 0.0)) throw InputError(where + "spindle speeds must be finite and > 0");
      if (std::abs(a - b) > 1e-9 * std::abs(a))
        throw InputError(where + "method '" + ml.method + "' row " + std::to_string(i + 1) + " is at " +
                         short_num(b, 10) + " rev/min, '" + methods.front().method + "' at " + short_num(a, 10));
    }
  }
}

// The style (index into method_styles()) of each method: registered methods
// keep theirs, the others take the next unused.
std::vector<std::size_t> compare_styles(const std::vector<MethodLimits>& methods) {
  const std::size_t kMaxMethods = method_styles().size();
  std::vector<std::size_t> style_of(methods.size(), kMaxMethods);
  std::vector<bool> taken(kMaxMethods, false);
  const auto& registry = solver_registry();
  for (std::size_t m = 0; m < methods.size(); ++m)
    for (std::size_t k = 0; k < registry.size(); ++k)
      if (methods[m].method == registry[k].name) {
        style_of[m] = k;
        taken[k] = true;
      }
  for (std::size_t m = 0; m < methods.size(); ++m)
    if (style_of[m] == kMaxMethods) {
      std::size_t k = 0;
      while (taken[k]) ++k;  // methods.size() <= kMaxMethods: there is one
      style_of[m] = k;
      taken[k] = true;
    }
  return style_of;
}

// Top of the depth axis (mm): every bounded limit of every method visible
// with a margin (as lobes_y_max), at least 3 × the smallest one.
double compare_y_max(const std::vector<double>& bounded, double depth_max_mm) {
  double y_max = depth_max_mm;
  if (!bounded.empty()) {
    const double lowest = *std::min_element(bounded.begin(), bounded.end());
    const double highest = *std::max_element(bounded.begin(), bounded.end());
    y_max = std::min(depth_max_mm, nice_ceil(std::max(kDepthAxisMargin * highest, 3.0 * lowest)));
  }
  return y_max;
}

// The .dat of plot_compare: limits per speed (index 0), flip/fold runs (1).
// marks[m][type] counts the rows of method m marked with that type.
std::string compare_data(const std::string& title, const std::vector<MethodLimits>& methods, double depth_max_mm,
                         std::vector<std::array<std::size_t, 3>>& marks) {
  const std::size_t rows = methods.front().limits.size();
  std::ostringstream dat;
  dat << "# " << one_line(title) << ": depth limit by method (chatter " << version() << ")\n"
      << "# depth_max_mm = " << num(depth_max_mm) << " (deepest cut searched)\n"
      << "# methods:";
  for (std::size_t m = 0; m < methods.size(); ++m) dat << ' ' << m << '=' << one_line(methods[m].method);
  dat << "\n# Missing values are '?' (gnuplot: set datafile missing '?').\n\n"
      << "# index 0: one row per spindle speed; per method the depth limit (mm; '?' where there is no\n"
      << "# limit below depth_max_mm) and bounded (1 = a limit, 0 = none).\n"
      << "# spindle_rpm";
  for (const auto& ml : methods) {
    const std::string w = column_word(ml.method);
    dat << " depth_limit_mm_" << w << " bounded_" << w;
  }
  dat << '\n';
  for (std::size_t i = 0; i < rows; ++i) {
    dat << num(methods.front().limits[i].spindle_rpm);
    for (const auto& ml : methods) {
      const auto& r = ml.limits[i];
      dat << ' ' << (r.bounded() ? num(r.depth_limit_m * 1e3) : "?") << ' ' << (r.bounded() ? 1 : 0);
    }
    dat << '\n';
  }
  // Runs of consecutive speeds where a method's limit is set by a flip or a
  // fold multiplier: one block each, drawn over that method's line.
  dat << "\n\n# index 1: speeds where a method's limit is set by a flip (period doubling) or fold\n"
      << "# multiplier (methods that report the multiplier type, e.g. sdm); one block per run of\n"
      << "# consecutive speeds (blocks separated by one blank line); method = its number above\n"
      << "# spindle_rpm depth_limit_mm method multiplier_type\n";
  marks.assign(methods.size(), {0, 0, 0});
  bool first_run = true;
  for (std::size_t m = 0; m < methods.size(); ++m) {
    const MethodLimits& ml = methods[m];
    if (ml.multiplier_type.empty()) continue;
    int run_type = -1;  // type of the open run, -1 if none
    for (std::size_t i = 0; i < rows; ++i) {
      const auto& r = ml.limits[i];
      const int ty = r.bounded() ? static_cast<int>(ml.multiplier_type[i]) : -1;
      if (ty <= 0) {  // Hopf or no limit: the run ends
        run_type = -1;
        continue;
      }
      if (ty != run_type) {
        if (!first_run) dat << '\n';
        first_run = false;
        run_type = ty;
      }
      dat << num(r.spindle_rpm) << ' ' << num(r.depth_limit_m * 1e3) << ' ' << m << ' '
          << type_word(ml.multiplier_type[i]) << '\n';
      ++marks[m][static_cast<std::size_t>(ty)];
    }
  }
  return dat.str();
}

// The variables, colours and axes of the plot_compare script, up to "plot".
std::string compare_script_head(const Target& t, const PlotOptions& options, const std::string& title,
                                const std::vector<MethodLimits>& methods, const std::vector<std::size_t>& style_of,
                                double rpm_lo, double rpm_hi, double y_max, double depth_max_mm, bool any_bounded) {
  const std::vector<MethodStyle>& kMethodStyles = method_styles();
  std::ostringstream gp;
  gp << script_preamble(t, options, "Depth limit by method (chatter compare)")
     << "# Values from the engine (mm, rev/min)\n"
     << "y_max = " << short_num(y_max, 6) << "          # top of the depth axis\n"
     << "depth_max = " << short_num(depth_max_mm, 6) << "      # deepest cut searched\n"
     << "# Columns of method m (0 = first): depth limit and bounded flag\n"
     << "col_depth(m) = 2 + 2*m\n"
     << "col_bounded(m) = 3 + 2*m\n"
     << "# A gap where a method has no limit (a NaN breaks the line; a '?' row would be joined across).\n"
     << "limit(m) = column(col_bounded(m)) > 0 ? column(col_depth(m)) : NaN\n\n"
     << "# Colours, one per method\n";
  for (std::size_t m = 0; m < methods.size(); ++m)
    gp << "c_m" << m << " = " << quote(kMethodStyles[style_of[m]].colour) << "   # " << one_line(methods[m].method)
       << "\n";
  gp << "c_flip = " << quote(kFlipLine) << "; c_fold = " << quote(kFoldLine)
     << "   # where a limit is set by a flip / fold multiplier\n"
     << "\nset multiplot title " << quote(title) << " noenhanced font ','.(fs+3)\n"
     << "set lmargin at screen 0.085; set rmargin at screen 0.975\n"
     << "set tmargin at screen 0.85; set bmargin at screen 0.11\n"
     << "set key at screen 0.53, screen 0.895 center center horizontal reverse Left samplen 3 width 1 "
        "font ','.(fs-1)\n"
     << "set border lw 1 lc rgb '#404040'\n"
     << "set grid xtics ytics mxtics mytics back lw 1 lc rgb " << quote(kGrid) << ", lw 0.5 lc rgb '#e4e4e4'\n"
     << "set mxtics 2; set mytics 2\n"
     << "set xrange [" << short_num(rpm_lo, 10) << ":" << short_num(rpm_hi, 10) << "]\n"
     << "set yrange [0:y_max]\n"
     << "set xlabel 'spindle speed (rev/min)'\n"
     << "set ylabel 'depth limit (mm)'\n";
  if (!any_bounded)
    gp << "set label 3 sprintf('no method finds chatter below %g mm at any speed in the sweep', depth_max) "
          "at graph 0.5, graph 0.5 center front\n";
  return gp.str();
}

// The plot command of plot_compare: the lines widest first, the key, the
// flip/fold marks, then the methods drawn as points on top.
std::string compare_plot_clauses(const std::vector<MethodLimits>& methods, const std::vector<std::size_t>& style_of,
                                 const std::vector<std::array<std::size_t, 3>>& marks, bool gaps, bool any_bounded) {
  const std::vector<MethodStyle>& kMethodStyles = method_styles();
  const std::size_t rows = methods.front().limits.size();
  PlotCommand gp;
  auto add = [&](const std::string& clause) { gp.add(clause); };
  // Lines widest first (untitled), then the key in the methods' order.
  std::vector<std::size_t> order(methods.size());
  for (std::size_t m = 0; m < order.size(); ++m) order[m] = m;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return kMethodStyles[style_of[a]].width > kMethodStyles[style_of[b]].width;
  });
  auto style = [&](std::size_t m) {
    const MethodStyle& st = kMethodStyles[style_of[m]];
    if (st.point_type != 0)
      return "points pt " + std::to_string(st.point_type) + " ps 1.1 lw " + short_num(st.width) + " lc rgb c_m" +
             std::to_string(m);
    return "lines lw " + short_num(st.width) + st.dash + " lc rgb c_m" + std::to_string(m);
  };
  auto drawn_as_points = [&](std::size_t m) { return kMethodStyles[style_of[m]].point_type != 0; };
  // Points: at most about 100 per method, or they merge into a thick line.
  const std::size_t point_every = std::max<std::size_t>(1, (rows + 99) / 100);
  auto draw = [&](std::size_t m) {
    add("data index 0" + (drawn_as_points(m) ? " every " + std::to_string(point_every) : std::string()) +
        " using 1:(limit(" + std::to_string(m) + ")) with " + style(m) + " notitle");
  };
  for (std::size_t m : order)
    if (!drawn_as_points(m)) draw(m);
  for (std::size_t m = 0; m < methods.size(); ++m)
    add("keyentry with " + style(m) + " title " + quote(methods[m].method));
  for (std::size_t m = 0; m < methods.size(); ++m)
    for (int ty : {1, 2})
      if (marks[m][static_cast<std::size_t>(ty)] > 0) {
        const std::string word = type_word(static_cast<MultiplierType>(ty));
        add("data index 1 using 1:($3 == " + std::to_string(m) + " && strcol(4) eq '" + word +
            "' ? $2 : NaN) with linespoints lw 3.5 pt 7 ps 0.6 pi 4 lc rgb " + (ty == 1 ? "c_flip" : "c_fold") +
            " title " + quote(methods[m].method + (ty == 1 ? ": flip (period doubling)" : ": fold")));
      }
  for (std::size_t m : order)
    if (drawn_as_points(m)) draw(m);
  if (gaps && any_bounded)
    add("keyentry with lines lt nodraw title sprintf('gap: no limit below %g mm', depth_max)");
  return gp.str();
}

}  // namespace

namespace {

void draw_compare(const Target& t, const std::string& title, const std::vector<MethodLimits>& methods,
                  double depth_max_m, const PlotOptions& options) {
  check_compare_input(t.label + ": comparison: ", methods, depth_max_m, method_styles().size());
  const std::vector<std::size_t> style_of = compare_styles(methods);
  const double depth_max_mm = depth_max_m * 1e3;
  const auto [rpm_lo, rpm_hi] = speed_axis(methods.front().limits);
  std::vector<double> bounded;
  bool gaps = false;
  for (const auto& ml : methods)
    for (const auto& r : ml.limits) {
      if (r.bounded()) bounded.push_back(std::min(r.depth_limit_m * 1e3, depth_max_mm));
      else gaps = true;
    }
  const double y_max = options.depth_axis_max_mm > 0.0 ? options.depth_axis_max_mm : compare_y_max(bounded, depth_max_mm);
  std::vector<std::array<std::size_t, 3>> marks;
  const std::string dat = compare_data(title, methods, depth_max_mm, marks);
  const std::string gp =
      compare_script_head(t, options, title, methods, style_of, rpm_lo, rpm_hi, y_max, depth_max_mm,
                          !bounded.empty()) +
      compare_plot_clauses(methods, style_of, marks, gaps, !bounded.empty()) + "\nunset multiplot\n";
  write_and_render(t, dat, gp);
}

}  // namespace

PlotFiles plot_compare(const fs::path& image, const std::string& title, const std::vector<MethodLimits>& methods,
                       double depth_max_m, const PlotOptions& options) {
  const Target t = make_target(image, options);
  draw_compare(t, title, methods, depth_max_m, options);
  return {t.image, t.script, t.data};
}

void plot_compare(PlotWindow& window, const std::string& title, const std::vector<MethodLimits>& methods,
                  double depth_max_m, const PlotOptions& options) {
  draw_compare(live_target(window, options), title, methods, depth_max_m, options);
}

}  // namespace chatter
