"""The module gives the CLI's numbers for the same inputs, for every shipped
config and every method: lobe tables against the CSV (10 significant digits,
compared as the CSV's own text) and the --json table (bitwise after the same
rounding), point / check / simulate against their JSON bitwise (full double)."""
import json
import pathlib

import numpy as np
import pytest

import chatter
from conftest import CONFIGS, SOURCE_DIR, cli_error_lines, cli_json, run_cli

# Speeds per lobe table: enough rows to cross several lobes, few enough that
# the whole matrix runs in seconds. time-domain bisects a simulation per
# speed (~0.3 s), so it gets a short range near the top of the sweep.
ROWS = {"analytic": 40, "coupled": 40, "sdm": 12, "time-domain": 2}


def cell(x):
    """A float as the CSV prints it (%.10g; 'inf'), '' for NaN (empty cell)."""
    return "" if np.isnan(x) else ("inf" if np.isinf(x) else "%.10g" % x)


def sweep_args(job, method):
    s = job.sweep
    if method == "time-domain":
        lo = s["rpm_min"] + 0.8 * (s["rpm_max"] - s["rpm_min"])
        return {"rpm_min": lo, "rpm_max": s["rpm_max"], "rpm_points": ROWS[method]}
    return {"rpm_points": ROWS[method]}


CASES = [(c, m) for c in CONFIGS for m in chatter.methods()]


@pytest.mark.parametrize("config,method", CASES, ids=[f"{c.stem}-{m}" for c, m in CASES])
def test_lobes_match_cli(config, method, tmp_path):
    job = chatter.load(config)
    args = sweep_args(job, method)
    cli = ["lobes", config, "--method", method, "--quiet", "--table", tmp_path / "t.csv", "--json", tmp_path / "t.json"]
    for k, v in args.items():
        cli += ["--" + k.replace("_", "-"), repr(v)]
    status, _, err = run_cli(*cli)
    if status == 2:  # the method refuses this config: the module must say the same
        with pytest.raises(chatter.InputError) as e:
            chatter.lobes(job, method, **args)
        assert str(e.value).splitlines() == cli_error_lines(err)
        return
    assert status == 0, err
    t = chatter.lobes(job, method, **args)
    lines = (tmp_path / "t.csv").read_text().splitlines()
    header = lines[0].split(",")
    assert list(t.keys()) == header
    rows = [l.split(",") for l in lines[1:]]
    assert len(rows) == len(t["spindle_rpm"])
    for c, name in enumerate(header):
        col = t[name]
        for i, r in enumerate(rows):
            if name == "lobe":
                got = "" if col[i] < 0 else str(col[i])
            elif col.dtype.kind == "f":
                got = cell(col[i])
            else:
                got = str(col[i])
            assert got == r[c], f"{name}[{i}]: module {got!r}, CLI {r[c]!r}"
    # The JSON rows: the CLI rounds to the CSV's 10 digits, then writes the
    # double; the module's value rounded the same way is bitwise that double.
    js = json.loads((tmp_path / "t.json").read_text())["rows"]
    for i, r in enumerate(js):
        for name in ("spindle_rpm", "depth_limit_mm", "chatter_frequency_hz"):
            x = t[name][i]
            want = None if not np.isfinite(x) else float("%.10g" % x)
            assert r[name] == want, f"{name}[{i}]: module {want!r}, JSON {r[name]!r}"


@pytest.mark.parametrize("config,method", CASES, ids=[f"{c.stem}-{m}" for c, m in CASES])
def test_point_matches_cli_json(config, method):
    job = chatter.load(config)
    s = job.sweep
    rpm = 0.37 * s["rpm_min"] + 0.63 * s["rpm_max"]
    depth = 1.0
    status, out, err = run_cli("point", config, "--method", method, "--rpm", repr(rpm), "--depth-mm", repr(depth))
    if status == 2:
        with pytest.raises(chatter.InputError) as e:
            chatter.point(job, rpm=rpm, depth_mm=depth, method=method)
        assert str(e.value).splitlines() == cli_error_lines(err)
        return
    assert status == 0, err
    want = json.loads(out)
    got = chatter.point(job, rpm=rpm, depth_mm=depth, method=method)
    assert got == want  # every key, every double bitwise


OPS = [("seed_turning_1dof", "case_a_ops.csv"), ("milling_benchmark_ae005_down", "case_c_ops.csv")]


@pytest.mark.parametrize("config,ops", OPS)
def test_check_matches_cli_json(config, ops, tmp_path):
    cfg = SOURCE_DIR / "configs" / f"{config}.toml"
    path = SOURCE_DIR / "examples" / "operations" / ops
    out = tmp_path / "check.json"
    status, _, err = run_cli("check", cfg, "--operations", path, "--json", out, "--quiet")
    assert status in (0, 2, 3), err
    want = json.loads(out.read_text())
    job = chatter.load(cfg)
    assert chatter.check(job, str(path)) == want


def test_check_with_the_spindle_limits_matches_cli_json(tmp_path):
    """The cutting load and the spindle's verdict: the keywords are the flags."""
    cfg = SOURCE_DIR / "examples" / "operations" / "two_mode_half_up.toml"
    path = SOURCE_DIR / "examples" / "operations" / "two_mode_ops.csv"
    out = tmp_path / "check.json"
    status, _, err = run_cli("check", cfg, "--operations", path, "--method", "analytic", "--tool-diameter-mm", "12",
                             "--max-power-kw", "0.45", "--max-torque-nm", "0.5", "--json", out, "--quiet")
    assert status == 3, err
    want = json.loads(out.read_text())
    got = chatter.check(chatter.load(cfg), str(path), method="analytic", tool_diameter_mm=12, max_power_kw=0.45,
                        max_torque_nm=0.5)
    assert got == want
    assert want["summary"]["overloaded"] == 2


def test_check_list_of_dicts_is_the_file(tmp_path):
    """The same operations as dicts give the same verdicts as the file."""
    cfg = SOURCE_DIR / "configs" / "milling_benchmark_ae005_down.toml"
    job = chatter.load(cfg)
    ops = [{"id": "rough", "spindle_rpm": 14000.0, "depth_mm": 3.0, "feed_per_tooth_mm": 0.05},
           {"id": "finish", "spindle_rpm": 21000, "depth_mm": 0.8, "radial_immersion": 0.1, "milling_direction": "up"}]
    text = "id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm,milling_direction\n" \
           "rough,14000,3.0,,0.05,\nfinish,21000,0.8,0.1,,up\n"
    (tmp_path / "ops.csv").write_text(text)
    from_file = chatter.check(job, tmp_path / "ops.csv")
    from_list = chatter.check(job, ops)
    for d in (from_file, from_list):
        d.pop("operations_file")
    assert from_list == from_file


def test_simulate_matches_cli(tmp_path):
    cfg = SOURCE_DIR / "configs" / "milling_benchmark_ae005_down.toml"
    status, out, err = run_cli("simulate", cfg, "--rpm", "17000", "--depth-mm", "2", "--periods", "40",
                               "--out", tmp_path / "s.csv", "--spectrum", tmp_path / "f.csv")
    assert status == 0, err
    want = json.loads(out)
    got = chatter.simulate(chatter.load(cfg), rpm=17000, depth_mm=2, periods=40)
    series, spectrum = got.pop("series"), got.pop("spectrum")
    got.pop("periodic")
    assert got == want
    lines = (tmp_path / "s.csv").read_text().splitlines()
    header = lines[0].split(",")
    assert len(lines) - 1 == len(series["time_s"])
    for i, l in enumerate(lines[1:]):
        for name, v in zip(header, l.split(",")):
            x = series[name][i]
            assert (str(int(x)) if name == "in_cut" else cell(x)) == v, f"{name}[{i}]"
    lines = (tmp_path / "f.csv").read_text().splitlines()[1:]
    assert len(lines) == len(spectrum["frequency_hz"])
    for i, l in enumerate(lines):
        f, a, h = l.split(",")
        assert (cell(spectrum["frequency_hz"][i]), cell(spectrum["amplitude_um"][i])) == (f, a)
        assert (str(spectrum["harmonic"][i]) if spectrum["harmonic"][i] else "") == h


@pytest.mark.parametrize("config", CONFIGS, ids=[c.stem for c in CONFIGS])
def test_default_method_is_the_clis(config):
    """No method given: the module and the CLI both use auto (analytic for
    turning, sdm for milling and for spindle speed variation, which analytic
    cannot solve), name it, and give the same record."""
    job = chatter.load(config)
    s = job.sweep
    rpm = 0.5 * (s["rpm_min"] + s["rpm_max"])
    status, out, err = run_cli("point", config, "--rpm", repr(rpm), "--depth-mm", "0.5")
    assert status == 0, err
    want = json.loads(out)
    got = chatter.point(job, rpm=rpm, depth_mm=0.5)
    assert got == want
    ssv = "speed_variation" in pathlib.Path(config).read_text()
    assert got["method"] == ("sdm" if job.operation == "milling" or ssv else "analytic")
    if job.operation == "turning":
        assert got["tooth_passing_hz"] == rpm / 60.0
    t = chatter.lobes(job, rpm_points=3)
    status, out, err = run_cli("lobes", config, "--rpm-points", "3")
    assert status == 0, err
    assert out.splitlines()[0].split(",") == list(t.keys())


def test_collocation_matches_cli(tmp_path):
    """sdm with Gauss collocation (options={"collocation": 3} = --collocation 3):
    the same table and point as the CLI, and the same refusal on a nose radius."""
    config = SOURCE_DIR / "configs" / "milling_benchmark_ae005_down.toml"
    job = chatter.load(config)
    status, _, err = run_cli("lobes", config, "--method", "sdm", "--collocation", "3", "--rpm-points", "6",
                             "--quiet", "--table", tmp_path / "t.csv")
    assert status == 0, err
    t = chatter.lobes(job, "sdm", rpm_points=6, options={"collocation": 3})
    rows = [l.split(",") for l in (tmp_path / "t.csv").read_text().splitlines()[1:]]
    assert [cell(x) for x in t["depth_limit_mm"]] == [r[1] for r in rows]
    assert [cell(x) for x in t["chatter_frequency_hz"]] == [r[2] for r in rows]
    status, out, err = run_cli("point", config, "--method", "sdm", "--collocation", "3", "--rpm", "16000",
                               "--depth-mm", "1")
    assert status == 0, err
    assert chatter.point(job, rpm=16000.0, depth_mm=1.0, method="sdm", options={"collocation": 3}) == json.loads(out)
    turning = chatter.load(SOURCE_DIR / "configs" / "turning_insert_lead_angle.toml")
    status, _, err = run_cli("lobes", SOURCE_DIR / "configs" / "turning_insert_lead_angle.toml", "--method", "sdm",
                             "--collocation", "3", "--quiet", "--table", tmp_path / "u.csv")
    assert status == 2
    with pytest.raises(chatter.InputError) as e:
        chatter.lobes(turning, "sdm", options={"collocation": 3})
    assert str(e.value).splitlines() == cli_error_lines(err)
