"""`rattle.transmission` against `rattle transmission`: the same document bit for bit, its
columns and Dataset, refusals naming the parameter, the same result on Dask, and H₁ within
its radius of the linear response on a linear scene.

The Dask test needs `dask` and `distributed` and is skipped without them; the Dataset test
needs xarray."""

import cmath
import json
import os

import numpy as np
import pytest

import rattle
from conftest import SCENES

ISOLATED = SCENES / "base-isolated.json"
SIGNAL = "random:band=0.2-2.5,rms=0.01,seed=5"
#: A small estimate: two levels (the higher one reaches the stop), two seeds each.
SMALL = dict(duration=300, levels=[0.01, 0.05], seeds=2)
SMALL_FLAGS = ("--duration", "300", "--levels", "0.01,0.05", "--seeds", "2")


@pytest.fixture(scope="module")
def isolated():
    return rattle.Scene.from_file(ISOLATED)


@pytest.fixture(scope="module")
def small(isolated):
    return rattle.transmission(isolated, SIGNAL, **SMALL)


def test_the_document_is_the_commands(rattle_cli, small):
    expected = rattle_cli.json("transmission", ISOLATED, "--signal", SIGNAL, *SMALL_FLAGS)
    assert small.to_dict() == expected
    assert small.keys() == ["scene", "observe", "settings", "linear", "levels"]
    assert small.levels[1].impacts == expected["levels"][1]["impacts"] > 0
    assert small.settings.seeds == 2


def test_every_option_reaches_the_command(rattle_cli, isolated):
    options = dict(segment=40, overlap=0.25, confidence=0.9, transient=50)
    got = rattle.transmission(isolated, SIGNAL, 200, **options)
    expected = rattle_cli.json(
        "transmission", ISOLATED, "--signal", SIGNAL, "--duration", "200",
        "--segment", "40", "--overlap", "0.25", "--confidence", "0.9", "--transient", "50",
    )  # fmt: skip
    assert got.to_dict() == expected
    # The transient cut is rounded up to a whole sample.
    assert got.settings.overlap == 0.25
    assert 50 <= got.settings.transient < 50 + got.settings.sampling_step
    # A single level as a number.
    one = rattle.transmission(isolated, SIGNAL, 200, levels=0.02, segment=40)
    assert one.settings.levels == [0.02]


def test_the_columns_are_the_rows(small, rattle_cli, tmp_path):
    rows = [row for level in small.to_dict()["levels"] for row in level["rows"]]
    assert list(small.table.columns) == list(rows[0])
    assert len(small.table) == len(rows)
    for name, column in small.table.columns.items():
        assert column.dtype == np.float64
        assert list(column) == [np.nan if r[name] is None else r[name] for r in rows]
    assert len(small.tables) == 2
    for level, table in zip(small.levels, small.tables):
        assert set(table.level) == {level.level}
        assert list(table.omega) == [row.omega for row in level.rows]
    # The command's CSV has the same columns.
    out = tmp_path / "t.csv"
    code, _, err = rattle_cli.run(
        "transmission", ISOLATED, "--signal", SIGNAL, *SMALL_FLAGS, "--out", out
    )
    assert code == 0, err
    header, *lines = out.read_text().splitlines()
    assert header.split(",") == list(small.table.columns)
    assert len(lines) == len(small.table)


def test_the_dataset_is_over_level_and_omega(small):
    xarray = pytest.importorskip("xarray")
    ds = small.to_xarray()
    assert isinstance(ds, xarray.Dataset)
    frequencies = small.settings.frequencies
    assert dict(ds.sizes) == {"level": 2, "omega": frequencies}
    assert list(ds.data_vars) == list(rattle.TRANSMISSION_VARIABLES)
    assert list(ds.level.values) == [0.01, 0.05]
    assert list(ds.omega.values) == [row.omega for row in small.levels[0].rows]
    for i, level in enumerate(small.levels):
        for name in rattle.TRANSMISSION_VARIABLES:
            assert list(ds[name].values[i]) == list(small.tables[i].columns[name])
        assert ds.impacts.values[i] == level.impacts
        assert ds.effective_averages.values[i] == level.effective_averages
    assert ds.h1_magnitude.sel(level=0.05).dims == ("omega",)
    assert ds.attrs["scene"] == small.scene and ds.attrs["observe"] == small.observe
    assert ds.attrs["signal"] == SIGNAL and ds.attrs["seeds"] == 2
    assert list(ds.attrs["band"]) == [0.2, 2.5]


@pytest.mark.parametrize(
    "change, name",
    [
        (dict(duration=-1), "duration = -1"),
        (dict(signal="tone-burst:omega=1,cycles=3"), "signal tone-burst"),
        (dict(levels=[0.1, 0.0]), "levels[1] = 0"),
        (dict(seeds=0), "seeds = 0"),
        (dict(seeds=-3), "seeds = -3"),
        (dict(overlap=1), "overlap = 1 is out of range: must be in [0, 1)"),
        (dict(confidence=1), "confidence = 1"),
        (dict(transient=300), "transient = 300"),
        (dict(segment=1000), "segment = 1000"),
        (dict(segment=0.5), "segment = 0.5"),
    ],
)
def test_bad_input_raises_value_error_naming_the_parameter(isolated, change, name):
    arguments = dict(signal=SIGNAL, **SMALL)
    arguments.update(change)
    with pytest.raises(ValueError) as raised:
        rattle.transmission(isolated, **arguments)
    message = str(raised.value)
    assert message.startswith(name), message
    assert "--" not in message, message


def test_the_messages_are_the_commands(rattle_cli, isolated):
    with pytest.raises(ValueError) as raised:
        rattle.transmission(isolated, SIGNAL, 1000, overlap=1)
    command = rattle_cli.error(
        "transmission", ISOLATED, "--signal", SIGNAL, "--duration", "1000", "--overlap", "1"
    )
    assert "--" + str(raised.value) == command


def test_parts_merged_are_the_whole(isolated, small):
    parts = [
        rattle._rattle.transmission_part(
            isolated._native, SIGNAL, 300.0, [0.01, 0.05], 2, part=(k, 3)
        )
        for k in (3, 1, 2)
    ]
    merged = rattle._rattle.merge_transmission_parts(parts)
    assert rattle.Transmission(json.loads(merged)) == small
    with pytest.raises(ValueError, match=r"shards \[1, 3\] given; need each of 1..=3 once"):
        rattle._rattle.merge_transmission_parts(parts[:2])
    with pytest.raises(ValueError, match=r"parts\[0\]"):
        rattle._rattle.merge_transmission_parts(["{}"])


def test_h1_is_within_its_radius_of_the_linear_response(isolated):
    # The linear level (the stop never reached), its radii at a confidence that holds for
    # every frequency at once (Bonferroni over the level's frequencies); segments long
    # against the time constant 10 s, so the window's smoothing stays inside the radius.
    arguments = dict(duration=1000, seeds=2, segment=320)
    first = rattle.transmission(isolated, SIGNAL, **arguments)
    confidence = 1 - 0.05 / first.settings.frequencies
    t = rattle.transmission(isolated, SIGNAL, confidence=confidence, **arguments)
    assert t.settings.simultaneous_confidence >= 0.95 - 1e-12
    assert t.levels[0].impacts == 0
    rows = t.tables[0]
    h1 = rows.h1_magnitude * np.exp(1j * rows.h1_phase)
    h = rows.linear_magnitude * np.exp(1j * rows.linear_phase)
    assert len(rows) > 100
    assert np.all(np.abs(h1 - h) <= rows.h1_radius)
    # The reference is the structure's own, H = (1 + 0.2iω)/(1 − ω² + 0.2iω).
    exact = [(1 + 0.2j * w) / (1 - w * w + 0.2j * w) for w in rows.omega]
    assert np.allclose(h, exact, rtol=1e-12, atol=0)
    assert abs(cmath.phase(h1[0]) - cmath.phase(h[0])) < 0.2


# Dask: the runs as tasks on a LocalCluster of worker processes.

try:
    import distributed
    from distributed import Client, LocalCluster
except ImportError:  # pragma: no cover - the test below is skipped
    distributed = None


@pytest.mark.skipif(distributed is None, reason="dask.distributed is not installed")
def test_on_dask_the_result_is_the_local_one(isolated, small):
    os.environ["RAYON_NUM_THREADS"] = "1"
    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=40
    ) as cluster, Client(cluster) as client:
        for parts in (None, 3, 4):
            got = rattle.transmission(
                isolated, SIGNAL, **SMALL, client=client, parts=parts, progress=False
            )
            assert got == small, parts
            assert got.to_dict() == small.to_dict()
            assert np.array_equal(got.table.h1_magnitude, small.table.h1_magnitude, equal_nan=True)
        with pytest.raises(ValueError, match=r"^overlap = 1"):
            rattle.transmission(isolated, SIGNAL, 300, overlap=1, client=client)
