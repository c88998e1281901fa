"""``rattle.map`` over two scene parameters (``x=``, ``y=``), on a structure and on a chain:
the command's ``rattle map --x PATH --y PATH`` file byte for byte, whole, in parts merged and
on a Dask cluster; its axes and columns; its refusals as the command's, named as here.

The Dask test needs ``dask`` and ``distributed`` and is skipped without them.
"""

import csv

import numpy as np
import pytest

import rattle
from conftest import SCENES

OSCILLATOR = SCENES / "impact-oscillator.json"
GRADED = SCENES / "paper-graded-4.json"

#: The impact oscillator over its stop's gap and restitution: 3 x 2 lines of 5 frequencies.
STRUCTURE = dict(
    x=("structure.stops[0].gap_plus", 0.2, 1.0, 3),
    y=("structure.stops[0].restitution", 0.5, 0.9, 2),
    omega=(0.6, 1.8, 5),
)
STRUCTURE_FLAGS = [
    "--x", "structure.stops[0].gap_plus", "--x-min", "0.2", "--x-max", "1.0", "--x-count", "3",
    "--y", "structure.stops[0].restitution", "--y-min", "0.5", "--y-max", "0.9", "--y-count", "2",
    "--omega-min", "0.6", "--omega-max", "1.8", "--points", "5",
]
#: A graded chain over one cell's gap and every cell's inner mass: 2 x 2 lines of 4 frequencies.
CHAIN = dict(
    x=("chain[2].stops.gap", 0.2, 0.6, 2),
    y=("unit.inner_mass", 0.9, 1.1, 2),
    omega=(1.5, 2.5, 4),
)
CHAIN_FLAGS = [
    "--x", "chain[2].stops.gap", "--x-min", "0.2", "--x-max", "0.6", "--x-count", "2",
    "--y", "unit.inner_mass", "--y-min", "0.9", "--y-max", "1.1", "--y-count", "2",
    "--omega-min", "1.5", "--omega-max", "2.5", "--points", "4",
]


def command_file(rattle_cli, path, *args):
    code, _, err = rattle_cli.run("map", *args, "--out", path)
    assert code == 0, err
    return path.read_text()


@pytest.fixture(scope="module")
def oscillator():
    return rattle.Scene.from_file(OSCILLATOR)


@pytest.mark.parametrize(
    "scene_file, kwargs, flags",
    [(OSCILLATOR, STRUCTURE, STRUCTURE_FLAGS), (GRADED, CHAIN, CHAIN_FLAGS)],
    ids=["structure", "chain"],
)
def test_a_map_over_two_parameters_is_the_commands_file(
    rattle_cli, tmp_path, scene_file, kwargs, flags
):
    m = rattle.map(rattle.Scene.from_file(scene_file), **kwargs)
    assert m.document == command_file(rattle_cli, tmp_path / "m.json", scene_file, *flags)
    rows = list(csv.reader(command_file(rattle_cli, tmp_path / "m.csv", scene_file, *flags).splitlines()))
    assert list(m.columns) == rows[0]
    assert rows[0][:3] == ["x", "y", "omega"]
    assert len(m) == len(rows) - 1
    for k, name in enumerate(rows[0][:3]):
        assert [float(r[k]) for r in rows[1:]] == m.columns[name].tolist(), name
    # The axes: the paths and the values of the grid, lines x-major.
    (x_path, *x), (y_path, *y) = kwargs["x"], kwargs["y"]
    assert (m.x_path, m.y_path) == (x_path, y_path)
    assert list(m.axes) == ["x", "y", "omega"]
    assert np.array_equal(m.axes["x"], rattle.frequencies(*x))
    assert np.array_equal(m.axes["y"], rattle.frequencies(*y))
    assert np.array_equal(np.unique(m.x), m.axes["x"]) and np.array_equal(np.unique(m.y), m.axes["y"])
    assert m.x[0] == m.axes["x"][0] and m.y[len(m.axes["omega"])] == m.axes["y"][1]


def test_a_structures_map_lists_every_body(oscillator):
    m = rattle.map(oscillator, **STRUCTURE)
    assert m.form == "structure" and m.bodies == ["x"] and m.observed == "x"
    assert "simulated_body_amplitudes" in m.columns
    assert "simulated_cell_outer_amplitudes" not in m.columns
    by_body = m.body_amplitudes()
    assert list(by_body) == ["x"]
    assert np.array_equal(by_body["x"], m.simulated_outer_amplitude, equal_nan=True)
    # The oscillator is forced, not base-driven: no transmittance, amplitudes only.
    assert np.isnan(m.simulated_transmittance_db).all()
    chain = rattle.map(rattle.Scene.from_file(GRADED), **CHAIN)
    assert chain.form == "cells" and "simulated_cell_outer_amplitudes" in chain.columns
    with pytest.raises(ValueError, match="Map.body_amplitudes"):
        chain.body_amplitudes()


def test_parts_of_a_map_over_two_parameters_merge_into_the_whole(oscillator):
    whole = rattle.map(oscillator, **STRUCTURE)
    for n in (2, 7):  # 7 parts of 6 lines: one part is empty
        parts = [rattle.map(oscillator, **STRUCTURE, shard=(k, n)) for k in range(n, 0, -1)]
        merged = rattle.merge(parts)
        assert merged == whole and merged.document == whole.document, n
        assert merged.x_path == whole.x_path
        empty = [p for p in parts if len(p) == 0]
        assert all(list(p.columns) == list(whole.columns) for p in empty)


def test_xarray_puts_a_map_over_two_parameters_on_x_and_y(oscillator):
    pytest.importorskip("xarray")
    m = rattle.map(oscillator, **STRUCTURE)
    ds = m.to_xarray()
    assert ds["simulated_outer_amplitude"].dims == ("x", "y", "omega")
    assert ds.attrs == {"x_path": m.x_path, "y_path": m.y_path}
    assert ds["simulated_outer_amplitude"].values[2, 1, 4] == m.simulated_outer_amplitude[-1]


@pytest.mark.parametrize(
    "kwargs, flags, names",
    [
        (
            dict(x=("structure.stops[0].gap_minus", 0.2, 1.0, 2), y=STRUCTURE["y"]),
            ["--x", "structure.stops[0].gap_minus", "--x-min", "0.2", "--x-max", "1",
             "--y", "structure.stops[0].restitution", "--y-min", "0.5", "--y-max", "0.9"],
            [("--x", "x[0]")],
        ),
        (
            dict(x=("structure.bodies[0].mass", 0.0, 1.0, 2), y=STRUCTURE["y"]),
            ["--x", "structure.bodies[0].mass", "--x-min", "0", "--x-max", "1",
             "--y", "structure.stops[0].restitution", "--y-min", "0.5", "--y-max", "0.9"],
            [("--x-min", "x[1]")],
        ),
        (
            dict(x=STRUCTURE["x"], y=("structure.stops[0].restitution", 0.5, 1.5, 2)),
            ["--x", "structure.stops[0].gap_plus", "--x-min", "0.2", "--x-max", "1",
             "--y", "structure.stops[0].restitution", "--y-min", "0.5", "--y-max", "1.5"],
            [("--y-max", "y[2]")],
        ),
        (
            dict(x=STRUCTURE["x"], y=("structure.stops[0].restitution", 0.5, 0.9, 0)),
            ["--x", "structure.stops[0].gap_plus", "--x-min", "0.2", "--x-max", "1",
             "--y", "structure.stops[0].restitution", "--y-min", "0.5", "--y-max", "0.9",
             "--y-count", "0"],
            [("--y-count", "y[3]")],
        ),
        (
            dict(x=STRUCTURE["x"], y=STRUCTURE["x"]),
            ["--x", "structure.stops[0].gap_plus", "--x-min", "0.2", "--x-max", "1",
             "--y", "structure.stops[0].gap_plus", "--y-min", "0.2", "--y-max", "1"],
            [("--y", "y[0]"), ("--x", "x[0]")],
        ),
        (
            dict(x=("stops.gap", 0.2, 1.0, 2), y=STRUCTURE["y"]),
            ["--x", "stops.gap", "--x-min", "0.2", "--x-max", "1",
             "--y", "structure.stops[0].restitution", "--y-min", "0.5", "--y-max", "0.9"],
            [("--x", "x[0]")],
        ),
        (
            dict(x=STRUCTURE["x"]),
            ["--x", "structure.stops[0].gap_plus", "--x-min", "0.2", "--x-max", "1"],
            [("--x PATH --y PATH", "x[0] PATH y[0] PATH"), ("--x", "x[0]"), ("--y", "y[0]")],
        ),
        (
            dict(x=STRUCTURE["x"], y=STRUCTURE["y"], restitution=(0.1, 0.2, 2)),
            ["--x", "structure.stops[0].gap_plus", "--x-min", "0.2", "--x-max", "1",
             "--y", "structure.stops[0].restitution", "--y-min", "0.5", "--y-max", "0.9",
             "--restitutions", "2"],
            [("--restitutions", "restitution"), ("--x and --y", "x and y")],
        ),
        (
            dict(),
            [],
            [("--x and --y", "x and y")],
        ),
    ],
    ids=["absent side", "mass 0", "restitution 1.5", "no values", "same path", "unit path",
         "x alone", "restitution with x", "no axes"],
)
def test_a_bad_parameter_axis_is_the_commands_value_error(
    rattle_cli, oscillator, kwargs, flags, names
):
    message = rattle_cli.error("map", OSCILLATOR, *flags, "--out", "never.csv")
    for option, name in names:
        message = message.replace(option, name)
    with pytest.raises(ValueError) as e:
        rattle.map(oscillator, **kwargs)
    assert str(e.value) == message


try:
    from distributed import Client, LocalCluster
except ImportError:  # pragma: no cover - the test below is skipped
    Client = None


@pytest.mark.skipif(Client is None, reason="dask.distributed is not installed")
def test_a_map_over_two_parameters_on_a_cluster_is_the_single_machine_one(oscillator):
    import os

    os.environ["RAYON_NUM_THREADS"] = "1"
    expected = rattle.map(oscillator, **STRUCTURE).document
    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=40
    ) as c, Client(c) as client:
        got = rattle.map(oscillator, **STRUCTURE, client=client, parts=3, progress=False)
        assert got.document == expected
        assert got.x_path == STRUCTURE["x"][0]
        with pytest.raises(ValueError, match=r"x\[1\]"):
            rattle.map(
                oscillator,
                x=("structure.stops[0].gap_plus", -1.0, 1.0, 2),
                y=STRUCTURE["y"],
                client=client,
            )
