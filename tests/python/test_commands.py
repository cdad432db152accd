"""Every command of the CLI from Python (issue 30): the module has a function
for each command `chatter --help` lists (and each `chatter grind`
subcommand), and each new function answers with its record, its tables as
NumPy arrays, numbers built in from known answers, and messages that name its
keywords (the library checks the arguments once, for both front ends)."""
import math
import re

import numpy as np
import pytest

import chatter
from conftest import SOURCE_DIR, cli_json, run_cli

CONFIGS = SOURCE_DIR / "configs"
CASE_A = CONFIGS / "seed_turning_1dof.toml"
CASE_C = CONFIGS / "milling_benchmark_ae005_down.toml"
TAP_TEST = SOURCE_DIR / "examples" / "tap_test" / "end_mill_xx.csv"

# The module's functions of a CLI command, where they are not its name
# (dashes become underscores otherwise: `forced` is chatter.forced). `lobes`
# has two: the table, and its Monte Carlo (lobes --samples).
MODULE_NAMES = {"lobes": ["lobes", "uncertain_lobes"]}


def command_list(*args):
    """The commands a help text lists under 'Commands:' (two-space indent)."""
    status, out, err = run_cli(*args, "--help")
    assert status == 0, err
    section = out.split("Commands:\n", 1)[1].split("\n\n", 1)[0]
    return [m.group(1) for m in re.finditer(r"^  ([a-z][a-z0-9-]*)\s", section, re.M)]


def test_the_help_lists_are_read():
    """The parser below reads the lists (it would pass vacuously on none)."""
    commands = command_list()
    assert {"lobes", "point", "check", "recommend", "map", "compare", "simulate", "surface", "fit", "frf",
            "coefficients", "detect", "grind"} <= set(commands)
    assert {"predict", "sweep", "fit", "impacts", "simulate", "plan"} <= set(command_list("grind"))


def test_every_cli_command_is_a_module_function():
    missing = []
    for command in command_list():
        if command == "grind":
            names = ["grind_" + sub.replace("-", "_") for sub in command_list("grind")]
        else:
            names = MODULE_NAMES.get(command, [command.replace("-", "_")])
        missing += [f"{command}: chatter.{n}" for n in names if not callable(getattr(chatter, n, None))]
    assert not missing, "CLI commands the module lacks: " + ", ".join(missing)


# ---------------------------------------------------------------- recommend


def test_recommend_is_the_record_and_checks_name_the_keywords():
    job = chatter.load(CASE_C)
    r = chatter.recommend(job, feed_per_tooth_mm=0.05, max_power_kw=1.0, tool_diameter_mm=10)
    assert r["format"] == "chatter-recommendation" and r["method"] == "sdm"
    assert r["depth_mm"] <= 0.8 * r["speed_band"]["worst_limit_mm"] * (1 + 1e-12)  # safety x the worst limit
    assert r["power_kw"] <= 1.0 * (1 + 1e-9)
    assert "explanation" in r and r["inputs"]["max_power_kw"] == 1.0
    # The part's tolerance on the forced vibration (chatter recommend --max-sle-um).
    xy = chatter.load(str(SOURCE_DIR / "examples" / "forced" / "case_c_xy.toml"))
    t = chatter.recommend(xy, feed_per_tooth_mm=0.05, max_sle_um=10, rpm_min=5000, rpm_max=25000, depth_max_mm=10)
    assert "surface_error" in t["binding"] and t["part_error_um"] <= 10 * (1 + 1e-9)
    assert t["inputs"]["max_sle_um"] == 10
    with pytest.raises(chatter.InputError, match=r"^max_sle_um = 0: must be > 0$"):
        chatter.recommend(xy, feed_per_tooth_mm=0.05, max_sle_um=0)
    with pytest.raises(chatter.InputError, match=r"^feed_per_tooth_mm = -1: must be > 0$"):
        chatter.recommend(job, feed_per_tooth_mm=-1)
    with pytest.raises(chatter.InputError, match=r"^workpiece_diameter_mm: only for turning"):
        chatter.recommend(job, feed_per_tooth_mm=0.05, workpiece_diameter_mm=50)
    with pytest.raises(chatter.InputError, match=r"^a power or torque limit needs the tool diameter \(tool_diameter_mm\)"):
        chatter.recommend(chatter.Job(dict(_case_c_dict(), process={**_case_c_dict()["process"],
                                                                    "tool_diameter_mm": None})),
                          feed_per_tooth_mm=0.05, max_power_kw=1.0)


def _case_c_dict():
    return {"name": "C", "process": {"operation": "milling", "teeth": 2, "tangential_coefficient_n_per_m2": 6e8,
                                     "radial_coefficient_n_per_m2": 2e8, "radial_immersion": 0.05,
                                     "milling_direction": "down"},
            "tool": {"modes": [{"frequency_hz": 922, "damping_ratio": 0.011, "mass_kg": 0.03993, "direction": "x"}]},
            "sweep": {"rpm_min": 5000, "rpm_max": 25000}}


# ---------------------------------------------------------------- compare, map, frf


def test_compare_tables_and_explanation():
    job = chatter.load(CASE_C)
    c = chatter.compare(job, rpm_points=30)
    assert c["methods"] == ["analytic", "coupled", "sdm"]
    assert c["spindle_rpm"].shape == (30,) and c["multiplier_type_sdm"].shape == (30,)
    # analytic and coupled solve the same averaged equation: round-off apart.
    a, b = c["depth_limit_mm_analytic"], c["depth_limit_mm_coupled"]
    assert np.allclose(a, b, rtol=1e-9)
    pair = c["pairs"][0]
    assert pair["methods"] == ["analytic", "coupled"] and pair["largest_relative_difference"] < 1e-9
    assert "flip" in c["explanation"] and "flip" in set(c["multiplier_type_sdm"])
    # Options go to the methods that have them; a list of names is --methods.
    c2 = chatter.compare(job, ["analytic", "sdm"], rpm_points=5, options={"steps": 30})
    assert c2["solver_options"]["sdm"]["steps_per_period"] == 30
    with pytest.raises(chatter.InputError, match=r"^methods 'analytic,nope': unknown method 'nope'"):
        chatter.compare(job, "analytic,nope")
    with pytest.raises(chatter.InputError, match=r"^options: 'feed_per_tooth_mm': not an option of the methods"):
        chatter.compare(job, "analytic", options={"feed_per_tooth_mm": 0.1})


def test_map_grid_boundary_and_flip_points():
    job = chatter.load(CASE_C)
    m = chatter.map(job, rpm_points=16, depth_points=9, multiplier_types=True)
    rho = m["spectral_radius"]
    assert rho.shape == (16, 9) and m["depth_mm"][0] == 0.0 and m["depth_mm"][-1] == 10.0
    assert np.all(rho[:, 0] < 1.0), "no cut, no chatter"
    assert m["unstable_points"] == int(np.sum(rho >= 1.0))
    types = m["multiplier_type"]
    assert set(types[rho < 1.0].ravel()) == {""} and "flip" in set(types.ravel())
    # The map's boundary is the lobe table's limit: at each speed the first
    # unstable depth lies above the limit and the last stable one below it.
    lobes = chatter.lobes(job, "sdm", rpm=m["spindle_rpm"])
    for i, limit in enumerate(lobes["depth_limit_mm"]):
        unstable = m["depth_mm"][rho[i] >= 1.0]
        if unstable.size:
            assert unstable[0] >= limit * (1 - 1e-3)
    with pytest.raises(chatter.InputError, match=r"^method analytic: map needs method sdm$"):
        chatter.map(job, "analytic")
    with pytest.raises(chatter.InputError, match=r"^depth_points = 1: must be >= 2$"):
        chatter.map(job, depth_points=1)


def test_frf_is_the_receptance_of_the_modes():
    job = chatter.load(CASE_C)
    f = chatter.frf(job, fmin=900, fmax=950, points=51)
    status, out, _ = run_cli("frf", CASE_C, "--points", "3")
    assert list(k for k in f if k not in ("name", "warnings")) == out.splitlines()[0].split(",")
    g = f.receptance("relative", "xx")
    k = 0.03993 * (2 * math.pi * 922) ** 2
    assert abs(g[np.argmin(np.abs(f["frequency_hz"] - 922))]) == pytest.approx(1 / (2 * 0.011 * k), rel=1e-6)
    assert np.allclose(g, f.receptance("tool", "xx") + f.receptance("workpiece", "xx"))
    with pytest.raises(chatter.InputError, match=r"^fmax = 100: must be > fmin \(900\)$"):
        chatter.frf(job, fmin=900, fmax=100)


# ---------------------------------------------------------------- fit, coefficients, detect


def test_fit_finds_the_tap_tests_modes_and_its_fragment_loads():
    r = chatter.fit(TAP_TEST)
    (rec,) = r["records"]
    modes = rec["modes"]
    assert len(modes) == 2
    # examples/tap_test/make_tap_test.py: 922 Hz, 0.011, 1.34 N/um and 1840 Hz, 0.03, 5 N/um, 2 % noise.
    assert modes[0]["frequency_hz"] == pytest.approx(922.0, rel=1e-3)
    assert modes[0]["damping_ratio"] == pytest.approx(0.011, rel=0.03)
    assert modes[0]["stiffness_n_per_m"] == pytest.approx(0.03993 * (2 * math.pi * 922) ** 2, rel=0.03)
    assert modes[1]["frequency_hz"] == pytest.approx(1840.0, rel=1e-3)
    assert rec["measured_receptance_m_per_n"].dtype == np.complex128
    assert rec["fitted_frequency_hz"][0] == rec["band_min_hz"]
    job = chatter.Job.from_toml(r["fragment"] + '\n[process]\noperation = "milling"\nteeth = 2\n'
                                "tangential_coefficient_n_per_m2 = 6e8\nradial_coefficient_n_per_m2 = 2e8\n"
                                "radial_immersion = 0.05\n")
    assert chatter.point(job, rpm=12000, depth_mm=0.5)["method"] == "sdm"
    with pytest.raises(chatter.InputError, match=r"^modes = 0: must be >= 1"):
        chatter.fit(TAP_TEST, modes=0)
    with pytest.raises(chatter.InputError, match=r"band 5000 6000 Hz lies outside the measured lines"):
        chatter.fit(TAP_TEST, band=(5000, 6000))


# Coefficients of the test cuts below (N/m^2, N/m): K_tc, K_rc, K_te, K_re.
K_TRUE = (8e8, 2.5e8, 2.5e4, 3.0e4)


def slot_mean_forces(feed_m, depth_m, teeth=2):
    """Mean forces of a full slot (radial immersion 1): each tooth cuts from
    0 to pi; the tooth forces of the linear edge model, averaged over a
    revolution (midpoint rule, 20 000 points: 1e-9 relative)."""
    n = 20000
    phi = (np.arange(n) + 0.5) * math.pi / n
    ft = K_TRUE[0] * depth_m * feed_m * np.sin(phi) + K_TRUE[2] * depth_m
    fr = K_TRUE[1] * depth_m * feed_m * np.sin(phi) + K_TRUE[3] * depth_m
    fx = (-ft * np.cos(phi) - fr * np.sin(phi)).mean() * teeth / 2
    fy = (ft * np.sin(phi) - fr * np.cos(phi)).mean() * teeth / 2
    return fx, fy


def test_coefficients_find_the_known_coefficients(tmp_path):
    rows = ["feed_per_tooth_mm,depth_mm,fx_mean_n,fy_mean_n"]
    for a in (1.0, 2.0):
        for f in (0.05, 0.1, 0.15, 0.2):
            fx, fy = slot_mean_forces(f * 1e-3, a * 1e-3)
            rows.append(f"{f},{a},{fx:.12g},{fy:.12g}")
    tests = tmp_path / "tests.csv"
    tests.write_text("\n".join(rows) + "\n")
    r = chatter.coefficients(tests, teeth=2, radial_immersion=1, milling_direction="up")
    for key, want in zip(("tangential_coefficient_n_per_m2", "radial_coefficient_n_per_m2",
                          "tangential_edge_coefficient_n_per_m", "radial_edge_coefficient_n_per_m"), K_TRUE):
        assert r[key] == pytest.approx(want, rel=1e-6), key
    assert r["route"] == "forces" and len(r["tests"]) == 8
    assert "[process]" in r["fragment"] and "teeth = 2" in r["fragment"]
    with pytest.raises(chatter.InputError, match=r"^milling_direction 'sideways': use down or up$"):
        chatter.coefficients(tests, teeth=2, radial_immersion=1, milling_direction="sideways")
    with pytest.raises(chatter.InputError, match=r"^radial_immersion = 2: must be in \(0, 1\]"):
        chatter.coefficients(tests, teeth=2, radial_immersion=2, milling_direction="up")


def test_coefficients_on_turning_tests_give_kienzle_law_as_the_cli(tmp_path):
    # Seed 003's table 14 and a third cut: Kienzle's law per direction, the
    # CLI's --json record number for number, and the fragment.
    tests = tmp_path / "turning.csv"
    tests.write_text("feed_mm_per_rev,depth_mm,tangential_force_n,feed_force_n\n"
                     "0.35,1.5,736,501\n0.089,1.5,342,175\n0.2,1.5,560,330\n")
    r = chatter.coefficients(tests)
    cli = cli_json("coefficients", tests, "--json", "-")
    assert r["force_law"] == "kienzle" and r["degrees_of_freedom"] == 1
    for key in ("specific_force_n_per_mm2", "exponent", "standard_error", "r_squared"):
        assert r[key] == cli[key], key
    # Through the seed's two points only: 1 - m = ln(736/342) / ln(0.35/0.089).
    two = tmp_path / "two.csv"
    two.write_text("feed_mm_per_rev,depth_mm,tangential_force_n,feed_force_n\n0.35,1.5,736,501\n0.089,1.5,342,175\n")
    m = 1 - math.log(736 / 342) / math.log(0.35 / 0.089)
    assert chatter.coefficients(two)["exponent"]["tangential"] == pytest.approx(m, rel=1e-12)
    assert 'force_law = "kienzle"' in r["fragment"]
    with pytest.raises(chatter.InputError, match=r"^teeth: for milling tests"):
        chatter.coefficients(tests, teeth=3)


def test_detect_hears_the_chatter_line_and_suggests_speeds(tmp_path):
    rpm, teeth, rate = 6000.0, 2, 20000.0
    t = np.arange(int(2.0 * rate)) / rate
    tooth = rpm * teeth / 60.0
    signal = (0.2 * np.sin(2 * math.pi * tooth * t) + 0.05 * np.sin(2 * math.pi * 2 * tooth * t)
              + 0.1 * np.sin(2 * math.pi * rpm / 60 * t)
              + 0.3 * np.minimum(1.0, t / 1.0) * np.sin(2 * math.pi * 1777.0 * t)
              + 0.002 * np.random.default_rng(3).standard_normal(t.size))
    rec = tmp_path / "cut.csv"
    np.savetxt(rec, np.column_stack([t, signal]), delimiter=",", header="time_s,value", comments="", fmt="%.9g")
    d = chatter.detect(rec, rpm=rpm, teeth=teeth)
    assert d["chatter"] and d["chatter_frequency_hz"] == pytest.approx(1777.0, abs=1.0)
    # The classic correction: N_k = 60 f_c / (teeth k), nearest to 6000 first.
    k = d["suggestions"][0]["k"]
    assert d["suggestions"][0]["rpm"] == pytest.approx(60 * d["chatter_frequency_hz"] / (teeth * k), rel=1e-12)
    assert d["spectrum"]["frequency_hz"].shape == d["spectrum"]["amplitude"].shape
    # Checked against a model (a Job), each suggestion gets its margin.
    d2 = chatter.detect(rec, rpm=rpm, teeth=teeth, config=chatter.load(CASE_C), depth_mm=1.0)
    assert d2["check_method"] == "sdm" and all("stable_in_model" in s for s in d2["suggestions"])
    with pytest.raises(chatter.InputError, match=r"is rpm \(or teeth\) right\?.*force=True analyses"):
        chatter.detect(rec, rpm=4100, teeth=teeth)
    with pytest.raises(chatter.InputError, match=r"^depth_mm: give config too"):
        chatter.detect(rec, rpm=rpm, teeth=teeth, depth_mm=1.0)


# ---------------------------------------------------------------- grinding


def test_grinding_subcommands():
    scompi = CONFIGS / "grinding_scompi_ch4.toml"
    s = chatter.grind_sweep(scompi, power_w_min=250, power_w_max=2500, points=10)
    assert s["power_w"].shape[0] % 10 == 0 and np.all(np.diff(s["power_w"][:10]) > 0)
    removal = [k for k in s if k.startswith("removal")][0]
    assert np.all(np.diff(s[removal][:10]) > 0), "more power removes more"
    p = chatter.grind_plan(CONFIGS / "grinding_underwater_seed000.toml", power_w=2000, area_mm2=1.5e6, depth_mm=2)
    assert p["wheels_needed"] >= 1 and len(p["wheel_life"]) > 0
    with pytest.raises(chatter.InputError, match=r"^give volume_mm3, or area_mm2 with depth_mm"):
        chatter.grind_plan(scompi, power_w=1000)
    sim = chatter.grind_simulate(scompi, power_w=1000, turns=40, series_turns=5)
    assert sim["turns"] == 40 and sim["series"]["time_s"].size > 0


def test_grind_impacts_counts_the_simulated_contacts(tmp_path):
    """The simulation's force series read back as a force record: two counts
    of the same contacts (one per contact, in the turn of its peak)."""
    sim = chatter.grind_simulate(CONFIGS / "grinding_scompi_ch4.toml", power_w=1000, series_turns=200)
    t, force = sim["series"]["time_s"], sim["series"]["contact_force_n"]
    keep = np.concatenate([[True], np.diff(t) > 0])  # a contact event's second sample has the same time
    rec = tmp_path / "force.csv"
    np.savetxt(rec, np.column_stack([t[keep], force[keep]]), delimiter=",", header="time_s,normal_force_n",
               comments="", fmt="%.17g")
    imp = chatter.grind_impacts(rec, wheel_rpm=6000, threshold_n=1)
    assert imp["turns"] == 200
    assert imp["impacts_per_turn"] == pytest.approx(sim["impacts_per_turn"], rel=1e-12)
    assert imp["turns_table"][list(imp["turns_table"])[0]].size == 200
    with pytest.raises(chatter.InputError, match=r"threshold_rpm: .* is a force record: use threshold_n"):
        chatter.grind_impacts(rec, wheel_rpm=6000, threshold_rpm=100)


# ---------------------------------------------------------------- figures


def test_results_draw_themselves_and_lobes_mark_flips():
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    job = chatter.load(CASE_C)
    lobes = chatter.lobes(job, rpm_points=120)
    assert isinstance(lobes, dict) and lobes.info["method"] == "sdm"
    ax = lobes.plot()
    labels = [line.get_label() for line in ax.get_lines()]
    assert "flip (period doubling)" in labels and "stability limit" in labels
    flip = [line for line in ax.get_lines() if line.get_label() == "flip (period doubling)"][0]
    drawn = ~np.isnan(np.asarray(flip.get_ydata(), dtype=float))
    assert np.array_equal(drawn, lobes["multiplier_type"] == "flip")
    assert lobes._repr_png_().startswith(b"\x89PNG")
    results = [chatter.map(job, rpm_points=8, depth_points=6, multiplier_types=True),
               chatter.map(job, axes="radial-axial", rpm=10000, immersion_points=4, depth_points=6,
                           multiplier_types=True),
               chatter.compare(job, rpm_points=10), chatter.frf(job), chatter.fit(TAP_TEST),
               chatter.simulate(job, rpm=17000, depth_mm=3, periods=20),
               chatter.uncertain_lobes(chatter.load(CONFIGS / "seed_turning_1dof_uncertain.toml"), samples=8,
                                       rpm_points=20),
               chatter.surface(chatter.load(CONFIGS / "milling_case_c_positions.toml"), rpm_points=10,
                               position_points=3)]
    for r in results:
        drawn = r.plot()
        assert drawn is not None, type(r).__name__
        assert r._repr_png_().startswith(b"\x89PNG"), type(r).__name__
        plt.close("all")
    assert repr(lobes).startswith("<chatter.Lobes ")


def test_map_radial_axial_boundary_is_the_cli_one():
    # axes="radial-axial": immersion x axial depth at one speed; the boundary
    # (one sdm limit search per immersion) is the CLI's, and at the config's
    # own immersion (0.05) it is chatter.point's limit at that speed.
    job = chatter.load(CASE_C)
    m = chatter.map(job, axes="radial-axial", rpm=10000, immersion_min=0.05, immersion_max=0.5,
                    immersion_points=4, depth_points=11)
    assert m["axes"] == "radial-axial" and m["spectral_radius"].shape == (4, 11)
    assert m["radial_immersion"][0] == 0.05 and "radial_depth_mm" not in m  # case C gives no diameter
    p = chatter.point(job, rpm=10000, depth_mm=1, method="sdm")
    assert m["depth_limit_mm"][0] == pytest.approx(p["depth_limit_mm"], rel=1e-4)
    status, out, _ = run_cli("map", CASE_C, "--axes", "radial-axial", "--rpm", "10000", "--immersion-min", "0.05",
                             "--immersion-max", "0.5", "--immersion-points", "4", "--depth-points", "11",
                             "--json", "-")
    assert status == 0
    import json
    cli = json.loads(out)
    assert [b["depth_limit_mm"] for b in cli["boundary"]] == list(m["depth_limit_mm"])
    with pytest.raises(chatter.InputError, match=r"^rpm: required with axes=\"radial-axial\""):
        chatter.map(job, axes="radial-axial")
    with pytest.raises(chatter.InputError, match=r"^axes 'radial': unknown"):
        chatter.map(job, axes="radial")
    with pytest.raises(chatter.InputError, match=r"^immersion_min = 0: must be in \(0, 1\]"):
        chatter.map(job, axes="radial-axial", rpm=10000, immersion_min=0)
    with pytest.raises(chatter.InputError, match=r"^rpm: only with axes=\"radial-axial\""):
        chatter.map(job, rpm=10000)


# ---------------------------------------------------------------- design_pitch


def test_design_pitch_is_the_record_and_checks_name_the_keywords():
    job = chatter.load(CONFIGS / "milling_pitch_design_4flute.toml")
    d = chatter.design_pitch(job, rpm_min=6600, rpm_max=8000, teeth=4, rpm_points=11, scan_points=4)
    assert d["format"] == "chatter-pitch-design" and d["method"] == "sdm"
    assert abs(sum(d["pitch_angles_deg"]) - 360.0) < 1e-9
    designed = [row["depth_limit_designed_mm"] for row in d["band"]]
    equal = [row["depth_limit_equal_mm"] for row in d["band"]]
    assert d["designed"]["worst_limit_mm"] == min(designed) and d["equal"]["worst_limit_mm"] == min(equal)
    # The gain is the ratio of the limits in m; the record's limits are in mm
    # (×1e3 each), so the quotient agrees to round-off, not bit for bit.
    assert d["gain"] == pytest.approx(d["designed"]["worst_limit_mm"] / d["equal"]["worst_limit_mm"], rel=1e-12)
    assert d["gain"] > 1.0
    assert d["designed"]["worst_limit_mm"] >= d["start"]["worst_limit_mm"]
    with pytest.raises(chatter.InputError, match=r"^rpm_max = 6600: must be > rpm_min = 8000"):
        chatter.design_pitch(job, rpm_min=8000, rpm_max=6600)
    with pytest.raises(chatter.InputError, match=r"^teeth = 3: the config's cutter has 4 teeth"):
        chatter.design_pitch(job, rpm_min=6600, rpm_max=8000, teeth=3)
    with pytest.raises(chatter.InputError, match=r"^rpm_min: required"):
        chatter.design_pitch(job, rpm_max=8000)


# ---------------------------------------------------------------- program


@pytest.mark.skipif(not __import__("os").path.exists("/usr/bin/rs274"), reason="LinuxCNC's rs274 is not installed")
def test_program_is_the_cli_record():
    import json
    ex = SOURCE_DIR / "examples" / "program"
    r = chatter.program(str(ex / "shaft.ngc"), str(ex / "shaft_job.toml"), threads=1)
    status, out, err = run_cli("program", ex / "shaft.ngc", "--config", ex / "shaft_job.toml", "--json", "-",
                               "--threads", "1")
    assert status == 3, err  # the shaft's first pass chatters at the free end
    assert r == json.loads(out)
    assert r["summary"]["unstable_blocks"] == 1 and r["status"] == 3
    with pytest.raises(chatter.InputError, match="stock"):
        chatter.program(str(ex / "shaft.ngc"), str(ex / "insert.toml"))
