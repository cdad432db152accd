// A CAM integrator that links only the kernels (chatter::core: Eigen and
// SUNDIALS, no file formats): builds the model in code, no config file.
// Case A of the docs (1-DOF turning, flexible workpiece): prints the minimum
// of the lobes beside its closed form b_lim,min = 2kζ(1+ζ)/K_f.
// Usage: consumer_core
#include <cstdio>
#include <exception>

#include "chatter/error.hpp"
#include "chatter/transfer_function.hpp"

int main() {
  try {
    const double k = 45e6, zeta = 0.033, kf = 2.4e9;  // N/m, -, N/m²
    chatter::StructuralModel model;
    model.workpiece.modes.push_back(chatter::Mode::from_stiffness(94.22, zeta, k, {1.0, 0.0}));
    const chatter::Process process = chatter::Process::turning({kf});
    chatter::TransferFunctionOptions opt;
    opt.depth_max_m = 0.02;
    const chatter::AnalyticSolver solver(model, process, opt);
    const chatter::AbsoluteLimit a = solver.absolute_limit();
    std::printf("absolute limit %.4f mm (closed form %.4f mm)\n", a.depth_m * 1e3, 2.0 * k * zeta * (1.0 + zeta) / kf * 1e3);
    return 0;
  } catch (const chatter::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", e.what());
    return 1;
  }
}
