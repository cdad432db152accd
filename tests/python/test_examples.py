"""The Python examples run as tests: the post-processor hook's per-operation
and whole-program checks give the same verdicts (one chatter.check call per
operation, or one for the program: the check's rows do not depend on each
other), and its errors name the operation."""
import sys

import pytest

import chatter
from conftest import SOURCE_DIR

sys.path.insert(0, str(SOURCE_DIR / "examples" / "python"))
import post_processor_hook as hook  # noqa: E402

END_MILL = {"name": "D10 2-flute", "flutes": 2, "diameter_mm": 10.0, "k_t_n_per_mm2": 600.0,
            "k_r_n_per_mm2": 200.0,
            "modes": [{"frequency_hz": 922.0, "damping_ratio": 0.011, "mass_kg": 0.03993, "direction": "x"}]}
# Two operations on one cut (a_e = 0.5 mm), one on another; a narrow machine
# range keeps the speed scans short.
PROGRAM = [("rough", 14000, 3.0, 0.5), ("finish", 21000, 0.8, 0.5), ("slot", 16000, 0.4, 10.0)]
MACHINE = (12000.0, 22000.0)


def test_program_in_one_call_equals_one_call_per_operation():
    one = [hook.check_operation(END_MILL, rpm, ap, ae, op_id=i, machine_rpm=MACHINE) for i, rpm, ap, ae in PROGRAM]
    batch = hook.check_program(END_MILL, PROGRAM, machine_rpm=MACHINE)
    assert [r["details"]["id"] for r in batch] == [op[0] for op in PROGRAM]
    for a, b in zip(one, batch):
        # The row's line is its place in the call (index + 2): the one thing that differs.
        a["details"].pop("line"), b["details"].pop("line")
        assert a == b
    assert {r["verdict"] for r in batch} <= {"stable", "chatter"}


def test_a_bad_operation_is_named():
    with pytest.raises(chatter.InputError, match=r"^operation deep: .*depth_mm"):
        hook.check_program(END_MILL, [("ok", 14000, 1.0, 0.5), ("deep", 14000, -1.0, 0.5)], machine_rpm=MACHINE)
