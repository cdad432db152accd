"""chatter.grind_predict and chatter.grind_fit: the same records as
`chatter grind predict --json` and `chatter grind fit --json` (the io layer
writes them once), the seeds' numbers, and errors as chatter.InputError."""
import pytest

import chatter
from conftest import GRINDING_CONFIGS, SOURCE_DIR, cli_json, run_cli

SCOMPI = str(SOURCE_DIR / "configs" / "grinding_scompi_ch4.toml")
UNDERWATER = str(SOURCE_DIR / "configs" / "grinding_underwater_seed000.toml")
SYNTHETIC = str(SOURCE_DIR / "examples" / "grinding" / "scompi_tests_synthetic.csv")
PRINTED = str(SOURCE_DIR / "examples" / "grinding" / "underwater_tests_seed000.csv")


def test_grinding_configs_are_shipped():
    assert len(GRINDING_CONFIGS) >= 2


@pytest.mark.parametrize("config,args", [
    (SCOMPI, ["--power-w", "1000"]),
    (SCOMPI, ["--target-depth-mm", "0.2"]),
    (UNDERWATER, ["--power-w", "2021"]),
    (UNDERWATER, ["--current-a", "19"]),
])
def test_predict_is_the_cli_record(config, args):
    flag, value = args
    kw = {flag[2:].replace("-", "_"): float(value)}
    assert chatter.grind_predict(config, **kw) == cli_json("grind", "predict", config, *args, "--json", "-")


def test_predict_reproduces_seed_001():
    r = chatter.grind_predict(SCOMPI, power_w=1000)
    assert r["removal_rate_mm3_per_s"] == pytest.approx(52.2, abs=0.05)
    assert r["max_depth_mm"] == pytest.approx(0.101, abs=0.0005)
    assert r["friction_power_w"] == pytest.approx(477, abs=0.5)
    assert r["chip_power_w"] == pytest.approx(523, abs=0.5)


@pytest.mark.parametrize("tests,model", [(SYNTHETIC, "mechanistic"), (PRINTED, "poly11"), (PRINTED, "hahn_lindsay")])
def test_fit_is_the_cli_record(tests, model):
    r = chatter.grind_fit(tests, model=model)
    # The whole record, the fit's [grinding] fragment included: one builder
    # (records/grinding.hpp) for both.
    assert r == cli_json("grind", "fit", tests, "--model", model, "--json", "-")
    fragment = r["fragment"]
    assert fragment.startswith("# Fitted by `chatter grind fit")
    assert "[grinding]" in fragment


def test_errors_are_input_errors(tmp_path):
    with pytest.raises(chatter.InputError, match="power_w = 0: must be > 0 W"):
        chatter.grind_predict(SCOMPI, power_w=0)
    with pytest.raises(chatter.InputError, match="give exactly one of"):
        chatter.grind_predict(SCOMPI, power_w=1000, target_depth_mm=0.1)
    with pytest.raises(chatter.InputError, match="below the wheel radius"):
        chatter.grind_predict(SCOMPI, target_depth_mm=500)
    with pytest.raises(chatter.InputError, match="a grinding config"):
        chatter.load(SCOMPI)
    bad = tmp_path / "bad.csv"
    bad.write_text("power_w,removal_mm3_per_s\n1000,oops\n")
    with pytest.raises(chatter.InputError, match="line 2: removal_mm3_per_s = 'oops'"):
        chatter.grind_fit(bad, model="poly11")
    with pytest.raises(chatter.InputError, match="defaults: 'wheel_mm'"):
        chatter.grind_fit(SYNTHETIC, model="mechanistic", defaults={"wheel_mm": 3})
    status, _, err = run_cli("grind", "predict", SCOMPI, "--power-w", "0")
    assert status == 2 and "must be > 0 W" in err


def test_plan_objective_is_the_cli_record():
    args = dict(current_a=19, area_mm2=1.5e6, depth_mm=2, wheel_change_min=180, objective="g-ratio",
                wheel_rpm_min=2025, wheel_rpm_max=3375)
    r = chatter.grind_plan(UNDERWATER, **args)
    cli = cli_json("grind", "plan", UNDERWATER, "--current-a", "19", "--area-mm2", "1.5e6", "--depth-mm", "2",
                   "--wheel-change-min", "180", "--objective", "g-ratio", "--wheel-rpm-min", "2025",
                   "--wheel-rpm-max", "3375", "--json", "-")
    life = r.pop("wheel_life")
    assert r == cli
    assert r["wheels_saved_by_g_ratio"] == r["removal"]["wheels_needed"] - r["g_ratio"]["wheels_needed"]
    assert len(life["wheel_rpm"]) == 201
    with pytest.raises(chatter.InputError, match="wheel_rpm_min and wheel_rpm_max"):
        chatter.grind_plan(UNDERWATER, power_w=2000, volume_mm3=1e6, objective="removal")
    with pytest.raises(chatter.InputError, match="objective speed: must be removal or g-ratio"):
        chatter.grind_plan(UNDERWATER, power_w=2000, volume_mm3=1e6, objective="speed", wheel_rpm_min=2000,
                           wheel_rpm_max=3000)
