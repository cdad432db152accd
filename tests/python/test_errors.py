"""Bad input raises chatter.InputError (a ValueError) with the CLI's message
(file, key, rule); nothing else is a ValueError."""
import pytest

import chatter
from conftest import SOURCE_DIR, cli_error_lines, cli_json, run_cli

BAD_CONFIGS = {
    "negative_coefficient": '[process]\noperation = "turning"\nfeed_force_coefficient_n_per_m2 = -1\n'
                            '[[workpiece.modes]]\nfrequency_hz = 94.22\ndamping_ratio = 0.033\n'
                            'stiffness_n_per_m = 45e6\ndirection = "x"\n',
    "unknown_key": '[process]\noperation = "turning"\nfeed_force_coefficient_n_per_m2 = 2.4e9\nfeeed = 1\n'
                   '[[workpiece.modes]]\nfrequency_hz = 94.22\ndamping_ratio = 0.033\n'
                   'stiffness_n_per_m = 45e6\ndirection = "x"\n',
    "syntax": '[process\noperation = "turning"\n',
}


def test_input_error_is_value_error():
    assert issubclass(chatter.InputError, ValueError)
    assert not issubclass(chatter.NumericalError, ValueError)
    assert issubclass(chatter.NumericalError, RuntimeError)


@pytest.mark.parametrize("name", sorted(BAD_CONFIGS))
def test_bad_config_same_message_as_cli(name, tmp_path):
    path = tmp_path / f"{name}.toml"
    path.write_text(BAD_CONFIGS[name])
    status, _, err = run_cli("point", path, "--rpm", "1000", "--depth-mm", "1")
    assert status == 2
    with pytest.raises(chatter.InputError) as e:
        chatter.load(path)
    assert str(e.value).splitlines() == cli_error_lines(err)
    assert str(path) in str(e.value)


def test_missing_file():
    with pytest.raises(chatter.InputError) as e:
        chatter.load("/nonexistent/x.toml")
    assert "/nonexistent/x.toml" in str(e.value)


def test_job_in_code_is_validated_by_the_loader():
    with pytest.raises(chatter.InputError) as e:
        chatter.Job(process={"operation": "turning", "feed_force_coefficient_n_per_m2": -1},
                    workpiece_modes=[{"frequency_hz": 94.22, "damping_ratio": 0.033, "stiffness_n_per_m": 45e6,
                                      "direction": "x"}])
    assert str(e.value) == "<chatter.Job>: process.feed_force_coefficient_n_per_m2 = -1: must be > 0"


def test_job_in_code_equals_the_file():
    """A Job built from dicts with the config's values gives bitwise the file's numbers."""
    file_job = chatter.load(SOURCE_DIR / "configs" / "seed_turning_1dof.toml")
    code_job = chatter.Job(
        name="case A", process={"operation": "turning", "feed_force_coefficient_n_per_m2": 2.4e9},
        workpiece_modes=[{"frequency_hz": 94.22, "damping_ratio": 0.033, "stiffness_n_per_m": 45e6, "direction": "x"}],
        sweep={"rpm_min": 50, "rpm_max": 2000, "rpm_points": 400, "depth_max_mm": 20})
    a, b = chatter.lobes(file_job, rpm_points=50), chatter.lobes(code_job, rpm_points=50)
    for k in a:
        assert a[k].tobytes() == b[k].tobytes(), k
    assert chatter.point(file_job, rpm=1200, depth_mm=1.5) == chatter.point(code_job, rpm=1200, depth_mm=1.5)


@pytest.mark.parametrize("call,message", [
    (lambda j: chatter.point(j, rpm=-5, depth_mm=1), "rpm = -5: must be > 0 rev/min"),
    (lambda j: chatter.point(j, rpm=1000, depth_mm=0), "depth_mm = 0: must be > 0 mm (a cut of no depth cannot chatter)"),
    (lambda j: chatter.lobes(j, rpm_min=2000, rpm_max=100), "rpm_max = 100: must be > rpm_min (2000)"),
    (lambda j: chatter.lobes(j, rpm_points=1), "rpm_points = 1: must be >= 2"),
    (lambda j: chatter.lobes(j, rpm=[1000.0, float("nan")]), "rpm[1] = nan: must be > 0 rev/min"),
    (lambda j: chatter.lobes(j, "sdm", options={"stepz": 3}), "options: 'stepz': not an option of method sdm"),
    (lambda j: chatter.simulate(j, rpm=1000, depth_mm=1, periods=2), "periods = 2: must be in [4, 10000000]"),
    (lambda j: chatter.check(j, [{"id": "a", "spindle_rpm": 1000, "depth_mm": 1, "colour": "red"}]),
     "operations[0]: 'colour': unknown key"),
])
def test_bad_arguments(call, message):
    job = chatter.load(SOURCE_DIR / "configs" / "seed_turning_1dof.toml")
    with pytest.raises(chatter.InputError) as e:
        call(job)
    assert str(e.value).startswith(message), str(e.value)


def test_unknown_method_same_rule_as_cli():
    cfg = SOURCE_DIR / "configs" / "seed_turning_1dof.toml"
    status, _, err = run_cli("point", cfg, "--method", "magic", "--rpm", "1000", "--depth-mm", "1")
    assert status == 2
    with pytest.raises(chatter.InputError) as e:
        chatter.point(chatter.load(cfg), rpm=1000, depth_mm=1, method="magic")
    assert cli_error_lines(err) == ["--method: " + str(e.value)]


def test_rejected_operation_rows_are_reported_not_raised():
    job = chatter.load(SOURCE_DIR / "configs" / "seed_turning_1dof.toml")
    r = chatter.check(job, [{"id": "ok", "spindle_rpm": 1000, "depth_mm": 1},
                            {"id": "deep", "spindle_rpm": 1000, "depth_mm": -1}])
    assert [o["id"] for o in r["operations"]] == ["ok"]
    assert r["rejected"][0]["line"] == 3 and "depth_mm" in r["rejected"][0]["reason"]
    assert r["exit_status"] == 2


def test_check_with_no_operations_is_an_error():
    """An empty list checks nothing: InputError, never a go signal."""
    job = chatter.load(SOURCE_DIR / "configs" / "seed_turning_1dof.toml")
    with pytest.raises(chatter.InputError) as e:
        chatter.check(job, [])
    assert "no operations" in str(e.value)


def test_absent_key_is_missing_not_a_bad_number():
    job = chatter.load(SOURCE_DIR / "configs" / "seed_turning_1dof.toml")
    r = chatter.check(job, [{"id": "a", "spindle_rpm": 1200}, {"id": "b", "spindle_rpm": 1800, "depth_mm": 1.0}])
    assert [x["id"] for x in r["operations"]] == ["b"]
    assert r["rejected"][0]["reason"] == "depth_mm: missing (required)"
    assert r["exit_status"] == 2


def test_integral_floats_where_an_integer_is_expected():
    """teeth = 4.0 (NumPy often hands floats) is the integer 4."""
    import numpy as np
    modes = [{"frequency_hz": 922.0, "damping_ratio": 0.011, "mass_kg": 0.03993, "direction": "x"}]
    for teeth in (4.0, np.float64(4.0)):
        job = chatter.Job(process={"operation": "milling", "teeth": teeth, "tangential_coefficient_n_per_m2": 6e8,
                                   "radial_coefficient_n_per_m2": 2e8, "radial_immersion": 0.05},
                          tool_modes=modes)
        assert chatter.point(job, rpm=10000, depth_mm=0.5)["tooth_passing_hz"] == 10000 * 4 / 60
    with pytest.raises(chatter.InputError) as e:
        chatter.Job(process={"operation": "milling", "teeth": 4.5, "tangential_coefficient_n_per_m2": 6e8,
                             "radial_coefficient_n_per_m2": 2e8, "radial_immersion": 0.05}, tool_modes=modes)
    assert "process.teeth" in str(e.value)


def test_import_without_numpy_names_numpy():
    """A Python without NumPy is told so at import, not at the first call."""
    import subprocess
    import sys
    code = "import sys; sys.modules['numpy'] = None; import chatter"
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert p.returncode != 0
    assert "ImportError: chatter needs NumPy" in p.stderr, p.stderr


def test_an_interpreter_without_numpy_is_told_which_one_the_build_targets():
    """Issue 44: a python3 without NumPy (a pyenv one) stopped with "chatter
    needs NumPy" and no way on; the message names the running interpreter,
    the one the module was built for, and the three ways out. NumPy is hidden
    in a fresh interpreter (sys.modules['numpy'] = None)."""
    import subprocess
    import sys
    code = ("import sys; sys.modules['numpy'] = None\n"
            "try:\n    import chatter\nexcept ImportError as e:\n    print(e)\nelse:\n    print('imported')\n")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    message = p.stdout
    assert "chatter needs NumPy, which this Python (" + sys.executable + ") cannot find" in message, message
    assert "The module was built for /" in message, message
    assert "-DPython_EXECUTABLE=" + sys.executable in message, message


def test_keyword_outside_its_band_is_warned_as_the_cli_flag():
    """Rule 2 of docs/results.md: a keyword argument 1000 times off gets the
    warning its CLI flag gets (chatter/usual_bands.hpp), in the record's
    warnings, with the keyword's name."""
    job = chatter.load(SOURCE_DIR / "configs" / "seed_turning_1dof.toml")
    r = chatter.point(job, rpm=1200, depth_mm=0.0015)
    assert ("depth_mm = 0.0015: outside the 0.01 to 100 mm of a depth of cut; is it in m (depth_mm = 1.5)?"
            in r["warnings"]), r["warnings"]
    cli = cli_json("point", SOURCE_DIR / "configs" / "seed_turning_1dof.toml", "--rpm", "1200",
                   "--depth-mm", "0.0015")
    assert [w.replace("--depth-mm", "depth_mm") for w in cli["warnings"]] == r["warnings"]
    assert chatter.point(job, rpm=1200, depth_mm=1.5)["warnings"] == []
