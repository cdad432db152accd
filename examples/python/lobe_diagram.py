#!/usr/bin/env python3
"""Draws a stability-lobe diagram from the numbers of chatter.lobes(): with
matplotlib when it is installed, else with gnuplot (Debian gnuplot-nox, as
the CLI's plots).

  PYTHONPATH=build/python python3 examples/python/lobe_diagram.py \\
      configs/milling_benchmark_ae005_down.toml --method sdm --out lobes.png
"""
import argparse
import math
import subprocess

import numpy as np

import chatter


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config")
    ap.add_argument("--method", default="auto", choices=["auto", *chatter.methods()])
    ap.add_argument("--points", type=int, default=300)
    ap.add_argument("--out", default="lobes.png")
    a = ap.parse_args()

    job = chatter.load(a.config)
    t = chatter.lobes(job, a.method, rpm_points=a.points)
    rpm, depth = t["spindle_rpm"], t["depth_limit_mm"]
    finite = np.isfinite(depth)
    best = int(np.argmax(np.where(finite, depth, -np.inf)))
    print(f"{job.name} ({a.method}): deepest limit {depth[best]:.3f} mm at {rpm[best]:.0f} rev/min; "
          f"lowest {np.min(depth[finite]):.3f} mm" if finite.any() else "no limit in the sweep")
    top = 1.1 * np.max(depth[finite]) if finite.any() else 1.0
    plotted = np.where(finite, depth, top)  # no limit: drawn at the top of the axis
    title = f"{job.name} ({a.method})"
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(8, 4.5))
        ax.plot(rpm, plotted, "b-")
        ax.fill_between(rpm, 0, plotted, color="b", alpha=0.1, label="stable")
        ax.set(xlabel="spindle speed (rev/min)", ylabel="depth of cut (mm)", title=title, ylim=(0, top))
        ax.legend()
        fig.savefig(a.out, dpi=120, bbox_inches="tight")
    except ImportError:
        data = "\n".join(f"{x!r} {y!r}" for x, y in zip(rpm, plotted))
        term = {"png": "pngcairo size 900,500", "svg": "svg size 900,500", "pdf": "pdfcairo"}[a.out.rsplit(".", 1)[-1]]
        script = (f"set terminal {term}\nset output '{a.out}'\nset title \"{title}\"\n"
                  f"set xlabel 'spindle speed (rev/min)'\nset ylabel 'depth of cut (mm)'\n"
                  f"set yrange [0:{top!r}]\nset key top left\n"
                  f"plot '-' with filledcurves y1=0 fc rgb '#dde6ff' title 'stable', "
                  f"'-' with lines lw 2 lc rgb '#1f4fbf' title 'limit'\n{data}\ne\n{data}\ne\n")
        subprocess.run(["gnuplot"], input=script, text=True, check=True)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
