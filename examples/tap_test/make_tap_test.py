#!/usr/bin/env python3
"""Writes end_mill_xx.csv: the tap test of an end mill's tip along x, as a
modal-analysis program exports it (frequency_hz, real, imag of the
receptance in m/N, one line per 1 Hz from 200 to 2500 Hz).

Synthetic, so the answer is known: two modes, the Insperger-Stepan benchmark
cutter's (922 Hz, damping 0.011, modal mass 0.03993 kg: stiffness 1.34 N/um)
and a stiffer holder mode (1840 Hz, damping 0.03, 5 N/um), plus complex
noise of 2 % of the local response and 0.1 % of the peak (seeded: the file is
the same on every run). `chatter fit` finds the
modes back within the noise (examples/notebooks/lobes.ipynb, docs/frf.md).

  python3 examples/tap_test/make_tap_test.py
"""
import math
import pathlib

import numpy as np

MODES = [(922.0, 0.011, 0.03993 * (2 * math.pi * 922.0) ** 2),  # Hz, damping ratio, stiffness N/m
         (1840.0, 0.03, 5e6)]
NOISE_RELATIVE = 0.02   # of the receptance at each line
NOISE_FLOOR = 0.001     # of the largest receptance


def main():
    f = np.arange(200.0, 2500.0 + 0.5, 1.0)
    w = 2 * math.pi * f
    g = np.zeros_like(f, dtype=complex)
    for fn, zeta, k in MODES:
        wn = 2 * math.pi * fn
        g += 1.0 / (k * (1 - (w / wn) ** 2 + 2j * zeta * w / wn))
    rng = np.random.default_rng(20261125)
    scale = NOISE_RELATIVE * np.abs(g) + NOISE_FLOOR * np.abs(g).max()
    g += scale * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / math.sqrt(2)
    out = pathlib.Path(__file__).with_name("end_mill_xx.csv")
    with out.open("w") as fh:
        fh.write("frequency_hz,real_m_per_n,imag_m_per_n\n")
        for fi, gi in zip(f, g):
            fh.write(f"{fi:.1f},{gi.real:.6e},{gi.imag:.6e}\n")
    print(f"wrote {out} ({f.size} lines)")


if __name__ == "__main__":
    main()
