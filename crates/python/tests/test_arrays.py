"""Sweep columns as numpy arrays: one per column of the command, in its order, with fixed
dtypes, each the rows' values (NaN or False where a row has null); pandas when installed."""

import math

import numpy as np
import pytest
import rattle

NUMBER = {
    "omega", "linear_outer_amplitude", "linear_transmittance_db", "orbits",
    "stable_viable_orbits", "branch0_alpha", "branch0_outer_amplitude",
    "branch0_transmittance_db", "branch1_alpha", "branch1_outer_amplitude",
    "branch1_transmittance_db", "simulated_period", "simulated_impacts_per_period",
    "simulated_outer_amplitude", "simulated_transmittance_db", "relative_difference",
    "analytic_outer_amplitude", "analytic_energy_residual", "multiplier_difference",
    "largest_exponent", "largest_exponent_uncertainty",
}
FLAG = {
    "linear_touches_stops", "branch0_viable", "branch0_stable", "branch1_viable",
    "branch1_stable", "simulated_sticking", "analytic_viable", "analytic_stable",
}
#: Lists of numbers, one cell each: `;`-separated text, as the command writes them.
LIST = {
    "linear_cell_outer_amplitudes", "simulated_pair_impacts_per_period",
    "simulated_cell_outer_amplitudes", "analytic_cell_outer_amplitudes",
}
TEXT = {
    "simulated_regime", "simulated_status", "simulated_signature", "lyapunov_regime", "class",
    "class_detail",
    "matched", "error",
} | LIST


def numbers(cell):
    """A list column's cell as floats (NaN for an empty element)."""
    return [float(x) if x else math.nan for x in cell.split(";")]


@pytest.fixture(scope="module")
def both():
    return rattle.sweep(rattle.Scene.paper(), rattle.frequencies(0.5, 3.5, 7), solver="both")


def test_columns_are_the_rows_fields_in_order(both):
    rows = both.to_dict()["results"]
    assert len(both) == len(rows) == 7
    assert list(both.columns) == list(rows[0])
    assert set(both.columns) == NUMBER | FLAG | TEXT


def test_dtypes_and_shapes(both):
    for name, column in both.columns.items():
        assert isinstance(column, np.ndarray)
        assert column.shape == (7,), name
        expected = np.float64 if name in NUMBER else bool if name in FLAG else object
        assert column.dtype == np.dtype(expected), name
        assert not column.flags.writeable


def test_columns_hold_the_rows_values(both):
    rows = both.to_dict()["results"]
    for name, column in both.columns.items():
        for value, row in zip(column.tolist(), rows):
            cell = row[name]
            if name in NUMBER:
                assert (math.isnan(value) and cell is None) or value == cell, name
            elif name in FLAG:
                assert value == bool(cell), name
            else:
                assert value == cell, name


def test_a_units_lists_hold_its_one_cell_and_pair(both):
    # The paper scene is one cell with one contact pair: each list is its scalar column.
    for lists, scalar in [
        ("linear_cell_outer_amplitudes", "linear_outer_amplitude"),
        ("simulated_cell_outer_amplitudes", "simulated_outer_amplitude"),
        ("simulated_pair_impacts_per_period", "simulated_impacts_per_period"),
        ("analytic_cell_outer_amplitudes", "analytic_outer_amplitude"),
    ]:
        for cell, value in zip(both.columns[lists], both.columns[scalar]):
            if cell is None:
                assert math.isnan(value), lists
            else:
                assert numbers(cell) == [value], lists


def test_a_chains_lists_hold_every_cell_and_pair():
    chain = rattle.Scene.from_dict({
        "name": "two",
        "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0,
                 "inner_stiffness": 3.0},
        "base": {"amplitude": 1.0},
        "stops": {"gap": 0.5, "restitution": 0.8},
        "damping": {"outer": 0.1, "inner": 0.05},
        "cells": 2,
    })
    s = rattle.sweep(chain, [0.5, 1.7], solver="both")
    for i in range(len(s)):
        cells = numbers(s.simulated_cell_outer_amplitudes[i])
        assert len(cells) == 2 and cells[-1] == s.simulated_outer_amplitude[i]
        pairs = numbers(s.simulated_pair_impacts_per_period[i])
        assert len(pairs) == 2
        assert math.isclose(sum(pairs), s.simulated_impacts_per_period[i], rel_tol=1e-15)
        linear = numbers(s.linear_cell_outer_amplitudes[i])
        assert len(linear) == 2 and linear[-1] == s.linear_outer_amplitude[i]


def test_columns_are_attributes(both):
    assert both.omega is both.columns["omega"]
    assert both.class_ is both.columns["class"]
    with pytest.raises(AttributeError):
        both.no_such_column


@pytest.mark.parametrize("solver", ["analytic", "event"])
def test_one_solver_leaves_the_others_columns_empty(solver):
    s = rattle.sweep(rattle.Scene.paper(), [1.0, 2.0, 3.0], solver=solver)
    analytic = np.isnan(s.linear_transmittance_db)
    simulated = np.isnan(s.simulated_outer_amplitude)
    assert analytic.all() == (solver == "event")
    assert simulated.all() == (solver == "analytic")
    assert all(c is None for c in s.columns["class"])


def test_an_empty_sweep_has_empty_columns():
    s = rattle.sweep(rattle.Scene.paper(), [], solver="analytic")
    assert len(s) == 0 and s.points == 0
    assert s.omega.shape == (0,) and s.omega.dtype == np.float64
    assert s.to_dict()["results"] == []


def test_to_pandas_is_the_columns(both):
    pandas = pytest.importorskip("pandas")
    frame = both.to_pandas()
    assert isinstance(frame, pandas.DataFrame)
    assert list(frame.columns) == list(both.columns)
    assert frame.shape == (7, len(both.columns))
    np.testing.assert_array_equal(frame["omega"].to_numpy(), both.omega)


def test_to_pandas_without_pandas_says_what_to_install(both, monkeypatch):
    import builtins

    real_import = builtins.__import__

    def no_pandas(name, *args, **kwargs):
        if name == "pandas":
            raise ImportError("no pandas here")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_pandas)
    with pytest.raises(ImportError, match="pip install pandas"):
        both.to_pandas()
