"""msm_sim.lab.<command>(**options) against `msm_lab <command> ... --json`: the same dict to the
last digit, wall-clock timings aside, and the same error line."""
import json
import subprocess

import numpy as np
import pytest

from msm_sim import lab

BLOCK = {"model": "cubic", "size": [2.0, 1.0, 1.0], "spacing": 0.125, "youngs": 1.0e5,
         "poisson": 0.3, "density": 1100.0}
CASES = [
    ("compression", BLOCK),
    ("indent", {"size": [0.04, 0.04, 0.02], "spacing": 0.005, "sphere_radius": 0.005,
                "youngs": 1.0e5, "poisson": 0.3, "depth": 0.0015}),
    ("grasp", {"shape": "sphere", "radius": 0.02, "spacing": 0.008, "youngs": 2.0e5,
               "poisson": 0.3, "density": 1100.0, "lift": 0.02, "lift_time": 0.5,
               "force_ratio": 1.5}),
]


def without_timings(value):
    """The dict without its wall-clock fields (they differ from run to run)."""
    if isinstance(value, dict):
        return {k: without_timings(v) for k, v in value.items() if not is_timing(k)}
    if isinstance(value, list):
        return [without_timings(v) for v in value]
    return value


def is_timing(key):
    return key in ("seconds", "build_seconds", "real_time_factor")


def cli_json(msm_lab, command, options):
    run = subprocess.run([msm_lab] + lab.arguments(command, options), capture_output=True,
                         text=True, check=True)
    return json.loads(run.stdout)


@pytest.mark.parametrize("command, options", CASES, ids=[c for c, _ in CASES])
def test_lab_dict_equals_cli_json(command, options, msm_lab):
    from_python = getattr(lab, command)(**options)
    from_cli = cli_json(msm_lab, command, options)
    assert from_python and isinstance(from_python, dict)
    assert without_timings(from_python) == without_timings(from_cli)
    assert json.dumps(without_timings(from_python)) == json.dumps(without_timings(from_cli))


def test_every_command_is_a_function():
    for command in lab.COMMANDS:
        assert callable(getattr(lab, command.replace("-", "_")))
    assert lab.poisson_sweep.__name__ == "poisson_sweep"


def test_arguments_spell_the_command_line():
    assert lab.arguments("build", {"size": (0.1, 0.2, 0.3), "force_ratio": 0.1,
                                   "self_calibrate": True, "free_face_bending": False,
                                   "antialias": False, "seed": 3}) == [
        "build", "--size", "0.1", "0.2", "0.3", "--force-ratio", "0.1", "--self-calibrate",
        "--antialias", "off", "--seed", "3", "--json"]
    assert lab.arguments("build", {"size": np.array([0.1, 0.2, 0.3]), "spacing": np.float64(0.1)})[
        1:6] == ["--size", "0.1", "0.2", "0.3", "--spacing"]
    with pytest.raises(ValueError, match="unknown msm_lab command 'bend'"):
        lab.arguments("bend", {})


@pytest.mark.parametrize("options", [
    dict(BLOCK, size=[0.02, 0.01]),   # CLI11: --size needs 3 values
    dict(BLOCK, poisson=0.7),         # the material's range
    dict(BLOCK, colour="red"),        # an option compression does not have
])
def test_bad_options_raise_value_error_with_the_cli_line(options, msm_lab):
    run = subprocess.run([msm_lab] + lab.arguments("compression", options),
                         capture_output=True, text=True)
    assert run.returncode == 2
    with pytest.raises(ValueError) as raised:
        lab.compression(**options)
    assert str(raised.value) == run.stderr.strip()
    assert str(raised.value).startswith("msm_lab: error: ")
