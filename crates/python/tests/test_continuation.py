"""`continue_branch` against `rattle continue --json`: the same document, number for number,
on the unit and on a chain; its points as numpy columns; bad arguments as ValueError with the
command's message, the options named as the Python parameters."""

import json

import numpy as np
import pytest
import rattle
from test_trajectories import python_names

#: The command's example range on the paper scene: the two `+-` orbits at ω = 3 followed over
#: [2.7, 3.1], through branch points and period doublings (several branches and events).
ARGS = dict(signature="+-", omega=3.0, omega_min=2.7, omega_max=3.1)
CLI_ARGS = ["--signature", "+-", "--omega", 3.0, "--omega-min", 2.7, "--omega-max", 3.1]


@pytest.fixture(scope="module")
def followed():
    return rattle.continue_branch(rattle.Scene.paper(), **ARGS)


def test_continuation_is_the_commands(rattle_cli, followed):
    assert isinstance(followed, rattle.Continuation)
    theirs = rattle_cli.json("continue", *CLI_ARGS)
    assert followed.to_dict() == theirs
    assert followed.signature == "+-" and followed.period == 1
    assert len(followed.branches) == len(theirs["branches"]) > 1
    assert len(followed.events) == len(theirs["events"]) > 0
    assert len(followed.ends) == len(theirs["ends"]) > 0
    assert len(followed.points) == len(theirs["points"])


def test_one_orbit_without_switching_is_the_commands(rattle_cli):
    ours = rattle.continue_branch(
        rattle.Scene.paper(), **ARGS, orbit=1, switch=False, max_step=0.02, max_branches=3
    )
    theirs = rattle_cli.json(
        "continue", *CLI_ARGS, "--orbit", 1, "--no-switch", "--max-step", 0.02,
        "--max-branches", 3,
    )
    assert ours.to_dict() == theirs
    assert ours.followed_starts == [1]


def test_switching_depth_is_the_commands(rattle_cli):
    ours = rattle.continue_branch(rattle.Scene.paper(), **ARGS, max_depth=1)
    theirs = rattle_cli.json("continue", *CLI_ARGS, "--max-depth", 1)
    assert ours.to_dict() == theirs


def test_points_columns(followed):
    columns = followed.points_columns()
    points = followed.to_dict()["points"]
    assert list(columns) == [
        "branch", "omega", "alpha", "outer_amplitude", "transmittance_db", "stable", "viable",
    ]
    for name, column in columns.items():
        assert column.shape == (len(points),)
        if name == "branch":
            assert column.dtype == np.int64
        elif name in ("stable", "viable"):
            assert column.dtype == bool
        else:
            assert column.dtype == np.float64
        expected = [np.nan if p[name] is None else p[name] for p in points]
        np.testing.assert_array_equal(column, np.array(expected, dtype=column.dtype))
    assert np.all((columns["omega"] >= 2.7) & (columns["omega"] <= 3.1))


@pytest.mark.parametrize(
    "change, options",
    [
        (dict(omega=3.3), ["--omega", 3.3]),
        (dict(omega_min=0.0), ["--omega-min", 0.0]),
        (dict(omega_max=2.6), ["--omega-max", 2.6]),
        (dict(max_step=0.0), ["--max-step", 0.0]),
        (dict(max_step=float("nan")), ["--max-step", "NaN"]),
        (dict(max_branches=0), ["--max-branches", 0]),
        (dict(orbit=5), ["--orbit", 5]),
        (dict(period=9), ["--period", 9]),
    ],
)
def test_bad_arguments_are_the_commands_messages(rattle_cli, change, options):
    args = {**ARGS, **change}
    cli = dict(zip(CLI_ARGS[::2], CLI_ARGS[1::2]))
    cli.update(zip(options[::2], options[1::2]))
    theirs = rattle_cli.error("continue", *[x for kv in cli.items() for x in kv])
    with pytest.raises(ValueError) as e:
        rattle.continue_branch(rattle.Scene.paper(), **args)
    assert str(e.value) == python_names(theirs).replace("--period", "period")
    name = next(iter(change))
    assert name in str(e.value)


def test_other_bad_arguments():
    scene = rattle.Scene.paper()
    with pytest.raises(ValueError, match="orbit = -1 is out of range"):
        rattle.continue_branch(scene, **ARGS, orbit=-1)
    with pytest.raises(ValueError, match="max_branches = 0 is out of range"):
        rattle.continue_branch(scene, **ARGS, max_branches=-2)
    with pytest.raises(ValueError, match="max_depth = -1 is out of range"):
        rattle.continue_branch(scene, **ARGS, max_depth=-1)
    with pytest.raises(ValueError, match="signature"):
        rattle.continue_branch(scene, **{**ARGS, "signature": "+x"})
    free = rattle.Scene.from_dict(
        {k: v for k, v in scene.to_dict().items() if k != "stops"}
    )
    with pytest.raises(ValueError, match="stops"):
        rattle.continue_branch(free, **ARGS)


def test_nothing_to_follow_is_a_runtime_error(rattle_cli):
    theirs = rattle_cli.error(
        "continue", "--signature", "+-", "--omega", 0.3, "--omega-min", 0.2, "--omega-max", 0.4
    )
    with pytest.raises(RuntimeError) as e:
        rattle.continue_branch(
            rattle.Scene.paper(), signature="+-", omega=0.3, omega_min=0.2, omega_max=0.4
        )
    assert str(e.value) == theirs


#: Two of the paper's cells in series, lightly damped as `data/scenes/paper-chain-5.json`: the
#: sequence `0+ 1- 0- 1+` has a viable orbit at ω = 3.3 (the analytic crate's
#: `tests/continuation_chain.rs` follows it).
TWO_CELLS = {
    "name": "two",
    "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0,
             "inner_stiffness": 3.0},
    "base": {"amplitude": 1.0},
    "stops": {"gap": 0.5, "restitution": 0.8},
    "damping": {"outer": 0.1, "inner": 0.05},
    "cells": 2,
}


def test_a_chains_branch_is_the_commands(rattle_cli, tmp_path):
    path = tmp_path / "two.json"
    path.write_text(json.dumps(TWO_CELLS))
    sequence = "0+ 1- 0- 1+"
    ours = rattle.continue_branch(
        rattle.Scene.from_dict(TWO_CELLS), sequence, 3.3, 3.2, 3.4, max_depth=0
    )
    theirs = rattle_cli.json(
        "continue", path, "--signature", sequence, "--omega", 3.3, "--omega-min", 3.2,
        "--omega-max", 3.4, "--max-depth", 0,
    )
    assert ours.to_dict() == theirs
    assert ours.signature == sequence and ours.cells == 2
    assert len(ours.points) > 20
    for p in ours.to_dict()["points"]:
        assert len(p["cell_outer_amplitudes"]) == 2
        assert p["cell_outer_amplitudes"][-1] == p["outer_amplitude"]
    assert "neimark-sacker" in [e["kind"] for e in ours.to_dict()["events"]]
    with pytest.raises(ValueError, match="pair 2"):
        rattle.continue_branch(
            rattle.Scene.from_dict(TWO_CELLS), "0+ 2-", 3.3, 3.2, 3.4, max_depth=0
        )
