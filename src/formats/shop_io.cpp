// Readers of shop data: tests tables, force series, recordings
// (include/chatter/io/shop_io.hpp). Audio through libsndfile.
#include "chatter/io/shop_io.hpp"
#include "chatter/number_text.hpp"

#include <dlfcn.h>
#include <sndfile.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <system_error>
#include <type_traits>

#include "chatter/error.hpp"

namespace chatter {
namespace {

namespace fs = std::filesystem;

// Uniform sampling tolerance of a CSV recording: a step may differ from the
// mean step by this fraction (timestamps printed with few digits jitter).
constexpr double kUniformStepRel = 0.01;

std::string trim(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && (s[a] == ' ' || s[a] == '\t' || s[a] == '\r' || s[a] == '"')) ++a;
  while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t' || s[b - 1] == '\r' || s[b - 1] == '"')) --b;
  return s.substr(a, b - a);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t c = line.find(',', start);
    out.push_back(trim(line.substr(start, c == std::string::npos ? std::string::npos : c - start)));
    if (c == std::string::npos) break;
    start = c + 1;
  }
  return out;
}

std::optional<double> parse_number(const std::string& s) {
  if (s.empty()) return std::nullopt;
  double v = 0;
  const char* b = s.data() + (s[0] == '+' ? 1 : 0);
  const auto [p, ec] = std::from_chars(b, s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// A CSV file as numbered, non-blank, non-comment lines.
struct Lines {
  std::vector<std::pair<int, std::string>> rows;
};

Lines read_lines(const fs::path& file, const char* what) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw InputError(file.string() + ": no such file (" + what + ")");
  if (fs::is_directory(file, ec)) throw InputError(file.string() + ": is a directory, not " + std::string(what));
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot be read (" + what + ")");
  Lines l;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    l.rows.emplace_back(n, line);
  }
  if (l.rows.empty()) throw InputError(file.string() + ": empty: no header and no data (" + what + ")");
  return l;
}

// Header → column index; missing required columns are an error naming them.
struct Header {
  std::map<std::string, std::size_t> col;
  bool has(const std::string& c) const { return col.count(c) > 0; }
};

Header parse_header(const fs::path& file, const std::pair<int, std::string>& row) {
  Header h;
  const auto cells = split(row.second);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    std::string c = cells[i];
    for (char& ch : c) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (!c.empty()) h.col.emplace(c, i);
  }
  (void)file;
  return h;
}

void require(const fs::path& file, int line, const Header& h, const std::vector<std::string>& cols,
             const std::string& why) {
  std::string missing;
  for (const auto& c : cols)
    if (!h.has(c)) missing += (missing.empty() ? "" : ", ") + c;
  if (!missing.empty())
    throw InputError(file.string() + ": line " + std::to_string(line) + ": missing column(s) " + missing + " (" +
                     why + ")");
}

double cell(const fs::path& file, int line, const std::vector<std::string>& cells, const Header& h,
            const std::string& c) {
  const std::size_t i = h.col.at(c);
  if (i >= cells.size())
    throw InputError(file.string() + ": line " + std::to_string(line) + ": column " + c + " is missing (" +
                     std::to_string(cells.size()) + " value(s) on the line)");
  const auto v = parse_number(cells[i]);
  if (!v)
    throw InputError(file.string() + ": line " + std::to_string(line) + ": " + c + " = '" + cells[i] +
                     "': not a number");
  return *v;
}

void rule(bool ok, const fs::path& file, int line, const std::string& c, double v, const char* r) {
  if (!ok) throw InputError(file.string() + ": line " + std::to_string(line) + ": " + c + " = " + number_text(v) + ": " + r);
}

/// Largest force magnitude a cutting test can measure, N (about 100 tonnes-force):
/// beyond it a column is in another unit or holds a glitch, and squaring it in
/// the fit overflowed (fuzzing: fy = 2.9e275 N made R^2 NaN).
constexpr double kMaxForceN = 1e6;

double force_cell(const fs::path& file, int line, const std::vector<std::string>& cells, const Header& h,
                  const std::string& column) {
  const double v = cell(file, line, cells, h, column);
  rule(std::abs(v) <= kMaxForceN, file, line, column, v,
       "must be within +-1e6 N (a cutting force in N; is the column in another unit?)");
  return v;
}

// libsndfile, loaded on first use: only the audio reader of `detect` needs
// it, and linking it (with the seven codec libraries it pulls in) cost every
// command ~0.6 ms of start-up (docs/performance.md). Thread-safe (a static
// initialised once); the library stays loaded.
struct Sndfile {
  decltype(&sf_open) open = nullptr;
  decltype(&sf_close) close = nullptr;
  decltype(&sf_readf_double) readf_double = nullptr;
  decltype(&sf_strerror) strerror = nullptr;
  decltype(&sf_command) command = nullptr;
  std::string error;  ///< why it could not be loaded; empty when loaded
};

const Sndfile& sndfile() {
  static const Sndfile lib = [] {
    Sndfile s;
    void* handle = dlopen("libsndfile.so.1", RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* e = dlerror();
      s.error = e ? e : "dlopen(libsndfile.so.1) failed";
      return s;
    }
    auto resolve = [&](auto& fn, const char* name) {
      fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(dlsym(handle, name));
      if (!fn && s.error.empty()) s.error = std::string("libsndfile.so.1 has no ") + name;
    };
    resolve(s.open, "sf_open");
    resolve(s.close, "sf_close");
    resolve(s.readf_double, "sf_readf_double");
    resolve(s.strerror, "sf_strerror");
    resolve(s.command, "sf_command");
    return s;
  }();
  return lib;
}

}  // namespace

ForceSeries read_force_series(const fs::path& file) {
  const Lines l = read_lines(file, "a force series time_s,fx_n,fy_n[,fz_n]");
  const Header h = parse_header(file, l.rows.front());
  require(file, l.rows.front().first, h, {"time_s", "fx_n", "fy_n"}, "a force series needs time_s, fx_n, fy_n");
  ForceSeries s;
  const bool z = h.has("fz_n");
  for (std::size_t r = 1; r < l.rows.size(); ++r) {
    const int line = l.rows[r].first;
    const auto cells = split(l.rows[r].second);
    const double t = cell(file, line, cells, h, "time_s");
    if (!s.time_s.empty() && !(t > s.time_s.back()))
      throw InputError(file.string() + ": line " + std::to_string(line) + ": time_s = " + number_text(t) +
                       " is not after the previous time " + number_text(s.time_s.back()) +
                       " s: time must increase strictly");
    s.time_s.push_back(t);
    s.fx_n.push_back(force_cell(file, line, cells, h, "fx_n"));
    s.fy_n.push_back(force_cell(file, line, cells, h, "fy_n"));
    if (z) s.fz_n.push_back(force_cell(file, line, cells, h, "fz_n"));
  }
  if (s.time_s.size() < 2)
    throw InputError(file.string() + ": " + std::to_string(s.time_s.size()) +
                     " sample(s) after the header: a force series needs at least 2");
  return s;
}

CoefficientTests read_coefficient_tests(const fs::path& file) {
  const Lines l = read_lines(file, "a cutting-tests table");
  const Header h = parse_header(file, l.rows.front());
  const int hl = l.rows.front().first;
  CoefficientTests t;
  const std::vector<std::string> base{"feed_per_tooth_mm", "depth_mm"};
  if (h.has("fx_mean_n") || h.has("fy_mean_n")) {
    t.route = CoefficientRoute::kForces;
    require(file, hl, h, {"feed_per_tooth_mm", "depth_mm", "fx_mean_n", "fy_mean_n"},
            "average forces need feed_per_tooth_mm, depth_mm, fx_mean_n, fy_mean_n");
  } else if (h.has("series")) {
    t.route = CoefficientRoute::kSeries;
    require(file, hl, h, {"feed_per_tooth_mm", "depth_mm", "spindle_rpm", "series"},
            "force series need feed_per_tooth_mm, depth_mm, spindle_rpm, series");
  } else if (h.has("power_w")) {
    t.route = CoefficientRoute::kPower;
    require(file, hl, h, {"feed_per_tooth_mm", "depth_mm", "spindle_rpm", "power_w"},
            "power tests need feed_per_tooth_mm, depth_mm, spindle_rpm, power_w");
  } else {
    throw InputError(file.string() + ": line " + std::to_string(hl) +
                     ": missing columns: give fx_mean_n,fy_mean_n (average forces), or series (force-series "
                     "files), or power_w (net spindle power), with feed_per_tooth_mm and depth_mm");
  }
  const bool z = h.has("fz_mean_n");
  for (std::size_t r = 1; r < l.rows.size(); ++r) {
    const int line = l.rows[r].first;
    const auto cells = split(l.rows[r].second);
    const double f = cell(file, line, cells, h, "feed_per_tooth_mm");
    rule(f > 0 && f < 100, file, line, "feed_per_tooth_mm", f, "must be in (0, 100) mm");
    const double a = cell(file, line, cells, h, "depth_mm");
    rule(a > 0 && a < 1000, file, line, "depth_mm", a, "must be in (0, 1000) mm");
    t.line.push_back(line);
    if (t.route == CoefficientRoute::kForces) {
      ForceTest ft{f * 1e-3, a * 1e-3, force_cell(file, line, cells, h, "fx_mean_n"),
                   force_cell(file, line, cells, h, "fy_mean_n")};
      t.forces.push_back(ft);
      if (z) t.fz_mean_n.push_back(force_cell(file, line, cells, h, "fz_mean_n"));
      continue;
    }
    const double rpm = cell(file, line, cells, h, "spindle_rpm");
    rule(rpm > 0 && rpm < 1e6, file, line, "spindle_rpm", rpm, "must be in (0, 1e6) rev/min");
    if (t.route == CoefficientRoute::kPower) {
      const double p = cell(file, line, cells, h, "power_w");
      rule(p >= 0, file, line, "power_w", p, "must be >= 0 W (net cutting power: cutting minus idle)");
      rule(p <= 1e7, file, line, "power_w", p, "must be <= 1e7 W (10 MW: is the column in W?)");
      t.power.push_back({f * 1e-3, a * 1e-3, rpm, p});
      continue;
    }
    const std::size_t i = h.col.at("series");
    const std::string name = i < cells.size() ? cells[i] : "";
    if (name.empty())
      throw InputError(file.string() + ": line " + std::to_string(line) + ": series is empty: name a force-series CSV");
    fs::path p = name;
    if (p.is_relative()) p = file.parent_path() / p;
    ForceSeries s;
    try {
      s = read_force_series(p);
    } catch (const InputError& e) {
      throw InputError(file.string() + ": line " + std::to_string(line) + ": series: " + e.what());
    }
    RevolutionAverage avg;
    try {
      avg = average_whole_revolutions(s.time_s, s.fx_n, s.fy_n, rpm);
    } catch (const InputError& e) {
      throw InputError(file.string() + ": line " + std::to_string(line) + ": series " + p.string() + ": " + e.what());
    }
    t.forces.push_back({f * 1e-3, a * 1e-3, avg.fx_mean_n, avg.fy_mean_n});
    t.spindle_rpm.push_back(rpm);
    t.series_file.push_back(p.string());
    t.series_average.push_back(avg);
  }
  if (t.line.empty()) throw InputError(file.string() + ": no tests after the header line");
  return t;
}

bool is_turning_tests_table(const fs::path& file) {
  const Lines l = read_lines(file, "a cutting-tests table");
  return parse_header(file, l.rows.front()).has("feed_mm_per_rev");
}

TurningTests read_turning_tests(const fs::path& file) {
  const Lines l = read_lines(file, "a turning cutting-tests table");
  const Header h = parse_header(file, l.rows.front());
  require(file, l.rows.front().first, h, {"feed_mm_per_rev", "depth_mm", "tangential_force_n", "feed_force_n"},
          "turning tests for Kienzle's law need feed_mm_per_rev, depth_mm, tangential_force_n, feed_force_n "
          "[, radial_force_n]");
  const bool radial = h.has("radial_force_n");
  TurningTests t;
  for (std::size_t r = 1; r < l.rows.size(); ++r) {
    const int line = l.rows[r].first;
    const auto cells = split(l.rows[r].second);
    TurningForceTest x;
    const double f = cell(file, line, cells, h, "feed_mm_per_rev");
    rule(f > 0 && f < 100, file, line, "feed_mm_per_rev", f, "must be in (0, 100) mm");
    const double a = cell(file, line, cells, h, "depth_mm");
    rule(a > 0 && a < 1000, file, line, "depth_mm", a, "must be in (0, 1000) mm");
    x.feed_per_rev_m = f * 1e-3;
    x.depth_m = a * 1e-3;
    for (const auto& [column, out] : {std::pair{"tangential_force_n", &x.tangential_n}, {"feed_force_n", &x.feed_n},
                                      {"radial_force_n", &x.radial_n}}) {
      if (std::string(column) == "radial_force_n" && !radial) continue;
      *out = force_cell(file, line, cells, h, column);
      rule(*out > 0, file, line, column, *out, "must be > 0 N (a force's magnitude: Kienzle's law takes its log)");
    }
    t.tests.push_back(x);
    t.line.push_back(line);
  }
  if (t.line.empty()) throw InputError(file.string() + ": no tests after the header line");
  return t;
}

Recording read_recording(const fs::path& file, int channel) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw InputError(file.string() + ": no such file (the recording)");
  if (fs::is_directory(file, ec)) throw InputError(file.string() + ": is a directory, not a recording");
  if (channel < 1) throw InputError("--channel = " + std::to_string(channel) + ": must be >= 1");
  std::string ext = file.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  Recording r;
  r.channel = channel;
  if (ext == ".csv") {
    if (channel != 1)
      throw InputError("--channel = " + std::to_string(channel) + ": " + file.string() + " is a CSV with one channel");
    const Lines l = read_lines(file, "a recording time_s,value");
    std::size_t first = 0;
    const auto head = split(l.rows.front().second);
    if (head.size() < 2 || !parse_number(head[0])) first = 1;  // a header line
    std::vector<double> t;
    for (std::size_t i = first; i < l.rows.size(); ++i) {
      const int line = l.rows[i].first;
      const auto c = split(l.rows[i].second);
      if (c.size() < 2)
        throw InputError(file.string() + ": line " + std::to_string(line) + ": expected time_s,value (2 columns), got " +
                         std::to_string(c.size()));
      const auto tv = parse_number(c[0]), v = parse_number(c[1]);
      if (!tv) throw InputError(file.string() + ": line " + std::to_string(line) + ": time_s = '" + c[0] + "': not a number");
      if (!v) throw InputError(file.string() + ": line " + std::to_string(line) + ": value = '" + c[1] + "': not a number");
      if (!t.empty() && !(*tv > t.back()))
        throw InputError(file.string() + ": line " + std::to_string(line) + ": time_s = " + number_text(*tv) +
                         " is not after the previous time " + number_text(t.back()) + " s: time must increase strictly");
      t.push_back(*tv);
      r.samples.push_back(*v);
    }
    if (t.size() < 2) throw InputError(file.string() + ": " + std::to_string(t.size()) + " sample(s): the recording is empty");
    const double dt = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
    for (std::size_t i = 1; i < t.size(); ++i)
      if (std::abs(t[i] - t[i - 1] - dt) > kUniformStepRel * dt)
        throw InputError(file.string() + ": line " + std::to_string(l.rows[first + i].first) + ": time step " +
                         number_text(t[i] - t[i - 1]) + " s differs from the mean step " + number_text(dt) +
                         " s by more than 1 %: the recording must be uniformly sampled (resample it)");
    r.sample_rate_hz = 1.0 / dt;
    r.format = "CSV";
    return r;
  }
  const Sndfile& lib = sndfile();
  if (!lib.error.empty())
    throw InputError(file.string() + ": cannot read audio: libsndfile could not be loaded (" + lib.error +
                     "); install it (Debian: libsndfile1) or give a CSV time_s,value");
  SF_INFO info{};
  SNDFILE* sf = lib.open(file.c_str(), SFM_READ, &info);
  if (!sf)
    throw InputError(file.string() + ": cannot be read as audio (" + std::string(lib.strerror(nullptr)) +
                     "); give a WAV, FLAC or AIFF file, or a CSV time_s,value");
  struct Closer {
    const Sndfile& lib;
    SNDFILE* f;
    ~Closer() { lib.close(f); }
  } closer{lib, sf};
  if (info.frames <= 0 || info.channels < 1) throw InputError(file.string() + ": the audio file holds no samples");
  if (channel > info.channels)
    throw InputError("--channel = " + std::to_string(channel) + ": " + file.string() + " has " +
                     std::to_string(info.channels) + " channel(s)");
  std::vector<double> inter(static_cast<std::size_t>(info.frames) * info.channels);
  const sf_count_t got = lib.readf_double(sf, inter.data(), info.frames);
  if (got <= 0) throw InputError(file.string() + ": no audio samples could be read (" + lib.strerror(sf) + ")");
  r.samples.resize(static_cast<std::size_t>(got));
  for (sf_count_t i = 0; i < got; ++i) r.samples[i] = inter[i * info.channels + (channel - 1)];
  r.sample_rate_hz = info.samplerate;
  r.channels = info.channels;
  SF_FORMAT_INFO fi{};
  fi.format = info.format & SF_FORMAT_TYPEMASK;
  std::string major = lib.command(sf, SFC_GET_FORMAT_INFO, &fi, sizeof fi) == 0 && fi.name ? fi.name : "audio";
  fi = SF_FORMAT_INFO{};
  fi.format = info.format & SF_FORMAT_SUBMASK;
  std::string sub = lib.command(sf, SFC_GET_FORMAT_INFO, &fi, sizeof fi) == 0 && fi.name ? fi.name : "";
  r.format = major + (sub.empty() ? "" : " (" + sub + ")");
  return r;
}

}  // namespace chatter
