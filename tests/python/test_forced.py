"""chatter.forced and chatter.sle (issue 27, docs/forced.md) give the CLI's
numbers: forced's record is `chatter forced --json`'s, key for key and bit
for bit (the same io function writes both); sle's columns are `chatter sle`'s
table (10 significant digits). Bad arguments raise chatter.InputError naming
the keyword."""
import math

import numpy as np
import pytest

import chatter
from conftest import SOURCE_DIR, cli_json, run_cli

CASE_C = SOURCE_DIR / "configs" / "milling_benchmark_ae005_down.toml"
CASE_B = SOURCE_DIR / "configs" / "coupled_tool1_workpiece1.toml"
VARIABLE = SOURCE_DIR / "configs" / "milling_variable_pitch_helix.toml"


@pytest.mark.parametrize("config,args", [
    (CASE_C, {"rpm": 14000, "depth_mm": 2, "feed_per_tooth_mm": 0.05}),
    (CASE_C, {"rpm": 20000, "depth_mm": 3, "feed_per_tooth_mm": 0.05}),  # unstable
    (VARIABLE, {"rpm": 9000, "depth_mm": 1.5}),
    (CASE_B, {"rpm": 1000, "depth_mm": 1, "feed_mm_per_rev": 0.2, "position_mm": 250}),
])
def test_forced_is_the_cli_record(config, args):
    job = chatter.load(config)
    py = chatter.forced(job, **args)
    cli = ["forced", config, "--json", "-"]
    for k, v in args.items():
        cli += ["--" + k.replace("_", "-"), v]
    want = cli_json(*cli)
    path = py.pop("path", None)
    assert py == want
    if want["stable"] and want["operation"] == "milling":
        assert len(path["time_s"]) == len(path["rel_x_um"]) >= 720
        assert math.isclose(np.ptp(path["rel_x_um"]), want["peak_to_peak_um"]["x"], rel_tol=1e-12)


def test_sle_is_the_cli_table():
    job = chatter.load(CASE_C)
    py = chatter.sle(job, rpm_min=10000, rpm_max=20000, rpm_points=21, depth_mm=2, feed_per_tooth_mm=0.05)
    status, out, err = run_cli("sle", CASE_C, "--rpm-min", 10000, "--rpm-max", 20000, "--rpm-points", 21,
                               "--depth-mm", 2, "--feed-per-tooth-mm", 0.05, "--quiet")
    assert status == 0, err
    rows = [l.split(",") for l in out.strip().splitlines()[1:]]
    assert len(rows) == 21
    cell = lambda x: "" if np.isnan(x) else "%.10g" % x
    for i, r in enumerate(rows):
        assert r[0] == cell(py["spindle_rpm"][i])
        assert r[1:5] == [cell(py[k][i]) for k in ("surface_location_error_um", "peak_to_peak_x_um",
                                                    "peak_to_peak_y_um", "min_chip_thickness_um")]
        assert r[5] == ("1" if py["stable"][i] else "0")
    assert py["stable"].any() and not py["stable"].all()


@pytest.mark.parametrize("args,says", [
    ({"rpm": -1, "depth_mm": 1, "feed_per_tooth_mm": 0.05}, "rpm = -1: must be > 0"),
    ({"rpm": 1000, "depth_mm": 0, "feed_per_tooth_mm": 0.05}, "depth_mm = 0: must be in (0, 1000] mm"),
    ({"rpm": 1000, "depth_mm": 1, "feed_mm_per_rev": 0.05}, "feed_mm_per_rev:"),
    ({"rpm": 1000, "depth_mm": 1}, "missing feed_per_tooth_mm"),
    ({"rpm": 1000, "depth_mm": 1, "feed_per_tooth_mm": 0.05, "radial_immersion": 2}, "radial_immersion = 2:"),
])
def test_bad_arguments_name_the_keyword(args, says):
    with pytest.raises(chatter.InputError, match=None) as e:
        chatter.forced(chatter.load(CASE_C), **args)
    assert says in str(e.value)
