// Shop data (issue 18): `detect` on a 10 s, 48 kHz recording (target
// <= 0.2 s) and `coefficients` (instant). ./build/bench/bench_shop
#include <benchmark/benchmark.h>
#include <sndfile.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <vector>

#include "chatter/io/shop_io.hpp"
#include "chatter/shop.hpp"

namespace {

using namespace chatter;
constexpr double kPi = std::numbers::pi;
constexpr double kRate = 48000.0;

// 10 s at 48 kHz: tooth passing (3 teeth, 9000 rev/min) with harmonics,
// runout, a chatter line at 1234.5 Hz and noise.
std::vector<double> recording() {
  std::mt19937 rng(1);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::vector<double> x(static_cast<std::size_t>(10 * kRate));
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double t = static_cast<double>(i) / kRate;
    x[i] = 0.3 * std::sin(2 * kPi * 450 * t) + 0.1 * std::sin(2 * kPi * 900 * t) + 0.05 * std::sin(2 * kPi * 150 * t) +
           0.2 * std::sin(2 * kPi * 1234.5 * t) + 0.02 * n01(rng);
  }
  return x;
}

void BM_DetectTenSeconds48kHz(benchmark::State& state) {
  const auto x = recording();
  DetectOptions o;
  o.spindle_rpm = 9000;
  o.teeth = 3;
  for (auto _ : state) {
    const ChatterDetection d = detect_chatter(x, kRate, o);
    if (!d.chatter) state.SkipWithError("chatter not found");
    benchmark::DoNotOptimize(d.chatter_frequency_hz);
  }
}
BENCHMARK(BM_DetectTenSeconds48kHz)->Unit(benchmark::kMillisecond);

// The whole command's work: read a 16-bit WAV through libsndfile, then detect.
void BM_ReadWavAndDetect(benchmark::State& state) {
  const auto x = recording();
  const auto file = std::filesystem::temp_directory_path() / "chatter_bench_shop.wav";
  SF_INFO info{};
  info.samplerate = static_cast<int>(kRate);
  info.channels = 1;
  info.format = SF_FORMAT_WAV | SF_FORMAT_PCM_16;
  SNDFILE* f = sf_open(file.c_str(), SFM_WRITE, &info);
  sf_writef_double(f, x.data(), static_cast<sf_count_t>(x.size()));
  sf_close(f);
  DetectOptions o;
  o.spindle_rpm = 9000;
  o.teeth = 3;
  for (auto _ : state) {
    const Recording r = read_recording(file);
    const ChatterDetection d = detect_chatter(r.samples, r.sample_rate_hz, o);
    benchmark::DoNotOptimize(d.chatter_frequency_hz);
  }
  std::filesystem::remove(file);
}
BENCHMARK(BM_ReadWavAndDetect)->Unit(benchmark::kMillisecond);

void BM_CoefficientsFifteenTests(benchmark::State& state) {
  const MillingEngagement e{3, 0.5, MillingDirection::kDown};
  const std::array<double, 4> k{8e8, 2.5e8, 2.5e4, 3e4};
  std::vector<ForceTest> tests;
  for (double a : {1e-3, 2e-3, 4e-3})
    for (double f : {0.05e-3, 0.1e-3, 0.15e-3, 0.2e-3, 0.25e-3}) {
      const auto m = mean_forces(e, f, a, k);
      tests.push_back({f, a, m[0] + 0.3, m[1] - 0.2});
    }
  for (auto _ : state) benchmark::DoNotOptimize(fit_coefficients_from_forces(tests, e).r_squared);
}
BENCHMARK(BM_CoefficientsFifteenTests)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
