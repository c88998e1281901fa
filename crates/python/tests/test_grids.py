"""Maps and basins from Python: the command's files byte for byte, whole, in parts merged, and
on a Dask cluster of 1, 2 and 3 workers, also when a worker is killed mid-run.

The Dask tests need `dask` and `distributed` and are skipped without them.
"""

import csv
import math
import os
import signal
import threading
import time

import numpy as np
import pytest

import rattle
from conftest import SCENES

DAMPED = SCENES / "paper-damped.json"
# A small map: 2 x 3 lines of 6 frequencies around the paper's bands.
MAP = dict(restitution=(0.2, 0.9, 2), gap=(0.1, 0.8, 3), omega=(1.5, 2.5, 6))
MAP_FLAGS = [
    "--restitution-min", "0.2", "--restitution-max", "0.9", "--restitutions", "2",
    "--gap-min", "0.1", "--gap-max", "0.8", "--gaps", "3",
    "--omega-min", "1.5", "--omega-max", "2.5", "--points", "6",
]
# Basins at ω = 1.9 rad/s over ±4 m: `not periodic` first, then `++--` (two attractors, so a
# part's own numbering differs from the whole grid's).
BASINS = dict(omega=1.9, outer=(-4.0, 4.0), inner=(-4.0, 4.0), points=6)
BASINS_FLAGS = [
    "--omega", "1.9", "--outer-min", "-4", "--outer-max", "4",
    "--inner-min", "-4", "--inner-max", "4", "--points", "6",
]


def command_file(rattle_cli, tmp_path, name, *args):
    out = tmp_path / name
    code, _, err = rattle_cli.run(*args, "--out", out)
    assert code == 0, err
    return out.read_text()


@pytest.fixture(scope="module")
def damped():
    return rattle.Scene.from_file(DAMPED)


@pytest.fixture(scope="module")
def map_file(rattle_cli, tmp_path_factory):
    d = tmp_path_factory.mktemp("map")
    return (
        command_file(rattle_cli, d, "m.json", "map", DAMPED, *MAP_FLAGS),
        command_file(rattle_cli, d, "m.csv", "map", DAMPED, *MAP_FLAGS),
    )


@pytest.fixture(scope="module")
def basins_file(rattle_cli, tmp_path_factory):
    d = tmp_path_factory.mktemp("basins")
    return command_file(rattle_cli, d, "b.json", "basins", *BASINS_FLAGS)


def test_the_map_is_the_commands_file_and_its_columns(damped, map_file):
    m = rattle.map(damped, **MAP)
    assert m.document == map_file[0]
    rows = list(csv.reader(map_file[1].splitlines()))
    assert list(m.columns) == rows[0]
    assert len(m) == 2 * 3 * 6 == len(rows) - 1
    for k, name in enumerate(rows[0]):
        column = m.columns[name]
        for row, value in zip(rows[1:], column):
            cell = row[k]
            if column.dtype == np.float64:
                assert (math.isnan(value) and cell == "") or float(cell) == value, name
            elif column.dtype == bool:
                assert cell == ("true" if value else "false"), name
            elif column.dtype == np.int64:
                assert int(cell) == value, name
            else:
                assert cell == ("" if value is None else value), name


def test_map_parts_merge_into_the_whole_map(damped, map_file):
    for n in (1, 2, 4, 7):  # 7 parts of 6 lines: one part is empty
        parts = [rattle.map(damped, **MAP, shard=(k, n)) for k in range(n, 0, -1)]
        assert all(p.shard == (k, n) for p, k in zip(parts, range(n, 0, -1)))
        assert rattle.merge(parts).document == map_file[0], n


def test_basins_parts_merge_into_the_whole_grid(basins_file):
    b = rattle.basins(rattle.Scene.paper(), **BASINS)
    assert b.document == basins_file
    assert set(b.attractor) == {0, 1}
    for n in (2, 3, 37):  # 37 parts of 36 starts: one part is empty
        parts = [rattle.basins(rattle.Scene.paper(), **BASINS, shard=(k, n)) for k in range(1, n + 1)]
        assert rattle.merge(parts[::-1]).document == basins_file, n


def test_a_chains_basins_are_the_commands_file(rattle_cli, tmp_path):
    """A chain has no default plane: `x` and `y` name two of its coordinates, as `--x`/`--y`."""
    chain = SCENES / "paper-chain-5.json"
    out = tmp_path / "chain.json"
    code, _, err = rattle_cli.run(
        "basins", chain, "--omega", 1.9, "--x", "u:outer0", "--y", "v:inner1", "--points", 2,
        "--out", out,
    )
    assert code == 0, err
    ours = rattle.basins(rattle.Scene.from_file(chain), 1.9, x="u:outer0", y="v:inner1", points=2)
    assert ours.document == out.read_text()
    assert list(ours.columns)[:2] == ["outer0_start", "inner1_velocity_start"]
    with pytest.raises(ValueError, match=r"^x is required on a chain or a structure: one of u:outer0"):
        rattle.basins(rattle.Scene.from_file(chain), 1.9, points=2)


def test_sweep_parts_merge_into_the_whole_sweep():
    omegas = rattle.frequencies(0.5, 3.5, 30)
    whole = rattle.sweep(rattle.Scene.paper(), omegas, solver="analytic")
    parts = [rattle.sweep(rattle.Scene.paper(), omegas, "analytic", shard=(k, 4)) for k in (1, 2, 3, 4)]
    assert rattle.merge(parts).document == whole.document
    with pytest.raises(ValueError, match="need each of"):
        rattle.merge(parts[1:])


def assert_same_result(merged, whole, kind):
    """``merged`` is a ``kind`` equal to ``whole``: its document byte for byte, its columns
    value for value and type for type."""
    assert type(merged) is kind
    assert merged == whole
    assert merged.document == whole.document
    assert list(merged.columns) == list(whole.columns)
    for name, column in whole.columns.items():
        assert merged.columns[name].dtype == column.dtype, name
        assert not merged.columns[name].flags.writeable, name
        np.testing.assert_array_equal(merged.columns[name], column, err_msg=name)


def test_merged_map_parts_are_a_map_equal_to_the_whole(damped):
    whole = rattle.map(damped, **MAP)
    parts = [rattle.map(damped, **MAP, shard=(k, 2)) for k in (2, 1)]
    merged = rattle.merge(parts)
    assert_same_result(merged, whole, rattle.Map)
    assert merged.shard is None and merged.scene == whole.scene
    # Documents merge into a document, as before.
    assert rattle.merge([p.document for p in parts]) == whole.document
    # An empty part's columns have the whole map's types (7 parts of 6 lines: one is empty).
    sevenths = [rattle.map(damped, **MAP, shard=(k, 7)) for k in range(1, 8)]
    empty = next(p for p in sevenths if len(p) == 0)
    assert [c.dtype for c in empty.columns.values()] == [c.dtype for c in whole.columns.values()]


def test_merged_basins_parts_are_basins_equal_to_the_whole():
    whole = rattle.basins(rattle.Scene.paper(), **BASINS)
    parts = [rattle.basins(rattle.Scene.paper(), **BASINS, shard=(k, 2)) for k in (1, 2)]
    merged = rattle.merge(parts)
    assert_same_result(merged, whole, rattle.Basins)
    assert set(merged.attractor) == {0, 1}
    assert rattle.merge([p.document for p in parts]) == whole.document


def test_merged_sweep_parts_are_a_sweep_equal_to_the_whole():
    omegas = rattle.frequencies(0.5, 3.5, 5)
    whole = rattle.sweep(rattle.Scene.paper(), omegas, solver="both")
    parts = [rattle.sweep(rattle.Scene.paper(), omegas, "both", shard=(k, 2)) for k in (2, 1)]
    merged = rattle.merge(parts)
    assert_same_result(merged, whole, rattle.Sweep)
    assert len(merged) == len(whole) == 5
    assert (merged.scene, merged.solver, merged.effects, merged.points) == (
        whole.scene, whole.solver, whole.effects, whole.points
    )
    assert merged.to_dict() == whole.to_dict()
    assert rattle.merge([p.document for p in parts]) == whole.document


def test_a_sweep_read_from_its_document_has_the_same_column_types():
    for solver, omegas in [("analytic", []), ("event", [1.0, 2.0])]:
        native = rattle.sweep(rattle.Scene.paper(), omegas, solver=solver)
        assert_same_result(rattle.Sweep(native.document), native, rattle.Sweep)


def test_xarray_puts_the_columns_on_the_grids_axes(damped):
    xarray = pytest.importorskip("xarray")
    m = rattle.map(damped, **MAP)
    ds = m.to_xarray()
    assert isinstance(ds, xarray.Dataset)
    assert ds["simulated_transmittance_db"].dims == ("restitution", "gap_over_base_amplitude", "omega")
    assert np.array_equal(ds["omega"].values, rattle.frequencies(1.5, 2.5, 6))
    assert ds["simulated_transmittance_db"].values[1, 2, 5] == m.simulated_transmittance_db[-1]
    b = rattle.basins(rattle.Scene.paper(), **BASINS).to_xarray()
    assert b["attractor"].shape == (6, 6)
    assert b["outer_start"].values[[0, -1]].tolist() == [-4.0, 4.0]
    assert b["inner_start"].values[[0, -1]].tolist() == [-4.0, 4.0]


@pytest.mark.parametrize(
    "kwargs, flags, names",
    [
        (dict(restitution=(0.2, 0.9, 0)), ["--restitutions", "0"], [("--restitutions", "restitution[2]")]),
        (dict(gap=(-1.0, 0.8, 3)), ["--gap-min=-1"], [("--gap-min", "gap[0]")]),
        (dict(omega=(2.0, 1.0, 3)), ["--omega-min", "2", "--omega-max", "1"], [("--omega-max", "omega[1]")]),
    ],
)
def test_a_bad_map_is_the_commands_value_error(rattle_cli, damped, kwargs, flags, names):
    message = rattle_cli.error("map", DAMPED, *flags, "--out", "never.csv")
    for option, name in names:
        message = message.replace(option, name)
    with pytest.raises(ValueError) as e:
        rattle.map(damped, **kwargs)
    assert str(e.value) == message


@pytest.mark.parametrize(
    "kwargs, flags, names",
    [
        (dict(points=0), ["--points", "0"], [("--points", "points")]),
        (dict(outer=(1.0, -1.0)), ["--outer-min", "1", "--outer-max", "-1"], [("--outer-min", "outer[0]"), ("--outer-max", "outer[1]")]),
    ],
)
def test_a_bad_basins_grid_is_the_commands_value_error(rattle_cli, kwargs, flags, names):
    message = rattle_cli.error("basins", "--omega", "1.9", *flags, "--out", "never.csv")
    for option, name in names:
        message = message.replace(option, name)
    with pytest.raises(ValueError) as e:
        rattle.basins(rattle.Scene.paper(), 1.9, **kwargs)
    assert str(e.value) == message


def test_a_bad_shard_and_bad_parts_are_value_errors(damped):
    with pytest.raises(ValueError, match="shard"):
        rattle.map(damped, **MAP, shard=(3, 2))
    with pytest.raises(ValueError, match="no parts"):
        rattle.merge([])


# Dask: the same study as tasks on a LocalCluster of worker processes.

try:
    import distributed
    from distributed import Client, LocalCluster
except ImportError:  # pragma: no cover - the tests below are skipped
    distributed = None

needs_dask = pytest.mark.skipif(distributed is None, reason="dask.distributed is not installed")


def cluster(workers):
    # One Rust thread per task, as a worker of one thread should have.
    os.environ["RAYON_NUM_THREADS"] = "1"
    return LocalCluster(
        n_workers=workers,
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,
        silence_logs=40,
    )


@needs_dask
def test_a_study_on_1_2_and_3_workers_is_the_commands_file(damped, map_file, basins_file):
    for workers in (1, 2, 3):
        with cluster(workers) as c, Client(c) as client:
            m = rattle.map(damped, **MAP, client=client, parts=4, progress=False)
            assert m.document == map_file[0], workers
            b = rattle.basins(rattle.Scene.paper(), **BASINS, client=client, parts=3, progress=False)
            assert b.document == basins_file, workers


@needs_dask
def test_a_worker_killed_mid_run_loses_nothing(damped):
    # 16 lines of 25 frequencies, in 8 tasks of about a second each on this machine.
    study = dict(restitution=(0.2, 0.9, 4), gap=(0.1, 0.8, 4), omega=(0.5, 3.5, 25))
    expected = rattle.map(damped, **study).document
    with cluster(2) as c, Client(c) as client:
        pids = client.run(os.getpid)  # worker address -> its process
        killed = []

        def kill_one_busy_worker():
            deadline = time.monotonic() + 60
            while time.monotonic() < deadline and not killed:
                for worker, tasks in client.processing().items():
                    if any(str(t).startswith("rattle-map-") for t in tasks):
                        # Let the task run a little, then end its process as a crash would.
                        time.sleep(0.3)
                        os.kill(pids[worker], signal.SIGKILL)
                        killed.append(worker)
                        return
                time.sleep(0.02)

        killer = threading.Thread(target=kill_one_busy_worker)
        killer.start()
        got = rattle.map(damped, **study, client=client, parts=8, progress=False)
        killer.join()
        assert killed, "no worker was killed: the test did not test anything"
        assert got.document == expected


@needs_dask
def test_a_bad_study_on_a_cluster_fails_before_any_task(damped):
    with cluster(1) as c, Client(c) as client:
        with pytest.raises(ValueError, match=r"gap\[2\]"):
            rattle.map(damped, gap=(0.1, 0.8, 0), client=client)
        with pytest.raises(ValueError, match="points"):
            rattle.basins(rattle.Scene.paper(), 1.9, points=0, client=client)


def test_the_parts_are_chosen_from_the_estimated_work():
    from rattle._grids import parts_for

    assert parts_for(100.0, 1000) == 20  # one per TASK_SECONDS = 5 s
    assert parts_for(100.0, 10) == 10  # at most one per line or start
    assert parts_for(4.3, 36, workers=2) == 2  # one per worker, each at least 1 s
    assert parts_for(2.5, 36, workers=8) == 2
    assert parts_for(0.5, 36, workers=4) == 1
