"""The keys of every Python result that is a command's record are the CLI's
JSON keys for the same call (issue 43: one record per command, built in the
records layer; Python converts it and adds no result key of its own). Each
case runs the CLI with --json and the Python function with the same inputs,
and compares the key sets at every level of the two dicts (list elements:
the first one)."""
import json

import pytest

import chatter
from conftest import SOURCE_DIR, run_cli

CASE_C = SOURCE_DIR / "configs" / "milling_benchmark_ae005_down.toml"
SHAFT = SOURCE_DIR / "configs" / "turning_seed003_shaft.toml"
PITCH = SOURCE_DIR / "configs" / "milling_pitch_design_4flute.toml"
GRIND = SOURCE_DIR / "configs" / "grinding_scompi_ch4.toml"

# Keys the Python function adds on purpose, with why (arrays of a path that
# the CLI writes to its own CSV file).
PYTHON_ONLY = {"path"}


def keys(tree, at="", out=None):
    """Every key path of a JSON-like tree ("a.b", list elements as "a[]")."""
    out = set() if out is None else out
    if isinstance(tree, dict):
        for k, v in tree.items():
            if k in PYTHON_ONLY and not at:
                continue
            out.add(at + k)
            keys(v, at + k + ".", out)
    elif isinstance(tree, list) and tree and isinstance(tree[0], dict):
        keys(tree[0], at.rstrip(".") + "[].", out)
    return out


def cli_record(*args):
    status, out, err = run_cli(*args, "--json", "-")
    assert status in (0, 3), f"{args}: exit {status}: {err}"
    return json.loads(out)


CASES = {
    "forced": (("forced", CASE_C, "--rpm", "14000", "--depth-mm", "1", "--feed-per-tooth-mm", "0.05"),
               lambda: chatter.forced(chatter.load(CASE_C), rpm=14000, depth_mm=1, feed_per_tooth_mm=0.05)),
    "recommend": (("recommend", CASE_C, "--feed-per-tooth-mm", "0.05", "--rpm-min", "14000", "--rpm-max", "16000"),
                  lambda: chatter.recommend(chatter.load(CASE_C), feed_per_tooth_mm=0.05, rpm_min=14000,
                                            rpm_max=16000)),
    "performance": (("performance", SHAFT, "--cutting-speed-m-per-min", "200", "--feed-mm-per-rev", "0.35",
                     "--depth-mm", "1.5"),
                    lambda: chatter.performance(chatter.load(SHAFT), cutting_speed_m_per_min=200, feed_mm_per_rev=0.35,
                                                depth_mm=1.5)),
    "design-pitch": (("design-pitch", PITCH, "--rpm-min", "6600", "--rpm-max", "8000", "--rpm-points", "5",
                      "--scan-points", "2"),
                     lambda: chatter.design_pitch(chatter.load(PITCH), rpm_min=6600, rpm_max=8000, rpm_points=5,
                                                  scan_points=2)),
    "grind predict": (("grind", "predict", GRIND, "--power-w", "1000"),
                      lambda: chatter.grind_predict(GRIND, power_w=1000)),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_python_result_keys_are_the_cli_json_keys(name):
    args, call = CASES[name]
    want = cli_record(*args)
    got = call()
    assert isinstance(got, dict), type(got)
    missing, extra = keys(want) - keys(got), keys(got) - keys(want)
    assert not missing and not extra, f"{name}: missing in Python {sorted(missing)}, only in Python {sorted(extra)}"


# Results that also hold tables (chatter/records/columns.hpp): their keys are
# the CLI's JSON keys plus each table's columns, read from the header of the
# CSV the CLI writes for that table ("": the columns sit in the result
# itself; a name: in the dict under that key). Each: the CLI's record, the
# tables as (key, CLI arguments, the CSV's flag), the Python call.
SIM = ("simulate", CASE_C, "--rpm", "14000", "--depth-mm", "0.5", "--periods", "30")
TABLE_CASES = {
    "map": (lambda: cli_record("map", CASE_C, "--rpm-points", "4", "--depth-points", "3"),
            [("", ("map", CASE_C, "--rpm-points", "4", "--depth-points", "3"), "--out")],
            lambda: chatter.map(chatter.load(CASE_C), rpm_points=4, depth_points=3)),
    "compare": (lambda: cli_record("compare", CASE_C, "--rpm-points", "3"),
                [("", ("compare", CASE_C, "--rpm-points", "3"), "--table")],
                lambda: chatter.compare(chatter.load(CASE_C), rpm_points=3)),
    "simulate": (lambda: simulate_record(), [("series", SIM, "--out"), ("periodic", SIM, "--periodic"), ("spectrum", SIM, "--spectrum")],
                 lambda: chatter.simulate(chatter.load(CASE_C), rpm=14000, depth_mm=0.5, periods=30)),
}


def simulate_record():
    """chatter simulate prints its record on standard output (no --json)."""
    status, out, err = run_cli(*SIM)
    assert status in (0, 3), f"{SIM}: exit {status}: {err}"
    return json.loads(out)


def csv_header(args, flag, path):
    status, _, err = run_cli(*args, flag, path)
    assert status in (0, 3), f"{args} {flag}: exit {status}: {err}"
    with open(path) as f:
        return next(line for line in f if not line.startswith("#")).strip().split(",")


@pytest.mark.parametrize("name", sorted(TABLE_CASES))
def test_python_table_keys_are_the_cli_json_keys_and_csv_columns(name, tmp_path):
    record, tables, call = TABLE_CASES[name]
    want = keys(record())
    for k, (key, table_args, flag) in enumerate(tables):
        columns = csv_header(table_args, flag, tmp_path / f"table{k}.csv")
        want |= {(key + "." if key else "") + c for c in columns}
        if key:
            want.add(key)
    got = call()
    missing, extra = want - keys(got), keys(got) - want
    assert not missing and not extra, f"{name}: missing in Python {sorted(missing)}, only in Python {sorted(extra)}"
