// Time-domain simulation on SUNDIALS CVODE (see include/chatter/time_domain.hpp
// for the equations and docs/time_domain.md for the design).
#include "chatter/time_domain.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <unsupported/Eigen/FFT>

#include "chatter/error.hpp"
#include "chatter/transfer_function.hpp"
#include "sundials_raii.hpp"

namespace chatter {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Delay-propagated images of the start discontinuity that are stop points:
// the k-th image is a jump in the k-th derivative, beyond Adams order 5 after 6.
constexpr int kStartImages = 6;
// Delay-propagated images t_r + kτ of a chip zero crossing t_r that are stop
// points. The force has a kink at t_r (max(h, 0)), so d³r/dt³ jumps there and
// the delayed term jumps in its 3rd derivative at t_r + τ, its 5th at
// t_r + 2τ. With multiple regeneration the surface itself keeps the kink: the
// chip jumps in slope at t_r + τ, then in the 3rd and 5th derivatives.
constexpr int kRootImagesSingle = 2;
constexpr int kRootImagesMultiple = 3;
constexpr int kMaxAdamsOrder = 5;
// Nonlinear verdict: fraction of the cutting-arc time in air that counts as
// leaving the cut, and the margin below |mu| = 1 that then counts as chatter.
constexpr double kAirFraction = 0.005;
constexpr double kSaturatedMargin = 0.02;

// ---------------------------------------------------------------------------
// History ring buffer: one entry per stored instant (uniform grid + events),
// sorted by time; quintic Hermite interpolation of r between neighbours.
struct HistoryEntry {
  double t = 0.0;
  double r[2] = {0, 0}, v[2] = {0, 0};
  double a_left[2] = {0, 0}, a_right[2] = {0, 0};
};

class History {
 public:
  History(std::size_t capacity, int teeth) : teeth_(teeth) { reserve(capacity); }

  void push(const HistoryEntry& e, const double* gaps) {
    if (count_ == buf_.size()) reserve(2 * buf_.size());
    const std::size_t i = (head_ + count_) % buf_.size();
    buf_[i] = e;
    std::copy(gaps, gaps + teeth_, gap_.begin() + static_cast<std::ptrdiff_t>(i * teeth_));
    ++count_;
    max_count_ = std::max(max_count_, count_);
  }
  /// Drops entries while the second oldest is still at or before `t`.
  void drop_before(double t) {
    while (count_ > 2 && at(1).t <= t) {
      head_ = (head_ + 1) % buf_.size();
      --count_;
      hint_ = 0;
    }
  }
  std::size_t capacity() const { return buf_.size(); }
  std::size_t max_count() const { return max_count_; }
  const HistoryEntry& newest() const { return at(count_ - 1); }
  HistoryEntry& newest_mutable() { return buf_[(head_ + count_ - 1) % buf_.size()]; }
  double* newest_gaps() { return &gap_[((head_ + count_ - 1) % buf_.size()) * teeth_]; }

  /// r(t) (m). Outside the stored range the nearest interval's polynomial
  /// is used (counted in extrapolations()).
  void displacement(double t, double out[2]) const {
    const std::size_t k = interval(t);
    const HistoryEntry& e0 = at(k);
    const HistoryEntry& e1 = at(k + 1);
    const double h = e1.t - e0.t;
    if (!(h > 0.0)) {
      out[0] = e1.r[0];
      out[1] = e1.r[1];
      return;
    }
    const double s = (t - e0.t) / h, s2 = s * s, s3 = s2 * s, s4 = s3 * s, s5 = s4 * s;
    const double h0 = 1 - 10 * s3 + 15 * s4 - 6 * s5;
    const double h1 = s - 6 * s3 + 8 * s4 - 3 * s5;
    const double h2 = 0.5 * (s2 - 3 * s3 + 3 * s4 - s5);
    const double h3 = 10 * s3 - 15 * s4 + 6 * s5;
    const double h4 = -4 * s3 + 7 * s4 - 3 * s5;
    const double h5 = 0.5 * (s3 - 2 * s4 + s5);
    for (int c = 0; c < 2; ++c)
      out[c] = e0.r[c] * h0 + e0.v[c] * h * h1 + e0.a_right[c] * h * h * h2 + e1.r[c] * h3 + e1.v[c] * h * h4 +
               e1.a_left[c] * h * h * h5;
  }
  /// Gap (m) left in air by tooth `tooth` at time t, linear interpolation.
  double gap(double t, int tooth) const {
    const std::size_t k = interval(t);
    const std::size_t i0 = (head_ + k) % buf_.size(), i1 = (head_ + k + 1) % buf_.size();
    const double t0 = buf_[i0].t, t1 = buf_[i1].t;
    const double g0 = gap_[i0 * teeth_ + tooth], g1 = gap_[i1 * teeth_ + tooth];
    if (!(t1 > t0)) return g1;
    const double s = std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
    return g0 + s * (g1 - g0);
  }
  void scale(double factor) {
    for (std::size_t k = 0; k < count_; ++k) {
      HistoryEntry& e = buf_[(head_ + k) % buf_.size()];
      for (int c = 0; c < 2; ++c) {
        e.r[c] *= factor;
        e.v[c] *= factor;
        e.a_left[c] *= factor;
        e.a_right[c] *= factor;
      }
    }
  }
  long extrapolations() const { return extrapolations_; }

 private:
  const HistoryEntry& at(std::size_t k) const { return buf_[(head_ + k) % buf_.size()]; }
  // Index k with at(k).t <= t <= at(k+1).t (clamped to the stored range).
  std::size_t interval(double t) const {
    if (t < at(0).t || t > at(count_ - 1).t) ++extrapolations_;
    if (hint_ + 1 < count_ && at(hint_).t <= t && t <= at(hint_ + 1).t) return hint_;
    if (hint_ + 2 < count_ && at(hint_ + 1).t <= t && t <= at(hint_ + 2).t) return ++hint_;
    std::size_t lo = 0, hi = count_ - 1;  // invariant: answer in [lo, hi)
    while (hi - lo > 1) {
      const std::size_t mid = (lo + hi) / 2;
      if (at(mid).t <= t) lo = mid;
      else hi = mid;
    }
    hint_ = lo;
    return lo;
  }
  void reserve(std::size_t cap) {
    cap = std::max<std::size_t>(cap, 4);
    std::vector<HistoryEntry> nb(cap);
    std::vector<double> ng(cap * teeth_, 0.0);
    for (std::size_t k = 0; k < count_; ++k) {
      const std::size_t i = (head_ + k) % buf_.size();
      nb[k] = buf_[i];
      std::copy(gap_.begin() + static_cast<std::ptrdiff_t>(i * teeth_),
                gap_.begin() + static_cast<std::ptrdiff_t>((i + 1) * teeth_), ng.begin() + static_cast<std::ptrdiff_t>(k * teeth_));
    }
    buf_.swap(nb);
    gap_.swap(ng);
    head_ = 0;
    hint_ = 0;
  }

  int teeth_;
  std::vector<HistoryEntry> buf_;
  std::vector<double> gap_;
  std::size_t head_ = 0, count_ = 0, max_count_ = 0;
  mutable std::size_t hint_ = 0;
  mutable long extrapolations_ = 0;
};

// ---------------------------------------------------------------------------
// The right-hand side and everything it needs.
struct Diagnostics {
  double force[2] = {0, 0};
  double chip_max = 0.0;
  bool any_in_arc = false;
  bool in_cut = false;
  /// Every tooth in the arc is in air by more than the contact margin.
  bool in_air = false;
};

class Model {
 public:
  Model(const StructuralModel& model, const Process& process, const SimulationSettings& s, double tau)
      : mm_(modal_matrices(model)), process_(process), settings_(s), tau_(tau) {
    n_ = static_cast<int>(mm_.omega.size());
    tool_modes_ = static_cast<int>(model.tool.modes.size());
    milling_ = process.operation() == Operation::kMilling;
    teeth_ = milling_ ? process.milling_parameters().teeth : 1;
    omega_spindle_ = 2.0 * kPi * s.spindle_rpm / 60.0;
    if (milling_) {
      kt_ = process.milling_parameters().tangential_coefficient_n_per_m2;
      kr_ = process.milling_parameters().radial_coefficient_n_per_m2;
      phi_en_ = process.entry_angle();
      phi_ex_ = process.exit_angle();
    } else {
      kf_ = process.turning_parameters().feed_force_coefficient_n_per_m2;
    }
    in_arc_.assign(teeth_, milling_ ? 0 : 1);
    chips_.assign(teeth_, 0.0);
  }

  int n() const { return n_; }
  int teeth() const { return teeth_; }
  bool milling() const { return milling_; }
  const ModalMatrices& modal() const { return mm_; }
  int tool_modes() const { return tool_modes_; }

  void attach(History* h) { history_ = h; }
  /// Sets which teeth are inside the cutting arc for the segment around `t`.
  void set_segment(double t_mid) {
    if (!milling_) return;
    for (int j = 0; j < teeth_; ++j) {
      const double phi = wrap(angle(t_mid, j));
      in_arc_[j] = (phi >= phi_en_ && phi <= phi_ex_) ? 1 : 0;
    }
  }
  double angle(double t, int j) const { return omega_spindle_ * t + 2.0 * kPi * j / teeth_; }
  static double wrap(double phi) {
    phi = std::fmod(phi, 2.0 * kPi);
    return phi < 0 ? phi + 2.0 * kPi : phi;
  }
  /// Times in [0, t_end] at which a tooth enters or leaves the arc (milling).
  std::vector<double> arc_events(double t_end) const {
    std::vector<double> out;
    if (!milling_) return out;
    const double pitch = 2.0 * kPi / teeth_;
    for (double phi : {phi_en_, phi_ex_}) {
      const double t0 = std::fmod(phi, pitch) / omega_spindle_;
      for (long k = 0; t0 + static_cast<double>(k) * tau_ <= t_end; ++k) out.push_back(t0 + static_cast<double>(k) * tau_);
    }
    return out;
  }

  /// Unclipped chip thickness of every tooth in the arc at time t for state
  /// q (m); teeth outside the arc get +1 (a constant, for root finding).
  void chips(double t, const double* q, double* h) const {
    double r[2] = {0, 0};
    relative(q, r);
    double rd[2];
    history_->displacement(t - tau_, rd);
    const double dx = r[0] - rd[0], dy = r[1] - rd[1];
    const double feed = settings_.linear ? 0.0 : settings_.feed_m;
    for (int j = 0; j < teeth_; ++j) {
      if (!in_arc_[j]) {
        h[j] = 1.0;
        continue;
      }
      double hj;
      if (milling_) {
        const double phi = angle(t, j);
        const double sn = std::sin(phi), cs = std::cos(phi);
        hj = feed * sn + sn * dx + cs * dy;
      } else {
        hj = feed + dx;
      }
      if (settings_.multiple_regeneration && !settings_.linear)
        hj -= history_->gap(t - tau_, (j + teeth_ - 1) % teeth_);
      h[j] = hj;
    }
  }

  /// ẏ = f(t, y); fills `diag` when given. y = [q; q̇].
  void rhs(double t, const double* y, double* ydot, Diagnostics* diag) const {
    ++rhs_count_;
    const double* q = y;
    const double* qd = y + n_;
    chips(t, q, chips_.data());
    double F[2] = {0, 0};
    const double a = settings_.depth_m;
    double chip_max = 0.0;
    bool any_arc = false, cutting = false, touching = false;
    for (int j = 0; j < teeth_; ++j) {
      if (!in_arc_[j]) continue;
      any_arc = true;
      const double h = chips_[j];
      const double hc = settings_.linear ? h : std::max(0.0, h);
      if (h > 0.0) cutting = true;
      if (h > -air_margin_) touching = true;
      chip_max = std::max(chip_max, settings_.linear ? std::abs(h) : hc);
      if (milling_) {
        const double phi = angle(t, j);
        const double sn = std::sin(phi), cs = std::cos(phi);
        F[0] += -a * (kt_ * cs + kr_ * sn) * hc;
        F[1] += a * (kt_ * sn - kr_ * cs) * hc;
      } else {
        F[0] += -a * kf_ * hc;
      }
    }
    for (int i = 0; i < n_; ++i) {
      const double w = mm_.omega(i);
      ydot[i] = qd[i];
      ydot[n_ + i] = -2.0 * mm_.damping_ratio(i) * w * qd[i] - w * w * q[i] +
                     (mm_.S(0, i) * F[0] + mm_.S(1, i) * F[1]) / mm_.mass_kg(i);
    }
    if (diag) {
      diag->force[0] = F[0];
      diag->force[1] = F[1];
      diag->chip_max = chip_max;
      diag->any_in_arc = any_arc;
      diag->in_cut = cutting;
      diag->in_air = any_arc && !touching && !settings_.linear;
    }
  }

  void relative(const double* q, double r[2]) const {
    r[0] = r[1] = 0.0;
    for (int i = 0; i < n_; ++i) {
      r[0] += mm_.S(0, i) * q[i];
      r[1] += mm_.S(1, i) * q[i];
    }
  }

  long rhs_count() const { return rhs_count_; }
  /// A tooth counts as in air only when its chip is below −margin (m): the
  /// chip of a converged forced response touches 0 at the arc ends.
  void set_air_margin(double margin) { air_margin_ = margin; }
  const std::vector<char>& in_arc() const { return in_arc_; }

 private:
  ModalMatrices mm_;
  const Process& process_;
  const SimulationSettings& settings_;
  double tau_;
  int n_ = 0, tool_modes_ = 0, teeth_ = 1;
  bool milling_ = false;
  double omega_spindle_ = 0.0, kt_ = 0.0, kr_ = 0.0, kf_ = 0.0, phi_en_ = 0.0, phi_ex_ = 0.0;
  std::vector<char> in_arc_;
  History* history_ = nullptr;
  mutable std::vector<double> chips_;
  mutable long rhs_count_ = 0;
  double air_margin_ = 0.0;
};

int cvode_rhs(double t, N_Vector y, N_Vector ydot, void* user) {
  static_cast<const Model*>(user)->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot), nullptr);
  return 0;
}
int cvode_roots(double t, N_Vector y, double* g, void* user) {
  static_cast<const Model*>(user)->chips(t, N_VGetArrayPointer(y), g);
  return 0;
}

// ---------------------------------------------------------------------------
// Exact DMD of a period-to-period map from snapshot pairs (x_k -> y_k):
// the eigenvalue of largest modulus among the modes that carry at least
// 1e-3 of the final snapshot. Returns NaN when there is nothing to fit.
std::complex<double> dominant_multiplier(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y,
                                         const Eigen::VectorXd& last, double rank_tolerance) {
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

struct Spectrum {
  std::vector<double> f, amp;
  double resolution_hz = 0.0;
};

Spectrum amplitude_spectrum(const std::vector<double>& x, const std::vector<double>& y, double dt) {
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

}  // namespace

std::string to_string(SimulationVerdict v) { return v == SimulationVerdict::kStable ? "stable" : "chatter"; }

std::string TimeDomainOptions::validate() const {
  std::ostringstream os;
  if (!(relative_tolerance >= 1e-12 && relative_tolerance <= 1e-2))
    os << "relative_tolerance = " << relative_tolerance << ": must be in [1e-12, 1e-2]";
  else if (samples_per_period < 8)
    os << "samples_per_period = " << samples_per_period << ": must be >= 8";
  else if (samples_per_vibration_cycle < 8)
    os << "samples_per_vibration_cycle = " << samples_per_vibration_cycle << ": must be >= 8";
  else if (max_samples_per_period < samples_per_period)
    os << "max_samples_per_period = " << max_samples_per_period << ": must be >= samples_per_period";
  else if (max_steps < 1000)
    os << "max_steps = " << max_steps << ": must be >= 1000";
  else if (periods < 20)
    os << "periods = " << periods << ": must be >= 20";
  else if (!(depth_max_m > 0.0 && std::isfinite(depth_max_m)))
    os << "depth_max_m = " << depth_max_m << ": must be > 0 and finite";
  else if (!(depth_tolerance > 0.0 && depth_tolerance < 0.5))
    os << "depth_tolerance = " << depth_tolerance << ": must be in (0, 0.5)";
  else if (!(feed_m >= 0.0 && std::isfinite(feed_m)))
    os << "feed_m = " << feed_m << ": must be >= 0 and finite";
  return os.str();
}

TimeDomainSimulator::TimeDomainSimulator(StructuralModel model, Process process, TimeDomainOptions options)
    : model_(std::move(model)), process_(std::move(process)), options_(options) {
  const std::string why = options_.validate();
  if (!why.empty()) throw InputError("time-domain options: " + why);
  if (model_.mode_count() == 0)
    throw InputError("structural model: both bodies are rigid: give at least one mode");
  if (model_.has_measured())
    throw InputError("time-domain needs modes, not measured FRFs: fit modes to the measurement first "
                     "(chatter fit) and use them in the config");
}

SimulationResult TimeDomainSimulator::simulate(const SimulationSettings& s) const {
  if (!(s.spindle_rpm > 0.0 && std::isfinite(s.spindle_rpm)))
    throw InputError("spindle speed " + std::to_string(s.spindle_rpm) + " rev/min: must be > 0");
  if (!(s.depth_m >= 0.0 && std::isfinite(s.depth_m)))
    throw InputError("depth " + std::to_string(s.depth_m * 1e3) + " mm: must be >= 0");
  if (s.periods < 4) throw InputError("periods = " + std::to_string(s.periods) + ": must be >= 4");
  if (!(s.feed_m >= 0.0 && std::isfinite(s.feed_m)))
    throw InputError("feed " + std::to_string(s.feed_m * 1e3) + " mm: must be >= 0");
  if (!(s.analysed_fraction > 0.0 && s.analysed_fraction <= 1.0))
    throw InputError("analysed_fraction must be in (0, 1]");

  const double tau = process_.delay_s(s.spindle_rpm);
  Model m(model_, process_, s, tau);
  const int n = m.n();
  const int teeth = m.teeth();
  if (!s.initial_state.empty() && static_cast<int>(s.initial_state.size()) != 2 * n)
    throw InputError("initial state has " + std::to_string(s.initial_state.size()) + " values: needs 2 x " +
                     std::to_string(n) + " modes");

  double f_max = 0.0;
  for (int i = 0; i < n; ++i) f_max = std::max(f_max, m.modal().omega(i) / (2.0 * kPi));
  const double need = std::ceil(options_.samples_per_vibration_cycle * tau * f_max);
  if (need > options_.max_samples_per_period)
    throw InputError("time-domain: " + std::to_string(s.spindle_rpm) + " rev/min needs " +
                     std::to_string(static_cast<long>(need)) + " history samples per delay (limit " +
                     std::to_string(options_.max_samples_per_period) + "): raise the speed");
  const int M = std::max(options_.samples_per_period, static_cast<int>(need));
  const double dt = tau / M;

  // Initial state and displacement scale (for the absolute tolerances).
  std::vector<double> y0(2 * n, 0.0);
  if (!s.initial_state.empty()) {
    y0 = s.initial_state;
  } else if (s.linear || s.feed_m == 0.0) {
    for (int i = 0; i < n; ++i) {
      y0[i] = 1e-6;
      y0[n + i] = 0.5e-6 * m.modal().omega(i);
    }
  }
  double scale = 0.0;
  for (int i = 0; i < n; ++i) scale = std::max(scale, std::abs(y0[i]));
  if (!s.linear && s.feed_m > 0.0) {
    double kmin = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i)
      kmin = std::min(kmin, m.modal().mass_kg(i) * m.modal().omega(i) * m.modal().omega(i));
    const double coeff = m.milling() ? process_.milling_parameters().tangential_coefficient_n_per_m2
                                     : process_.turning_parameters().feed_force_coefficient_n_per_m2;
    scale = std::max(scale, s.depth_m * coeff * s.feed_m / kmin);
  }
  if (!(scale > 0.0)) scale = 1e-9;
  m.set_air_margin(1e-6 * std::max(scale, s.feed_m));

  // History: constant at the initial displacement before t = 0.
  // Entries held: about 1.5 delays of grid samples, the arc events and start
  // images in that span, at most root_cap + 1 root stops per period and as
  // many stops at each of their root_images delay images.
  const int root_cap = 8 * teeth + 8;
  const int root_images = s.linear ? 0 : (s.multiple_regeneration ? kRootImagesMultiple : kRootImagesSingle);
  const std::size_t capacity =
      static_cast<std::size_t>(M + M / 2 + 2 * (root_cap + 1) * (1 + root_images) + 4 * teeth + 16);
  History history(capacity, teeth);
  m.attach(&history);
  std::vector<double> zero_gaps(teeth, 0.0);
  {
    HistoryEntry e;
    m.relative(y0.data(), e.r);
    e.t = -tau - 2.0 * dt;
    history.push(e, zero_gaps.data());
    e.t = 0.0;
    history.push(e, zero_gaps.data());
  }

  // Stop points.
  const double t_end = s.periods * tau;
  std::vector<double> stops = m.arc_events(t_end);
  for (int k = 1; k <= kStartImages && k <= s.periods; ++k) stops.push_back(k * tau);
  stops.push_back(t_end);
  std::sort(stops.begin(), stops.end());
  {
    std::vector<double> merged;
    for (double t : stops) {
      if (t <= 1e-9 * tau || t >= t_end - 1e-9 * tau) continue;
      if (merged.empty() || t - merged.back() > 1e-9 * tau) merged.push_back(t);
    }
    merged.push_back(t_end);  // always the last stop, exactly
    stops.swap(merged);
  }

  // SUNDIALS objects.
  sundials::Context ctx;
  sundials::SerialVector y(2 * n, ctx), atol(2 * n, ctx);
  std::copy(y0.begin(), y0.end(), y.data());
  const double rtol = options_.relative_tolerance;
  for (int i = 0; i < n; ++i) {
    const double sc = std::max(1e-300, scale);
    atol.data()[i] = rtol * sc;
    atol.data()[n + i] = rtol * sc * m.modal().omega(i);
  }
  sundials::Cvode cv(CV_ADAMS, ctx);
  void* mem = cv.get();
  cv.check(CVodeInit(mem, cvode_rhs, 0.0, y), "CVodeInit");
  cv.check(CVodeSVtolerances(mem, rtol, atol), "CVodeSVtolerances");
  sundials::FixedPointSolver nls(y, 0, ctx);
  cv.check(CVodeSetNonlinearSolver(mem, nls), "CVodeSetNonlinearSolver");
  cv.check(CVodeSetUserData(mem, &m), "CVodeSetUserData");
  cv.check(CVodeSetMaxOrd(mem, kMaxAdamsOrder), "CVodeSetMaxOrd");
  cv.check(CVodeSetMaxStep(mem, 0.5 * tau), "CVodeSetMaxStep");
  cv.check(CVodeSetMaxNumSteps(mem, options_.max_steps), "CVodeSetMaxNumSteps");
  const bool use_roots = !s.linear;
  if (use_roots) {
    cv.check(CVodeRootInit(mem, teeth, cvode_roots), "CVodeRootInit");
    cv.check(CVodeSetNoInactiveRootWarn(mem), "CVodeSetNoInactiveRootWarn");
  }

  SimulationResult res;
  res.delay_s = tau;
  res.tooth_passing_hz = 1.0 / tau;
  res.periods = s.periods;
  res.samples_per_period = M;
  const int first_analysed = std::clamp(static_cast<int>(std::floor(s.periods * (1.0 - s.analysed_fraction))), 0,
                                        s.periods - 2);
  res.analysed_from_period = first_analysed;

  // Per-period observables for the DMD: r at the M grid points of the period
  // just ended, plus the modal state at its end (velocities / ω).
  const int zdim = 2 * M + 2 * n;
  std::vector<Eigen::VectorXd> snapshots;
  std::vector<double> snapshot_log_scale;
  Eigen::VectorXd period_r(2 * M);
  double log_scale = 0.0;  // linear mode: true state = stored × exp(log_scale)

  std::vector<double> win_x, win_y;  // uniform samples of r over the analysed window
  std::size_t arc_samples = 0, air_samples = 0;
  // The same in the first and second half of the analysed window.
  std::size_t arc_early = 0, air_early = 0, arc_late = 0, air_late = 0;
  double max_amp = 0.0;

  std::vector<double> ydot(2 * n);
  Diagnostics dg;
  auto make_sample = [&](double t, const double* yy, const Diagnostics& d) {
    SeriesSample smp;
    smp.t_s = t;
    const auto& mm = m.modal();
    const double ex = std::exp(log_scale);
    for (int i = 0; i < n; ++i) {
      // S column = ±u_i; the body's own displacement is u_i q_i.
      const double sign = i < m.tool_modes() ? 1.0 : -1.0;
      const double dx = sign * mm.S(0, i) * yy[i] * ex, dy = sign * mm.S(1, i) * yy[i] * ex;
      if (i < m.tool_modes()) {
        smp.tool_x_m += dx;
        smp.tool_y_m += dy;
      } else {
        smp.workpiece_x_m += dx;
        smp.workpiece_y_m += dy;
      }
    }
    smp.rel_x_m = smp.tool_x_m - smp.workpiece_x_m;
    smp.rel_y_m = smp.tool_y_m - smp.workpiece_y_m;
    smp.force_x_n = d.force[0] * ex;
    smp.force_y_n = d.force[1] * ex;
    smp.chip_m = d.chip_max * (s.linear ? ex : 1.0);
    smp.in_cut = d.in_cut;
    return smp;
  };

  // Stores a history entry at the current (t, y): a_left from the segment
  // that ends here, a_right from the one that starts (same when no event).
  auto store = [&](double t, bool segment_changes, double t_next_mid) {
    HistoryEntry e;
    e.t = t;
    m.relative(y.data(), e.r);
    m.rhs(t, y.data(), ydot.data(), &dg);
    // ṙ and r̈ from q̇ and q̈.
    double v[2] = {0, 0}, a[2] = {0, 0};
    for (int i = 0; i < n; ++i) {
      v[0] += m.modal().S(0, i) * ydot[i];
      v[1] += m.modal().S(1, i) * ydot[i];
      a[0] += m.modal().S(0, i) * ydot[n + i];
      a[1] += m.modal().S(1, i) * ydot[n + i];
    }
    e.v[0] = v[0];
    e.v[1] = v[1];
    e.a_left[0] = e.a_right[0] = a[0];
    e.a_left[1] = e.a_right[1] = a[1];
    Diagnostics left = dg;
    if (segment_changes) {
      m.set_segment(t_next_mid);
      m.rhs(t, y.data(), ydot.data(), &dg);
      double ar[2] = {0, 0};
      for (int i = 0; i < n; ++i) {
        ar[0] += m.modal().S(0, i) * ydot[n + i];
        ar[1] += m.modal().S(1, i) * ydot[n + i];
      }
      e.a_right[0] = ar[0];
      e.a_right[1] = ar[1];
    }
    // Gaps in air (multiple regeneration), from the chips after the event.
    std::vector<double> gaps(teeth, 0.0);
    if (s.multiple_regeneration && !s.linear) {
      std::vector<double> h(teeth);
      m.chips(t, y.data(), h.data());
      for (int j = 0; j < teeth; ++j) gaps[j] = m.in_arc()[j] ? std::max(0.0, -h[j]) : 0.0;
    }
    history.push(e, gaps.data());
    history.drop_before(t - 1.5 * tau);
    return left;
  };

  m.set_segment(stops.empty() ? 0.5 * dt : 0.5 * std::min(stops.front(), dt));
  // Right-limit acceleration at t = 0 for the newest (t = 0) entry.
  {
    m.rhs(0.0, y.data(), ydot.data(), &dg);
    HistoryEntry& e0 = history.newest_mutable();
    double a[2] = {0, 0}, v[2] = {0, 0};
    for (int i = 0; i < n; ++i) {
      v[0] += m.modal().S(0, i) * ydot[i];
      v[1] += m.modal().S(1, i) * ydot[i];
      a[0] += m.modal().S(0, i) * ydot[n + i];
      a[1] += m.modal().S(1, i) * ydot[n + i];
    }
    (void)v;
    e0.a_right[0] = a[0];
    e0.a_right[1] = a[1];
    if (s.record_series) res.series.push_back(make_sample(0.0, y.data(), dg));
    res.once_per_period.push_back(make_sample(0.0, y.data(), dg));
  }

  // Pending images of the chip zero crossings, sorted; they lie within
  // root_images delays ahead, so at most about (root_cap + 1) x root_images
  // are held, whatever the simulated time.
  std::deque<double> images;
  std::size_t next_stop = 0;
  long restarts = 0, root_stops = 0;
  // The next stop (skip = 0) or the one after it (skip = 1): the earlier of
  // the fixed list and the pending images; two within 1e-9 τ are one.
  auto next_event = [&](int skip) {
    double a[2] = {t_end, t_end};
    std::size_t i = next_stop, j = 0;
    for (int k = 0; k < 2; ++k) {
      const double si = i < stops.size() ? stops[i] : t_end, ij = j < images.size() ? images[j] : t_end;
      a[k] = std::min(si, ij);
      while (i < stops.size() && stops[i] - a[k] <= 1e-9 * tau) ++i;
      while (j < images.size() && images[j] - a[k] <= 1e-9 * tau) ++j;
    }
    return a[skip];
  };
  // Passes the event at tt (the fixed stop and / or the images there).
  auto pass_event = [&](double tt) {
    if (next_stop < stops.size() && stops[next_stop] - tt <= 1e-9 * tau) ++next_stop;
    while (!images.empty() && images.front() - tt <= 1e-9 * tau) images.pop_front();
  };
  // A chip zero crossing at tr: count it and queue its delay images.
  auto on_root = [&](double tr) {
    ++root_stops;
    for (int k = 1; k <= root_images; ++k) {
      const double ti = tr + k * tau;
      if (ti >= t_end - 1e-9 * tau) break;
      const auto at = std::lower_bound(images.begin(), images.end(), ti - 1e-9 * tau);
      if (at != images.end() && *at - ti <= 1e-9 * tau) continue;  // already there (e.g. roots at tooth exit)
      images.insert(at, ti);
    }
  };
  // A time inside the segment that starts at tt and ends at the next event
  // t_next (the arc test at an event itself would be ambiguous).
  auto segment_mid = [&](double tt, double t_next) {
    return 0.5 * (tt + (t_next > tt + 1e-9 * tau ? std::min(t_next, tt + dt) : tt + dt));
  };
  cv.check(CVodeSetStopTime(mem, stops[0]), "CVodeSetStopTime");
  double t = 0.0;
  int roots_this_period = 0;
  bool roots_on = use_roots;
  const long total = static_cast<long>(s.periods) * M;
  long steps_done = 0, rhs_done = 0;  // CVodeReInit resets CVODE's counters
  auto restart = [&](double tt) {
    long ns = 0, nf = 0;
    CVodeGetNumSteps(mem, &ns);
    CVodeGetNumRhsEvals(mem, &nf);
    steps_done += ns;
    rhs_done += nf;
    cv.check(CVodeReInit(mem, tt, y), "CVodeReInit");
    cv.check(CVodeSetStopTime(mem, next_event(0)), "CVodeSetStopTime");
    ++restarts;
  };

  for (long i = 1; i <= total; ++i) {
    const double target = static_cast<double>(i) * tau / M;
    bool root_at_grid = false;
    while (true) {
      const int flag = CVode(mem, target, y, &t, CV_NORMAL);
      cv.check(flag, "CVode");
      if (t >= target - 1e-12 * tau) {  // at the grid point (possibly also a stop or a root)
        if (flag == CV_ROOT_RETURN) {
          on_root(t);
          root_at_grid = true;
        }
        break;
      }
      if (next_event(0) - t <= 1e-9 * tau) {
        // An event before the grid point (reached as a stop, or a root that
        // fell on it): step onto it and change segment.
        const double t_next = next_event(1);
        store(t, true, segment_mid(t, t_next));
        pass_event(t);
        if (flag == CV_ROOT_RETURN) on_root(t);
        restart(t);
        continue;
      }
      if (flag == CV_ROOT_RETURN) {
        on_root(t);
        store(t, false, 0.0);
        if (++roots_this_period > root_cap && roots_on) {
          cv.check(CVodeRootInit(mem, 0, nullptr), "CVodeRootInit");
          roots_on = false;
        }
        restart(t);
        continue;
      }
      throw NumericalError("time-domain: internal error: CVODE stopped at t = " + std::to_string(t) +
                           " s, neither a grid point, a stop nor a root");
    }
    t = target;
    const bool at_stop = std::abs(next_event(0) - target) <= 1e-9 * tau;
    const double t_next = at_stop ? next_event(1) : t_end;
    const Diagnostics left = store(target, at_stop, segment_mid(target, t_next));
    if (at_stop) pass_event(target);
    const long period = (i - 1) / M;  // 0-based period this sample ends or lies in
    const long in_period = (i - 1) % M;
    period_r(2 * in_period) = history.newest().r[0];
    period_r(2 * in_period + 1) = history.newest().r[1];
    const SeriesSample smp = make_sample(target, y.data(), left);
    if (s.record_series) res.series.push_back(smp);
    if (period >= first_analysed) {
      win_x.push_back(smp.rel_x_m);
      win_y.push_back(smp.rel_y_m);
      max_amp = std::max(max_amp, std::hypot(smp.rel_x_m, smp.rel_y_m));
      if (left.any_in_arc) {
        ++arc_samples;
        if (left.in_air) ++air_samples;
        const bool late = 2 * (period - first_analysed) >= (s.periods - first_analysed);
        (late ? arc_late : arc_early) += 1;
        if (left.in_air) (late ? air_late : air_early) += 1;
      }
    }
    const bool period_end = (i % M) == 0;
    if (period_end) {
      res.once_per_period.push_back(smp);
      Eigen::VectorXd z(zdim);
      z.head(2 * M) = period_r;
      for (int k = 0; k < n; ++k) {
        z(2 * M + k) = y.data()[k];
        z(2 * M + n + k) = y.data()[n + k] / m.modal().omega(k);
      }
      snapshots.push_back(z);
      snapshot_log_scale.push_back(log_scale);
      roots_this_period = 0;
      bool need_restart = at_stop;
      if (use_roots && !roots_on) {
        cv.check(CVodeRootInit(mem, teeth, cvode_roots), "CVodeRootInit");
        roots_on = true;
        need_restart = true;
      }
      if (s.linear) {
        // Keep the state near the initial scale (linear: exact rescaling).
        double norm = 0.0;
        for (int k = 0; k < n; ++k) norm = std::max(norm, std::abs(y.data()[k]));
        if (norm > 0.0 && (norm > 1e3 * scale || norm < 1e-3 * scale)) {
          const double f = scale / norm;
          for (int k = 0; k < 2 * n; ++k) y.data()[k] *= f;
          history.scale(f);
          log_scale -= std::log(f);
          need_restart = true;
        }
      }
      if (need_restart) root_at_grid = true;
    }
    if (at_stop || root_at_grid) restart(target);
  }

  long nsteps = 0;
  CVodeGetNumSteps(mem, &nsteps);
  res.steps = steps_done + nsteps;
  long nrhs = 0;
  CVodeGetNumRhsEvals(mem, &nrhs);
  res.rhs_evaluations = rhs_done + nrhs;
  res.restarts = restarts;
  res.root_stops = root_stops;
  res.history_capacity = history.capacity();
  res.history_max_entries = history.max_count();
  res.max_amplitude_m = max_amp;
  res.out_of_cut_fraction = arc_samples ? static_cast<double>(air_samples) / static_cast<double>(arc_samples) : 0.0;

  // --- growth per period from the analysed window ---
  const int K = static_cast<int>(snapshots.size());  // snapshot k at t = (k+1)τ
  const int k0 = std::max(0, first_analysed - 1);
  std::vector<Eigen::VectorXd> seq;   // states (linear) or increments (nonlinear), true scale relative
  std::vector<double> seq_log;
  if (s.linear) {
    for (int k = k0; k < K; ++k) {
      seq.push_back(snapshots[k]);
      seq_log.push_back(snapshot_log_scale[k]);
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
  bool converged = false;
  std::vector<int> usable;
  for (std::size_t k = 0; k + 1 < seq.size(); ++k) {
    const double a0 = seq[k].norm(), a1 = seq[k + 1].norm() * std::exp(seq_log[k + 1] - seq_log[k]);
    if (s.linear || (a0 > floor && a1 > floor)) usable.push_back(static_cast<int>(k));
  }
  if (!s.linear && !seq.empty() && seq.back().norm() <= floor) converged = true;
  std::complex<double> mu{kNaN, 0.0};
  if (usable.size() >= 4) {
    Eigen::MatrixXd X(zdim, static_cast<Eigen::Index>(usable.size())), Y(zdim, static_cast<Eigen::Index>(usable.size()));
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
    const double noise = s.linear ? 30.0 * rtol : 30.0 * rtol * amp_ref / std::max(smallest, 1e-300);
    mu = dominant_multiplier(X, Y, seq[last] / std::max(seq[last].norm(), 1e-300), std::clamp(noise, 1e-9, 0.05));
  }
  res.dominant_multiplier = mu;
  res.growth_per_period = std::abs(mu);

  // --- spectrum and the chatter frequency ---
  const Spectrum sp = amplitude_spectrum(win_x, win_y, dt);
  res.spectrum_hz = sp.f;
  res.spectrum_amplitude_m = sp.amp;
  const double ftp = 1.0 / tau;
  auto harmonic_of = [&](double f) {
    const double k = std::round(f / ftp);
    return std::abs(f - k * ftp) <= 2.5 * sp.resolution_hz ? static_cast<int>(k) : -1;
  };
  double best_amp = 0.0, best_f = kNaN, amp_all = 0.0;
  std::size_t best_k = 0;
  for (std::size_t k = 1; k + 1 < sp.f.size(); ++k) {
    amp_all = std::max(amp_all, sp.amp[k]);
    if (harmonic_of(sp.f[k]) >= 0) continue;
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
  res.dominant_nonharmonic_hz = best_f;
  for (int k = 1; sp.f.size() > 1 && k * ftp <= std::min(sp.f.back(), 3.0 * f_max) && k <= 60; ++k) {
    SpectralPeak pk;
    pk.frequency_hz = k * ftp;
    pk.harmonic = k;
    const auto c = static_cast<std::size_t>(std::llround(k * ftp / (sp.f[1] - sp.f[0])));
    for (std::size_t j = c >= 3 ? c - 3 : 0; j <= c + 3 && j < sp.f.size(); ++j)
      pk.amplitude_m = std::max(pk.amplitude_m, sp.amp[j]);
    res.harmonics.push_back(pk);
  }

  // --- verdict ---
  std::ostringstream why;
  why.precision(4);
  const int analysed = s.periods - first_analysed;
  if (s.linear) {
    if (std::isnan(res.growth_per_period)) {
      res.verdict = SimulationVerdict::kStable;
      why << "no motion to analyse";
    } else {
      res.verdict = res.growth_per_period < 1.0 ? SimulationVerdict::kStable : SimulationVerdict::kChatter;
      why << "linear mode: growth per period |mu| = " << res.growth_per_period << " over the last " << analysed
          << " periods (" << (res.growth_per_period < 1.0 ? "< 1: decays" : ">= 1: grows") << ")";
    }
  } else if (converged) {
    res.verdict = SimulationVerdict::kStable;
    why << "periodic: the once-per-period increments fell below " << 1e4 * rtol
        << " of the amplitude (forced vibration only)";
  } else if (std::isnan(res.growth_per_period)) {
    res.verdict = res.out_of_cut_fraction > kAirFraction ? SimulationVerdict::kChatter : SimulationVerdict::kStable;
    why << "the tool was in air during " << 100.0 * res.out_of_cut_fraction << " % of the cutting-arc time in the last "
        << analysed << " periods";
  } else {
    // Saturated chatter (the tool leaves the cut) is a limit cycle or torus
    // of the increments: |mu| = 1 up to the fit, so it counts from 1 − margin.
    const bool air = res.out_of_cut_fraction > kAirFraction;
    const double early = arc_early ? static_cast<double>(air_early) / static_cast<double>(arc_early) : 0.0;
    const double late = arc_late ? static_cast<double>(air_late) / static_cast<double>(arc_late) : 0.0;
    // Persisting contact loss: at least half as often in the second half of
    // the window as in the first (a decaying transient loses contact less
    // and less; a saturated chatter vibration keeps doing it).
    const bool persisting = air && late > kAirFraction && late >= 0.5 * early;
    const double threshold = persisting ? 1.0 - kSaturatedMargin : 1.0;
    res.verdict = res.growth_per_period < threshold ? SimulationVerdict::kStable : SimulationVerdict::kChatter;
    why << "once-per-period increments " << (res.growth_per_period < 1.0 ? "decay" : "grow") << " by |mu| = "
        << res.growth_per_period << " per period over the last " << analysed << " periods";
    if (air)
      why << "; the tool was in air during " << 100.0 * res.out_of_cut_fraction << " % of the cutting-arc time ("
          << 100.0 * early << " % then " << 100.0 * late << " % in the two halves"
          << (persisting ? ": persisting, saturated chatter has |mu| = 1" : ": dying out") << ")";
    else
      why << "; the tool stayed in the cut";
  }
  res.verdict_measure = why.str();
  res.chatter_frequency_hz = res.verdict == SimulationVerdict::kChatter ? best_f : kNaN;
  if (history.extrapolations() > 0)
    throw NumericalError("time-domain: internal error: the delayed state was needed outside the stored history (" +
                         std::to_string(history.extrapolations()) + " times)");
  return res;
}

// ---------------------------------------------------------------------------
namespace {

/// The zeroth-order analytic solver as the depth search's starting guess, or
/// null when the analytic method does not apply to this model and process
/// (its constructor's rules, e.g. a model with both bodies rigid).
std::shared_ptr<const LobeSolver> default_starting_guess(const TimeDomainSimulator& sim) {
  TransferFunctionOptions to;
  to.depth_max_m = sim.options().depth_max_m;
  if (!to.validate().empty() || sim.model().rigid()) return nullptr;
  return std::make_shared<const AnalyticSolver>(sim.model(), sim.process(), to);
}

}  // namespace

TimeDomainSolver::TimeDomainSolver(StructuralModel model, Process process, TimeDomainOptions options,
                                   std::shared_ptr<const LobeSolver> starting_guess)
    : simulator_(std::move(model), std::move(process), options), starting_guess_(std::move(starting_guess)) {
  if (!starting_guess_) starting_guess_ = default_starting_guess(simulator_);
}

SimulationResult TimeDomainSolver::verdict_run(double rpm, double depth_m) const {
  SimulationSettings st;
  st.spindle_rpm = rpm;
  st.depth_m = depth_m;
  st.periods = simulator_.options().periods;
  st.feed_m = simulator_.options().feed_m;
  st.linear = simulator_.options().linear;
  st.multiple_regeneration = simulator_.options().multiple_regeneration;
  st.record_series = false;
  return simulator_.simulate(st);
}

StabilityLimit TimeDomainSolver::limit_at(double rpm) const {
  if (!(rpm > 0.0 && std::isfinite(rpm))) throw InputError("spindle speed must be > 0 rev/min");
  const TimeDomainOptions& o = simulator_.options();
  StabilityLimit out;
  out.spindle_rpm = rpm;
  // Starting guess (header): only places the scan, never the answer.
  double guess = o.depth_max_m / 4.0;
  if (starting_guess_) {
    std::optional<StabilityLimit> g;
    try {
      g = starting_guess_->limit_at(rpm);
    } catch (const InputError&) {
      // The guess refuses this speed (documented in the header): no guess.
    }
    if (g && g->bounded() && g->depth_limit_m > 0.0) guess = std::min(g->depth_limit_m, o.depth_max_m);
  }
  double lo = 0.0, hi = 0.0;
  SimulationResult at_hi;
  double a = guess / 16.0;
  bool found = false;
  SimulationResult r = verdict_run(rpm, a);
  if (r.verdict == SimulationVerdict::kChatter) {
    // Unstable already: go down.
    hi = a;
    at_hi = r;
    for (int k = 0; k < 30; ++k) {
      a /= 2.0;
      r = verdict_run(rpm, a);
      if (r.verdict == SimulationVerdict::kStable) {
        lo = a;
        found = true;
        break;
      }
      hi = a;
      at_hi = r;
    }
    if (!found) {
      out.depth_limit_m = 0.0;
      return out;
    }
  } else {
    lo = a;
    while (true) {
      if (a >= o.depth_max_m) return out;  // stable up to the searched depth
      a = std::min(2.0 * a, o.depth_max_m);
      r = verdict_run(rpm, a);
      if (r.verdict == SimulationVerdict::kChatter) {
        hi = a;
        at_hi = r;
        break;
      }
      lo = a;
    }
  }
  while (hi - lo > o.depth_tolerance * hi) {
    const double mid = 0.5 * (lo + hi);
    r = verdict_run(rpm, mid);
    if (r.verdict == SimulationVerdict::kChatter) {
      hi = mid;
      at_hi = r;
    } else {
      lo = mid;
    }
  }
  out.depth_limit_m = 0.5 * (lo + hi);
  out.chatter_frequency_hz = at_hi.chatter_frequency_hz;
  if (std::isnan(out.chatter_frequency_hz)) out.chatter_frequency_hz = at_hi.dominant_nonharmonic_hz;
  out.lobe = std::isfinite(out.chatter_frequency_hz)
                 ? static_cast<int>(std::floor(out.chatter_frequency_hz * at_hi.delay_s))
                 : 0;
  return out;
}

}  // namespace chatter
