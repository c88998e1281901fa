"""`rattle.respond` against `rattle respond`: the same document bit for bit, the same sampled
table, and refusals naming the parameter."""

import csv
import math

import pytest

import rattle
from conftest import SCENES

DAMPED = SCENES / "paper-damped.json"


@pytest.mark.parametrize(
    "signal",
    [
        "tone-burst:omega=2,cycles=5,amplitude=0.3",
        "sweep:from=0.5,to=3,rate=0.05",
        "sweep:from=3,to=0.5,rate=0.05,steps=6",
        "random:band=0.5-3,rms=0.1,seed=7",
    ],
)
def test_the_document_is_the_commands(rattle_cli, signal):
    scene = rattle.Scene.from_file(DAMPED)
    result = rattle.respond(scene, signal, 60, at=[10, 30.5])
    expected = rattle_cli.json(
        "respond", DAMPED, "--signal", signal, "--duration", "60", "--at", "10,30.5"
    )
    assert result.to_dict() == expected
    assert result.summary.rms.outer == expected["summary"]["rms"]["outer"]


def test_the_samples_are_the_commands_table(rattle_cli, tmp_path):
    scene = rattle.Scene.from_file(DAMPED)
    signal = "tone-burst:omega=2,cycles=5"
    result = rattle.respond(scene, signal, 40, samples=200)
    out = tmp_path / "r.csv"
    code, _, err = rattle_cli.run(
        "respond", DAMPED, "--signal", signal, "--duration", "40", "--out", out, "--samples", "200"
    )
    assert code == 0, err
    with open(out, newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == list(result.samples.columns)
    assert rows[0] == ["t", "u_g", "u:outer", "u:inner", "v:outer", "v:inner"]
    assert len(result.samples) == 201 == len(rows) - 1
    for name, column in zip(rows[0], zip(*rows[1:])):
        assert [float(x) for x in column] == list(result.samples.columns[name])
    assert result.samples.u_outer is result.samples.columns["u:outer"]


def test_a_force_record_acts_on_the_body_named(rattle_cli, tmp_path):
    record = tmp_path / "hammer.csv"
    record.write_text("t,F\n0,0\n0.1,5\n0.2,0\n")
    scene = rattle.Scene.from_file(DAMPED)
    result = rattle.respond(scene, str(record), 20, on="inner", at=[20])
    expected = rattle_cli.json(
        "respond", DAMPED, "--signal", record, "--duration", "20", "--on", "inner", "--at", "20"
    )
    assert result.to_dict() == expected
    assert result.input == "force" and result.on == "inner"
    assert math.isfinite(result.summary.work) and result.summary.work > 0


@pytest.mark.parametrize(
    "kwargs, field",
    [
        (dict(signal="random:band=3-1,rms=0.1,seed=1", duration=10), "band"),
        (dict(signal="random:band=1-3,rms=0,seed=1", duration=10), "rms"),
        (dict(signal="tone-burst:omega=1,cycles=0.5", duration=10), "cycles"),
        (dict(signal="sweep:from=1,to=2,rate=0", duration=10), "rate"),
        (dict(signal="tone-burst:omega=1,cycles=3", duration=-1), "duration"),
        (dict(signal="tone-burst:omega=1,cycles=3", duration=10, at=[11]), "at[0]"),
        (dict(signal="tone-burst:omega=1,cycles=3", duration=10, on="outer"), "on"),
        (dict(signal="tone-burst:omega=1,cycles=3", duration=10, samples=0), "samples"),
    ],
)
def test_bad_input_names_the_parameter(kwargs, field):
    with pytest.raises(ValueError, match=field.replace("[", r"\[")):
        rattle.respond(rattle.Scene.from_file(DAMPED), **kwargs)
