"""chatter.performance, chatter.optimize, chatter.adapt and chatter.adapt_step
(issue 29, docs/optimization.md): the CLI's records, the source study's
numbers (removal 1750 mm^3/s, table 14's loss 16.01 from its indices), the
controller's loop stepped from Python converging onto the optimum, and bad
arguments raising chatter.InputError naming the argument."""
import math

import pytest

import chatter
from conftest import SOURCE_DIR, cli_json

SEED = SOURCE_DIR / "configs" / "turning_seed003_shaft.toml"
PLAIN = SOURCE_DIR / "configs" / "seed_turning_1dof.toml"
TABLE14 = {"diametral_error_um": 55.83, "surface_roughness_um": 6.40, "removal_rate_mm3_per_s": 1750,
           "cost": 0.80, "production_rate_per_h": 75.68}


@pytest.fixture(scope="module")
def job():
    return chatter.load(SEED)


def test_performance_is_the_cli_record(job):
    py = chatter.performance(job, cutting_speed_m_per_min=200, feed_mm_per_rev=0.35, depth_mm=1.5, index=TABLE14)
    args = ["performance", SEED, "--cutting-speed-m-per-min", 200, "--feed-mm-per-rev", 0.35, "--depth-mm", 1.5,
            "--json", "-"]
    for k, v in TABLE14.items():
        args += ["--index", f"{k}={v}"]
    cli = cli_json(*args)
    for key in ("loss", "alpha", "loss_terms", "constraints", "stability_margin", "removal_rate_mm3_per_s",
                "feasible", "measured", "predicted"):
        assert py[key] == cli[key], key
    assert py["loss"] == pytest.approx(16.01, abs=0.02)
    assert py["predicted"]["removal_rate_mm3_per_s"] == pytest.approx(1750.0, rel=1e-12)
    failing = [c["name"] for c in py["constraints"] if not c["ok"]]
    assert failing == ["max_diametral_error_um", "max_roughness_um"]


def test_optimize_is_the_cli_record_and_stability_binds_with_free_depth(job):
    py = chatter.optimize(job)
    cli = cli_json("optimize", SEED, "--json", "-")
    assert py["found"] and py["optimum"]["feasible"]
    assert py["optimum"]["loss"] == pytest.approx(cli["optimum"]["loss"], rel=1e-12)
    assert py["binding"] == cli["binding"]
    assert py["optimum"]["loss"] < 7.13
    free = chatter.optimize(job, depth_mm=(0.5, 5))
    assert free["bounds"]["depth_mm"] == [0.5, 5.0]
    blind = chatter.optimize(job, depth_mm=(0.5, 5), stability=False)
    assert blind["optimum"]["stability_margin"] is None
    assert blind["stability"] is False


def test_adapt_runs_the_loop_with_a_bias(job):
    run = chatter.adapt(job, 20, start={"cutting_speed_m_per_min": 200, "feed_mm_per_rev": 0.35, "depth_mm": 1.5},
                        bias=["all=5@10"])
    assert len(run["rows"]) == 20
    assert run["final_state"]["converged"]
    assert run["final_state"]["correction"]["surface_roughness_um"] == pytest.approx(1.05, rel=1e-12)
    rows = chatter.adapt(job, 5, measurements=[{"diametral_error_um": 50.0}, {"surface_roughness_um": 3.0}])["rows"]
    assert len(rows) == 2 and rows[0]["diametral_error_um"] == 50.0


def test_adapt_step_converges_as_a_controller_calls_it(job):
    best = chatter.optimize(job)["optimum"]["loss"]
    state = {"cutting_speed_m_per_min": 200, "feed_mm_per_rev": 0.35, "depth_mm": 1.5}
    names = ("diametral_error_um", "surface_roughness_um", "removal_rate_mm3_per_s", "cost",
             "production_rate_per_h", "force_n")
    converged_at = None
    for k in range(1, 31):
        p = chatter.performance(job, cutting_speed_m_per_min=state["cutting_speed_m_per_min"],
                                feed_mm_per_rev=state["feed_mm_per_rev"], depth_mm=state["depth_mm"])
        step = chatter.adapt_step(job, state, {n: p[n] for n in names})
        assert step["format"] == "chatter-adapt-step"
        assert step["state"]["iteration"] == state.get("iteration", 0) + 1
        state = step["state"]
        if state["converged"] and converged_at is None:
            converged_at = k
    assert converged_at is not None and converged_at <= 30
    assert math.isclose(state["loss"], best, rel_tol=0.05)


@pytest.mark.parametrize("call,word", [
    (lambda j: chatter.performance(j, cutting_speed_m_per_min=200, feed_mm_per_rev=0.35, depth_mm=-1), "depth_mm"),
    (lambda j: chatter.performance(j, cutting_speed_m_per_min=200, feed_per_tooth_mm=0.35, depth_mm=1),
     "feed_mm_per_rev"),
    (lambda j: chatter.performance(j, rpm=2000, feed_mm_per_rev=0.3, depth_mm=1, index={"speed": 3}), "speed"),
    (lambda j: chatter.optimize(j, depth_mm=(3, 1)), "depth_mm"),
    (lambda j: chatter.adapt(j, 3, bias=["all=5"]), "bias"),
    (lambda j: chatter.adapt_step(j, {"feed_mm_per_rev": 0.3, "depth_mm": 1}), "spindle_rpm"),
    (lambda j: chatter.adapt_step(j, {"spindle_rpm": 2000, "feed_mm_per_rev": 0.3, "depth_mm": 1}, gamma=2),
     "gamma"),
])
def test_bad_arguments_name_the_argument(job, call, word):
    with pytest.raises(chatter.InputError, match=word):
        call(job)


def test_a_config_without_optimization_is_refused():
    with pytest.raises(chatter.InputError, match=r"\[optimization\]"):
        chatter.optimize(chatter.load(PLAIN))
