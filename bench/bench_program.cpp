// `chatter program` on programs of the size a CAM system writes (issue 42,
// item 10): the whole path — LinuxCNC's interpreter run as a process, the
// stock simulated, every block's limit through the solve cache, load, part
// error — one thread, wall time.
//
//   BM_Pocket10000Blocks: a 100 × 100 × 30 mm aluminium box at 0.1 mm
//     (1 001 × 1 001 Z-map cells), the 10 mm 3-flute end mill of
//     examples/program (sdm), a zig-zag pocket written as CAM output writes
//     it, in 1 mm segments: 7 levels of 1.5 mm, 16 rows of 90 mm at 6 mm
//     step-over per level, 10 192 feed moves. Target ≤ 10 s on one core.
//   BM_Turning200Blocks: the 25 mm shaft of examples/program (analytic),
//     10 roughing passes of 0.5 mm on the radius, each 20 segments of 3.5 mm
//     along 70 mm: 200 cutting moves. Target ≤ 1 s.
//
// Run: ./build/bench/bench_program --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "chatter/io/job.hpp"
#include "chatter/records/program.hpp"

namespace {

using namespace chatter;
namespace fs = std::filesystem;

const fs::path kExamples = fs::path(CHATTER_SOURCE_DIR) / "examples" / "program";

fs::path scratch() {
  fs::path dir = fs::temp_directory_path() / "chatter_bench_program";
  fs::create_directories(dir);
  return dir;
}

void write(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
}

/// The pocket: zig-zag rows along X in 1 mm segments, levels 1.5 mm apart.
std::string pocket_program(int& moves) {
  std::ostringstream p;
  p << "G17 G21 G90 G94\nT1 M6\nS9000 M3\nG0 X5 Y5 Z5\n";
  moves = 0;
  for (int level = 1; level <= 7; ++level) {
    p << "G0 X5 Y5\nG1 Z" << -1.5 * level << " F300\n";
    ++moves;
    for (int row = 0; row < 16; ++row) {
      const double y = 5.0 + 6.0 * row;
      if (row > 0) {
        p << "G1 Y" << y << " F900\n";
        ++moves;
      }
      for (int s = 1; s <= 90; ++s) {
        const double x = row % 2 == 0 ? 5.0 + s : 95.0 - s;
        p << "G1 X" << x << " F900\n";
        ++moves;
      }
    }
    p << "G0 Z5\n";
  }
  p << "M5\nM2\n";
  return p.str();
}

/// The shaft: 10 passes of 0.5 mm on the radius, 20 segments each.
std::string turning_program(int& moves) {
  std::ostringstream p;
  p << "G18 G21 G7 G90\nT1 M6\nG97 S1800 M3\nG95 F0.15\n";
  moves = 0;
  for (int pass = 1; pass <= 10; ++pass) {
    const double diameter = 25.0 - 1.0 * pass;
    p << "G0 X27 Z2\nG0 Z0.5\nG1 X" << diameter << "\n";
    for (int s = 1; s <= 20; ++s) p << "G1 Z" << -3.5 * s << "\n";
    moves += 20;
  }
  p << "G0 X30\nM5\nM2\n";
  return p.str();
}

void run(benchmark::State& state, const fs::path& program, const fs::path& job_file, int moves) {
  const Job job = load_job(job_file);
  ProgramOptions options;
  options.threads = 1;
  ProgramSummary summary;
  for (auto _ : state) {
    const ProgramReport report = run_program(program, job, options);
    summary = report.summary;
    benchmark::DoNotOptimize(summary.worst_margin);
  }
  state.counters["moves_written"] = moves;
  state.counters["blocks"] = static_cast<double>(summary.blocks);
  state.counters["cutting"] = static_cast<double>(summary.cutting_blocks);
  state.counters["solves"] = static_cast<double>(summary.solves);
  state.counters["cache_hits"] = static_cast<double>(summary.cache_hits);
  state.counters["removed_cm3"] = summary.removed_volume_mm3 / 1000.0;
}

void BM_Pocket10000Blocks(benchmark::State& state) {
  const fs::path dir = scratch();
  int moves = 0;
  write(dir / "pocket10k.ngc", pocket_program(moves));
  write(dir / "pocket10k.toml",
        "[stock]\nshape = \"box\"\nmin_mm = [0, 0, -30]\nmax_mm = [100, 100, 0]\nresolution_mm = 0.1\n"
        "[[tools]]\nnumber = 1\nconfig = \"" + (kExamples / "end_mill.toml").string() + "\"\n"
        "[machine]\nrpm_min = 2000\nrpm_max = 15000\nmax_power_kw = 3.0\nmax_torque_nm = 8\n");
  run(state, dir / "pocket10k.ngc", dir / "pocket10k.toml", moves);
}
BENCHMARK(BM_Pocket10000Blocks)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

void BM_Turning200Blocks(benchmark::State& state) {
  const fs::path dir = scratch();
  int moves = 0;
  write(dir / "shaft200.ngc", turning_program(moves));
  std::ifstream in(kExamples / "shaft_job.toml");
  std::stringstream job;
  job << in.rdbuf();
  std::string text = job.str();
  const std::string from = "config = \"insert.toml\"";
  text.replace(text.find(from), from.size(), "config = \"" + (kExamples / "insert.toml").string() + "\"");
  write(dir / "shaft200.toml", text);
  run(state, dir / "shaft200.ngc", dir / "shaft200.toml", moves);
}
BENCHMARK(BM_Turning200Blocks)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
