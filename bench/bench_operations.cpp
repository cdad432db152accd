// `chatter check` and `chatter recommend` for CAM post-processors: the library
// calls behind them on the benchmark jobs of docs/performance.md, with the
// solver `auto` picks for milling (sdm) and 2 threads (the CLI's default on
// the 2-core machine). Wall time (UseRealTime).
// Run: ./build/bench/bench_operations --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <string>

#include "chatter/io/config.hpp"
#include "chatter/operations.hpp"

namespace {

using namespace chatter;

const std::string kSource = CHATTER_SOURCE_DIR;

MachineLimits machine(double lo, double hi) {
  MachineLimits m;
  m.rpm_min = lo;
  m.rpm_max = hi;
  return m;
}

void run_check(benchmark::State& state, const std::string& config, const std::string& ops) {
  const Config cfg = load_config(kSource + "/" + config);
  CheckOptions o;
  o.machine = machine(5000, 25000);
  o.threads = 2;
  const OperationsFile f = read_operations(kSource + "/" + ops, cfg.process.operation(), o.machine);
  for (auto _ : state) benchmark::DoNotOptimize(check_operations(cfg.model, cfg.process, f.rows, o));
}

// Six operations of case C, four distinct (immersion, direction) processes.
void BM_CheckCaseC6Rows4Processes(benchmark::State& state) {
  run_check(state, "configs/milling_benchmark_ae005_down.toml", "examples/operations/case_c_six_ops.csv");
}
// Four operations of the 4-flute half-immersion up-milling job (2-mode tool).
void BM_CheckTwoMode4Rows(benchmark::State& state) {
  run_check(state, "examples/operations/two_mode_half_up.toml", "examples/operations/two_mode_ops.csv");
}
// One operation of that job.
void BM_CheckTwoMode1Row(benchmark::State& state) {
  const Config cfg = load_config(kSource + "/examples/operations/two_mode_half_up.toml");
  CheckOptions o;
  o.machine = machine(5000, 25000);
  o.threads = 2;
  const OperationsFile f = parse_operations("id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm\nr,12000,3,,\n",
                                            "one.csv", Operation::kMilling, o.machine);
  for (auto _ : state) benchmark::DoNotOptimize(check_operations(cfg.model, cfg.process, f.rows, o));
}
// Recommendation on that job (16 mm tool, feed 0.05 mm, flute length 16 mm).
void BM_RecommendTwoMode(benchmark::State& state) {
  const Config cfg = load_config(kSource + "/examples/operations/two_mode_half_up.toml");
  RecommendOptions o;
  o.machine = machine(5000, 25000);
  o.feed_per_tooth_m = 0.05e-3;
  o.diameter_m = 16e-3;
  o.depth_max_m = 30e-3;
  o.flute_length_m = cfg.flute_length_m;
  o.threads = 2;
  for (auto _ : state) benchmark::DoNotOptimize(recommend(cfg.model, cfg.process, o));
}

BENCHMARK(BM_CheckCaseC6Rows4Processes)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
BENCHMARK(BM_CheckTwoMode4Rows)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
BENCHMARK(BM_CheckTwoMode1Row)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
BENCHMARK(BM_RecommendTwoMode)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
