"""Every function on the paper scene (and the shipped scene files) against the `rattle`
command's JSON for the same inputs: equal dictionaries, number for number (a float parsed
from the command's shortest round-trip text is the same double the package computed)."""

import json

import pytest
import rattle
from conftest import SCENES

#: Frequencies covering the paper scene's regimes: below the first resonance (no impact on a
#: settled motion), between them (two-impact motion, 2.0), near the unstable orbit at 2.9,
#: and above both (3.5).
OMEGAS = [0.8, 2.0, 2.9, 3.5]


@pytest.mark.parametrize("omega", OMEGAS)
def test_orbit_is_the_commands(rattle_cli, omega):
    ours = rattle.orbit(rattle.Scene.paper(), omega)
    assert isinstance(ours, rattle.OrbitResult)
    assert ours.to_dict() == rattle_cli.json("orbit", "--omega", omega)
    symmetric = rattle.orbit(rattle.Scene.paper(), omega, symmetric_only=True)
    assert symmetric.to_dict() == rattle_cli.json(
        "orbit", "--omega", omega, "--symmetric-only"
    )


@pytest.mark.parametrize(
    "signature, period, omega", [("+-", 1, 2.0), ("-+", 1, 2.9), ("++--", 2, 1.2), ("+", 1, 3.5)]
)
def test_orbit_of_a_signature_is_the_commands(rattle_cli, signature, period, omega):
    ours = rattle.orbit(rattle.Scene.paper(), omega, signature=signature, period=period)
    assert isinstance(ours, rattle.SignatureOrbits)
    theirs = rattle_cli.json(
        "orbit", "--omega", omega, "--signature", signature, "--period", period
    )
    assert ours.to_dict() == theirs


@pytest.mark.parametrize("omega", OMEGAS)
def test_simulate_is_the_commands(rattle_cli, omega):
    ours = rattle.simulate(rattle.Scene.paper(), omega)
    assert isinstance(ours, rattle.Simulation)
    assert ours.to_dict() == rattle_cli.json("simulate", "--omega", omega)


def test_simulate_with_options_is_the_commands(rattle_cli):
    scene = rattle.Scene.paper()
    ours = rattle.simulate(scene, 2.0, periods=100, tol=1e-10)
    theirs = rattle_cli.json("simulate", "--omega", 2.0, "--periods", 100, "--tol", 1e-10)
    assert ours.to_dict() == theirs
    ours = rattle.simulate(scene, 3.5, steady_tol=1e-8, max_periods=50, max_oscillations=500.0)
    theirs = rattle_cli.json(
        "simulate", "--omega", 3.5, "--steady-tol", 1e-8, "--max-periods", 50,
        "--max-oscillations", 500.0,
    )
    assert ours.to_dict() == theirs


#: The Lyapunov fields of `rattle simulate --lyapunov --json`.
LYAPUNOV_FIELDS = [
    "lyapunov_exponents",
    "lyapunov_uncertainty",
    "lyapunov_uncertainties",
    "lyapunov_collapsed",
    "lyapunov_periods",
    "lyapunov_regime",
]


@pytest.mark.parametrize(
    "omega, options, regime",
    [
        # The chaotic motion of figures/poincare, at the command's defaults (2000 periods).
        (1.25, {}, "chaotic"),
        # A periodic `+-` motion: no regime, exponents from the tangent flow all the same.
        (2.0, {"lyapunov_periods": 300}, None),
        # A fixed run of a few periods: the exponents from where it ended, whatever it is.
        (2.9, {"lyapunov_periods": 10, "periods": 40}, "any"),
    ],
)
def test_simulate_with_lyapunov_is_the_commands(rattle_cli, omega, options, regime):
    ours = rattle.simulate(rattle.Scene.paper(), omega, lyapunov=True, **options)
    args = ["simulate", "--omega", omega, "--lyapunov"]
    if "lyapunov_periods" in options:
        args += ["--lyapunov-periods", options["lyapunov_periods"]]
    if "periods" in options:
        args += ["--periods", options["periods"]]
    theirs = rattle_cli.json(*args)
    assert ours.to_dict() == theirs
    assert list(ours.to_dict()) == list(theirs)  # same fields, same order
    # Bit for bit: the same doubles, not merely equal-looking ones.
    assert [x.hex() for x in ours.lyapunov_exponents] == [
        x.hex() for x in theirs["lyapunov_exponents"]
    ]
    assert ours.lyapunov_uncertainty.hex() == theirs["lyapunov_uncertainty"].hex()
    assert ours.lyapunov_periods == options.get("lyapunov_periods", rattle.LYAPUNOV_PERIODS)
    assert len(ours.lyapunov_exponents) + ours.lyapunov_collapsed == 4
    if regime != "any":
        assert ours.lyapunov_regime == regime
        assert (ours.status == "periodic") == (regime is None)


def test_lyapunov_periods_alone_adds_nothing(rattle_cli):
    """As the command's `--lyapunov-periods` without `--lyapunov`."""
    ours = rattle.simulate(rattle.Scene.paper(), 2.0, lyapunov_periods=50)
    assert not set(LYAPUNOV_FIELDS) & set(ours.to_dict())
    assert ours.to_dict() == rattle_cli.json(
        "simulate", "--omega", 2.0, "--lyapunov-periods", 50
    )


@pytest.mark.parametrize("omega", OMEGAS)
def test_compare_is_the_commands(rattle_cli, omega):
    ours = rattle.compare(rattle.Scene.paper(), omega)
    assert isinstance(ours, rattle.Comparison)
    assert ours.to_dict() == rattle_cli.json("compare", "--omega", omega)
    assert ours.class_ == ours.to_dict()["class"]


@pytest.mark.parametrize("solver, points", [("analytic", 40), ("event", 9), ("both", 7)])
def test_sweep_is_the_commands(rattle_cli, tmp_path, solver, points):
    out = tmp_path / "sweep.json"
    code, _, err = rattle_cli.run(
        "sweep", "--omega-min", 0.5, "--omega-max", 3.5, "--points", points,
        "--solver", solver, "--out", out,
    )
    assert code == 0, err
    theirs = json.loads(out.read_text())
    ours = rattle.sweep(rattle.Scene.paper(), rattle.frequencies(0.5, 3.5, points), solver=solver)
    assert ours.to_dict() == theirs
    assert (ours.scene, ours.solver, ours.effects, ours.points) == (
        theirs["scene"], theirs["solver"], theirs["effects"], theirs["points"]
    )


@pytest.mark.parametrize("path", sorted(SCENES.glob("*.json")), ids=lambda p: p.name)
def test_scene_files_give_the_commands_results(rattle_cli, path):
    document = json.loads(path.read_text())
    scene = rattle.Scene.from_file(path)
    assert scene.to_dict() == rattle.Scene.from_dict(document).to_dict()
    if "structure" in document or "harmonics" in document["base"]:
        # The structure form (a unit whose base has harmonics runs as its structure):
        # simulate, orbit with a signature, compare and sweep take it (test_structures.py);
        # orbit without a signature refuses it by name, as the command.
        assert scene.form == "structure"
        assert "structure form" in rattle_cli.error("orbit", path, "--omega", 2.0)
        with pytest.raises(ValueError, match="structure form"):
            rattle.orbit(scene, 2.0)
        result = rattle.simulate(scene, 2.0)
        assert result.to_dict() == rattle_cli.json("simulate", path, "--omega", 2.0)
        if "structure" in document:
            names = [b["name"] for b in document["structure"]["bodies"]]
        else:
            names = ["outer", "inner"]
        assert list(result.to_dict()["body_amplitudes"]) == names
        return
    assert scene.form == "cells"
    if "cells" in document or "chain" in document:
        # A chain: the two-impact orbits are a single unit's; both refuse, naming the chain.
        assert "chain of" in rattle_cli.error("orbit", path, "--omega", 2.0)
        with pytest.raises(ValueError, match="chain of"):
            rattle.orbit(scene, 2.0)
    else:
        assert rattle.orbit(scene, 2.0).to_dict() == rattle_cli.json(
            "orbit", path, "--omega", 2.0
        )
    assert rattle.simulate(scene, 2.0).to_dict() == rattle_cli.json(
        "simulate", path, "--omega", 2.0
    )


def test_the_paper_scene_is_the_commands_built_in_scene():
    shipped = json.loads((SCENES / "paper.json").read_text())
    assert rattle.Scene.paper().to_dict() == shipped
    assert rattle.Scene.paper() == rattle.Scene.from_dict(shipped)
    assert rattle.Scene.paper().effects == ["stops"]


def test_attributes_are_the_documents_fields():
    result = rattle.simulate(rattle.Scene.paper(), 2.0)
    document = result.to_dict()
    assert result.keys() == list(document)
    for key, value in document.items():
        assert getattr(result, key) == value or isinstance(value, (dict, list))
    orbits = rattle.orbit(rattle.Scene.paper(), 2.0)
    assert orbits.linear.transmittance_db == orbits.to_dict()["linear"]["transmittance_db"]
    assert [o.branch for o in orbits.orbits] == [o["branch"] for o in orbits.to_dict()["orbits"]]
    # to_dict hands out a copy: changing it changes nothing.
    document["omega"] = -1.0
    assert result.to_dict()["omega"] == 2.0


def test_frequencies_are_the_commands_axis(rattle_cli, tmp_path):
    out = tmp_path / "axis.json"
    code, _, err = rattle_cli.run(
        "sweep", "--omega-min", 0.1, "--omega-max", 4.0, "--points", 400,
        "--solver", "analytic", "--out", out,
    )
    assert code == 0, err
    theirs = [row["omega"] for row in json.loads(out.read_text())["results"]]
    assert rattle.frequencies(0.1, 4.0, 400).tolist() == theirs


@pytest.mark.parametrize("omega", [1.0, 2.5])
def test_simulate_on_a_chain_is_the_commands(rattle_cli, omega):
    path = SCENES / "paper-chain-5.json"
    ours = rattle.simulate(rattle.Scene.from_file(path), omega, max_periods=300)
    theirs = rattle_cli.json("simulate", path, "--omega", omega, "--max-periods", 300)
    assert ours.to_dict() == theirs
    assert len(ours.to_dict()["cell_outer_amplitudes"]) == 5


def test_single_unit_functions_refuse_a_chain_by_name():
    chain = rattle.Scene.from_file(SCENES / "paper-graded-4.json")
    # `continue_branch` takes chains (test_continuation.py).
    for call in (lambda: rattle.orbit(chain, 2.0),):
        with pytest.raises(ValueError, match="chain of 4 cells"):
            call()


#: Two of the paper's cells in series, lightly damped as `data/scenes/paper-chain-5.json`.
TWO_CELLS = {
    "name": "two",
    "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0,
             "inner_stiffness": 3.0},
    "base": {"amplitude": 1.0},
    "stops": {"gap": 0.5, "restitution": 0.8},
    "damping": {"outer": 0.1, "inner": 0.05},
    "cells": 2,
}


@pytest.fixture(scope="module")
def two_cells(tmp_path_factory):
    path = tmp_path_factory.mktemp("chain") / "two.json"
    path.write_text(json.dumps(TWO_CELLS))
    return path


@pytest.mark.parametrize("sequence, period, omega", [("1- 0- 1+ 0+", 1, 3.3), ("0+ 0-", 1, 2.0)])
def test_orbit_of_a_sequence_on_a_chain_is_the_commands(rattle_cli, two_cells, sequence, period, omega):
    scene = rattle.Scene.from_file(two_cells)
    ours = rattle.orbit(scene, omega, signature=sequence, period=period)
    theirs = rattle_cli.json(
        "orbit", two_cells, "--omega", omega, "--signature", sequence, "--period", period
    )
    assert ours.to_dict() == theirs
    assert ours.cells == 2 and ours.sequence == theirs["sequence"]


def test_a_bad_sequence_on_a_chain_is_the_commands_error(rattle_cli, two_cells):
    scene = rattle.Scene.from_file(two_cells)
    theirs = rattle_cli.error("orbit", two_cells, "--omega", 2.0, "--signature", "2+ 2-")
    with pytest.raises(ValueError) as ours:
        rattle.orbit(scene, 2.0, signature="2+ 2-")
    assert str(ours.value) == theirs.replace("--signature", "signature")


@pytest.mark.parametrize("omega", [0.5, 1.7])
def test_compare_on_a_chain_is_the_commands(rattle_cli, two_cells, omega):
    ours = rattle.compare(rattle.Scene.from_file(two_cells), omega)
    theirs = rattle_cli.json("compare", two_cells, "--omega", omega)
    assert ours.to_dict() == theirs
    assert ours.cells == 2 and ours.class_ == theirs["class"]
    assert len(ours.simulated.cell_outer_amplitudes) == 2


def test_sweep_both_on_a_chain_is_the_commands(rattle_cli, two_cells, tmp_path):
    out = tmp_path / "sweep.json"
    code, _, err = rattle_cli.run(
        "sweep", two_cells, "--omega-min", 0.5, "--omega-max", 1.7, "--points", 2,
        "--solver", "both", "--out", out,
    )
    assert code == 0, err
    theirs = json.loads(out.read_text())
    ours = rattle.sweep(rattle.Scene.from_file(two_cells), rattle.frequencies(0.5, 1.7, 2))
    assert ours.to_dict() == theirs
