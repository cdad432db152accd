// libFuzzer target: the logged-test readers a process engineer feeds the
// engine (issue 44): the grinding tests table of `chatter grind fit`
// (include/chatter/io/grinding_io.hpp) and the measurement log of `chatter
// adapt` (include/chatter/io/optimization_files.hpp).
//   tests.csv   read_grinding_tests (through a file in a private folder under
//               /dev/shm), then fit_grinding_tests with the mechanistic model
//               and poly11 on every table it accepts
//   the bytes   parse_measurements for a turning and a milling operation
// Allowed outcomes: data obeying the readers' rules (every accepted number
// finite, powers and removals > 0, a fit whose coefficients and statistics
// are finite), or an InputError. Anything else aborts: a crash, a hang,
// another exception, a NaN in accepted data.
//
// Build and run: bash scripts/fuzz.sh logs [seconds] [runs] (docs/reliability.md).
// The same entry point runs over fuzz/corpus/logs/ in the test suite
// (test_fuzz_logs_corpus).
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>

#include "chatter/error.hpp"
#include "chatter/io/grinding_io.hpp"
#include "chatter/io/optimization_files.hpp"
#include "fuzz_folder.hpp"

namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz_logs: invariant violated: %s\n", what);
  std::abort();
}

bool finite_or_absent(const std::optional<double>& v) { return !v || std::isfinite(*v); }

const fs::path& folder() {
  static const chatter::fuzz::Folder f("logs");
  return f.path();
}

void check_fit(const chatter::GrindingFitReport& r) {
  for (const auto& t : r.targets) {
    for (double c : t.fit.coefficients)
      if (!std::isfinite(c)) fail("grinding fit: a coefficient is not finite");
    if (std::isnan(t.fit.r_squared) || !std::isfinite(t.fit.rmse)) fail("grinding fit: R^2 or RMSE not finite");
    if (t.rows.empty()) fail("grinding fit: a target without tests");
  }
}

void grinding_tests(const fs::path& p) {
  std::vector<chatter::GrindingTest> tests;
  try {
    tests = chatter::read_grinding_tests(p, {});
  } catch (const chatter::InputError&) {
    return;
  }
  if (tests.empty()) fail("grinding tests: accepted without tests");
  for (const chatter::GrindingTest& t : tests) {
    if (t.line < 1) fail("grinding tests: a test without its line");
    for (const auto* v : {&t.power_w, &t.removal_mm3_per_s, &t.wear_mm3_per_s, &t.normal_force_n, &t.impacts_per_turn,
                          &t.wheel_diameter_mm, &t.wheel_width_mm, &t.wheel_rpm, &t.feed_mm_per_s,
                          &t.cutting_speed_m_per_s, &t.friction_coefficient, &t.g_ratio, &t.depth_per_pass_mm,
                          &t.specific_energy_j_per_mm3})
      if (!finite_or_absent(*v)) fail("grinding tests: a value is not finite");
    if ((t.power_w && !(*t.power_w > 0)) || (t.removal_mm3_per_s && !(*t.removal_mm3_per_s > 0)))
      fail("grinding tests: a power or removal <= 0 accepted");
  }
  for (const char* model : {"mechanistic", "poly11"}) {
    try {
      check_fit(chatter::fit_grinding_tests(tests, model, "", p.string()));
    } catch (const chatter::InputError&) {
    }
  }
}

void measurements(std::string_view text) {
  for (const chatter::Operation op : {chatter::Operation::kTurning, chatter::Operation::kMilling}) {
    try {
      const auto rows = chatter::parse_measurements(text, "log.csv", op);
      if (rows.empty()) fail("measurements: accepted without rows");
      for (const auto& row : rows)
        for (double v : row)
          if (!(std::isnan(v) || (std::isfinite(v) && v > 0))) fail("measurements: a value neither > 0 nor missing");
    } catch (const chatter::InputError&) {
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const fs::path p = folder() / "tests.csv";
  chatter::fuzz::write_input(p, bytes);
  grinding_tests(p);
  measurements(bytes);
  return 0;
}
