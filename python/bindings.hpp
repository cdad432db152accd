// The pieces the Python module `chatter` is assembled from: each bind_*
// function adds its functions to the module, called from the PYBIND11_MODULE
// block of python/chatter_module.cpp. A plain list of declarations.
#pragma once

#include <memory>

#include <pybind11/pybind11.h>

namespace chatter {
struct Config;
}

/// The config of a chatter.Job (python/chatter_module.cpp, where Job lives).
/// @throws pybind11::cast_error when `job` is not a chatter.Job.
std::shared_ptr<const chatter::Config> job_config(const pybind11::handle& job);

/// chatter.forced, chatter.sle (python/bind_forced.cpp; docs/python.md).
void bind_forced(pybind11::module_& m);
