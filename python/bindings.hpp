// Internal: the parts of the Python module `chatter` defined outside
// chatter_module.cpp, each adding its functions to the module.
#pragma once

#include <pybind11/pybind11.h>

/// grind_predict, grind_fit (python/bind_grinding.cpp; docs/python.md, docs/grinding.md).
void bind_grinding(pybind11::module_& m);
