// The analysers of a time-domain run (time_domain_parts.hpp): growth per
// period by exact DMD, the amplitude spectrum and its peaks, the verdict.
#include "time_domain_parts.hpp"

#include <Eigen/Dense>
#include <unsupported/Eigen/FFT>

namespace chatter::detail {

std::complex<double> dominant_multiplier(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y,
                                         const Eigen::VectorXd& last, double rank_tolerance) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  if (X.cols() < 2) return {kNaN, 0.0};
  Eigen::BDCSVD<Eigen::MatrixXd> svd(X, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  if (sv.size() == 0 || !(sv(0) > 0.0)) return {kNaN, 0.0};
  Eigen::Index r = 0;
  while (r < sv.size() && sv(r) > rank_tolerance * sv(0)) ++r;
  const Eigen::MatrixXd Ur = svd.matrixU().leftCols(r);
  const Eigen::MatrixXd Vr = svd.matrixV().leftCols(r);
  const Eigen::MatrixXd At = Ur.transpose() * Y * Vr * sv.head(r).cwiseInverse().asDiagonal();
  Eigen::EigenSolver<Eigen::MatrixXd> es(At);
  if (es.info() != Eigen::Success) return {kNaN, 0.0};
  const Eigen::VectorXcd lambda = es.eigenvalues();
  // Amplitudes of the last snapshot on the (projected) eigenvectors.
  const Eigen::VectorXcd coord = Ur.transpose() * last;
  const Eigen::VectorXcd b = es.eigenvectors().colPivHouseholderQr().solve(coord);
  const double bmax = b.cwiseAbs().maxCoeff();
  std::complex<double> best{kNaN, 0.0};
  double best_abs = -1.0;
  for (Eigen::Index i = 0; i < lambda.size(); ++i) {
    if (std::abs(b(i)) < 1e-3 * bmax) continue;
    if (std::abs(lambda(i)) > best_abs) {
      best_abs = std::abs(lambda(i));
      best = lambda(i);
    }
  }
  if (best.imag() < 0) best = std::conj(best);
  return best;
}

GrowthEstimate growth_per_period(const PeriodSnapshots& snap, int first_analysed, bool linear, double rtol) {
  GrowthEstimate out;
  const std::vector<Eigen::VectorXd>& snapshots = snap.states;
  const int K = static_cast<int>(snapshots.size());  // snapshot k at t = (k+1)τ
  const int k0 = std::max(0, first_analysed - 1);
  std::vector<Eigen::VectorXd> seq;  // states (linear) or increments (nonlinear), true scale relative
  std::vector<double> seq_log;
  if (linear) {
    for (int k = k0; k < K; ++k) {
      seq.push_back(snapshots[k]);
      seq_log.push_back(snap.log_scale[k]);
    }
  } else {
    for (int k = k0; k + 1 < K; ++k) {
      seq.push_back(snapshots[k + 1] - snapshots[k]);
      seq_log.push_back(0.0);
    }
  }
  double amp_ref = 0.0;
  if (!snapshots.empty()) amp_ref = snapshots.back().norm();
  const double floor = 1e4 * rtol * std::max(amp_ref, 1e-300);
  std::vector<int> usable;
  for (std::size_t k = 0; k + 1 < seq.size(); ++k) {
    const double a0 = seq[k].norm(), a1 = seq[k + 1].norm() * std::exp(seq_log[k + 1] - seq_log[k]);
    if (linear || (a0 > floor && a1 > floor)) usable.push_back(static_cast<int>(k));
  }
  if (!linear && !seq.empty() && seq.back().norm() <= floor) out.converged = true;
  if (usable.size() >= 4) {
    const Eigen::Index zdim = seq.front().size();
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(zdim, static_cast<Eigen::Index>(usable.size()));
    Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(zdim, static_cast<Eigen::Index>(usable.size()));
    for (std::size_t c = 0; c < usable.size(); ++c) {
      const int k = usable[c];
      const double nk = seq[k].norm();
      if (!(nk > 0.0)) continue;
      X.col(static_cast<Eigen::Index>(c)) = seq[k] / nk;
      Y.col(static_cast<Eigen::Index>(c)) = seq[k + 1] * (std::exp(seq_log[k + 1] - seq_log[k]) / nk);
    }
    const int last = usable.back() + 1;
    // Singular values below the integration noise (≈ rtol × |z| on every
    // snapshot, relative to the smallest fitted one) are not dynamics.
    double smallest = std::numeric_limits<double>::infinity();
    for (int k : usable) smallest = std::min(smallest, seq[k].norm());
    const double noise = linear ? 30.0 * rtol : 30.0 * rtol * amp_ref / std::max(smallest, 1e-300);
    out.multiplier =
        dominant_multiplier(X, Y, seq[last] / std::max(seq[last].norm(), 1e-300), std::clamp(noise, 1e-9, 0.05));
  }
  return out;
}

Spectrum amplitude_spectrum(const std::vector<double>& x, const std::vector<double>& y, double dt) {
  constexpr double kPi = std::numbers::pi;
  Spectrum s;
  const std::size_t n = x.size();
  if (n < 8) return s;
  std::size_t nfft = 1;
  while (nfft < n) nfft *= 2;
  std::vector<double> w(n);
  double wsum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    w[i] = 0.5 - 0.5 * std::cos(2.0 * kPi * static_cast<double>(i) / static_cast<double>(n - 1));
    wsum += w[i];
  }
  Eigen::FFT<double> fft;
  std::vector<double> mag2(nfft / 2 + 1, 0.0);
  for (const std::vector<double>* comp : {&x, &y}) {
    double mean = 0.0;
    for (double v : *comp) mean += v;
    mean /= static_cast<double>(n);
    std::vector<double> in(nfft, 0.0);
    for (std::size_t i = 0; i < n; ++i) in[i] = ((*comp)[i] - mean) * w[i];
    std::vector<std::complex<double>> out;
    fft.fwd(out, in);
    for (std::size_t k = 0; k <= nfft / 2; ++k) mag2[k] += std::norm(out[k]);
  }
  s.f.resize(nfft / 2 + 1);
  s.amp.resize(nfft / 2 + 1);
  for (std::size_t k = 0; k <= nfft / 2; ++k) {
    s.f[k] = static_cast<double>(k) / (static_cast<double>(nfft) * dt);
    s.amp[k] = 2.0 * std::sqrt(mag2[k]) / wsum;
  }
  s.resolution_hz = 1.0 / (static_cast<double>(n) * dt);
  return s;
}

double dominant_nonharmonic_hz(const Spectrum& sp, double tooth_passing_hz) {
  double best_amp = 0.0, best_f = std::numeric_limits<double>::quiet_NaN(), amp_all = 0.0;
  std::size_t best_k = 0;
  for (std::size_t k = 1; k + 1 < sp.f.size(); ++k) {
    amp_all = std::max(amp_all, sp.amp[k]);
    if (harmonic_index(sp.f[k], tooth_passing_hz, sp.resolution_hz) >= 0) continue;
    if (sp.amp[k] > best_amp && sp.amp[k] >= sp.amp[k - 1] && sp.amp[k] >= sp.amp[k + 1]) {
      best_amp = sp.amp[k];
      best_k = k;
    }
  }
  if (best_k > 0 && best_amp > 1e-9 * amp_all) {
    // Parabolic refinement on the log amplitude.
    const double l0 = std::log(std::max(sp.amp[best_k - 1], 1e-300)), l1 = std::log(sp.amp[best_k]),
                 l2 = std::log(std::max(sp.amp[best_k + 1], 1e-300));
    const double den = l0 - 2 * l1 + l2;
    const double shift = den < 0 ? std::clamp(0.5 * (l0 - l2) / den, -0.5, 0.5) : 0.0;
    best_f = sp.f[best_k] + shift * (sp.f[1] - sp.f[0]);
  }
  return best_f;
}

std::vector<SpectralPeak> tooth_passing_harmonics(const Spectrum& sp, double tooth_passing_hz,
                                                  double max_frequency_hz) {
  std::vector<SpectralPeak> out;
  const double ftp = tooth_passing_hz;
  for (int k = 1; sp.f.size() > 1 && k * ftp <= std::min(sp.f.back(), max_frequency_hz) && k <= 60; ++k) {
    SpectralPeak pk;
    pk.frequency_hz = k * ftp;
    pk.harmonic = k;
    const auto c = static_cast<std::size_t>(std::llround(k * ftp / (sp.f[1] - sp.f[0])));
    for (std::size_t j = c >= 3 ? c - 3 : 0; j <= c + 3 && j < sp.f.size(); ++j)
      pk.amplitude_m = std::max(pk.amplitude_m, sp.amp[j]);
    out.push_back(pk);
  }
  return out;
}

VerdictOutcome decide_verdict(const VerdictInput& in) {
  VerdictOutcome out;
  std::ostringstream why;
  why.precision(4);
  const double growth = std::abs(in.growth.multiplier);
  const double air_fraction = in.air.fraction();
  const int analysed = in.analysed_periods;
  if (in.linear) {
    if (std::isnan(growth)) {
      out.verdict = SimulationVerdict::kStable;
      why << "no motion to analyse";
    } else {
      out.verdict = growth < 1.0 ? SimulationVerdict::kStable : SimulationVerdict::kChatter;
      why << "linear mode: growth per period |mu| = " << growth << " over the last " << analysed << " periods ("
          << (growth < 1.0 ? "< 1: decays" : ">= 1: grows") << ")";
    }
  } else if (in.growth.converged) {
    out.verdict = SimulationVerdict::kStable;
    why << "periodic: the once-per-period increments fell below " << 1e4 * in.relative_tolerance
        << " of the amplitude (forced vibration only)";
  } else if (std::isnan(growth)) {
    out.verdict = air_fraction > kAirFraction ? SimulationVerdict::kChatter : SimulationVerdict::kStable;
    why << "the tool was in air during " << 100.0 * air_fraction << " % of the cutting-arc time in the last "
        << analysed << " periods";
  } else {
    const bool air = air_fraction > kAirFraction;
    const double early = in.air.early_fraction();
    const double late = in.air.late_fraction();
    // Persisting contact loss: at least half as often in the second half of
    // the window as in the first (a decaying transient loses contact less
    // and less; a saturated chatter vibration keeps doing it).
    const bool persisting = air && late > kAirFraction && late >= 0.5 * early;
    const double threshold = persisting ? 1.0 - kSaturatedMargin : 1.0;
    out.verdict = growth < threshold ? SimulationVerdict::kStable : SimulationVerdict::kChatter;
    why << "once-per-period increments " << (growth < 1.0 ? "decay" : "grow") << " by |mu| = " << growth
        << " per period over the last " << analysed << " periods";
    if (air)
      why << "; the tool was in air during " << 100.0 * air_fraction << " % of the cutting-arc time ("
          << 100.0 * early << " % then " << 100.0 * late << " % in the two halves"
          << (persisting ? ": persisting, saturated chatter has |mu| = 1" : ": dying out") << ")";
    else
      why << "; the tool stayed in the cut";
  }
  out.measure = why.str();
  return out;
}

}  // namespace chatter::detail
