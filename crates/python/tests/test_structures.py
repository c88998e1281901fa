"""Scenes in the structure form (bodies, springs, dashpots, stops, forcing) against the
`rattle` command's JSON for the same inputs: simulate (with its trajectory tables and
Lyapunov exponents), orbit with a signature, orbit_trajectory (with its tables), compare,
sweep (whole and in parts) and basins (over any two coordinates) give the command's documents,
and every other function refuses a structure with a ValueError naming it, as the command
refuses one."""

import csv
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
COMPLIANT = SCENES / "compliant-oscillator.json"
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


def test_a_poincare_section_is_the_commands(rattle_cli, tmp_path):
    scene = rattle.Scene.from_file(DAMPER)
    ours = rattle.simulate(
        scene, 1.0, trajectory=True, samples_per_period=1, sampled_periods=6
    )
    states, impacts = tmp_path / "states.json", tmp_path / "impacts.json"
    rattle_cli.json(
        "simulate", DAMPER, "--omega", 1.0, "--trajectory", states, "--impacts", impacts,
        "--samples-per-period", 1, "--sampled-periods", 6,
    )
    for ours_table, file in ((ours.trajectory, states), (ours.impact_table, impacts)):
        theirs_table = _table(file)
        for name, column in theirs_table.items():
            assert _same_column(ours_table.columns[name], column), name
    assert list(ours.trajectory.kind).count("sample") == 7
    with pytest.raises(ValueError, match="sampled_periods = 0"):
        rattle.simulate(scene, 1.0, trajectory=True, sampled_periods=0)


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


@pytest.mark.parametrize(
    "path, omega, signature, k",
    [(OSCILLATOR, 1.8, "+", 0), (OSCILLATOR, 1.8, "+", 1), (DAMPER, 1.0, "0+ 0-", 1),
     (ASYMMETRIC, 3.0, "+-", 0)],
)
def test_orbit_trajectory_on_a_structure_is_the_commands(
    rattle_cli, tmp_path, path, omega, signature, k
):
    states, impacts = tmp_path / "states.json", tmp_path / "impacts.json"
    theirs = rattle_cli.json(
        "orbit", path, "--omega", omega, "--signature", signature, "--orbit", k,
        "--trajectory", states, "--impacts", impacts, "--samples-per-period", 24,
    )
    scene = rattle.Scene.from_file(path)
    ours = rattle.orbit_trajectory(scene, omega, signature, orbit=k, samples_per_period=24)
    assert isinstance(ours.orbits, rattle.StructureOrbits)
    assert ours.orbits.to_dict() == theirs
    assert ours.orbit.to_dict() == theirs["orbits"][k] and ours.index == k
    assert repr(ours).startswith(f"OrbitCycle(signature={theirs['sequence']!r}")
    # The tables: the command's, cell for cell, with the columns of the simulated ones.
    simulated = rattle.simulate(scene, omega, trajectory=True, samples_per_period=4)
    assert list(ours.trajectory.columns) == list(simulated.trajectory.columns)
    assert list(ours.impact_table.columns) == list(simulated.impact_table.columns)
    for ours_table, file in ((ours.trajectory, states), (ours.impact_table, impacts)):
        theirs_table = _table(file)
        assert list(ours_table.columns) == list(theirs_table)
        for name, column in theirs_table.items():
            assert _same_column(ours_table.columns[name], column), name
    assert len(ours.trajectory) == 24 + 2 * len(ours.impact_table)
    with pytest.raises(ValueError, match=r"orbit = 9 is out of range: \d orbit\(s\) of "):
        rattle.orbit_trajectory(scene, omega, signature, orbit=9)


def test_a_structures_sweep_parts_merge_into_the_whole_sweep(rattle_cli, tmp_path):
    omegas = rattle.frequencies(0.5, 3.0, 5)
    scene = rattle.Scene.from_file(ASYMMETRIC)
    whole = rattle.sweep(scene, omegas, solver="event")
    parts = [rattle.sweep(scene, omegas, solver="event", shard=(k, 2)) for k in (2, 1)]
    assert [len(p) for p in parts] == [3, 2]
    merged = rattle.merge(parts)
    assert isinstance(merged, rattle.Sweep) and merged == whole
    assert merged.document == whole.document
    # Each part is the command's part, byte for byte.
    out = tmp_path / "part.json"
    code, _, err = rattle_cli.run(
        "sweep", ASYMMETRIC, "--omega-min", 0.5, "--omega-max", 3.0, "--points", 5,
        "--solver", "event", "--shard", "2/2", "--out", out,
    )
    assert code == 0, err
    assert parts[0].document == out.read_text()
    assert json.loads(parts[0].document)["shard"] == {"index": 2, "count": 2}


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
        (COMPLIANT, 0.8),
        (COMPLIANT, 1.2),
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


def test_continue_branch_on_a_structure_is_the_commands(rattle_cli):
    scene = rattle.Scene.from_file(OSCILLATOR)
    ours = rattle.continue_branch(scene, "+", 1.8, 1.2, 2.5, orbit=0, switch=False)
    theirs = rattle_cli.json(
        "continue", OSCILLATOR, "--signature", "+", "--omega", 1.8, "--omega-min", 1.2,
        "--omega-max", 2.5, "--orbit", 0, "--no-switch",
    )
    assert ours.to_dict() == theirs
    assert ours.signature == "0+"
    by_body = ours.body_amplitudes()
    assert list(by_body) == ["x"]
    assert np.array_equal(
        by_body["x"], ours.points_columns()["outer_amplitude"], equal_nan=True
    )
    with pytest.raises(ValueError, match="Continuation.body_amplitudes"):
        rattle.continue_branch(
            rattle.Scene.paper(), "+-", 2.0, 1.9, 2.1, orbit=0, switch=False, max_branches=1
        ).body_amplitudes()


def test_boundary_on_a_structure_is_the_commands(rattle_cli):
    scene = rattle.Scene.from_file(OSCILLATOR)
    path = "structure.stops[0].gap_plus"
    ours = rattle.boundary(
        scene, "+", "fold", 1.85, path, 0.4, 0.6, at=[0.5], omega_min=1.0, omega_max=2.6
    )
    theirs = rattle_cli.json(
        "boundary", OSCILLATOR, "--signature", "+", "--event", "fold", "--omega", 1.85,
        "--param", path, "--min", 0.4, "--max", 0.6, "--at", 0.5, "--omega-min", 1.0,
        "--omega-max", 2.6,
    )
    assert ours.to_dict() == theirs
    assert theirs["param"] == path and theirs["at"]
    with pytest.raises(ValueError, match=r"param.*structure\.stops\[K\]\.gap_plus"):
        rattle.boundary(scene, "+", "fold", 1.85, "stops.gap", 0.4, 0.6)


#: Basins of structures on small grids, as `rattle basins SCENE --omega W --x … --out F`: the
#: impact damper's free body against its primary's displacement (the clearance ±0.8 holds the
#: starts with the ball at ±0.55 inside, the others run), and the impact oscillator's
#: displacement against its velocity (a start beyond the stop at 0.5 is not run).
BASINS = [
    (
        DAMPER, 0.7,
        dict(x="u:primary", x_min=-0.2, x_max=0.2, y="u:ball", y_min=-0.55, y_max=0.55, points=3),
    ),
    (OSCILLATOR, 1.8, dict(x="u:x", x_min=-0.5, x_max=0.6, y="v:x", y_min=-0.5, y_max=0.5, points=3)),
]


def _basins_flags(kwargs):
    """The command's flags for the keyword arguments of `rattle.basins`."""
    flags = []
    for name, value in kwargs.items():
        flags += [f"--{name.replace('_', '-')}", value]
    return flags


@pytest.mark.parametrize("path, omega, kwargs", BASINS, ids=lambda v: getattr(v, "stem", None))
def test_basins_on_a_structure_is_the_commands(rattle_cli, tmp_path, path, omega, kwargs):
    scene = rattle.Scene.from_file(path)
    ours = rattle.basins(scene, omega, **kwargs)
    for ext in ("json", "csv"):
        out = tmp_path / f"basins.{ext}"
        code, _, err = rattle_cli.run(
            "basins", path, "--omega", omega, *_basins_flags(kwargs), "--out", out
        )
        assert code == 0, err
        if ext == "json":
            assert ours.document == out.read_text()
            continue
        # The columns are the command's CSV columns, named by the coordinates, cell for cell.
        header, *rows = list(csv.reader(out.read_text().splitlines()))
        assert list(ours.columns) == header
        assert len(ours) == kwargs["points"] ** 2 == len(rows)
        for k, name in enumerate(header):
            column = ours.columns[name]
            for row, value in zip(rows, column):
                cell = row[k]
                if column.dtype == np.float64:
                    assert (math.isnan(value) and cell == "") or float(cell) == value, name
                elif column.dtype == np.int64:
                    assert int(cell) == value, name
                else:
                    assert cell == ("" if value is None else value), name
    names = [b["name"] for b in json.loads(path.read_text())["structure"]["bodies"]]
    assert list(ours.columns)[-1] == "body_amplitudes"
    assert all(
        a is None or len(a.split(";")) == len(names) for a in ours.body_amplitudes
    )
    # In parts, merged: the whole grid, byte for byte.
    parts = [rattle.basins(scene, omega, **kwargs, shard=(k, 2)) for k in (2, 1)]
    merged = rattle.merge(parts)
    assert isinstance(merged, rattle.Basins) and merged == ours
    assert list(merged.columns) == list(ours.columns)


def test_a_structures_basins_go_on_their_coordinates_axes():
    pytest.importorskip("xarray")
    path, omega, kwargs = BASINS[1]
    ds = rattle.basins(rattle.Scene.from_file(path), omega, **kwargs).to_xarray()
    assert ds["attractor"].dims == ("x_start", "x_velocity_start")
    assert ds["x_start"].values[[0, -1]].tolist() == [kwargs["x_min"], kwargs["x_max"]]
    assert ds["x_velocity_start"].values[[0, -1]].tolist() == [kwargs["y_min"], kwargs["y_max"]]


@pytest.mark.parametrize(
    "kwargs, flags",
    [
        (dict(points=2), ["--points", "2"]),
        (dict(x="u:x", points=2), ["--x", "u:x", "--points", "2"]),
        (dict(x="u:wall", y="v:x", points=2), ["--x", "u:wall", "--y", "v:x", "--points", "2"]),
        (dict(x="u:x", y="u:x", points=2), ["--x", "u:x", "--y", "u:x", "--points", "2"]),
        (dict(x="u:x", y="v:x", x_min=1.0, x_max=-1.0, points=2),
         ["--x", "u:x", "--y", "v:x", "--x-min", "1", "--x-max", "-1", "--points", "2"]),
        (dict(outer=(-1.0, 1.0), points=2), ["--outer-min", "-1", "--outer-max", "1", "--points", "2"]),
        (dict(x="u:x", y="v:x", points=0), ["--x", "u:x", "--y", "v:x", "--points", "0"]),
    ],
)
def test_a_bad_basins_request_on_a_structure_is_the_commands_error(rattle_cli, kwargs, flags):
    message = rattle_cli.error("basins", OSCILLATOR, "--omega", 1.8, *flags, "--out", "never.csv")
    for option, name in [
        ("--outer-min/--outer-max/--inner-min/--inner-max", "outer/inner"),
        ("--x-min", "x_min"), ("--x-max", "x_max"), ("--x and --y", "x and y"),
        ("--x", "x"), ("--y", "y"), ("--points", "points"),
    ]:
        message = message.replace(option, name)
    with pytest.raises(ValueError) as e:
        rattle.basins(rattle.Scene.from_file(OSCILLATOR), 1.8, **kwargs)
    assert str(e.value) == message


def test_basins_mixing_the_default_plane_and_named_axes_is_the_commands_error(rattle_cli):
    message = rattle_cli.error(
        "basins", "--omega", 1.9, "--outer-min", -1, "--x", "u:outer", "--out", "never.csv"
    )
    with pytest.raises(ValueError) as e:
        rattle.basins(rattle.Scene.paper(), 1.9, outer=(-1.0, 2.0), x="u:outer", points=2)
    assert str(e.value) == (
        message.replace("--outer-min/--outer-max/--inner-min/--inner-max", "outer/inner")
        .replace("--x-min/--x-max/--y-min/--y-max", "x_min/x_max/y_min/y_max")
        .replace("--x/--y", "x/y")
    )


def test_basins_on_the_units_named_plane_is_its_default_plane():
    """`x="u:outer", y="u:inner"` on the unit is its default plane, byte for byte."""
    default = rattle.basins(rattle.Scene.paper(), 1.9, outer=(-1.0, 1.0), inner=(-1.0, 1.0), points=3)
    named = rattle.basins(
        rattle.Scene.paper(), 1.9, x="u:outer", y="u:inner", x_min=-1.0, x_max=1.0,
        y_min=-1.0, y_max=1.0, points=3,
    )
    assert named == default
    assert list(named.columns)[:2] == ["outer_start", "inner_start"]


#: Every call of the package that takes the unit and chain forms only, on a structure.
REFUSALS = {
    "rattle.orbit(signature=None)": lambda s: rattle.orbit(s, 1.8),
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
    ],
    ids=lambda a: " ".join(map(str, a[:1] + a[-2:])),
)
def test_the_command_refuses_the_same_calls(rattle_cli, tmp_path, args):
    args = [tmp_path / a if isinstance(a, str) and "." in a else a for a in args]
    message = rattle_cli.error(args[0], OSCILLATOR, *args[1:])
    assert "structure form" in message, message


HARMONICS = SCENES / "paper-two-harmonics.json"


def test_a_unit_with_base_harmonics_runs_as_its_structure(rattle_cli):
    document = json.loads(HARMONICS.read_text())
    scene = rattle.Scene.from_file(HARMONICS)
    assert scene.form == "structure"
    assert rattle.Scene.from_dict(document) == scene
    assert "harmonics" in scene.effects
    ours = rattle.compare(scene, 2.2)
    theirs = rattle_cli.json("compare", HARMONICS, "--omega", 2.2)
    assert ours.to_dict() == theirs
    assert theirs["class"] == "agreement"
    assert [h["order"] for h in theirs["harmonics"]] == [2, 3]


def test_a_harmonics_bad_value_is_named_by_its_path():
    document = json.loads(HARMONICS.read_text())
    document["base"]["harmonics"][1]["amplitude"] = math.nan
    with pytest.raises(ValueError, match=r"dict: base\.harmonics\[1\]\.amplitude: NaN"):
        rattle.Scene.from_dict(document)
    document["base"]["harmonics"][1]["amplitude"] = 0.1
    document["base"]["harmonics"][1]["order"] = 1
    with pytest.raises(ValueError, match=r"base\.harmonics\[1\]\.order: 1 is out of range"):
        rattle.Scene.from_dict(document)
    oscillator = json.loads(OSCILLATOR.read_text())
    oscillator["forcing"]["forces"][0]["harmonics"] = [{"order": 2, "amplitude": math.inf}]
    with pytest.raises(
        ValueError, match=r"forcing\.forces\[0\]\.harmonics\[0\]\.amplitude: inf"
    ):
        rattle.Scene.from_dict(oscillator)


def test_a_compliant_stops_contacts_are_the_commands_and_in_agreement(rattle_cli):
    scene = rattle.Scene.from_file(COMPLIANT)
    ours = rattle.compare(scene, 1.2)
    assert ours.class_ == "agreement"
    assert ours.simulated.pair_signatures == ["+c"]
    assert ours.simulated.contacts_per_period == 1.0
    assert ours.analytic.sequence == "0+c"
    simulated = rattle.simulate(scene, 1.2)
    assert simulated.to_dict() == rattle_cli.json("simulate", COMPLIANT, "--omega", 1.2)
    assert simulated.contact_time_per_period > 0
    orbits = rattle.orbit(scene, 1.2, signature="0+c")
    assert orbits.to_dict() == rattle_cli.json(
        "orbit", COMPLIANT, "--omega", 1.2, "--signature", "0+c"
    )
