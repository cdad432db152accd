// Chatter in a recording: amplitude spectrum (Hann window, Eigen's FFT
// module with its kissfft back end), forced lines (spindle and tooth-passing
// harmonics) masked, the strongest remaining line judged against the forced
// response and the noise floor; the classic speed correction
// N_k = 60 f_c / (N_t k). See include/chatter/shop.hpp and docs/shop_data.md.
#include <unsupported/Eigen/FFT>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include "chatter/error.hpp"
#include "chatter/number_text.hpp"
#include "chatter/shop.hpp"
#include "chatter/kinematics.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;

// The programmed speed is trusted to this fraction when locating the
// tooth-passing line (a spindle under load runs within a few per mille).
constexpr double kSpeedSearchRel = 0.01;
// After refinement from the tooth-passing line, the spindle frequency is
// known to about this fraction (the line's interpolated position).
constexpr double kRefinedSpeedRel = 0.0005;
// Half-width of the mask around a forced line, in frequency bins (fs / n):
// the Hann main lobe is ±2 bins; one more for the interpolation error.
constexpr double kMaskBins = 3.0;
// Lowest frequency searched for chatter, as a fraction of the spindle
// frequency (and never below kMinChatterHz: microphone rumble, drift).
constexpr double kMinChatterSpindleFraction = 0.5;
constexpr double kMinChatterHz = 10.0;
// Fraction of samples at the extreme value above which the recording is
// reported as clipped.
constexpr double kClippedFraction = 0.002;
// Windows for the growth / onset estimate.
constexpr int kGrowthWindows = 8;
// A spectral line "stands" when it is this many times the noise floor (the
// median of the spectrum): only then is the tooth-passing line trusted to
// refine the spindle speed, or taken as proof that the given speed is right.
constexpr double kLineOverFloor = 10.0;
// How far from N N_t / 60 (relative) the tooth-passing line may sit for the
// given speed to count as right (a loaded spindle runs within ~1 %).
constexpr double kToothPassingMatchRel = 0.02;
// ... and stands this many times above the spectrum 3 bins away on both
// sides (the Hann window's main lobe is ±2 bins; its first sidelobe is 31 dB
// down, so a line gives about 30 here and a neighbour's skirt about 1).
constexpr double kLineOverSkirt = 3.0;
// A chatter line whose amplitude changes by less than this factor over the
// recording, present from its first window, is steady: a forced line or a
// wrong speed, more likely than chatter (which grows from the stable cut).
constexpr double kSteadyGrowth = 1.5;

// Peak position refined by a parabola through the log amplitudes of the
// three bins around `k` (exact for a Gaussian; for the Hann window the error
// is a few hundredths of a bin).
double interpolate(const std::vector<double>& amp, std::size_t k, double df) {
  if (k == 0 || k + 1 >= amp.size() || amp[k - 1] <= 0 || amp[k + 1] <= 0 || amp[k] <= 0) return static_cast<double>(k) * df;
  const double a = std::log(amp[k - 1]), b = std::log(amp[k]), c = std::log(amp[k + 1]);
  const double den = a - 2 * b + c;
  // Only a local maximum has its vertex within half a bin: on a slope the
  // parabola's vertex can lie anywhere (found by fuzzing: -1502 Hz).
  if (!(den < 0) || b < a || b < c) return static_cast<double>(k) * df;
  return (static_cast<double>(k) + 0.5 * (a - c) / den) * df;
}

// Amplitude of the line at f in samples [begin, end) (Hann window, direct DFT).
double window_amplitude(const std::vector<double>& x, std::size_t begin, std::size_t end, double f, double fs) {
  const std::size_t m = end - begin;
  std::complex<double> acc = 0, rot = std::polar(1.0, -2 * kPi * f / fs), ph = 1;
  double wsum = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const double w = 0.5 - 0.5 * std::cos(2 * kPi * static_cast<double>(i) / static_cast<double>(m));
    acc += w * x[begin + i] * ph;
    wsum += w;
    ph *= rot;
    if ((i & 1023) == 1023) ph /= std::abs(ph);  // keep the rotator on the unit circle
  }
  return wsum > 0 ? 2 * std::abs(acc) / wsum : 0.0;
}

}  // namespace

std::vector<SpeedSuggestion> speed_corrections(double fc, int teeth, double current_rpm, double rpm_min,
                                               double rpm_max, int max_count) {
  std::vector<SpeedSuggestion> s;
  if (!(fc > 0) || teeth < 1 || !(rpm_max >= rpm_min) || !(rpm_min > 0)) return s;
  for (int k = 1;; ++k) {
    const double n = rpm_from_tooth_passing_hz(fc, teeth * k);
    if (n < rpm_min) break;
    if (n <= rpm_max) s.push_back({n, k});
  }
  std::stable_sort(s.begin(), s.end(), [&](const SpeedSuggestion& a, const SpeedSuggestion& b) {
    return std::abs(a.spindle_rpm - current_rpm) < std::abs(b.spindle_rpm - current_rpm);
  });
  if (max_count >= 0 && s.size() > static_cast<std::size_t>(max_count)) s.resize(max_count);
  return s;
}

namespace {

// The recording's limits: a speed, teeth, sample rate and thresholds that
// make sense, enough revolutions, tooth passing below Nyquist, finite samples.
void check_recording(const std::vector<double>& samples, double fs, const DetectOptions& o) {
  if (!(o.spindle_rpm > 0 && std::isfinite(o.spindle_rpm)))
    throw InputError("spindle speed = " + number_text(o.spindle_rpm) + " rev/min: must be > 0");
  if (o.teeth < 1) throw InputError("teeth = " + std::to_string(o.teeth) + ": must be >= 1");
  if (!(fs > 0 && std::isfinite(fs))) throw InputError("sample rate = " + number_text(fs) + " Hz: must be > 0");
  if (!(o.peak_ratio_threshold > 0) || !(o.prominence_threshold > 1) || !(o.min_revolutions >= 1))
    throw InputError("detector thresholds: peak ratio must be > 0, prominence > 1, minimum revolutions >= 1");
  const std::size_t n = samples.size();
  const double duration = static_cast<double>(n) / fs;
  const double f_sp0 = revolutions_per_s(o.spindle_rpm);
  const double revolutions = duration * f_sp0;
  if (n < 64 || revolutions < o.min_revolutions)
    throw InputError("the recording lasts " + number_text(duration) + " s (" + std::to_string(n) + " samples) = " +
                     number_text(revolutions) + " spindle revolutions at " + number_text(o.spindle_rpm) + " rev/min; at least " +
                     number_text(o.min_revolutions) +
                     " revolutions are needed to tell the spindle harmonics from chatter: record longer");
  if (f_sp0 * o.teeth >= 0.5 * fs)
    throw InputError("the tooth-passing frequency " + number_text(f_sp0 * o.teeth) + " Hz is above half the sample rate (" +
                     number_text(0.5 * fs) + " Hz): record at a higher sample rate");
  for (double v : samples)
    if (!std::isfinite(v)) throw InputError("the recording holds a non-finite sample (NaN or inf)");
}

// Clipping: many samples sitting at the extreme value.
void warn_clipping(const std::vector<double>& samples, std::vector<std::string>& warnings) {
  double peak = 0;
  for (double v : samples) peak = std::max(peak, std::abs(v));
  if (!(peak > 0)) return;
  std::size_t at = 0;
  for (double v : samples)
    if (std::abs(v) >= peak * (1 - 1e-6)) ++at;
  const double n = static_cast<double>(samples.size());
  if (static_cast<double>(at) > kClippedFraction * n)
    warnings.push_back("the recording looks clipped (" + number_text(100.0 * static_cast<double>(at) / n) +
                       " % of the samples at the extreme value " + number_text(peak) +
                       "): lower the input gain; clipping adds harmonics of every line");
}

// The Hann-windowed amplitude spectrum of the recording (zero-padded to a
// power of two) and the questions the detector asks of it.
struct Spectrum {
  std::vector<double> amp;  // single-sided amplitude per bin
  double df = 0.0;          // bin spacing, Hz
  double bin = 0.0;         // resolution of the record itself, fs / n
  double floor0 = 0.0;      // first noise floor (set by the caller)

  std::size_t index(double f) const {
    return static_cast<std::size_t>(std::clamp(std::lround(f / df), 0L, static_cast<long>(amp.size()) - 1));
  }
  std::size_t argmax(double lo, double hi) const {
    std::size_t a = index(lo), b = index(hi), best = a;
    for (std::size_t k = a; k <= b; ++k)
      if (amp[k] > amp[best]) best = k;
    return best;
  }
  // A line "stands" at bin k: a local maximum above the floor that also
  // stands out of its own surroundings (kLineOverSkirt x the bins 3 away,
  // beyond the Hann main lobe), so the skirt of a strong neighbouring line
  // is not taken for one.
  bool stands(std::size_t k) const {
    if (k < 3 || k + 3 >= amp.size() || !(amp[k] > 0.0)) return false;
    return amp[k] >= amp[k - 1] && amp[k] >= amp[k + 1] && amp[k] >= kLineOverFloor * floor0 &&
           amp[k] >= kLineOverSkirt * std::max(amp[k - 3], amp[k + 3]);
  }
  // The median amplitude of the bins from frequency f up (most hold noise only).
  double median_from(double f) const {
    std::vector<double> v(amp.begin() + static_cast<std::ptrdiff_t>(std::min(index(f), amp.size() - 1)), amp.end());
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  }
};

Spectrum hann_spectrum(const std::vector<double>& samples, double fs) {
  const std::size_t n = samples.size();
  double mean = 0;
  for (double v : samples) mean += v;
  mean /= static_cast<double>(n);
  std::size_t nfft = 1;
  while (nfft < n) nfft <<= 1;
  std::vector<double> x(nfft, 0.0);
  double wsum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double w = 0.5 - 0.5 * std::cos(2 * kPi * static_cast<double>(i) / static_cast<double>(n));
    x[i] = w * (samples[i] - mean);
    wsum += w;
  }
  Eigen::FFT<double> fft;
  fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);
  std::vector<std::complex<double>> X;
  fft.fwd(X, x);
  Spectrum sp;
  sp.df = fs / static_cast<double>(nfft);
  sp.bin = fs / static_cast<double>(n);
  sp.amp.resize(X.size());
  for (std::size_t k = 0; k < X.size(); ++k) sp.amp[k] = 2 * std::abs(X[k]) / wsum;
  return sp;
}

// The spindle and tooth-passing lines: whether the recording holds the
// tooth-passing line of the given speed (or its second harmonic; if not, the
// speed or the teeth are wrong), the speeds the strongest line implies, and
// the spindle frequency refined from the tooth-passing line when it stands
// out of the noise. Returns the relative accuracy of r.spindle_hz.
double locate_spindle(const Spectrum& sp, double fs, const DetectOptions& o, double f_lo0, ChatterDetection& r) {
  const double f_sp0 = revolutions_per_s(o.spindle_rpm), nyquist = 0.5 * fs, ftp0 = f_sp0 * o.teeth;
  for (int k = 1; k <= 2 && !r.tooth_passing_found; ++k) {
    const double fk = k * ftp0;
    if (fk * (1 + kToothPassingMatchRel) >= nyquist) break;
    for (std::size_t b = sp.index(fk * (1 - kToothPassingMatchRel)); b <= sp.index(fk * (1 + kToothPassingMatchRel)); ++b)
      if (sp.stands(b)) {
        r.tooth_passing_found = true;
        break;
      }
  }
  const std::size_t top = sp.argmax(f_lo0, std::min(0.95 * nyquist, static_cast<double>(sp.amp.size() - 1) * sp.df));
  r.strongest_line_hz = interpolate(sp.amp, top, sp.df);
  for (int k = 1; k <= 3; ++k) r.implied_rpm.push_back(rpm_from_tooth_passing_hz(r.strongest_line_hz, o.teeth * k));
  double f_sp = f_sp0, speed_rel = kSpeedSearchRel;
  const double lo = ftp0 * (1 - kSpeedSearchRel), hi = ftp0 * (1 + kSpeedSearchRel);
  const std::size_t k = sp.argmax(lo - sp.bin, hi + sp.bin);
  const double f = interpolate(sp.amp, k, sp.df);
  if (k > sp.index(lo - sp.bin) && k < sp.index(hi + sp.bin) && f >= lo && f <= hi && sp.stands(k)) {
    f_sp = f / o.teeth;
    speed_rel = kRefinedSpeedRel;
  }
  r.spindle_hz = f_sp;
  r.tooth_passing_hz = f_sp * o.teeth;
  return speed_rel;
}

// The forced lines (spindle harmonics, tooth passing among them) masked,
// with DC and the band below the chatter search; the strongest forced line.
struct ForcedLines {
  std::vector<char> masked;
  std::vector<DetectedPeak> lines;
  double strongest = 0.0;
};
ForcedLines mask_forced(const Spectrum& sp, double f_sp, double speed_rel, int teeth, double f_top) {
  ForcedLines m;
  m.masked.assign(sp.amp.size(), 0);
  for (int h = 1; h * f_sp <= f_top; ++h) {
    const double fh = h * f_sp;
    const double hw = kMaskBins * sp.bin + h * f_sp * speed_rel;
    const std::size_t a = sp.index(fh - hw), b = sp.index(fh + hw);
    std::size_t best = a;
    for (std::size_t k = a; k <= b; ++k) {
      m.masked[k] = 1;
      if (sp.amp[k] > sp.amp[best]) best = k;
    }
    m.strongest = std::max(m.strongest, sp.amp[best]);
    DetectedPeak p;
    p.frequency_hz = interpolate(sp.amp, best, sp.df);
    p.amplitude = sp.amp[best];
    p.kind = h % teeth == 0 ? "tooth-passing" : "spindle";
    p.harmonic = h % teeth == 0 ? h / teeth : h;
    m.lines.push_back(p);
  }
  const double f_lo = std::max(kMinChatterHz, kMinChatterSpindleFraction * f_sp);
  for (std::size_t k = 0; k < sp.amp.size() && static_cast<double>(k) * sp.df < f_lo; ++k) m.masked[k] = 1;
  return m;
}

// Growth over time and onset at the candidate frequency fc (windows of the
// recording), and the warning when a "chatter" line is there, steady, from
// the start.
void growth_and_onset(const std::vector<double>& samples, double fs, double fc, ChatterDetection& r) {
  const std::size_t len = samples.size() / kGrowthWindows;
  std::vector<double> a;
  for (int w = 0; w < kGrowthWindows && len >= 16; ++w)
    a.push_back(window_amplitude(samples, w * len, (w + 1) * len, fc, fs));
  if (a.size() >= 2 && a.front() > 0) r.growth_ratio = a.back() / a.front();
  if (r.chatter && !a.empty()) {
    const double top = *std::max_element(a.begin(), a.end());
    for (std::size_t w = 0; w < a.size(); ++w)
      if (a[w] >= 0.5 * top) {
        r.onset_s = static_cast<double>(w * len) / fs;
        break;
      }
  }
  if (r.chatter && r.onset_s == 0.0 && std::isfinite(r.growth_ratio) && r.growth_ratio < kSteadyGrowth &&
      r.growth_ratio > 1.0 / kSteadyGrowth)
    r.warnings.push_back("the chatter line at " + number_text(fc) + " Hz is there from t = 0 and steady (x" +
                         number_text(r.growth_ratio) + " over the recording): chatter grows out of a stable cut; a line "
                         "present from the start at a steady level is more likely forced, or an input error (--rpm, "
                         "--teeth)?");
}

}  // namespace

ChatterDetection detect_chatter(const std::vector<double>& samples, double fs, const DetectOptions& o) {
  check_recording(samples, fs, o);
  ChatterDetection r;
  r.duration_s = static_cast<double>(samples.size()) / fs;
  warn_clipping(samples, r.warnings);
  Spectrum sp = hann_spectrum(samples, fs);
  r.frequency_resolution_hz = sp.bin;
  r.spectrum_frequency_hz.resize(sp.amp.size());
  for (std::size_t k = 0; k < sp.amp.size(); ++k) r.spectrum_frequency_hz[k] = static_cast<double>(k) * sp.df;
  // A first noise floor: the median of the spectrum above the lowest chatter
  // frequency (most bins hold noise only).
  const double f_lo0 = std::max(kMinChatterHz, kMinChatterSpindleFraction * revolutions_per_s(o.spindle_rpm));
  sp.floor0 = sp.median_from(f_lo0);
  const double speed_rel = locate_spindle(sp, fs, o, f_lo0, r);
  const double f_top = std::min(0.95 * 0.5 * fs, r.spectrum_frequency_hz.back());
  const ForcedLines forced = mask_forced(sp, r.spindle_hz, speed_rel, o.teeth, f_top);

  // Strongest unmasked line and the noise floor (median of unmasked bins).
  std::vector<double> free;
  std::size_t cand = 0;
  bool have = false;
  for (std::size_t k = 0; k < sp.amp.size() && static_cast<double>(k) * sp.df <= f_top; ++k) {
    if (forced.masked[k]) continue;
    free.push_back(sp.amp[k]);
    if (!have || sp.amp[k] > sp.amp[cand]) {
      cand = k;
      have = true;
    }
  }
  // Keep the forced lines that stand out of the floor, strongest first.
  double floor = 0;
  if (!free.empty()) {
    std::nth_element(free.begin(), free.begin() + free.size() / 2, free.end());
    floor = free[free.size() / 2];
  }
  for (const auto& p : forced.lines)
    if (p.amplitude > 10 * floor) r.peaks.push_back(p);
  std::stable_sort(r.peaks.begin(), r.peaks.end(),
                   [](const DetectedPeak& a, const DetectedPeak& b) { return a.amplitude > b.amplitude; });
  if (r.peaks.size() > 40) r.peaks.resize(40);
  if (!have) {
    r.spectrum_amplitude = std::move(sp.amp);
    return r;
  }

  const double fc = interpolate(sp.amp, cand, sp.df);
  r.candidate_frequency_hz = fc;
  r.peak_ratio = forced.strongest > 0 ? sp.amp[cand] / forced.strongest : std::numeric_limits<double>::infinity();
  r.prominence = floor > 0 ? sp.amp[cand] / floor : std::numeric_limits<double>::infinity();
  r.chatter = r.peak_ratio >= o.peak_ratio_threshold && r.prominence >= o.prominence_threshold;
  growth_and_onset(samples, fs, fc, r);
  if (r.chatter) {
    r.chatter_frequency_hz = fc;
    DetectedPeak p;
    p.frequency_hz = fc;
    p.amplitude = sp.amp[cand];
    p.kind = "chatter";
    r.peaks.push_back(p);
    const double lo = o.rpm_min > 0 ? o.rpm_min : 0.5 * o.spindle_rpm;
    const double hi = o.rpm_max > 0 ? o.rpm_max : 1.5 * o.spindle_rpm;
    r.suggestions = speed_corrections(fc, o.teeth, o.spindle_rpm, lo, hi, o.max_suggestions);
  }
  r.spectrum_amplitude = std::move(sp.amp);
  return r;
}

}  // namespace chatter
