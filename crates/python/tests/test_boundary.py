"""`boundary` against `rattle boundary --json`: the same document, number for number; its
lists as numpy columns; bad arguments as ValueError with the command's message, the options
named as the Python parameters; nothing to follow as the command's RuntimeError."""

import numpy as np
import pytest
import rattle
from test_trajectories import python_names

#: The command's period-doubling curve of the paper scene's `+-` orbits near ω = 2.85 over the
#: gap (as `crates/compare/tests/boundary.rs`), with three `at` values, the scene's own gap
#: among them.
ARGS = dict(
    signature="+-", event="period-doubling", omega=2.85, param="stops.gap", min=0.45, max=0.55
)
CLI_ARGS = [
    "--signature", "+-", "--event", "period-doubling", "--omega", 2.85, "--param", "stops.gap",
    "--min", 0.45, "--max", 0.55,
]


def boundary_names(message):
    """The command's message with its options named as `boundary`'s parameters."""
    message = python_names(message)
    for option, parameter in [
        ("--event", "event"), ("--param", "param"), ("--min", "min"), ("--max", "max"),
        ("--at", "at"), ("--period", "period"), ("--signature", "signature"),
        ("boundary.max_step", "max_step"),
    ]:
        message = message.replace(option, parameter)
    return message


@pytest.fixture(scope="module")
def followed():
    return rattle.boundary(rattle.Scene.paper(), **ARGS, at=[0.47, 0.5, 0.53])


def test_boundary_is_the_commands(rattle_cli, followed):
    assert isinstance(followed, rattle.Boundary)
    theirs = rattle_cli.json("boundary", *CLI_ARGS, "--at", "0.47,0.5,0.53")
    assert followed.to_dict() == theirs
    assert followed.event == "period-doubling" and followed.param == "stops.gap"
    assert len(followed.points) > 10
    assert [a.param_value for a in followed.at] == [0.47, 0.5, 0.53]
    assert len(followed.ends) == 2


def test_options_are_the_commands(rattle_cli):
    """A fold curve over the restitution, with every option the command has."""
    ours = rattle.boundary(
        rattle.Scene.paper(), "+-", "fold", 0.7, "stops.restitution", 0.7, 0.9, period=1,
        at=[0.75], omega_min=0.5, omega_max=1.0, max_step=0.01,
    )
    theirs = rattle_cli.json(
        "boundary", "--signature", "+-", "--event", "fold", "--omega", 0.7, "--param",
        "stops.restitution", "--min", 0.7, "--max", 0.9, "--period", 1, "--at", 0.75,
        "--omega-min", 0.5, "--omega-max", 1.0, "--max-step", 0.01,
    )
    assert ours.to_dict() == theirs
    assert ours.event == "fold" and len(ours.points) > 10


def test_columns_are_the_documents_lists(followed):
    doc = followed.to_dict()
    points = followed.points_columns()
    assert list(points) == [
        "param_value", "omega", "outer_amplitude", "critical_multiplier", "special"
    ]
    # Which special point a point is, if any (the document's `special`, null elsewhere).
    assert [None if isinstance(k, float) else k for k in points["special"]] == [
        p["special"] for p in doc["points"]
    ]
    for name in ["param_value", "omega", "outer_amplitude"]:
        assert points[name].dtype == np.float64
        np.testing.assert_array_equal(points[name], [p[name] for p in doc["points"]])
    mu = points["critical_multiplier"]
    assert mu.dtype == np.complex128
    np.testing.assert_array_equal(
        mu, [complex(*p["critical_multiplier"]) for p in doc["points"]]
    )
    # A period doubling: a multiplier at −1 on every point (the command's test holds it to
    # 1e-8).
    assert np.all(np.abs(mu + 1.0) < 1e-8)
    assert np.all((points["param_value"] >= 0.45) & (points["param_value"] <= 0.55))
    at = followed.at_columns()
    assert list(at) == ["param_value", "omega"]
    np.testing.assert_array_equal(at["omega"], [a["omega"] for a in doc["at"]])
    ends = followed.ends_columns()
    assert list(ends) == ["param_value", "omega", "reason"]
    assert ends["reason"].dtype == object
    assert list(ends["reason"]) == [e["reason"] for e in doc["ends"]]
    special = followed.special_points_columns()
    assert all(len(c) == len(doc["special_points"]) for c in special.values())


@pytest.mark.parametrize(
    "change, options",
    [
        (dict(event="cusp"), ["--event", "cusp"]),
        (dict(param="stops.width"), ["--param", "stops.width"]),
        (dict(min=0.0), ["--min", 0.0]),
        (dict(max=0.4), ["--max", 0.4]),
        (dict(omega=0.0), ["--omega", 0.0]),
        (dict(omega=5.0), ["--omega", 5.0]),
        (dict(signature="+x"), ["--signature", "+x"]),
        (dict(period=9), ["--period", 9]),
        (dict(at=[0.6]), ["--at", 0.6]),
        (dict(omega_min=0.0), ["--omega-min", 0.0]),
        (dict(omega_max=float("nan")), ["--omega-max", "NaN"]),
        (dict(max_step=0.0), ["--max-step", 0.0]),
    ],
)
def test_bad_arguments_are_the_commands_messages(rattle_cli, change, options):
    cli = dict(zip(CLI_ARGS[::2], CLI_ARGS[1::2]))
    cli.update(zip(options[::2], options[1::2]))
    theirs = rattle_cli.error("boundary", *[x for kv in cli.items() for x in kv])
    with pytest.raises(ValueError) as e:
        rattle.boundary(rattle.Scene.paper(), **{**ARGS, **change})
    assert str(e.value) == boundary_names(theirs)
    assert next(iter(change)) in str(e.value)


#: The damped 2-cell chain of compare's `tests/boundary.rs`: its `0+ 1- 0- 1+` orbits at
#: ω = 3.3 have a Neimark–Sacker point on their branch.
DAMPED_CHAIN = {
    "name": "damped-two",
    "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0},
    "base": {"amplitude": 1.0},
    "stops": {"gap": 0.5, "restitution": 0.8},
    "damping": {"outer": 0.1, "inner": 0.05},
    "cells": 2,
}


def test_a_chain_is_the_commands(rattle_cli, tmp_path):
    """A chain's Neimark–Sacker curve over one cell's restitution, as the command's."""
    path = tmp_path / "damped-two.json"
    path.write_text(__import__("json").dumps(DAMPED_CHAIN))
    ours = rattle.boundary(
        rattle.Scene.from_dict(DAMPED_CHAIN), "0+ 1- 0- 1+", "neimark-sacker", 3.3,
        "chain[1].stops.restitution", 0.76, 0.84, at=[0.78, 0.8], omega_min=2.8, omega_max=4.0,
    )
    theirs = rattle_cli.json(
        "boundary", str(path), "--signature", "0+ 1- 0- 1+", "--event", "neimark-sacker",
        "--omega", 3.3, "--param", "chain[1].stops.restitution", "--min", 0.76, "--max", 0.84,
        "--at", "0.78,0.8", "--omega-min", 2.8, "--omega-max", 4.0,
    )
    assert ours.to_dict() == theirs
    assert ours.param == "chain[1].stops.restitution" and len(ours.points) > 2
    mu = ours.points_columns()["critical_multiplier"]
    assert np.all(np.abs(np.abs(mu) - 1.0) < 1e-8)


def test_a_free_unit_is_refused_by_name():
    scene = rattle.Scene.paper()
    free = rattle.Scene.from_dict({k: v for k, v in scene.to_dict().items() if k != "stops"})
    with pytest.raises(ValueError, match="stops"):
        rattle.boundary(free, **ARGS)


def test_nothing_to_follow_is_the_commands_runtime_error(rattle_cli):
    """No `+-` orbit at ω = 0.3 on the paper scene (`continue_branch`'s test of the same)."""
    theirs = rattle_cli.error(
        "boundary", *CLI_ARGS[:4], "--omega", 0.3, *CLI_ARGS[6:]
    )
    with pytest.raises(RuntimeError) as e:
        rattle.boundary(rattle.Scene.paper(), **{**ARGS, "omega": 0.3})
    assert str(e.value) == theirs
