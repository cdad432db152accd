"""Monte Carlo lobes in the module (docs/uncertainty.md): uncertain_lobes()
gives `chatter lobes --samples`'s numbers (the CSV's text for the quantile
columns and the probability table), is independent of the thread count,
reduces to the nominal lobes when every spread is 0, follows the closed form
of a stiffness-only spread, and refuses bad arguments with the CLI's rules."""
import copy

import numpy as np
import pytest

import chatter
from conftest import SOURCE_DIR, run_cli

UNCERTAIN = SOURCE_DIR / "configs" / "seed_turning_1dof_uncertain.toml"
PLAIN = SOURCE_DIR / "configs" / "seed_turning_1dof.toml"
QUANTILES = ["depth_limit_p05_mm", "depth_limit_p50_mm", "depth_limit_p95_mm"]

# Case A (seed_turning_1dof.toml) as config keys, for spreads set in code.
CASE_A = {
    "process": {"operation": "turning", "feed_force_coefficient_n_per_m2": 2.4e9},
    "workpiece": {"modes": [{"frequency_hz": 94.22, "damping_ratio": 0.033, "stiffness_n_per_m": 45e6,
                             "direction": "x"}]},
    "sweep": {"rpm_min": 50, "rpm_max": 2000, "depth_max_mm": 20},
}


def cell(x):
    """A float as the CSV prints it (%.10g; 'inf')."""
    return "inf" if np.isinf(x) else "%.10g" % x


def job_with(spreads):
    config = copy.deepcopy(CASE_A)
    config["uncertainty"] = spreads
    return chatter.Job(config)


def test_same_numbers_as_the_cli(tmp_path):
    status, _, err = run_cli("lobes", UNCERTAIN, "--samples", 60, "--seed", 7, "--rpm-points", 25,
                             "--depth-points", 11, "--quiet", "--table", tmp_path / "t.csv",
                             "--probability-table", tmp_path / "p.csv")
    assert status == 0, err
    lines = (tmp_path / "t.csv").read_text().splitlines()
    header = lines[0].split(",")
    rows = [l.split(",") for l in lines[1:]]
    r = chatter.uncertain_lobes(chatter.load(UNCERTAIN), samples=60, seed=7, rpm_points=25, depth_points=11)
    assert r["samples"] == 60 and r["seed"] == 7 and r["method"] == "analytic"
    for name in ["spindle_rpm", "depth_limit_mm"] + QUANTILES:
        column = header.index(name)
        assert [cell(x) for x in r[name]] == [row[column] for row in rows], name
    prob = [l.split(",") for l in (tmp_path / "p.csv").read_text().splitlines()[1:]]
    assert r["probability_stable"].shape == (25, 11)
    assert len(prob) == 25 * 11
    for k, (rpm, depth, p) in enumerate(prob):
        i, j = divmod(k, 11)
        assert (cell(r["spindle_rpm"][i]), cell(r["depth_mm"][j]), cell(r["probability_stable"][i, j])) == (rpm, depth, p)


def test_bitwise_independent_of_threads():
    job = chatter.load(UNCERTAIN)
    one = chatter.uncertain_lobes(job, samples=40, seed=3, rpm_points=20, threads=1)
    two = chatter.uncertain_lobes(job, samples=40, seed=3, rpm_points=20, threads=2)
    for name in QUANTILES + ["probability_stable", "depth_mm"]:
        assert np.array_equal(one[name], two[name]), name
    other_seed = chatter.uncertain_lobes(job, samples=40, seed=4, rpm_points=20, threads=1)
    assert not np.array_equal(one["depth_limit_p05_mm"], other_seed["depth_limit_p05_mm"])


def test_zero_spreads_give_the_nominal_lobes():
    r = chatter.uncertain_lobes(job_with({"stiffness_percent": 0}), samples=5, rpm_points=30, depth_points=21)
    nominal = chatter.lobes(chatter.load(PLAIN), rpm_points=30)
    for name in QUANTILES:
        assert np.array_equal(r[name], nominal["depth_limit_mm"]), name
    # Every sample is the nominal model: stable (1) strictly below its limit, 0 from it on.
    expected = (r["depth_mm"][None, :] < nominal["depth_limit_mm"][:, None]).astype(float)
    assert np.array_equal(r["probability_stable"], expected)


def test_stiffness_only_spread_scales_every_limit_alike():
    # One mode, only k uncertain: G(w) = shape(w) / k, so every sample's limit
    # is the nominal one times k_sample / k at every speed: the quantile lobes
    # are the nominal lobes times one factor, the quantile of (1 + s z) with
    # z standard normal truncated at |z| <= 3 (z_0.05 = -1.6449).
    s = 0.08
    r = chatter.uncertain_lobes(job_with({"stiffness_percent": 100 * s}), samples=2000, seed=11, rpm_points=40)
    nominal = r["depth_limit_mm"]
    for name, z in [("depth_limit_p05_mm", -1.6449), ("depth_limit_p50_mm", 0.0), ("depth_limit_p95_mm", 1.6449)]:
        finite = np.isfinite(r[name]) & np.isfinite(nominal)  # lobe tops above the searched 20 mm are inf
        assert finite.sum() >= 30, name
        ratio = r[name][finite] / nominal[finite]
        # One factor at every speed, to the solver's depth tolerance.
        assert np.ptp(ratio) < 1e-7 * ratio.mean(), name
        # Sampling error of a 5 % quantile of 2000 draws: about 0.05 in z, 0.004 in the ratio.
        assert ratio.mean() == pytest.approx(1 + s * z, abs=0.012), name


@pytest.mark.parametrize("kwargs,message", [
    ({"samples": 0}, "samples = 0: must be >= 1"),
    ({"samples": 10, "seed": -1}, "seed = -1: must be an integer >= 0"),
    ({"samples": 10, "depth_points": 1}, "depth_points = 1: must be in [2, 10000]"),
    ({"samples": 10, "probability_depth_max_mm": 0.0}, "probability_depth_max_mm = 0: must be > 0 mm"),
    ({"samples": 10 ** 6, "rpm_points": 400}, "samples x rpm_points = 1000000 x 400: at most 25000000"),
])
def test_bad_arguments(kwargs, message):
    with pytest.raises(chatter.InputError, match=message.replace("[", r"\[").replace("]", r"\]")):
        chatter.uncertain_lobes(chatter.load(UNCERTAIN), **kwargs)


def test_config_without_uncertainty_is_refused_as_the_cli():
    with pytest.raises(chatter.InputError, match=r"seed_turning_1dof\.toml: no \[uncertainty\] table"):
        chatter.uncertain_lobes(chatter.load(PLAIN), samples=10)
    status, _, err = run_cli("lobes", PLAIN, "--samples", 10, "--quiet")
    assert status == 2 and "no [uncertainty] table" in err
