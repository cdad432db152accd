// libFuzzer target: the shop-data readers (include/chatter/io/shop_io.hpp) of
// `chatter coefficients` and `chatter detect`, then the numerics they feed.
// The readers only take paths, so the bytes go through files in a private
// temporary folder (under /dev/shm when it exists: memory, no disk):
//   tests.csv  read_coefficient_tests (forces, power or series route), then
//              fit_coefficients_from_forces / _from_power on what it accepts
//   s.csv      read_force_series; also the file a series-route table names
//   rec.csv    read_recording, the CSV signal reader
//   rec.wav    read_recording through libsndfile (its format is found from
//              the bytes: WAV, AIFF, FLAC, ... whatever the header says)
// then detect_chatter (6000 rev/min, 2 teeth) on every accepted recording of
// at most kMaxDetectSamples samples.
// The input is the first file's bytes; a line "====" splits off the bytes of
// s.csv (without one, s.csv gets the same bytes as the others).
// Allowed outcomes: data obeying the readers' rules (and a fit / a detection
// whose numbers are finite), or an InputError. Anything else aborts: a crash,
// a hang, another exception, a NaN in accepted data.
//
// Build and run: bash scripts/fuzz.sh shop [seconds] [runs]
// (docs/reliability.md). The same entry point runs over fuzz/corpus/shop/ in
// the test suite (test_fuzz_shop_corpus).
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "chatter/error.hpp"
#include "chatter/io/shop_io.hpp"
#include "chatter/shop.hpp"
#include "fuzz_folder.hpp"

namespace {

namespace fs = std::filesystem;

// detect_chatter costs O(n log n): a compressed audio file of 4 kB can decode
// to millions of samples; the detector's own cost is not the readers' target.
constexpr std::size_t kMaxDetectSamples = 1u << 16;

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz_shop: invariant violated: %s\n", what);
  std::abort();
}

const fs::path& folder() {
  static const chatter::fuzz::Folder f("shop");
  return f.path();
}

void write(const fs::path& p, std::string_view bytes) { chatter::fuzz::write_input(p, bytes); }

bool finite(double v) { return std::isfinite(v); }

void check_fit(const chatter::CoefficientFit& f, bool forces) {
  if (!finite(f.tangential_coefficient_n_per_m2) || !finite(f.tangential_edge_coefficient_n_per_m))
    fail("fit: tangential coefficient not finite");
  if (forces && (!finite(f.radial_coefficient_n_per_m2) || !finite(f.radial_edge_coefficient_n_per_m)))
    fail("fit: radial coefficient not finite");
  if (std::isnan(f.r_squared)) fail("fit: R^2 NaN");
  if (forces && (std::isnan(f.r_squared_x) || std::isnan(f.r_squared_y))) fail("fit: R^2 of x or y NaN");
  for (double r : f.residual_x_n)
    if (!finite(r)) fail("fit: residual not finite");
  for (double r : f.residual_y_n)
    if (!finite(r)) fail("fit: residual not finite");
}

void tests_table(const fs::path& p) {
  chatter::CoefficientTests t;
  try {
    t = chatter::read_coefficient_tests(p);
  } catch (const chatter::InputError&) {
    return;
  }
  if (t.line.empty()) fail("tests: accepted without tests");
  const bool power = t.route == chatter::CoefficientRoute::kPower;
  if ((power ? t.power.size() : t.forces.size()) != t.line.size()) fail("tests: one line per test");
  for (const chatter::ForceTest& f : t.forces)
    if (!(f.feed_per_tooth_m > 0 && f.depth_m > 0 && finite(f.feed_per_tooth_m) && finite(f.depth_m) &&
          finite(f.fx_mean_n) && finite(f.fy_mean_n)))
      fail("tests: force test out of its rules");
  for (const chatter::PowerTest& q : t.power)
    if (!(q.feed_per_tooth_m > 0 && q.depth_m > 0 && q.spindle_rpm > 0 && q.power_w >= 0 && finite(q.power_w) &&
          finite(q.spindle_rpm)))
      fail("tests: power test out of its rules");
  for (const chatter::RevolutionAverage& a : t.series_average)
    if (!(a.revolutions >= 1 && finite(a.fx_mean_n) && finite(a.fy_mean_n) && a.duration_s > 0))
      fail("tests: series average out of its rules");
  const chatter::MillingEngagement e{3, 0.5, chatter::MillingDirection::kDown};
  try {
    if (power)
      check_fit(chatter::fit_coefficients_from_power(t.power, e, 0.012), false);
    else
      check_fit(chatter::fit_coefficients_from_forces(t.forces, e), true);
  } catch (const chatter::InputError&) {
  }
}

void force_series(const fs::path& p) {
  chatter::ForceSeries s;
  try {
    s = chatter::read_force_series(p);
  } catch (const chatter::InputError&) {
    return;
  }
  if (s.time_s.size() < 2 || s.fx_n.size() != s.time_s.size() || s.fy_n.size() != s.time_s.size() ||
      !(s.fz_n.empty() || s.fz_n.size() == s.time_s.size()))
    fail("series: sizes");
  for (std::size_t i = 0; i < s.time_s.size(); ++i) {
    if (!finite(s.time_s[i]) || !finite(s.fx_n[i]) || !finite(s.fy_n[i])) fail("series: value not finite");
    if (i > 0 && !(s.time_s[i] > s.time_s[i - 1])) fail("series: time not increasing");
  }
}

void recording(const fs::path& p, bool csv) {
  chatter::Recording r;
  try {
    r = chatter::read_recording(p, 1);
  } catch (const chatter::InputError&) {
    return;
  }
  if (r.samples.empty()) fail("recording: accepted without samples");
  if (!(finite(r.sample_rate_hz) && r.sample_rate_hz > 0)) fail("recording: sample rate not finite and > 0");
  if (r.channel != 1 || r.channels < 1) fail("recording: channels");
  if (csv)
    for (double v : r.samples)
      if (!finite(v)) fail("recording: CSV sample not finite");
  if (r.samples.size() > kMaxDetectSamples) return;
  chatter::DetectOptions o;
  o.spindle_rpm = 6000.0;
  o.teeth = 2;
  chatter::ChatterDetection d;
  try {
    d = chatter::detect_chatter(r.samples, r.sample_rate_hz, o);
  } catch (const chatter::InputError&) {
    return;
  }
  if (!(finite(d.tooth_passing_hz) && d.tooth_passing_hz > 0 && finite(d.spindle_hz) && d.spindle_hz > 0))
    fail("detect: forced frequencies");
  if (!(finite(d.frequency_resolution_hz) && d.frequency_resolution_hz > 0)) fail("detect: resolution");
  if (std::isnan(d.peak_ratio) || std::isnan(d.prominence)) fail("detect: peak ratio or prominence NaN");
  if (d.chatter && !(finite(d.chatter_frequency_hz) && d.chatter_frequency_hz > 0)) fail("detect: chatter frequency");
  for (const chatter::SpeedSuggestion& s : d.suggestions)
    if (!(finite(s.spindle_rpm) && s.spindle_rpm > 0 && s.k >= 1)) fail("detect: suggestion");
  for (const chatter::DetectedPeak& k : d.peaks)
    if (!(finite(k.frequency_hz) && finite(k.amplitude))) fail("detect: peak not finite");
  if (d.spectrum_frequency_hz.size() != d.spectrum_amplitude.size()) fail("detect: spectrum sizes");
  for (double a : d.spectrum_amplitude)
    if (!finite(a)) fail("detect: spectrum amplitude not finite");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view all(reinterpret_cast<const char*>(data), size);
  std::string_view first = all, series = all;
  if (const std::size_t cut = all.find("\n====\n"); cut != std::string_view::npos) {
    first = all.substr(0, cut + 1);
    series = all.substr(cut + 6);
  }
  const fs::path& d = folder();
  write(d / "tests.csv", first);
  write(d / "s.csv", series);
  write(d / "rec.csv", first);
  write(d / "rec.wav", first);
  tests_table(d / "tests.csv");
  force_series(d / "s.csv");
  recording(d / "rec.csv", true);
  recording(d / "rec.wav", false);
  return 0;
}
