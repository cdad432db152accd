#!/usr/bin/env python3
"""Speed of the Python package where it is used in a loop (issue 30 targets;
results in docs/performance.md, "Python in a loop").

  hook:  examples/python/post_processor_hook.py's three operations (a
         FreeCAD-style post-processor calls chatter.check once per
         operation): the script run as a user runs it (a fresh interpreter:
         import, job built in code, three checks), the three calls alone in a
         warm interpreter, and the hook's check_program (the three in one
         chatter.check call). Target <= 0.3 s.
  check: chatter.check on 100 operations of 4 processes (case C's cutter at
         radial immersions 0.05, 0.1, 0.25 and 0.5, 25 operations each, at
         seeded random speeds and depths), one call. Target <= 1 s.

Best of several repeats (time.perf_counter; the machine is shared). Run from
the repository after scripts/build.sh:
  PYTHONPATH=build/python python3 bench/bench_python_loop.py [--repeats N]
"""
import argparse
import os
import pathlib
import subprocess
import sys
import time

import numpy as np

import chatter

ROOT = pathlib.Path(__file__).resolve().parents[1]
HOOK = ROOT / "examples" / "python" / "post_processor_hook.py"


def best(f, repeats):
    out = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        f()
        out = min(out, time.perf_counter() - t0)
    return out


def hook_script():
    env = dict(os.environ, PYTHONPATH=os.environ.get("PYTHONPATH", str(ROOT / "build" / "python")))
    subprocess.run([sys.executable, str(HOOK)], check=True, env=env, stdout=subprocess.DEVNULL)


def hook_calls():
    sys.path.insert(0, str(HOOK.parent))
    import post_processor_hook as hook
    end_mill = {"name": "D10 2-flute", "flutes": 2, "diameter_mm": 10.0, "k_t_n_per_mm2": 600.0,
                "k_r_n_per_mm2": 200.0,
                "modes": [{"frequency_hz": 922.0, "damping_ratio": 0.011, "mass_kg": 0.03993, "direction": "x"}]}
    program = [("rough", 14000, 3.0, 0.5), ("slot", 12000, 1.0, 10.0), ("finish", 21000, 0.8, 0.5)]
    hook._job(end_mill)  # the job is built once per tool (the hook caches it)
    return (lambda: [hook.check_operation(end_mill, rpm, ap, ae, op_id=i) for i, rpm, ap, ae in program],
            lambda: hook.check_program(end_mill, program))


def hundred_operations():
    job = chatter.load(ROOT / "configs" / "milling_benchmark_ae005_down.toml")
    rng = np.random.default_rng(30)
    ops = []
    for p, ae in enumerate((0.05, 0.1, 0.25, 0.5)):
        for k in range(25):
            ops.append({"id": f"p{p}-{k}", "spindle_rpm": float(rng.uniform(5000, 25000)),
                        "depth_mm": float(rng.uniform(0.2, 3.0)), "radial_immersion": ae})
    report = chatter.check(job, ops)
    assert report["summary"]["checked"] == 100, report["summary"]
    return lambda: chatter.check(job, ops)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    print(f"cores {os.cpu_count()}, load {os.getloadavg()[0]:.1f}")
    t = best(hook_script, a.repeats)
    print(f"hook script (3 operations, fresh interpreter): {t:.3f} s (target <= 0.3 s)")
    calls, batched = hook_calls()
    t = best(calls, a.repeats)
    print(f"hook, 3 check_operation calls (warm): {t:.3f} s")
    t = best(batched, a.repeats)
    print(f"hook, 1 check_program call of the 3 operations (warm): {t:.3f} s")
    check = hundred_operations()
    t = best(check, a.repeats)
    print(f"check, 100 operations of 4 processes: {t:.3f} s (target <= 1 s)")


if __name__ == "__main__":
    main()
