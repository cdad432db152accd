#!/usr/bin/env python3
"""Speed of the Python module (issue 19 targets; results in docs/performance.md).

  chatter.point, analytic, case A (configs/seed_turning_1dof.toml, 1200 rev/min,
  1.5 mm): time per call from Python, target <= 50 us.
  chatter.lobes: time of the call from Python against the C++ work alone
  (chatter._time_lobes_cpp: solver built + lobe_envelope, no Python objects),
  target overhead < 5 %.

Timing with time.perf_counter, best of several repeats (the machine is
shared). Run from the repository after scripts/build.sh:
  PYTHONPATH=build/python python3 bench/bench_python.py
"""
import pathlib
import time

import numpy as np

import chatter

ROOT = pathlib.Path(__file__).resolve().parents[1]
REPEATS = 7


def best_of(f, n, repeats=REPEATS):
    """Smallest mean time per call of f over `repeats` runs of n calls."""
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(n):
            f()
        best = min(best, (time.perf_counter() - t0) / n)
    return best


def main():
    case_a = chatter.load(ROOT / "configs" / "seed_turning_1dof.toml")
    case_c = chatter.load(ROOT / "configs" / "milling_benchmark_ae005_down.toml")
    chatter.point(case_a, rpm=1200, depth_mm=1.5)  # builds the cached solver
    t = best_of(lambda: chatter.point(case_a, rpm=1200, depth_mm=1.5), 20000)
    print(f"point analytic case A: {t * 1e6:.2f} us per call (target <= 50 us)")

    for name, job, method, points in [("case A", case_a, "analytic", 2000), ("case C", case_c, "analytic", 2000),
                                      ("case C", case_c, "sdm", 200)]:
        s = job.sweep
        rpm = np.linspace(s["rpm_min"], s["rpm_max"], points)
        dmax = s["depth_max_mm"]
        reps = 3 if method == "sdm" else 25
        # Interleaved, best of each: the two see the same machine load.
        py_t, cpp_t = float("inf"), float("inf")
        for _ in range(reps):
            t0 = time.perf_counter()
            chatter.lobes(job, method, rpm=rpm, depth_max_mm=dmax, threads=1)
            py_t = min(py_t, time.perf_counter() - t0)
            cpp_t = min(cpp_t, chatter._time_lobes_cpp(job, method, rpm, dmax, threads=1))
        print(f"lobes {method} {name}, {points} speeds, 1 thread: Python {py_t * 1e3:.3f} ms, "
              f"C++ {cpp_t * 1e3:.3f} ms, overhead {(py_t - cpp_t) * 1e6:+.0f} us = {100 * (py_t / cpp_t - 1):+.2f} % "
              f"(target < 5 %)")


if __name__ == "__main__":
    main()
