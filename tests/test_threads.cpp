// Solvers hold no mutable state: one solver queried from several threads, and
// two models in two threads, give exactly the serial answers.
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "chatter/io/config.hpp"
#include "chatter/transfer_function.hpp"

namespace chatter {
namespace {

Config config(const char* name) { return load_config(std::string(CHATTER_SOURCE_DIR) + "/configs/" + name); }

TransferFunctionOptions depth_max(double d) {
  TransferFunctionOptions o;
  o.depth_max_m = d;
  return o;
}

TEST(Threads, OneSolverManyReaders) {
  const Config c = config("coupled_tool1_workpiece1.toml");
  const AnalyticSolver solver(c.model, c.process, depth_max(0.02));
  const auto speeds = evenly_spaced_speeds(500, 10000, 400);
  const auto serial = lobe_envelope(solver, speeds);
  constexpr int kThreads = 4;
  std::vector<std::vector<StabilityLimit>> results(kThreads);
  std::vector<std::thread> pool;
  for (int t = 0; t < kThreads; ++t)
    pool.emplace_back([&, t] {
      // Each thread walks the speeds in its own order (multipliers coprime with 400).
      constexpr std::size_t kStride[kThreads] = {1, 3, 7, 9};
      std::vector<StabilityLimit> out(speeds.size());
      for (std::size_t k = 0; k < speeds.size(); ++k) {
        const std::size_t i = (k * kStride[t] + static_cast<std::size_t>(t)) % speeds.size();
        out[i] = solver.limit_at(SpindleSpeed(speeds[i]));
      }
      results[static_cast<std::size_t>(t)] = std::move(out);
    });
  for (auto& th : pool) th.join();
  for (const auto& r : results)
    for (std::size_t i = 0; i < speeds.size(); ++i) {
      EXPECT_EQ(r[i].depth_limit_m, serial[i].depth_limit_m) << speeds[i];  // bitwise: same arithmetic
      EXPECT_EQ(r[i].chatter_frequency_hz, serial[i].chatter_frequency_hz);
      EXPECT_EQ(r[i].lobe, serial[i].lobe);
    }
}

TEST(Threads, TwoModelsTwoThreads) {
  const Config a = config("seed_turning_1dof.toml");
  const Config b = config("milling_benchmark_ae005_down.toml");
  const auto sa = evenly_spaced_speeds(50, 2000, 200);
  const auto sb = evenly_spaced_speeds(5000, 25000, 200);
  std::vector<StabilityLimit> ra, rb;
  std::thread ta([&] { ra = lobe_envelope(CoupledSolver(a.model, a.process, depth_max(0.02)), sa); });
  std::thread tb([&] { rb = lobe_envelope(AnalyticSolver(b.model, b.process, depth_max(0.01)), sb); });
  ta.join();
  tb.join();
  const auto ea = lobe_envelope(CoupledSolver(a.model, a.process, depth_max(0.02)), sa);
  const auto eb = lobe_envelope(AnalyticSolver(b.model, b.process, depth_max(0.01)), sb);
  for (std::size_t i = 0; i < sa.size(); ++i) EXPECT_EQ(ra[i].depth_limit_m, ea[i].depth_limit_m);
  for (std::size_t i = 0; i < sb.size(); ++i) EXPECT_EQ(rb[i].depth_limit_m, eb[i].depth_limit_m);
}

}  // namespace
}  // namespace chatter
