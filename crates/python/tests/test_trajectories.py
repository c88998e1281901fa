"""Trajectories (`simulate(..., trajectory=True)`, `orbit_trajectory`) against the files
`rattle simulate/orbit --trajectory F.csv --impacts I.csv` writes, value for value, and the
physics every sampled cycle must obey on the paper scene (gap 0.5, restitution 0.8): the
relative displacement stays within the stops, and each impact reverses the relative velocity
scaled by the restitution."""

import csv
import json

import numpy as np
import pytest
import rattle

#: The paper scene's stops (`Scene.paper()`, `data/scenes/paper.json`).
GAP = 0.5
RESTITUTION = 0.8

TRAJECTORY_COLUMNS = ["t", "kind", "cell", "base", "u_o", "u_i", "v_o", "v_i", "r"]
IMPACT_COLUMNS = [
    "t", "pair", "side", "relative_velocity_before", "u_o", "u_i", "v_o_before", "v_i_before",
]

#: The options of the command named as this module's parameters, for its messages.
PYTHON_NAMES = [
    ("--samples-per-period", "samples_per_period"),
    ("--orbit", "orbit"),
    ("--max-step", "max_step"),
    ("--max-branches", "max_branches"),
    ("--omega-min", "omega_min"),
    ("--omega-max", "omega_max"),
    ("--omega", "omega"),
]


def python_names(message):
    for option, parameter in PYTHON_NAMES:
        message = message.replace(option, parameter)
    return message


def read_csv(path):
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = list(reader)
    return header, rows


def assert_table_is_the_files(table, path, columns, words):
    """Each column of `table` equals the file's, as float64 (empty cell: NaN), int or str."""
    header, rows = read_csv(path)
    assert header == columns == list(table.columns)
    assert len(table) == len(rows) > 0
    for k, name in enumerate(header):
        column = table.columns[name]
        assert column.shape == (len(rows),)
        cells = [row[k] for row in rows]
        if name in words:
            assert column.dtype == object
            assert list(column) == cells
        elif name in ("side", "pair", "cell"):
            assert column.dtype == np.int64
            assert column.tolist() == [int(c) for c in cells]
        else:
            assert column.dtype == np.float64
            expected = np.array([float(c) if c else np.nan for c in cells])
            np.testing.assert_array_equal(column, expected)


def assert_physical(table, impacts, slack):
    """|r| ≤ gap + `slack` on every row, and ṙ⁺ = −e ṙ⁻ on every impact (to rounding)."""
    relative_velocity = table.v_i - table.v_o
    speed = np.max(np.abs(relative_velocity))
    assert np.all(np.abs(table.r) <= GAP + slack)
    np.testing.assert_array_equal(table.r, table.u_i - table.u_o)
    before = np.flatnonzero(table.kind == "before_impact")
    after = np.flatnonzero(table.kind == "after_impact")
    assert len(before) == len(after) == len(impacts) > 0
    np.testing.assert_array_equal(after, before + 1)
    np.testing.assert_array_equal(table.t[before], impacts.t)
    np.testing.assert_array_equal(relative_velocity[before], impacts.relative_velocity_before)
    expected_after = -RESTITUTION * impacts.relative_velocity_before
    # Rounding only: the jump is applied to the velocities, whose difference is taken here.
    np.testing.assert_allclose(relative_velocity[after], expected_after, rtol=0, atol=1e-12 * speed)
    np.testing.assert_allclose(np.abs(impacts.u_i - impacts.u_o), GAP, rtol=1e-9)
    sides = np.where(impacts.u_i - impacts.u_o > 0, 1, 2)
    np.testing.assert_array_equal(impacts.side, sides)


@pytest.mark.parametrize("omega, periods", [(2.0, None), (2.0, 50), (3.5, None)])
def test_simulated_trajectory_is_the_commands(rattle_cli, tmp_path, omega, periods):
    fixed = [] if periods is None else ["--periods", periods]
    samples = 50
    f, i = tmp_path / "f.csv", tmp_path / "i.csv"
    theirs = rattle_cli.json(
        "simulate", "--omega", omega, *fixed, "--trajectory", f, "--impacts", i,
        "--samples-per-period", samples,
    )
    ours = rattle.simulate(
        rattle.Scene.paper(), omega, periods=periods, trajectory=True, samples_per_period=samples
    )
    assert ours.to_dict() == theirs
    assert_table_is_the_files(ours.trajectory, f, TRAJECTORY_COLUMNS, {"kind"})
    assert_table_is_the_files(ours.impact_table, i, IMPACT_COLUMNS, set())
    if ours.period is not None:
        # A periodic cycle, both its ends sampled.
        assert int(np.sum(ours.trajectory.kind == "sample")) == samples * ours.period + 1


def test_simulated_trajectory_obeys_stops_and_restitution():
    sim = rattle.simulate(rattle.Scene.paper(), 2.0, trajectory=True)
    assert sim.regime is not None and sim.impacts_per_period > 0
    assert int(np.sum(sim.trajectory.kind == "sample")) == rattle.SAMPLES_PER_PERIOD + 1
    # Contact times are found to the relative tolerance `tol`: r may pass the stop by at most
    # that error in time (relative to the cycle's end time) times the largest relative speed.
    t = sim.trajectory
    slack = rattle.DEFAULTS["tol"] * t.t[-1] * np.max(np.abs(t.v_i - t.v_o))
    assert_physical(t, sim.impact_table, slack)
    assert not sim.trajectory.t.flags.writeable


def test_without_trajectory_there_is_none():
    sim = rattle.simulate(rattle.Scene.paper(), 2.0)
    assert sim.trajectory is None and sim.impact_table is None


#: At ω = 2 the paper scene has 8 orbits of `+-`; the 8th (index 7) is the viable, stable
#: symmetric one (`rattle orbit --omega 2 --signature +-`), index 2 a non-viable one.
@pytest.mark.parametrize("signature, period, omega, k", [("+-", 1, 2.0, 7), ("+-", 1, 2.0, 2),
                                                          ("++--", 2, 1.2, 0)])
def test_orbit_trajectory_is_the_commands(rattle_cli, tmp_path, signature, period, omega, k):
    f, i = tmp_path / "f.csv", tmp_path / "i.csv"
    theirs = rattle_cli.json(
        "orbit", "--omega", omega, "--signature", signature, "--period", period,
        "--orbit", k, "--trajectory", f, "--impacts", i, "--samples-per-period", 64,
    )
    ours = rattle.orbit_trajectory(
        rattle.Scene.paper(), omega, signature, period=period, orbit=k, samples_per_period=64
    )
    assert ours.orbits.to_dict() == theirs
    assert ours.orbit.to_dict() == theirs["orbits"][k] and ours.index == k
    assert_table_is_the_files(ours.trajectory, f, TRAJECTORY_COLUMNS, {"kind"})
    assert_table_is_the_files(ours.impact_table, i, IMPACT_COLUMNS, set())


#: Two of the paper's cells in series, undamped: the sequence `0+ 1- 0- 1+` has a viable orbit
#: at ω = 3.3 (`rattle orbit CHAIN --omega 3.3 --signature "0+ 1- 0- 1+"`).
TWO_CELLS = {
    "name": "two",
    "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0,
             "inner_stiffness": 3.0},
    "base": {"amplitude": 1.0},
    "stops": {"gap": GAP, "restitution": RESTITUTION},
    "cells": 2,
}


def test_a_chains_orbit_trajectory_is_the_commands(rattle_cli, tmp_path):
    path = tmp_path / "two.json"
    path.write_text(json.dumps(TWO_CELLS))
    f, i = tmp_path / "f.csv", tmp_path / "i.csv"
    theirs = rattle_cli.json(
        "orbit", path, "--omega", 3.3, "--signature", "0+ 1- 0- 1+", "--orbit", 0,
        "--trajectory", f, "--impacts", i, "--samples-per-period", 64,
    )
    ours = rattle.orbit_trajectory(
        rattle.Scene.from_dict(TWO_CELLS), 3.3, "0+ 1- 0- 1+", orbit=0, samples_per_period=64
    )
    assert isinstance(ours.orbits, rattle.ChainOrbits)
    assert ours.orbits.to_dict() == theirs
    assert_table_is_the_files(ours.trajectory, f, TRAJECTORY_COLUMNS, {"kind"})
    assert_table_is_the_files(ours.impact_table, i, IMPACT_COLUMNS, set())
    t = ours.trajectory
    assert sorted(set(t.cell.tolist())) == [0, 1]
    assert sorted(set(ours.impact_table.pair.tolist())) == [0, 1]
    # Within the stops (the closed form reaches the gap up to rounding) on every cell.
    assert np.all(np.abs(t.r) <= GAP * (1 + 1e-9))
    with pytest.raises(ValueError, match="orbit = 5 is out of range"):
        rattle.orbit_trajectory(rattle.Scene.from_dict(TWO_CELLS), 3.3, "0+ 1- 0- 1+", orbit=5)


def test_viable_orbit_obeys_stops_and_restitution():
    cycle = rattle.orbit_trajectory(rattle.Scene.paper(), 2.0, "+-", orbit=7)
    assert cycle.orbit.viable
    # The closed form at the solved impact times: r = u_i − u_o reaches the gap up to the
    # rounding of a few modal terms per coordinate, 16 ulps of the largest displacement.
    t = cycle.trajectory
    slack = 16 * np.finfo(np.float64).eps * max(np.max(np.abs(t.u_o)), np.max(np.abs(t.u_i)))
    assert_physical(t, cycle.impact_table, slack)


def test_simulated_and_analytic_cycles_share_the_columns():
    scene = rattle.Scene.paper()
    sim = rattle.simulate(scene, 2.0, trajectory=True)
    cycle = rattle.orbit_trajectory(scene, 2.0, sim.signature, orbit=7)
    assert list(sim.trajectory.columns) == list(cycle.trajectory.columns)
    assert list(sim.impact_table.columns) == list(cycle.impact_table.columns)


@pytest.mark.parametrize("samples", [0, -3, 100001])
def test_bad_samples_per_period_is_the_commands_message(rattle_cli, tmp_path, samples):
    f = tmp_path / "f.csv"
    scene = rattle.Scene.paper()
    if samples >= 0:  # the command's parser refuses a negative count before it runs
        theirs = rattle_cli.error(
            "simulate", "--omega", 2.0, "--trajectory", f, f"--samples-per-period={samples}"
        )
        with pytest.raises(ValueError) as e:
            rattle.simulate(scene, 2.0, trajectory=True, samples_per_period=samples)
        assert str(e.value) == python_names(theirs)
    with pytest.raises(ValueError, match="samples_per_period = .* is out of range"):
        rattle.simulate(scene, 2.0, trajectory=True, samples_per_period=samples)
    with pytest.raises(ValueError, match="samples_per_period = .* is out of range"):
        rattle.orbit_trajectory(scene, 2.0, "+-", samples_per_period=samples)


def test_bad_orbit_index_is_the_commands_message(rattle_cli, tmp_path):
    theirs = rattle_cli.error(
        "orbit", "--omega", 2.0, "--signature", "+-", "--orbit", 8, "--trajectory",
        tmp_path / "f.csv",
    )
    with pytest.raises(ValueError) as e:
        rattle.orbit_trajectory(rattle.Scene.paper(), 2.0, "+-", orbit=8)
    assert str(e.value) == python_names(theirs)
    with pytest.raises(ValueError, match="orbit = -1 is out of range"):
        rattle.orbit_trajectory(rattle.Scene.paper(), 2.0, "+-", orbit=-1)


def test_orbit_trajectory_bad_signature_and_scene():
    with pytest.raises(ValueError, match="signature"):
        rattle.orbit_trajectory(rattle.Scene.paper(), 2.0, "+x")
    with pytest.raises(ValueError, match="period"):
        rattle.orbit_trajectory(rattle.Scene.paper(), 2.0, "+-", period=9)
    free = rattle.Scene.from_dict({k: v for k, v in rattle.Scene.paper().to_dict().items()
                                   if k != "stops"})
    with pytest.raises(ValueError, match="no `stops`"):
        rattle.orbit_trajectory(free, 2.0, "+-")
