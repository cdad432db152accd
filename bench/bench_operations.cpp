// `chatter check` and `chatter recommend` for CAM post-processors: the library
// calls behind them on the benchmark jobs of docs/performance.md, with the
// solver `auto` picks for milling (sdm) and 2 threads (the CLI's default on
// the 2-core machine). Wall time (UseRealTime).
// The per-row check time (issue 26, item 5): one row at 200, 1 000 and
// 10 000 rev/min of case C over a machine range 100-25 000 rev/min, of case A
// turning with sdm over 50-12 000, and one row at 300 rev/min of the
// variable-pitch cutter over 200-12 000; one thread, so that the CPU time is
// the whole cost (the figure to compare on a shared machine).
// Run: ./build/bench/bench_operations --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
//      ./build/bench/bench_operations --benchmark_filter=CheckRow
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

// One row at `rpm` (state.range(0)) on `config`, machine [lo, hi], one thread.
void run_check_row(benchmark::State& state, const std::string& config, const std::string& method, double lo,
                   double hi, double depth_mm) {
  const Config cfg = load_config(kSource + "/" + config);
  CheckOptions o;
  o.machine = machine(lo, hi);
  o.method = method;
  o.threads = 1;
  const std::string csv = "id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm\nr," +
                          std::to_string(state.range(0)) + "," + std::to_string(depth_mm) + ",,\n";
  const OperationsFile f = parse_operations(csv, "row.csv", cfg.process.operation(), o.machine);
  for (auto _ : state) benchmark::DoNotOptimize(check_operations(cfg.model, cfg.process, f.rows, o));
}
// Case C (a_e/D = 0.05 down, sdm), a 0.5 mm row, machine 100-25 000 rev/min.
void BM_CheckRowCaseC(benchmark::State& state) {
  run_check_row(state, "configs/milling_benchmark_ae005_down.toml", "auto", 100, 25000, 0.5);
}
// Case A turning with sdm (branch roots at low speed), a 1 mm row, machine 50-12 000 rev/min.
void BM_CheckRowTurningSdm(benchmark::State& state) {
  run_check_row(state, "configs/seed_turning_1dof.toml", "sdm", 50, 12000, 1.0);
}
// The 4-flute variable-pitch, 30 deg helix cutter (sdm), a 1 mm row, machine 200-12 000 rev/min.
void BM_CheckRowVariablePitch(benchmark::State& state) {
  run_check_row(state, "configs/milling_variable_pitch_helix.toml", "auto", 200, 12000, 1.0);
}

BENCHMARK(BM_CheckCaseC6Rows4Processes)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
BENCHMARK(BM_CheckTwoMode4Rows)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
BENCHMARK(BM_CheckTwoMode1Row)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
BENCHMARK(BM_RecommendTwoMode)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
BENCHMARK(BM_CheckRowCaseC)->Arg(200)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_CheckRowTurningSdm)->Arg(200)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_CheckRowVariablePitch)->Arg(300)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
