"""Bad input raises the right exception, with the command's message: a scene's field path and
allowed range word for word (the origin is the file, or `dict`), options named as the Python
parameters; a failure inside the Rust side is a RuntimeError, never a panic."""

import json
import math

import pytest
import rattle
from conftest import SCENES

PAPER = json.loads((SCENES / "paper.json").read_text())


def _with(path, value):
    scene = json.loads(json.dumps(PAPER))
    *parents, last = path.split(".")
    node = scene
    for key in parents:
        node = node.setdefault(key, {})
    node[last] = value
    return scene


#: (field path, bad value, words of the allowed range the message must carry).
OUT_OF_RANGE = [
    ("unit.outer_mass", -1.0, "> 0"),
    ("unit.inner_mass", 0.0, "> 0"),
    ("unit.outer_stiffness", -6.0, "> 0"),
    ("base.amplitude", -1.0, None),
    ("stops.gap", -0.5, None),
    ("stops.restitution", 1.5, "[0, 1]"),
    ("damping.outer", -0.1, None),
    ("damping.inner", -0.1, None),
]


@pytest.mark.parametrize("path, value, allowed", OUT_OF_RANGE)
def test_out_of_range_values_are_the_commands_messages(rattle_cli, tmp_path, path, value, allowed):
    scene = _with(path, value)
    file = tmp_path / "scene.json"
    file.write_text(json.dumps(scene))
    theirs = rattle_cli.error("simulate", file, "--omega", 2.0)
    assert path in theirs and "out of range" in theirs
    if allowed:
        assert allowed in theirs
    with pytest.raises(ValueError) as from_file:
        rattle.Scene.from_file(file)
    assert str(from_file.value) == theirs
    with pytest.raises(ValueError) as from_dict:
        rattle.Scene.from_dict(scene)
    assert str(from_dict.value) == theirs.replace(str(file), "dict", 1)


@pytest.mark.parametrize(
    "edit, path, words",
    [
        (lambda s: s["stops"].update(gapp=s["stops"].pop("gap")), "stops.gapp", "unknown field"),
        (lambda s: s["unit"].update(outer_mass="2"), "unit.outer_mass", "invalid type"),
        (lambda s: s.pop("base"), ".", "missing field `base`"),
    ],
)
def test_malformed_scenes_are_the_commands_messages(rattle_cli, tmp_path, edit, path, words):
    scene = json.loads(json.dumps(PAPER))
    edit(scene)
    file = tmp_path / "scene.json"
    file.write_text(json.dumps(scene))
    theirs = rattle_cli.error("orbit", file, "--omega", 2.0)
    assert path in theirs and words in theirs
    with pytest.raises(ValueError) as from_file:
        rattle.Scene.from_file(file)
    assert str(from_file.value) == theirs
    with pytest.raises(ValueError) as from_dict:
        rattle.Scene.from_dict(scene)
    # A dictionary has no lines: the message is the command's without its position.
    assert str(from_dict.value) == theirs.replace(str(file), "dict", 1).rsplit(" (line ", 1)[0]


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_numbers_name_the_field_and_range(bad):
    with pytest.raises(ValueError) as e:
        rattle.Scene.from_dict(_with("stops.restitution", bad))
    assert str(e.value).startswith("dict: stops.restitution = ")
    assert "out of range: must be in [0, 1]" in str(e.value)


def test_a_missing_file_is_an_os_error(rattle_cli, tmp_path):
    missing = tmp_path / "missing.json"
    with pytest.raises(FileNotFoundError) as e:
        rattle.Scene.from_file(missing)
    assert str(e.value) == rattle_cli.error("orbit", missing, "--omega", 2.0)


def test_a_scene_is_a_dict():
    with pytest.raises(TypeError):
        rattle.Scene.from_dict("paper")
    with pytest.raises(TypeError):
        rattle.simulate(PAPER, 2.0)


@pytest.mark.parametrize("omega", [0.0, -1.0, math.nan, math.inf])
@pytest.mark.parametrize("function", [rattle.orbit, rattle.simulate, rattle.compare])
def test_a_bad_frequency_is_the_commands_message(rattle_cli, function, omega):
    with pytest.raises(ValueError) as e:
        function(rattle.Scene.paper(), omega)
    theirs = rattle_cli.error(function.__name__, "--omega", omega)
    assert str(e.value) == theirs.replace("--omega", "omega")


@pytest.mark.parametrize(
    "keyword, value, option",
    [
        ("tol", 1.0, "--tol"),
        ("tol", 1e-16, "--tol"),
        ("steady_tol", 1e-15, "--steady-tol"),
        ("max_oscillations", -1.0, "--max-oscillations"),
        ("max_periods", 0, "--max-periods"),
    ],
)
def test_bad_accuracy_options_are_the_commands_messages(rattle_cli, keyword, value, option):
    theirs = rattle_cli.error("simulate", "--omega", 2.0, f"{option}={value}")
    expected = theirs.replace(option, keyword)
    for function in (rattle.simulate, rattle.compare):
        with pytest.raises(ValueError) as e:
            function(rattle.Scene.paper(), 2.0, **{keyword: value})
        assert str(e.value) == expected
    with pytest.raises(ValueError) as e:
        rattle.sweep(rattle.Scene.paper(), [2.0], **{keyword: value})
    assert str(e.value) == expected


def test_a_bad_run_length_is_refused(rattle_cli):
    for periods in (0, -3):
        with pytest.raises(ValueError, match="periods must be > 0"):
            rattle.simulate(rattle.Scene.paper(), 2.0, periods=periods)
    assert "--periods must be > 0" in rattle_cli.error("simulate", "--omega", 2, "--periods", 0)


@pytest.mark.parametrize(
    "signature, period", [("", 1), ("+x-", 1), ("+-", 0), ("+-", 9), ("+" * 40, 1)]
)
def test_bad_signatures_are_the_commands_messages(rattle_cli, signature, period):
    theirs = rattle_cli.error(
        "orbit", "--omega", 2.0, "--signature", signature, "--period", period
    )
    with pytest.raises(ValueError) as e:
        rattle.orbit(rattle.Scene.paper(), 2.0, signature=signature, period=period)
    assert str(e.value) == theirs.replace("--signature", "signature").replace(
        "--period", "period"
    )


def test_orbit_arguments_that_exclude_each_other():
    scene = rattle.Scene.paper()
    with pytest.raises(ValueError, match="signature"):
        rattle.orbit(scene, 2.0, period=2)
    with pytest.raises(ValueError, match="symmetric_only"):
        rattle.orbit(scene, 2.0, signature="+-", symmetric_only=True)
    linear = rattle.Scene.from_dict({k: v for k, v in PAPER.items() if k != "stops"})
    with pytest.raises(ValueError, match="no `stops`"):
        rattle.orbit(linear, 2.0, signature="+-")


def test_bad_sweep_inputs():
    scene = rattle.Scene.paper()
    with pytest.raises(ValueError, match=r"solver = \"fast\""):
        rattle.sweep(scene, [2.0], solver="fast")
    with pytest.raises(ValueError, match=r"omegas\[1\] = -2 is out of range"):
        rattle.sweep(scene, [1.0, -2.0])
    with pytest.raises(ValueError, match="one-dimensional"):
        rattle.sweep(scene, [[1.0, 2.0]])
    with pytest.raises(ValueError, match="omega_max = 1 is out of range"):
        rattle.frequencies(2.0, 1.0, 3)
    with pytest.raises(ValueError, match="points must be"):
        rattle.frequencies(1.0, 2.0, 0)


def test_bad_lyapunov_periods_are_the_commands_message(rattle_cli):
    scene = rattle.Scene.paper()
    theirs = rattle_cli.error(
        "simulate", "--omega", 2.0, "--lyapunov", "--lyapunov-periods", 5
    )
    assert theirs == "--lyapunov-periods = 5 is out of range: must be at least 10"
    with pytest.raises(ValueError) as raised:
        rattle.simulate(scene, 2.0, lyapunov=True, lyapunov_periods=5)
    assert str(raised.value) == theirs.replace("--lyapunov-periods", "lyapunov_periods")
    with pytest.raises(ValueError, match=r"^lyapunov_periods = -3 is out of range"):
        rattle.simulate(scene, 2.0, lyapunov=True, lyapunov_periods=-3)


def test_failures_inside_rust_are_runtime_errors():
    from rattle import _rattle

    with pytest.raises(RuntimeError, match="^numerical failure: a failure from the boundary"):
        _rattle._boundary_check("error")
    # A panic is caught on the Rust side: a RuntimeError, not pyo3's PanicException (which
    # derives from BaseException and would escape `except Exception`).
    with pytest.raises(RuntimeError, match="internal error .*a panic from the boundary check"):
        _rattle._boundary_check("panic")
    _rattle._boundary_check("none")


@pytest.mark.parametrize("omega", [1e-300, 1e-6, 1e300])
@pytest.mark.parametrize("function", [rattle.orbit, rattle.simulate, rattle.compare])
def test_a_frequency_that_would_not_end_is_the_commands_message(rattle_cli, function, omega):
    """Far below or above the scene's modes a run does not end in bounded time; it is refused
    at once with the scene's range, as the command refuses it."""
    with pytest.raises(ValueError) as e:
        function(rattle.Scene.paper(), omega)
    theirs = rattle_cli.error(function.__name__, "--omega", omega)
    assert "out of range for this scene: must be in [" in theirs
    assert str(e.value) == theirs.replace("--omega", "omega")


def test_sweeps_and_continuations_refuse_frequencies_that_would_not_end():
    scene = rattle.Scene.paper()
    with pytest.raises(ValueError, match=r"omegas\[1\] = 1e-6 is out of range for this scene"):
        rattle.sweep(scene, [2.0, 1e-6])
    with pytest.raises(ValueError, match="omega_min = 1e-300 is out of range for this scene"):
        rattle.continue_branch(scene, "+-", 1.0, 1e-300, 2.0)


def test_maps_and_basins_refuse_frequencies_that_would_not_end():
    scene = rattle.Scene.paper()
    with pytest.raises(ValueError, match=r"omega\[0\] = 1e-6 is out of range for this scene"):
        rattle.map(scene, restitution=(0.8, 0.8, 1), gap=(0.5, 0.5, 1), omega=(1e-6, 2.0, 3))
    with pytest.raises(ValueError, match="omega = 1e-6 is out of range for this scene"):
        rattle.basins(scene, 1e-6, outer=(-1.0, 1.0), inner=(-1.0, 1.0), points=2)
