"""Tool position in the module (docs/position.md): `position_mm=` on lobes,
point, check and simulate, Job.at_position and surface() give the CLI's
numbers for `--position-mm` and `chatter surface` (the CSV's text for the
tables, bitwise for the JSON's full doubles), and bad positions raise
InputError with the CLI's message (the argument named instead of the flag)."""
import json

import numpy as np
import pytest

import chatter
from conftest import SOURCE_DIR, cli_error_lines, cli_json, run_cli

CASE_B = SOURCE_DIR / "configs" / "coupled_tool1_workpiece1.toml"  # cantilever shaft, 0 to 500 mm
SURFACE_COLUMNS = ["position_mm", "spindle_rpm", "depth_limit_mm", "chatter_frequency_hz", "lobe"]


def cell(x):
    """A float as the CSV prints it (%.10g; 'inf'), '' for NaN (empty cell)."""
    return "" if np.isnan(x) else ("inf" if np.isinf(x) else "%.10g" % x)


def table_text(t, columns):
    """The module's arrays as the CSV's rows."""
    rows = []
    for i in range(len(t[columns[0]])):
        cells = []
        for name in columns:
            x = t[name][i]
            cells.append(("" if x < 0 else str(x)) if name == "lobe" else cell(x))
        rows.append(",".join(cells))
    return rows


@pytest.mark.parametrize("method,points", [("analytic", 30), ("sdm", 6)])
def test_lobes_at_position_is_the_cli_table(method, points, tmp_path):
    job = chatter.load(CASE_B)
    status, _, err = run_cli("lobes", CASE_B, "--method", method, "--rpm-points", points, "--position-mm", "200",
                             "--quiet", "--table", tmp_path / "t.csv")
    assert status == 0, err
    lines = (tmp_path / "t.csv").read_text().splitlines()
    t = chatter.lobes(job, method, rpm_points=points, position_mm=200)
    columns = lines[0].split(",")
    assert list(t.keys()) == columns
    if method == "analytic":
        assert table_text(t, columns) == lines[1:]
    else:  # sdm's extra columns: compare the common ones
        common = ["spindle_rpm", "depth_limit_mm", "chatter_frequency_hz", "lobe"]
        assert table_text(t, common) == [",".join(l.split(",")[:4]) for l in lines[1:]]
    # The position changes the answer (the shaft is stiffer at 200 mm than at its free end).
    free_end = chatter.lobes(job, method, rpm_points=points)
    assert not np.array_equal(free_end["depth_limit_mm"], t["depth_limit_mm"])
    # Job.at_position is the same structure.
    again = chatter.lobes(job.at_position(200), method, rpm_points=points)
    assert np.array_equal(again["depth_limit_mm"], t["depth_limit_mm"])


def test_point_check_simulate_at_position_are_the_cli_json(tmp_path):
    job = chatter.load(CASE_B)
    want = cli_json("point", CASE_B, "--rpm", "3000", "--depth-mm", "1", "--position-mm", "200")
    got = chatter.point(job, rpm=3000, depth_mm=1, position_mm=200)
    assert got == want  # bitwise: the JSON writes full doubles
    assert got["position_mm"] == 200
    assert "position_mm" not in chatter.point(job, rpm=3000, depth_mm=1)

    ops = tmp_path / "ops.csv"
    ops.write_text("id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm\nop1,3000,5,,0.1\n")
    out = tmp_path / "check.json"
    status, _, err = run_cli("check", CASE_B, "--operations", ops, "--position-mm", "0", "--json", out, "--quiet")
    assert status == 0, err
    assert chatter.check(job, str(ops), position_mm=0) == json.loads(out.read_text())

    want = cli_json("simulate", CASE_B, "--rpm", "3000", "--depth-mm", "1", "--periods", "20", "--position-mm", "200")
    got = chatter.simulate(job, rpm=3000, depth_mm=1, periods=20, position_mm=200, record_series=False)
    for key, value in want.items():
        assert got[key] == value, key


@pytest.mark.parametrize("threads", [1, 2])
def test_surface_is_the_cli_csv(threads, tmp_path):
    job = chatter.load(CASE_B)
    status, _, err = run_cli("surface", CASE_B, "--position-min-mm", "50", "--position-max-mm", "500",
                             "--position-points", "4", "--rpm-points", "25", "--quiet", "--table", tmp_path / "s.csv")
    assert status == 0, err
    lines = (tmp_path / "s.csv").read_text().splitlines()
    s = chatter.surface(job, position_min_mm=50, position_max_mm=500, position_points=4, rpm_points=25,
                        threads=threads)
    assert list(s.keys()) == SURFACE_COLUMNS == lines[0].split(",")
    assert table_text(s, SURFACE_COLUMNS) == lines[1:]
    # Each block is the lobe table at that position, bitwise.
    at = chatter.lobes(job, rpm_points=25, position_mm=200)
    block = s["position_mm"] == 200
    assert np.array_equal(s["depth_limit_mm"][block], at["depth_limit_mm"])
    # Default ends: the whole part, 21 positions.
    d = chatter.surface(job, rpm_points=3)
    assert d["position_mm"][0] == 0 and d["position_mm"][-1] == 500 and len(d["position_mm"]) == 21 * 3
    assert job.position_range_mm == (0.0, 500.0)


def test_bad_positions_raise_the_cli_message():
    job = chatter.load(CASE_B)
    status, _, err = run_cli("lobes", CASE_B, "--position-mm", "600", "--table", "-")
    assert status == 2
    cli = cli_error_lines(err)
    assert cli[0].startswith("--position-mm = 600: outside the part")
    with pytest.raises(chatter.InputError) as e:
        chatter.lobes(job, position_mm=600)
    assert str(e.value) == cli[0].replace("--position-mm", "position_mm", 1)
    for call in (lambda: chatter.point(job, rpm=3000, depth_mm=1, position_mm=-1),
                 lambda: chatter.check(job, [{"id": "a", "spindle_rpm": 3000, "depth_mm": 1}], position_mm=501),
                 lambda: job.at_position(float("nan"))):
        with pytest.raises(chatter.InputError, match="position_mm = .*: outside the part"):
            call()
    with pytest.raises(chatter.InputError, match=r"position_max_mm = 700: outside the part \[0, 500\] mm"):
        chatter.surface(job, position_max_mm=700, rpm_points=3)
    with pytest.raises(chatter.InputError, match=r"position_max_mm = 100: must be > position_min_mm \(300\)"):
        chatter.surface(job, position_min_mm=300, position_max_mm=100, rpm_points=3)
    with pytest.raises(chatter.InputError, match="position_points = 1: must be >= 2"):
        chatter.surface(job, position_points=1, rpm_points=3)
    plain = chatter.load(SOURCE_DIR / "configs" / "seed_turning_1dof.toml")
    assert plain.position_range_mm is None
    status, _, err = run_cli("point", SOURCE_DIR / "configs" / "seed_turning_1dof.toml", "--rpm", "1000",
                             "--depth-mm", "1", "--position-mm", "10")
    assert status == 2
    with pytest.raises(chatter.InputError) as e:
        chatter.point(plain, rpm=1000, depth_mm=1, position_mm=10)
    assert str(e.value) == cli_error_lines(err)[0].replace("--position-mm", "position_mm", 1)
    with pytest.raises(chatter.InputError, match="does not depend on the position"):
        chatter.surface(plain, rpm_points=3)
