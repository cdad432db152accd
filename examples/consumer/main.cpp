// Checks a few operating points of a part program against the lobes of a
// config, as a CAM post-processor would. Usage: consumer CONFIG
#include <cstdio>
#include <exception>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/transfer_function.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer CONFIG\n");
    return 2;
  }
  try {
    const chatter::Config cfg = chatter::load_config(argv[1]);
    chatter::TransferFunctionOptions opt;
    opt.depth_max_m = 0.02;
    const chatter::AnalyticSolver solver(cfg.model, cfg.process, opt);
    const struct { double rpm, depth_mm; } ops[] = {{1200, 1.0}, {1200, 1.5}, {1800, 2.5}};
    for (const auto& op : ops) {
      const chatter::StabilityLimit lim = solver.limit_at(chatter::SpindleSpeed(op.rpm));
      const bool stable = op.depth_mm * 1e-3 < lim.depth_limit_m;
      std::printf("%.0f rev/min, %.2f mm: %s (limit %.4f mm)\n", op.rpm, op.depth_mm, stable ? "stable" : "CHATTER",
                  lim.depth_limit_m * 1e3);
    }
    return 0;
  } catch (const chatter::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", e.what());
    return 1;
  }
}
