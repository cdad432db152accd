// libFuzzer target: the three FRF readers of include/chatter/io/frf.hpp on
// the same bytes, through their in-memory twins (parse_frf_csv,
// parse_frf_tab, parse_uff58_records), each with the default options and
// with a conversion (mobility or accelerance, a scale, drop_zero_hz).
// Allowed outcomes: tables that pass every rule of docs/frf.md (>= 2 lines,
// as many values as frequencies, frequencies finite, >= 0 and strictly
// increasing, values finite, a source), or InputError. Anything else aborts:
// a crash, a hang, another exception, an accepted table breaking a rule.
//
// Build and run: bash scripts/fuzz.sh frf [seconds] (docs/reliability.md).
// The same entry point runs over fuzz/corpus/frf/ in the test suite
// (test_fuzz_frf_corpus).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/frf.hpp"

namespace {

[[noreturn]] void fail(const char* reader, const char* what) {
  std::fprintf(stderr, "fuzz_frf: %s: invariant violated: %s\n", reader, what);
  std::abort();
}

void check_table(const char* reader, const chatter::FrfTable& t) {
  if (t.frequency_hz.size() < 2) fail(reader, "fewer than 2 lines");
  if (t.value.size() != t.frequency_hz.size()) fail(reader, "value and frequency counts differ");
  if (t.source.empty()) fail(reader, "empty source");
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double f = t.frequency_hz[i];
    if (!std::isfinite(f) || f < 0.0) fail(reader, "frequency not finite or negative");
    if (i > 0 && !(f > t.frequency_hz[i - 1])) fail(reader, "frequencies not strictly increasing");
    if (!std::isfinite(t.value[i].real()) || !std::isfinite(t.value[i].imag())) fail(reader, "value not finite");
  }
  try {
    chatter::validate(t);
  } catch (const chatter::InputError&) {
    fail(reader, "validate() refuses an accepted table");
  }
}

// Runs one reader; InputError is an allowed outcome, anything else aborts.
template <class F>
void run(const char* reader, F&& f) {
  try {
    f();
  } catch (const chatter::InputError&) {
    // refused with a message: fine
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_frf: %s: unexpected exception: %s\n", reader, e.what());
    std::abort();
  } catch (...) {
    fail(reader, "unexpected non-standard exception");
  }
}

void read_all(std::string_view text, const chatter::FrfReadOptions& o) {
  run("parse_frf_csv", [&] { check_table("parse_frf_csv", chatter::parse_frf_csv(text, "fuzz.csv", o)); });
  run("parse_frf_tab", [&] { check_table("parse_frf_tab", chatter::parse_frf_tab(text, "fuzz.frf", o)); });
  run("parse_uff58_records", [&] {
    const std::vector<chatter::UffFrfRecord> recs = chatter::parse_uff58_records(text, "fuzz.uff", o);
    if (recs.empty()) fail("parse_uff58_records", "no record and no InputError");
    int previous = 0;
    for (const auto& r : recs) {
      check_table("parse_uff58_records", r.table);
      if (r.record <= previous) fail("parse_uff58_records", "record numbers not increasing");
      previous = r.record;
      if (r.line < 1) fail("parse_uff58_records", "line < 1");
      if (r.ordinate_data_type != 2 && r.ordinate_data_type != 4 && r.ordinate_data_type != 5 &&
          r.ordinate_data_type != 6)
        fail("parse_uff58_records", "unsupported ordinate data type accepted");
    }
  });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  read_all(text, chatter::FrfReadOptions{});
  // A conversion chosen from the input (deterministic, so a crash reproduces).
  chatter::FrfReadOptions conv;
  conv.quantity = (size % 2 == 0) ? chatter::FrfQuantity::kAccelerance : chatter::FrfQuantity::kMobility;
  conv.scale = 1e-6;
  conv.drop_zero_hz = (size % 4) < 2;
  read_all(text, conv);
  return 0;
}
