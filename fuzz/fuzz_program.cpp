// libFuzzer target: what `chatter program` reads besides the G-code itself
// (LinuxCNC's interpreter reads that; issue 44): the job file JOB.toml
// (load_job, include/chatter/io/job.hpp) and the interpreter's canonical-call
// log (parse_canon_log, include/chatter/io/nc_program.hpp), the text our
// code parses out of the program.
// The input's bytes up to a line "====" are JOB.toml, written into a private
// folder (under /dev/shm) beside the shipped examples' tool configs
// (examples/program/end_mill.toml, insert.toml: a job may name them); the
// rest is the canonical-call log (without "====": the same bytes for both).
// Allowed outcomes: a job with distinct tool numbers, each with its config,
// finite machine limits; a toolpath whose moves have finite coordinates,
// feeds and speeds and lines >= 0; or an InputError. Anything else aborts.
//
// Build and run: bash scripts/fuzz.sh program [seconds] [runs]
// (docs/reliability.md). The same entry point runs over fuzz/corpus/program/
// in the test suite (test_fuzz_program_corpus).
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <string_view>

#include "chatter/error.hpp"
#include "chatter/io/job.hpp"
#include "chatter/io/nc_program.hpp"
#include "chatter/toolpath.hpp"
#include "fuzz_folder.hpp"

#ifndef CHATTER_SOURCE_DIR
#define CHATTER_SOURCE_DIR "."
#endif

namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz_program: invariant violated: %s\n", what);
  std::abort();
}

// The folder, with the tool configs a shipped job names (so that its seeds load).
const fs::path& folder() {
  static const chatter::fuzz::Folder f("program");
  static const bool copied = [] {
    for (const char* name : {"end_mill.toml", "insert.toml"}) {
      std::error_code ec;
      fs::copy_file(fs::path(CHATTER_SOURCE_DIR) / "examples/program" / name, f.path() / name,
                    fs::copy_options::overwrite_existing, ec);
    }
    return true;
  }();
  (void)copied;
  return f.path();
}

void job(const fs::path& p) {
  chatter::Job j;
  try {
    j = chatter::load_job(p);
  } catch (const chatter::InputError&) {
    return;
  }
  if (j.tools.empty()) fail("job: accepted without tools");
  std::set<int> numbers;
  for (const chatter::JobTool& t : j.tools)
    if (!numbers.insert(t.number).second) fail("job: two tools with one number");
  for (const auto* v : {&j.machine.rpm_min, &j.machine.rpm_max, &j.machine.max_power_kw, &j.machine.max_torque_nm})
    if (*v && !(std::isfinite(**v) && **v > 0)) fail("job: a machine limit not finite and > 0");
  if (!(std::isfinite(j.speed_tolerance) && j.speed_tolerance >= 0)) fail("job: speed tolerance");
}

void canon_log(const std::string& log) {
  chatter::Toolpath path;
  try {
    path = chatter::parse_canon_log(log, "fuzz.ngc");
  } catch (const chatter::InputError&) {
    return;
  }
  for (const chatter::ToolpathMove& m : path.moves) {
    if (m.line < 0) fail("toolpath: a negative line");
    if (!m.start.allFinite() || !m.end.allFinite() || !m.centre.allFinite()) fail("toolpath: a coordinate not finite");
    if (!(std::isfinite(m.feed) && m.feed >= 0)) fail("toolpath: a feed not finite and >= 0");
    if (!(std::isfinite(m.spindle_rpm) && m.spindle_rpm >= 0)) fail("toolpath: a speed not finite and >= 0");
    if (!std::isfinite(chatter::move_length_mm(m))) fail("toolpath: a move's length not finite");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view all(reinterpret_cast<const char*>(data), size);
  std::string_view first = all, second = all;
  if (const std::size_t cut = all.find("\n====\n"); cut != std::string_view::npos) {
    first = all.substr(0, cut + 1);
    second = all.substr(cut + 6);
  }
  const fs::path p = folder() / "JOB.toml";
  chatter::fuzz::write_input(p, first);
  job(p);
  canon_log(std::string(second));
  return 0;
}
