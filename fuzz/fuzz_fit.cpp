// libFuzzer target: the modal fit (fit_modes, include/chatter/modal_fit.hpp)
// on fuzzed FRF tables and options. The bytes are decoded, not parsed as
// text (the readers have their own target, fuzz_frf.cpp), so that every
// execution reaches the peak picking and the Levenberg–Marquardt loop:
//   byte 0: modes = b % 4 (0 = auto), bit 2: residual terms, bit 3: a band
//           (bytes 1, 2 pick its ends as fractions of the table's range)
//   byte 3: max_iterations = 1 + b % 16 (the per-input cost cap: with 64
//           evaluations over a few hundred lines libFuzzer ran at 30
//           executions per second; scripts/fuzz.sh also caps the input at
//           512 bytes = 84 lines)
//   byte 4: frequency scale 10^((b % 16) − 4) Hz per step (1e-4 … 1e11 Hz)
//   byte 5: receptance scale 10^(b − 160) m/N (1e-160 … 1e95)
//   then 6 bytes per line: uint16 frequency step (+1: strictly increasing
//   unless the scale rounds it away), int16 real and int16 imaginary part.
// Allowed outcomes: a fit whose modes are physical (finite f > 0, ζ in (0, 1),
// finite k > 0), whose errors, residual terms and receptance over the band are
// finite, or an InputError, or the documented NumericalError "modal fit left
// the physical range" (which `chatter fit` reports as an InputError). Anything
// else aborts: a crash, a hang, a NaN in an accepted fit, another exception.
//
// Build and run: bash scripts/fuzz.sh fit [seconds] [runs]
// (docs/reliability.md). The same entry point runs over fuzz/corpus/fit/ in
// the test suite (test_fuzz_fit_corpus).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "chatter/error.hpp"
#include "chatter/frf_data.hpp"
#include "chatter/modal_fit.hpp"

namespace {

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz_fit: invariant violated: %s\n", what);
  std::abort();
}

constexpr std::size_t kHeaderBytes = 6;
constexpr std::size_t kLineBytes = 6;

int i16(const std::uint8_t* p) { return static_cast<std::int16_t>(static_cast<std::uint16_t>(p[0] | (p[1] << 8))); }
unsigned u16(const std::uint8_t* p) { return static_cast<unsigned>(p[0] | (p[1] << 8)); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < kHeaderBytes) return 0;
  chatter::ModalFitOptions o;
  o.modes = data[0] % 4;
  o.residuals = (data[0] & 4) != 0;
  o.max_iterations = 1 + data[3] % 16;
  const double f_scale = std::pow(10.0, static_cast<double>(data[4] % 16) - 4.0);
  const double g_scale = std::pow(10.0, static_cast<double>(data[5]) - 160.0);

  chatter::FrfTable t;
  t.source = "fuzz.frf";
  double f = 0.0;
  for (std::size_t p = kHeaderBytes; p + kLineBytes <= size; p += kLineBytes) {
    f += static_cast<double>(u16(data + p)) * f_scale;
    t.frequency_hz.push_back(f);
    t.value.emplace_back(i16(data + p + 2) * g_scale / 32768.0, i16(data + p + 4) * g_scale / 32768.0);
    f += f_scale;
  }
  if (t.size() >= 1 && (data[0] & 8) != 0) {
    const double lo = t.frequency_hz.front(), hi = t.frequency_hz.back();
    o.f_min_hz = lo + (hi - lo) * (data[1] / 255.0);
    o.f_max_hz = lo + (hi - lo) * (data[2] / 255.0);
  }

  chatter::ModalFitResult r;
  try {
    r = chatter::fit_modes(t, o);
  } catch (const chatter::InputError&) {
    return 0;  // refused with a message: fine
  } catch (const chatter::NumericalError& e) {
    // The one documented NumericalError of fit_modes (modal_fit.hpp): the
    // fit left the physical range (e.g. ζ driven to 0 on data no mode fits);
    // `chatter fit` turns it into an InputError with advice (exit 2).
    if (std::string(e.what()).find("modal fit left the physical range") == std::string::npos) throw;
    return 0;
  }
  if (r.modes.empty()) fail("accepted fit without modes");
  if (r.modes.size() != r.initial_modes.size()) fail("fitted and initial mode counts differ");
  if (o.modes > 0 && r.modes.size() != static_cast<std::size_t>(o.modes)) fail("mode count differs from the one asked");
  for (const chatter::Mode& m : r.modes) {
    if (!(std::isfinite(m.natural_frequency_hz) && m.natural_frequency_hz > 0)) fail("fitted frequency");
    if (!(m.damping_ratio > 0 && m.damping_ratio < 1)) fail("fitted damping");
    if (!(std::isfinite(m.stiffness_n_per_m) && m.stiffness_n_per_m > 0)) fail("fitted stiffness");
  }
  for (std::size_t i = 1; i < r.modes.size(); ++i)
    if (r.modes[i].natural_frequency_hz < r.modes[i - 1].natural_frequency_hz) fail("modes not by increasing frequency");
  if (!std::isfinite(r.fit_error) || r.fit_error < 0) fail("fit_error NaN or negative");
  if (!std::isfinite(r.initial_error) || r.initial_error < 0) fail("initial_error NaN or negative");
  if (!std::isfinite(r.residual_upper) || !std::isfinite(r.residual_lower)) fail("residual term not finite");
  if (!(r.lines >= 3 && r.f_min_hz <= r.f_max_hz)) fail("band");
  if (r.iterations < 1 || r.iterations > o.max_iterations + 2) fail("iterations outside the budget");
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double fi = t.frequency_hz[i];
    if (fi < r.f_min_hz || fi > r.f_max_hz || fi <= 0.0) continue;
    const chatter::Complex g = r.receptance(fi);
    if (!std::isfinite(g.real()) || !std::isfinite(g.imag())) fail("fitted receptance not finite in the band");
  }
  return 0;
}
