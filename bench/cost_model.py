#!/usr/bin/env python3
"""How each command's cost grows, measured, and a loud check against it.

Runs the `chatter` commands a user waits on at several sizes of one parameter
each (speeds, depths, modes, teeth, slices, steps per period, periods,
positions, operations, revolutions), one thread, and reports for every case
the CPU time (user + system of the child process, start-up included) at each
size, the local scaling exponent p = d ln t / d ln n between the two largest
sizes (fixed costs included, so p is at most the exponent of the work that
grows) and the marginal cost per unit of n. docs/performance.md, "Cost model", holds the table.

    bench/cost_model.py [--build build]                # measure, print the table
    bench/cost_model.py --record bench/cost_baseline.json   # and record it
    bench/cost_model.py --only "16 mm" --record bench/cost_baseline.json   # record some cases
    bench/cost_model.py --check  bench/cost_baseline.json   # fail if 2x slower

--check re-measures every case at its largest size (best of 3) and exits
with status 1, naming each case, when one costs more than 2x its recorded
figure (floors of 20 ms absorb start-up noise). The figures hold for the
machine they were recorded on: on another CPU (the recorded /proc/cpuinfo
model name and core count differ) the check says so and exits 0 unless
--force. It is a benchmark, never part of ctest: timings on a shared machine
are not a test verdict.
"""
import argparse
import json
import math
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REGRESSION_FACTOR = 2.0
FLOOR_S = 0.02  # below this a time is start-up and scheduler noise


def machine():
    model = "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return {"cpu": model, "cores": os.cpu_count(), "system": platform.system()}


def cpu_time(cmd):
    """CPU seconds (user + system) of one run of cmd; raises on failure."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode not in (0, 3):  # 3: chatter found (a verdict, not an error)
        raise RuntimeError(f"{' '.join(cmd)} exited {r.returncode}: {r.stderr.strip()[:400]}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def best_time(cmd, repeats):
    """The least CPU time of `repeats` runs: noise on a shared machine only adds."""
    return min(cpu_time(cmd) for _ in range(repeats))


def write(path, text):
    with open(path, "w") as f:
        f.write(text)
    return path


def modes_config(tmp, k):
    """Case C's process on a tool of k modes (x and y alternating, 800-1 400 Hz)."""
    lines = ['name = "cost model: %d modes"' % k, "[process]", 'operation = "milling"', "teeth = 2",
             "tangential_coefficient_n_per_m2 = 6e8", "radial_coefficient_n_per_m2 = 2e8",
             "radial_immersion = 0.5", 'milling_direction = "down"']
    for i in range(k):
        f = 800.0 + 600.0 * i / max(k - 1, 1)
        lines += ["[[tool.modes]]", "frequency_hz = %.1f" % f, "damping_ratio = 0.02",
                  "stiffness_n_per_m = %.3g" % (2e7 * (1 + i)), 'direction = "%s"' % ("xy"[i % 2])]
    lines += ["[sweep]", "rpm_min = 5000", "rpm_max = 25000", "rpm_points = 100", "depth_max_mm = 10"]
    return write(os.path.join(tmp, "modes%d.toml" % k), "\n".join(lines) + "\n")


def teeth_config(tmp, n):
    """Case C at half immersion with n teeth of variable pitch (360/n +- 10 %
    alternating): the period is a revolution, which holds n tooth periods.
    (An equally spaced cutter's period is one tooth period, shorter with more
    teeth: its cost does not grow with n.)"""
    src = open(os.path.join(ROOT, "configs/milling_benchmark_ae005_down.toml")).read()
    pitch = ", ".join("%.6g" % (360.0 / n * (1.1 if i % 2 == 0 else 0.9)) for i in range(n))
    src = src.replace("teeth = 2", "teeth = %d\npitch_angles_deg = [%s]" % (n, pitch))
    src = src.replace("radial_immersion = 0.05", "radial_immersion = 0.5")
    return write(os.path.join(tmp, "teeth%d.toml" % n), src)


def operations_file(tmp, n):
    rows = ["id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm,teeth,milling_direction"]
    for i in range(n):
        rows.append("op%d,%d,%.2f,,0.05,," % (i, 9000 + (i * 997) % 12000, 0.5 + (i % 7) * 0.5))
    return write(os.path.join(tmp, "ops%d.csv" % n), "\n".join(rows) + "\n")


def pocket_program(tmp, n):
    """A zig-zag pocket of n 1 mm feed moves (rows of 90 along X, 6 mm apart,
    1.5 mm levels) on a 100 x 100 x 30 mm box at 0.25 mm, and its job."""
    lines, moves, level = ["G17 G21 G90 G94", "T1 M6", "S9000 M3", "G0 X5 Y5 Z5"], 0, 0
    while moves < n:
        level += 1
        lines += ["G0 X5 Y5", "G1 Z%g F300" % (-1.5 * level)]
        moves += 1
        for row in range(16):
            if moves >= n:
                break
            if row:
                lines.append("G1 Y%g F900" % (5 + 6 * row))
                moves += 1
            for k in range(1, 91):
                if moves >= n:
                    break
                lines.append("G1 X%g F900" % (5 + k if row % 2 == 0 else 95 - k))
                moves += 1
        lines.append("G0 Z5")
    program = write(os.path.join(tmp, "pocket%d.ngc" % n), "\n".join(lines + ["M5", "M2"]) + "\n")
    job = write(os.path.join(tmp, "pocket_job.toml"),
                '[stock]\nshape = "box"\nmin_mm = [0, 0, -30]\nmax_mm = [100, 100, 0]\nresolution_mm = 0.25\n'
                '[[tools]]\nnumber = 1\nconfig = "%s"\n' % os.path.join(ROOT, "examples", "program", "end_mill.toml"))
    return program, job


def turning_program(tmp, n):
    """n feed moves along the examples/program shaft: passes of 0.5 mm on the
    radius, 20 segments of 3.5 mm each, and the shaft's job."""
    lines = ["G18 G21 G7 G90", "T1 M6", "G97 S1800 M3", "G95 F0.15"]
    for m in range(n):
        if m % 20 == 0:
            lines += ["G0 X27 Z2", "G0 Z0.5", "G1 X%g" % (25.0 - (m // 20 + 1) * 1.0)]
        lines.append("G1 Z%g" % (-3.5 * (m % 20 + 1)))
    program = write(os.path.join(tmp, "shaft%d.ngc" % n), "\n".join(lines + ["G0 X30", "M5", "M2"]) + "\n")
    job = open(os.path.join(ROOT, "examples", "program", "shaft_job.toml")).read().replace(
        'config = "insert.toml"', 'config = "%s"' % os.path.join(ROOT, "examples", "program", "insert.toml"))
    return program, write(os.path.join(tmp, "shaft_job.toml"), job)


def cases(chatter, tmp):
    """(name, parameter, sizes, command(size)) for each path a user waits on."""
    cfg = lambda name: os.path.join(ROOT, "configs", name)
    turning, case_c = cfg("seed_turning_1dof.toml"), cfg("milling_benchmark_ae005_down.toml")
    helix = cfg("milling_variable_pitch_helix.toml")
    end_mill = os.path.join(ROOT, "examples", "real_cutter", "aluminium_slot_16mm_3flute.toml")
    lobes = [chatter, "lobes", "--threads", "1", "--table", os.path.join(tmp, "t.csv")]
    return [
        ("lobes analytic, turning case A", "speeds", [2000, 8000, 32000, 128000],
         lambda n: lobes[:2] + [turning] + lobes[2:] + ["--method", "analytic", "--rpm-points", str(n)]),
        ("lobes sdm, case C", "speeds", [100, 200, 400, 800],
         lambda n: lobes[:2] + [case_c] + lobes[2:] + ["--method", "sdm", "--rpm-points", str(n)]),
        ("lobes sdm, case C, 400 speeds", "steps per period", [32, 64, 128, 256],
         lambda n: lobes[:2] + [case_c] + lobes[2:] + ["--method", "sdm", "--rpm-points", "400", "--steps", str(n)]),
        ("lobes sdm, 100 speeds, a_e/D 0.5", "modes", [1, 2, 4, 8],
         lambda n: lobes[:2] + [modes_config(tmp, n)] + lobes[2:] + ["--method", "sdm"]),
        ("lobes sdm, case C a_e/D 0.5 variable pitch, 400 speeds", "teeth", [2, 4, 8, 16],
         lambda n: lobes[:2] + [teeth_config(tmp, n)] + lobes[2:] + ["--method", "sdm", "--rpm-points", "400"]),
        ("lobes sdm, variable-pitch helix", "speeds", [10, 20, 40, 80],
         lambda n: lobes[:2] + [helix] + lobes[2:] + ["--method", "sdm", "--rpm-points", str(n)]),
        ("lobes sdm, 16 mm 3-flute helix slot, 500-24 000 rev/min", "speeds", [25, 50, 100, 200],
         lambda n: lobes[:2] + [end_mill] + lobes[2:] + ["--method", "sdm", "--rpm-points", str(n)]),
        ("point sdm, 16 mm 3-flute helix slot, 1 mm", "rev/min / 100", [40, 20, 10, 5],
         lambda n: [chatter, "point", end_mill, "--method", "sdm", "--rpm", str(100 * n), "--depth-mm", "1"]),
        ("recommend, 16 mm 3-flute helix slot from 500 rev/min", "top speed / 1 000 rev/min", [3, 6, 12, 24],
         lambda n: [chatter, "recommend", end_mill, "--threads", "1", "--feed-per-tooth-mm", "0.08",
                    "--rpm-min", "500", "--rpm-max", str(1000 * n)]),
        ("lobes time-domain, case C, 2 speeds", "periods per verdict", [50, 100, 200, 400],
         lambda n: lobes[:2] + [case_c] + lobes[2:] + ["--method", "time-domain", "--rpm-min", "14000",
                                                        "--rpm-max", "20000", "--rpm-points", "2", "--periods", str(n)]),
        ("lobes time-domain, variable-pitch helix, 2 speeds", "axial slices", [4, 8, 16, 32],
         lambda n: lobes[:2] + [helix] + lobes[2:] + ["--method", "time-domain", "--rpm-min", "10000",
                                                       "--rpm-max", "12000", "--rpm-points", "2",
                                                       "--axial-slices", str(n)]),
        ("map sdm, case C, 40 speeds", "depths", [10, 30, 90, 270],
         lambda n: [chatter, "map", case_c, "--threads", "1", "--rpm-points", "40", "--depth-points", str(n),
                    "--out", os.path.join(tmp, "m.csv")]),
        ("simulate, variable-pitch helix, 10 000 rev/min 2 mm", "revolutions", [75, 150, 300, 600],
         lambda n: [chatter, "simulate", helix, "--rpm", "10000", "--depth-mm", "2", "--revolutions", str(n)]),
        ("sle, case C, 1 mm", "speeds", [100, 200, 400, 800],
         lambda n: [chatter, "sle", case_c, "--threads", "1", "--quiet", "--depth-mm", "1", "--feed-per-tooth-mm",
                    "0.05", "--rpm-points", str(n), "--table", os.path.join(tmp, "s.csv")]),
        ("check, case C", "operations", [10, 40, 160, 640],
         lambda n: [chatter, "check", case_c, "--threads", "1", "--operations", operations_file(tmp, n)]),
        ("program, zig-zag pocket at 0.25 mm", "blocks", [500, 1000, 2000, 4000],
         lambda n: [chatter, "program", *pocket_program(tmp, n)[:1], "--config", pocket_program(tmp, n)[1],
                    "--threads", "1"]),
        ("program, turned shaft", "blocks", [25, 50, 100, 200],
         lambda n: [chatter, "program", turning_program(tmp, n)[0], "--config", turning_program(tmp, n)[1],
                    "--threads", "1"]),
    ]


def scaling(sizes, times):
    """The local exponent p = d ln t / d ln n between the two largest sizes
    (t the whole run's CPU time, fixed costs included, so p is at most the
    exponent of the work that grows) and the marginal cost (t4 - t3) /
    (n4 - n3) in ms per unit of n. p near 0: the cost does not grow with n."""
    (n3, n4), (t3, t4) = sizes[-2:], times[-2:]
    p = math.log(t4 / t3) / math.log(n4 / n3) if t3 > 0 and t4 > 0 else float("nan")
    return p, 1e3 * (t4 - t3) / (n4 - n3)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="build directory holding ./chatter")
    ap.add_argument("--repeats", type=int, default=3, help="runs per point (the least CPU time is kept)")
    ap.add_argument("--record", metavar="JSON", help="write the measured figures here")
    ap.add_argument("--check", metavar="JSON", help="re-measure the largest sizes, fail if 2x slower than recorded")
    ap.add_argument("--force", action="store_true", help="with --check: compare even on another machine")
    ap.add_argument("--only", help="run only the cases whose name or parameter contains this text")
    a = ap.parse_args()
    chatter = os.path.join(a.build, "chatter")
    if not os.access(chatter, os.X_OK):
        sys.exit(f"cost_model.py: {chatter} not found: build first (bash scripts/build.sh)")
    here = machine()
    with tempfile.TemporaryDirectory() as tmp:
        todo = [c for c in cases(chatter, tmp) if not a.only or a.only in c[0] or a.only in c[1]]
        if a.check:
            rec = json.load(open(a.check))
            if rec.get("machine") != here and not a.force:
                print(f"cost_model.py: {a.check} was recorded on {rec.get('machine')}, this is {here}: "
                      "figures of another machine are not comparable; nothing checked (--force to compare)")
                return 0
            failed = []
            for name, param, sizes, cmd in todo:
                if name not in rec["cases"]:
                    print(f"  {name}: not recorded, skipped")
                    continue
                old = rec["cases"][name]["times_s"][-1]
                new = best_time(cmd(sizes[-1]), a.repeats)
                ratio = max(new, FLOOR_S) / max(old, FLOOR_S)
                flag = "REGRESSION" if ratio > REGRESSION_FACTOR else "ok"
                print(f"  {flag:10s} {name}, {param} = {sizes[-1]}: {new:.3f} s CPU, recorded {old:.3f} s "
                      f"({ratio:.2f}x)")
                if ratio > REGRESSION_FACTOR:
                    failed.append(name)
            if failed:
                print(f"cost_model.py: FAILED: {len(failed)} path(s) more than {REGRESSION_FACTOR:g}x slower "
                      f"than recorded in {a.check}: " + "; ".join(failed), file=sys.stderr)
                return 1
            print(f"cost_model.py: every checked path within {REGRESSION_FACTOR:g}x of {a.check}")
            return 0
        out = {"machine": here, "date": time.strftime("%Y-%m-%d"), "repeats": a.repeats, "cases": {}}
        print("| command, case | grows with n | n | CPU s at each n | marginal ms per unit of n | exponent p |")
        print("|---|---|---|---|---|---|")
        for name, param, sizes, cmd in todo:
            times = [best_time(cmd(n), a.repeats) for n in sizes]
            p, marginal = scaling(sizes, times)
            out["cases"][name] = {"parameter": param, "sizes": sizes, "times_s": times,
                                  "marginal_ms_per_unit": marginal, "exponent": p}
            print(f"| {name} | {param} | {', '.join(map(str, sizes))} | "
                  f"{', '.join('%.3f' % t for t in times)} | {marginal:.3g} | {p:.2f} |", flush=True)
        if a.record:
            if a.only and os.path.exists(a.record):
                # Some cases only: merged into the record, each dated; the
                # others keep their figures (same machine only).
                rec = json.load(open(a.record))
                if rec.get("machine") != here:
                    sys.exit(f"cost_model.py: {a.record} holds figures of {rec.get('machine')}, this is {here}: "
                             "record every case here (without --only), not a mix")
                for name, case in out["cases"].items():
                    rec["cases"][name] = dict(case, date=out["date"])
                out = rec
            with open(a.record, "w") as f:
                json.dump(out, f, indent=1)
                f.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
