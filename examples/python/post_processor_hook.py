#!/usr/bin/env python3
"""A chatter check for a CAM post-processor (FreeCAD-style): the post calls
check_operation() once per milling operation, with the tool it uses and the
cut, and gets back a verdict, the margin and a spindle speed to suggest.

The tool carries what a tap test and the cutting data give: its modes at the
tip and the cutting coefficients of the material. One chatter.Job is built per
tool (in code, no config file) and reused for every operation.

Run (from the repository, after scripts/build.sh):
  PYTHONPATH=build/python python3 examples/python/post_processor_hook.py
"""
import chatter

# Jobs by tool name: building one validates the tool's data once.
_jobs = {}


def _job(tool):
    name = tool["name"]
    if name not in _jobs:
        _jobs[name] = chatter.Job(
            name=name,
            process={
                "operation": "milling",
                "teeth": tool["flutes"],
                "tool_diameter_mm": tool["diameter_mm"],
                "tangential_coefficient_n_per_mm2": tool["k_t_n_per_mm2"],
                "radial_coefficient_n_per_mm2": tool["k_r_n_per_mm2"],
                "radial_immersion": 1.0,  # each operation gives its own radial depth
                "milling_direction": tool.get("direction", "down"),
            },
            tool_modes=tool["modes"],
        )
    return _jobs[name]


def _operation(tool, op_id, spindle_rpm, axial_depth_mm, radial_depth_mm, feed_per_tooth_mm=None):
    return {"id": op_id, "spindle_rpm": float(spindle_rpm), "depth_mm": float(axial_depth_mm),
            "radial_immersion": float(radial_depth_mm) / float(tool["diameter_mm"]),
            "feed_per_tooth_mm": feed_per_tooth_mm}


def _verdict(row, warnings):
    s = row["suggestion"]
    return {
        "verdict": "stable" if row["stable"] else "chatter",
        "margin": row["margin"] if row["margin"] is not None else float("inf"),
        "depth_limit_mm": row["depth_limit_mm"],
        "suggested_rpm": s["spindle_rpm"] if s else None,
        "suggested_margin": (s["margin"] if s["margin"] is not None else float("inf")) if s else None,
        "warnings": warnings,
        "details": row,
    }


def check_operation(tool, spindle_rpm, axial_depth_mm, radial_depth_mm, *, op_id="op",
                    feed_per_tooth_mm=None, machine_rpm=(1000.0, 24000.0), speed_tolerance_pct=2.0):
    """Verdict on one operation.

    tool: dict with name, flutes, diameter_mm, k_t_n_per_mm2, k_r_n_per_mm2 and
          modes (list of {frequency_hz, damping_ratio, stiffness_n_per_um or
          mass_kg, direction}); radial_depth_mm in (0, diameter_mm].
    Returns a dict: verdict ("stable" / "chatter"), margin (depth limit /
    depth; > 1 stable, inf = no limit found), depth_limit_mm, suggested_rpm
    (None when no speed in the machine range is stable with that tolerance),
    suggested_margin and the full chatter.check record under "details".
    Raises chatter.InputError on bad tool data or a bad operation.
    """
    return check_program(tool, [(op_id, spindle_rpm, axial_depth_mm, radial_depth_mm, feed_per_tooth_mm)],
                         machine_rpm=machine_rpm, speed_tolerance_pct=speed_tolerance_pct)[0]


def check_program(tool, operations, *, machine_rpm=(1000.0, 24000.0), speed_tolerance_pct=2.0):
    """Verdicts on every operation of a program that uses `tool`, in one call:
    operations is a list of (op_id, spindle_rpm, axial_depth_mm,
    radial_depth_mm[, feed_per_tooth_mm]). The check scans the machine's
    speed range once per distinct cut (radial immersion), not once per
    operation: when the post-processor knows the whole program, this is the
    faster way (docs/performance.md, "Python in a loop"). Returns the
    verdicts of check_operation, in order.
    """
    job = _job(tool)
    ops = [_operation(tool, *op) for op in operations]
    report = chatter.check(job, ops, rpm_min=machine_rpm[0], rpm_max=machine_rpm[1],
                           speed_tolerance_pct=speed_tolerance_pct)
    for bad in report["rejected"] + report["not_judged"]:  # line = list index + 2
        raise chatter.InputError(f"operation {ops[bad['line'] - 2]['id']}: {bad['reason']}")
    return [_verdict(row, report["warnings"]) for row in report["operations"]]


if __name__ == "__main__":
    # The Insperger-Stepan benchmark cutter (case C of the docs): 2 flutes,
    # one mode at 922 Hz, aluminium coefficients.
    end_mill = {"name": "D10 2-flute", "flutes": 2, "diameter_mm": 10.0,
                "k_t_n_per_mm2": 600.0, "k_r_n_per_mm2": 200.0,
                "modes": [{"frequency_hz": 922.0, "damping_ratio": 0.011, "mass_kg": 0.03993, "direction": "x"}]}
    program = [("rough", 14000, 3.0, 0.5), ("slot", 12000, 1.0, 10.0), ("finish", 21000, 0.8, 0.5)]
    for op_id, rpm, ap, ae in program:
        r = check_operation(end_mill, rpm, ap, ae, op_id=op_id)
        sug = "none in range" if r["suggested_rpm"] is None else \
            f"{r['suggested_rpm']:.0f} rev/min (margin {r['suggested_margin']:.2f})"
        print(f"{op_id:7s} {rpm:6.0f} rev/min a_p {ap:4.1f} mm a_e {ae:4.1f} mm: {r['verdict']:7s} "
              f"margin {r['margin']:.2f}; suggest {sug}")
