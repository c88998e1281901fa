"""Scenes in the structure form (bodies, springs, dashpots, stops, forcing) against the
`rattle` command's JSON for the same inputs: simulate (with its trajectory tables and
Lyapunov exponents), orbit with a signature, compare and sweep give the command's documents,
and every other function refuses a structure with a ValueError naming it, as the command
refuses one."""

import json
import math

import numpy as np
import pytest
import rattle
from conftest import SCENES

OSCILLATOR = SCENES / "impact-oscillator.json"
#: A free body (the ball) in a clearance of a forced primary.
DAMPER = SCENES / "impact-damper.json"
ASYMMETRIC = SCENES / "asymmetric-unit.json"
STRUCTURES = [OSCILLATOR, DAMPER, ASYMMETRIC]

#: One frequency per structure where it impacts on a settled motion.
OMEGA = {OSCILLATOR: 1.8, DAMPER: 1.0, ASYMMETRIC: 3.0}


def _id(path):
    return path.stem


@pytest.mark.parametrize("path", STRUCTURES, ids=_id)
def test_a_structure_scene_is_taken_in_either_way(rattle_cli, path):
    document = json.loads(path.read_text())
    scene = rattle.Scene.from_file(path)
    assert scene.form == "structure"
    assert scene.name == document["name"]
    assert rattle.Scene.from_dict(document) == scene
    assert rattle.Scene.from_dict(scene.to_dict()) == scene
    assert scene.to_dict()["structure"]["bodies"] == document["structure"]["bodies"]
    # The effects are those of the command's records' heading.
    theirs = rattle_cli.json("simulate", path, "--omega", OMEGA[path], "--periods", 2)
    assert scene.effects == theirs["effects"]
    assert rattle.Scene.paper().form == "cells"


def test_a_structures_bad_value_is_named_by_its_path():
    document = json.loads(OSCILLATOR.read_text())
    document["structure"]["bodies"][0]["mass"] = -1.0
    with pytest.raises(ValueError, match=r"dict: structure\.bodies\[0\]\.mass"):
        rattle.Scene.from_dict(document)
    document["structure"]["bodies"][0]["mass"] = math.nan
    with pytest.raises(ValueError, match=r"dict: structure\.bodies\[0\]\.mass: NaN"):
        rattle.Scene.from_dict(document)
    document["structure"]["bodies"][0]["mass"] = 1.0
    document["structure"]["stops"][0]["restitution"] = math.inf
    with pytest.raises(ValueError, match=r"structure\.stops\[0\]\.restitution"):
        rattle.Scene.from_dict(document)


def _table(path):
    """A table the command writes as JSON, as columns of its cells (None where null)."""
    rows = json.loads(path.read_text())["results"]
    return {name: [row[name] for row in rows] for name in (rows[0] if rows else {})}


def _same_column(ours, theirs):
    """A numpy column of ours equals the command's JSON cells (NaN for null)."""
    if ours.dtype == np.float64:
        expected = np.array([math.nan if v is None else v for v in theirs], dtype=np.float64)
        return np.array_equal(ours, expected, equal_nan=True)
    return ours.tolist() == theirs


@pytest.mark.parametrize("path", STRUCTURES, ids=_id)
def test_simulate_with_tables_is_the_commands(rattle_cli, tmp_path, path):
    omega = OMEGA[path]
    scene = rattle.Scene.from_file(path)
    ours = rattle.simulate(scene, omega, trajectory=True, samples_per_period=20)
    states, impacts = tmp_path / "states.json", tmp_path / "impacts.json"
    theirs = rattle_cli.json(
        "simulate", path, "--omega", omega, "--trajectory", states, "--impacts", impacts,
        "--samples-per-period", 20,
    )
    assert isinstance(ours, rattle.Simulation)
    assert ours.to_dict() == theirs
    assert ours.form == "structure"
    names = [b["name"] for b in json.loads(path.read_text())["structure"]["bodies"]]
    assert list(ours.to_dict()["body_amplitudes"]) == names
    # The tables: a column per body and per stop, the command's, cell for cell.
    stops = len(json.loads(path.read_text())["structure"]["stops"])
    assert list(ours.trajectory.columns) == (
        ["t", "kind", "base"] + [f"u_{n}" for n in names] + [f"v_{n}" for n in names]
        + [f"r_{k}" for k in range(stops)]
    )
    for ours_table, file in ((ours.trajectory, states), (ours.impact_table, impacts)):
        theirs_table = _table(file)
        if theirs_table:
            assert list(ours_table.columns) == list(theirs_table)
        assert len(ours_table) == len(json.loads(file.read_text())["results"])
        for name, column in theirs_table.items():
            assert _same_column(ours_table.columns[name], column), name
    assert ours.impact_table.columns["stop"].dtype == np.int64
    assert ours.trajectory.kind.dtype == object


def test_simulate_with_lyapunov_on_a_structure_is_the_commands(rattle_cli):
    scene = rattle.Scene.from_file(OSCILLATOR)
    ours = rattle.simulate(scene, 1.8, lyapunov=True, lyapunov_periods=50)
    theirs = rattle_cli.json(
        "simulate", OSCILLATOR, "--omega", 1.8, "--lyapunov", "--lyapunov-periods", 50
    )
    assert ours.to_dict() == theirs
    assert list(ours.to_dict()) == list(theirs)
    # Two exponents per body.
    assert len(ours.lyapunov_exponents) + ours.lyapunov_collapsed == 2


def test_simulate_on_a_structure_with_options_is_the_commands(rattle_cli):
    ours = rattle.simulate(rattle.Scene.from_file(ASYMMETRIC), 2.0, periods=30, tol=1e-10)
    theirs = rattle_cli.json(
        "simulate", ASYMMETRIC, "--omega", 2.0, "--periods", 30, "--tol", 1e-10
    )
    assert ours.to_dict() == theirs


@pytest.mark.parametrize(
    "path, omega, signature, period",
    [
        (OSCILLATOR, 1.8, "+", 1),
        (OSCILLATOR, 0.9, "0+", 2),
        (DAMPER, 1.0, "+-", 1),
        (DAMPER, 1.25, "0+ 0-", 1),
        (ASYMMETRIC, 3.0, "+-", 1),
    ],
)
def test_orbit_of_a_sequence_on_a_structure_is_the_commands(
    rattle_cli, path, omega, signature, period
):
    ours = rattle.orbit(rattle.Scene.from_file(path), omega, signature=signature, period=period)
    theirs = rattle_cli.json(
        "orbit", path, "--omega", omega, "--signature", signature, "--period", period
    )
    assert isinstance(ours, rattle.StructureOrbits)
    assert ours.to_dict() == theirs
    assert ours.sequence == theirs["sequence"]


def test_a_bad_sequence_on_a_structure_is_the_commands_error(rattle_cli):
    theirs = rattle_cli.error("orbit", OSCILLATOR, "--omega", 1.8, "--signature", "3+")
    with pytest.raises(ValueError) as ours:
        rattle.orbit(rattle.Scene.from_file(OSCILLATOR), 1.8, signature="3+")
    assert str(ours.value) == theirs.replace("--signature", "signature")


@pytest.mark.parametrize(
    "path, omega",
    [
        (OSCILLATOR, 1.8),
        (OSCILLATOR, 3.0),
        (DAMPER, 1.0),
        (DAMPER, 1.25),
        (ASYMMETRIC, 3.0),
        (ASYMMETRIC, 1.25),
    ],
)
def test_compare_on_a_structure_is_the_commands(rattle_cli, path, omega):
    ours = rattle.compare(rattle.Scene.from_file(path), omega)
    theirs = rattle_cli.json("compare", path, "--omega", omega)
    assert isinstance(ours, rattle.StructureComparison)
    assert ours.to_dict() == theirs
    assert ours.class_ == theirs["class"]


@pytest.mark.parametrize("path", STRUCTURES, ids=_id)
@pytest.mark.parametrize("solver, points", [("analytic", 30), ("event", 5), ("both", 4)])
def test_sweep_on_a_structure_is_the_commands(rattle_cli, tmp_path, path, solver, points):
    out = tmp_path / "sweep.json"
    code, _, err = rattle_cli.run(
        "sweep", path, "--omega-min", 0.5, "--omega-max", 3.0, "--points", points,
        "--solver", solver, "--out", out,
    )
    assert code == 0, err
    theirs = json.loads(out.read_text())
    scene = rattle.Scene.from_file(path)
    ours = rattle.sweep(scene, rattle.frequencies(0.5, 3.0, points), solver=solver)
    assert ours.to_dict() == theirs
    assert ours.document == out.read_text()
    assert (ours.form, ours.solver, ours.bodies, ours.observed, ours.points) == (
        "structure", solver, theirs["bodies"], theirs["observed"], points
    )
    assert ours.effects is None
    # The columns are the command's, in its order, with their cells.
    assert list(ours.columns) == list(theirs["results"][0])
    for name in ours.columns:
        assert _same_column(ours.columns[name], [r[name] for r in theirs["results"]]) or (
            ours.columns[name].dtype == bool
        ), name
    # Read back from the command's document: the same sweep.
    assert rattle.Sweep(out.read_text()) == ours
    assert list(rattle.Sweep(out.read_text()).columns) == list(ours.columns)
    # Every body's amplitude, one column per body.
    by_body = ours.body_amplitudes("linear_body_amplitudes")
    assert list(by_body) == theirs["bodies"]
    observed = by_body[theirs["observed"]]
    assert np.array_equal(observed, ours.linear_outer_amplitude, equal_nan=True)


def test_body_amplitudes_of_a_units_sweep_is_refused():
    ours = rattle.sweep(rattle.Scene.paper(), [2.0], solver="analytic")
    assert ours.form == "cells" and ours.bodies is None
    with pytest.raises(ValueError, match="Sweep.body_amplitudes"):
        ours.body_amplitudes()


#: Every call of the package that takes the unit and chain forms only, on a structure.
REFUSALS = {
    "rattle.orbit(signature=None)": lambda s: rattle.orbit(s, 1.8),
    "rattle.orbit_trajectory": lambda s: rattle.orbit_trajectory(s, 1.8, "+"),
    "rattle.continue_branch": lambda s: rattle.continue_branch(s, "+", 1.8, 1.0, 2.0),
    "rattle.boundary": lambda s: rattle.boundary(s, "+", "grazing", 1.8, "stops.gap", 0.1, 1.0),
    "rattle.basins": lambda s: rattle.basins(s, 1.8, points=2),
    "rattle.sweep(shard=...)": lambda s: rattle.sweep(s, [1.0, 2.0], shard=(1, 2)),
}


@pytest.mark.parametrize("call", sorted(REFUSALS))
def test_a_structure_is_refused_by_name(call):
    scene = rattle.Scene.from_file(OSCILLATOR)
    with pytest.raises(ValueError) as refused:
        REFUSALS[call](scene)
    message = str(refused.value)
    assert message.startswith(f"{call} does not take scene 'impact-oscillator'"), message
    assert "structure form" in message and "unit and chain forms" in message


@pytest.mark.parametrize(
    "args",
    [
        ["orbit", "--omega", 1.8],
        ["orbit", "--omega", 1.8, "--signature", "+", "--trajectory", "t.csv"],
        ["continue", "--signature", "+", "--omega", 1.8, "--omega-min", 1.0, "--omega-max", 2.0],
        ["sweep", "--omega-min", 1.0, "--omega-max", 2.0, "--points", 2, "--shard", "1/2",
         "--out", "s.json"],
    ],
    ids=lambda a: " ".join(map(str, a[:1] + a[-2:])),
)
def test_the_command_refuses_the_same_calls(rattle_cli, tmp_path, args):
    args = [tmp_path / a if isinstance(a, str) and "." in a else a for a in args]
    message = rattle_cli.error(args[0], OSCILLATOR, *args[1:])
    assert "structure form" in message, message
