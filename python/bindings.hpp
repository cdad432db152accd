// The bindings of the Python module, one function per command family, each
// in its own bind_*.cpp; chatter_module.cpp calls them all.
#pragma once

#include <memory>

#include <pybind11/pybind11.h>

namespace chatter {
struct Config;
}

namespace chatter_py {

void bind_job(pybind11::module_& m);         // Job, load, methods (bind_job.cpp)
void bind_lobes(pybind11::module_& m);       // lobes, point, surface, uncertain_lobes (bind_lobes.cpp)
void bind_operations(pybind11::module_& m);  // check, recommend (bind_operations.cpp)
void bind_simulate(pybind11::module_& m);    // simulate (bind_simulate.cpp)
void bind_tables(pybind11::module_& m);      // compare, map, frf (bind_tables.cpp)
void bind_shop(pybind11::module_& m);        // coefficients, detect, fit (bind_shop.cpp)
void bind_optimization(pybind11::module_& m);  // performance, optimize, adapt, adapt_step (bind_optimization.cpp)
void bind_pitch(pybind11::module_& m);         // design_pitch (bind_pitch.cpp)
void bind_program(pybind11::module_& m);       // program (bind_program.cpp)

}  // namespace chatter_py

/// grind_predict, grind_fit (python/bind_grinding.cpp; docs/python.md, docs/grinding.md).
void bind_grinding(pybind11::module_& m);

/// The config of a chatter.Job (python/module_common.cpp, where Job lives).
/// @throws pybind11::cast_error when `job` is not a chatter.Job.
std::shared_ptr<const chatter::Config> job_config(const pybind11::handle& job);

/// chatter.forced, chatter.sle (python/bind_forced.cpp; docs/python.md).
void bind_forced(pybind11::module_& m);
