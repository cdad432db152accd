// libFuzzer target: the operations-file reader (parse_operations,
// include/chatter/operations.hpp) for a turning and a milling process, then
// process_for() on every accepted row.
// Allowed outcomes: an OperationsFile whose rows obey every rule of
// docs/operations.md (and give a valid process), with every rejected row
// carrying its line and a reason, or InputError (a file-level problem).
// Anything else aborts: a crash, a hang, another exception, an accepted row
// breaking a rule.
//
// Build and run: bash scripts/fuzz.sh operations [seconds]
// (docs/reliability.md). The same entry point runs over
// fuzz/corpus/operations/ in the test suite (test_fuzz_operations_corpus).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <set>
#include <string>
#include <string_view>

#include "chatter/error.hpp"
#include "chatter/operations.hpp"
#include "chatter/process.hpp"

namespace {

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz_operations: invariant violated: %s\n", what);
  std::abort();
}

constexpr double kRpmMin = 50.0, kRpmMax = 24000.0;

void check_file(const chatter::OperationsFile& f, const chatter::Process& base, std::size_t size) {
  const bool milling = base.operation() == chatter::Operation::kMilling;
  std::set<std::string> ids;
  int previous_line = 0;
  for (const chatter::OperationRow& r : f.rows) {
    if (r.line < 2) fail("row line < 2 (line 1 at best is the header)");
    if (r.line <= previous_line) fail("row lines not increasing");
    previous_line = r.line;
    if (static_cast<std::size_t>(r.line) > size + 1) fail("row line beyond the end of the input");
    if (r.id.empty()) fail("empty id accepted");
    if (!ids.insert(r.id).second) fail("duplicate id accepted");
    if (!(std::isfinite(r.spindle_rpm) && r.spindle_rpm >= kRpmMin && r.spindle_rpm <= kRpmMax))
      fail("spindle speed outside the machine range accepted");
    if (!(std::isfinite(r.depth_m) && r.depth_m > 0.0)) fail("depth <= 0 or not finite accepted");
    if (r.radial_immersion && !(*r.radial_immersion > 0.0 && *r.radial_immersion <= 1.0))
      fail("immersion outside (0, 1] accepted");
    if (r.feed_per_tooth_m && !(std::isfinite(*r.feed_per_tooth_m) && *r.feed_per_tooth_m > 0.0))
      fail("feed <= 0 or not finite accepted");
    if (r.teeth && *r.teeth < 1) fail("teeth < 1 accepted");
    if (!milling && (r.radial_immersion || r.teeth || r.direction)) fail("milling-only field accepted in turning");
    try {
      const chatter::Process p = chatter::process_for(base, r);
      const double tau = p.delay_s(r.spindle_rpm);
      if (!(std::isfinite(tau) && tau > 0.0)) fail("delay not finite and positive");
    } catch (const chatter::InputError&) {
      fail("process_for refuses an accepted row");
    }
  }
  for (const chatter::RejectedRow& r : f.rejected) {
    if (r.line < 1) fail("rejected row line < 1");
    if (r.reason.empty()) fail("rejected row without a reason");
  }
}

void parse(std::string_view text, const chatter::Process& base) {
  chatter::MachineLimits machine;
  machine.rpm_min = kRpmMin;
  machine.rpm_max = kRpmMax;
  try {
    const chatter::OperationsFile f = chatter::parse_operations(text, "fuzz.csv", base.operation(), machine);
    check_file(f, base, text.size());
  } catch (const chatter::InputError&) {
    // refused with a message: fine
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_operations: unexpected exception: %s\n", e.what());
    std::abort();
  } catch (...) {
    fail("unexpected non-standard exception");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const chatter::Process turning = chatter::Process::turning({2.4e9});
  static const chatter::Process milling = [] {
    chatter::MillingParameters p;
    p.teeth = 2;
    p.tangential_coefficient_n_per_m2 = 6e8;
    p.radial_coefficient_n_per_m2 = 2e8;
    p.radial_immersion = 0.05;
    return chatter::Process::milling(p);
  }();
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  parse(text, turning);
  parse(text, milling);
  return 0;
}
