// The compiled part `chatter._chatter` (pybind11) of the Python package
// `chatter` (python/chatter/__init__.py wraps it: result classes with plots):
// every CLI command through the library, for post-processors, notebooks and
// scripts, with the same numbers as the `chatter` CLI for the same inputs
// (each call builds the library record the CLI prints; nothing is printed).
// API reference: docs/python.md.
//
// Errors: chatter::InputError -> chatter.InputError (a ValueError) with the
// library's message ("<file>: <key> = <value>: <rule>"); the module's own
// argument checks name the keyword ("rpm = -1: must be > 0 rev/min").
// chatter::NumericalError -> chatter.NumericalError (a RuntimeError); any
// other failure -> RuntimeError. Every solve runs with the GIL released.
#include <pybind11/pybind11.h>

#include <string>

#include "bindings.hpp"
#include "chatter/error.hpp"
#include "chatter/io/table_writer.hpp"  // version()
#include "module.hpp"

using chatter::InputError;
namespace py = pybind11;

PYBIND11_MODULE(_chatter, m) {
  // Every table comes back as NumPy arrays: without NumPy, say so at import
  // (not as a ModuleNotFoundError at the first call). Found, not imported:
  // NumPy is imported at the first array (pybind11), so `import chatter`
  // costs ~10 ms instead of ~70 for a caller that only reads verdicts.
  bool numpy_found = false;
  try {
    numpy_found = !py::module_::import("importlib.util").attr("find_spec")("numpy").is_none();
  } catch (py::error_already_set&) {
    numpy_found = false;
  }
  if (!numpy_found) {
    // Which interpreter runs, which one the build targets, and how to use it
    // (issue 44: a pyenv python3 stopped with "needs NumPy" and no way on).
    const std::string running = py::str(py::module_::import("sys").attr("executable"));
    throw py::import_error("chatter needs NumPy, which this Python (" + running +
                           ") cannot find. The module was built for " CHATTER_PYTHON_BUILT_FOR
                           " (Debian's, NumPy from apt install python3-numpy): run it with that interpreter, "
                           "or give this one NumPy, or rebuild with -DPython_EXECUTABLE=" + running +
                           " (docs/python.md, \"Build and install\")");
  }
  m.doc() = "chatter: regenerative chatter prediction and stability lobes (docs/python.md)";
  m.attr("__version__") = chatter::version();
  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<chatter::NumericalError> numerical_error(m, "NumericalError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      input_error(e.what());
    } catch (const chatter::NumericalError& e) {
      numerical_error(e.what());
    }
  });

  chatter_py::bind_job(m);
  chatter_py::bind_lobes(m);
  chatter_py::bind_operations(m);
  chatter_py::bind_simulate(m);
  chatter_py::bind_tables(m);
  chatter_py::bind_shop(m);
  chatter_py::bind_optimization(m);
  chatter_py::bind_pitch(m);
  chatter_py::bind_program(m);
  bind_grinding(m);
  bind_forced(m);
}
