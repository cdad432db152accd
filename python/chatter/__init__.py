"""chatter: regenerative chatter prediction and stability lobes.

Every command of the `chatter` CLI as a function of the same name, with the
CLI's defaults, messages and numbers (the library builds each record once;
docs/python.md). Tables come back as NumPy arrays named as the CLI's CSV
columns; the results of lobes, map, surface, compare, simulate, frf, fit,
detect and uncertain_lobes draw themselves with Matplotlib
(``result.plot()``), and a notebook shows lobes as a figure.
"""
from . import _chatter
from ._chatter import (  # noqa: F401  (the compiled functions, re-exported)
    InputError,
    Job,
    NumericalError,
    __version__,
    check,
    coefficients,
    grind_fit,
    grind_impacts,
    grind_plan,
    grind_predict,
    grind_simulate,
    grind_sweep,
    load,
    methods,
    point,
    recommend,
)
from . import _results
from ._results import (  # noqa: F401
    Comparison,
    Detection,
    Frf,
    Lobes,
    ModalFit,
    Simulation,
    StabilityMap,
    Surface,
    UncertainLobes,
)

_time_lobes_cpp = _chatter._time_lobes_cpp  # bench/bench_python.py


def _wrap(compiled, result):
    """`compiled`'s call, its dict (or its (table, info) pair) handed to the
    result class `result`."""
    def call(*args, **kwargs):
        value = compiled(*args, **kwargs)
        return result(*value) if isinstance(value, tuple) else result(value)
    call.__name__ = compiled.__name__
    call.__qualname__ = compiled.__name__
    call.__doc__ = compiled.__doc__
    call.__wrapped__ = compiled
    return call


lobes = _wrap(_chatter.lobes, Lobes)
uncertain_lobes = _wrap(_chatter.uncertain_lobes, UncertainLobes)
surface = _wrap(_chatter.surface, Surface)
simulate = _wrap(_chatter.simulate, Simulation)
map = _wrap(_chatter.map, StabilityMap)  # noqa: A001  (the CLI's name; builtins.map stays reachable as such)
compare = _wrap(_chatter.compare, Comparison)
frf = _wrap(_chatter.frf, Frf)
fit = _wrap(_chatter.fit, ModalFit)
detect = _wrap(_chatter.detect, Detection)

# Any other public function of the compiled module (a command bound in a new
# bind_*.cpp) is the package's too, unwrapped, until it gets a result class.
for _name in dir(_chatter):
    if not _name.startswith("_") and _name not in globals():
        globals()[_name] = getattr(_chatter, _name)
del _name

__all__ = [
    "InputError", "NumericalError", "Job", "load", "methods", "__version__",
    "lobes", "uncertain_lobes", "point", "check", "recommend", "map", "compare", "simulate", "surface",
    "fit", "frf", "coefficients", "detect", "grind_predict", "grind_fit", "grind_sweep", "grind_plan",
    "grind_impacts", "grind_simulate", "forced", "sle", "performance", "optimize", "adapt", "adapt_step",
    "design_pitch", "program",
    "Lobes", "UncertainLobes", "Surface", "Simulation", "StabilityMap", "Comparison", "Frf", "ModalFit",
    "Detection",
]
