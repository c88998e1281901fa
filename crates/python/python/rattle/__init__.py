"""Steady states of an impacting mass-in-mass unit, two independent ways, from Python.

An inner mass rattles between two stops (``r = u_i - u_o = ±gap``) inside an outer mass whose
base moves as ``u_g cos(ωt)``. Two solvers that share no numerics describe it:

- the closed-form (Nigm–Shabana) orbits: :func:`orbit`;
- the exact event-driven simulator: :func:`simulate`;

and :func:`compare` and :func:`sweep` put them side by side; :func:`continue_branch` follows the
orbits of a signature in frequency, :func:`boundary` one of their events (a regime boundary) in
frequency and a scene parameter. ``simulate(..., trajectory=True)`` and
:func:`orbit_trajectory` give a cycle's time history, sampled from the closed form, as the
command's ``--trajectory`` and ``--impacts`` tables. Each function does what the
``rattle`` command of the same name does, on the same library calls, and its result's
``.to_dict()`` equals the command's ``--json`` output for the same inputs, number for number.

Errors: a bad scene or argument raises :class:`ValueError` (for a scene, the command's message:
the field's path and its allowed range); an unreadable scene file :class:`OSError`; a numerical
failure :class:`RuntimeError`. A frequency must be finite, > 0 and within the scene's bounds,
``[ω_fastest / 1e3, ω_slowest × 1e6]`` of its undamped natural frequencies (the paper's unit:
2.449e-3 to 1.225e6 rad/s), so that every call ends in bounded time; outside them the call
raises the command's :class:`ValueError` with the range. The computations release the GIL; a
sweep runs on the Rust thread pool (``RAYON_NUM_THREADS`` sets its size).

:func:`respond` is the exact response from rest to a non-periodic signal, and
:func:`transmission` the Welch estimate of the transmissibility under random base motion,
level by level, beside the linear response with the stops removed (on a Dask cluster with
``client=``), as ``rattle respond`` and ``rattle transmission``.

``simulate(..., lyapunov=True)`` adds the Lyapunov exponents of the motion, as
``rattle simulate --lyapunov``.

Chains of cells (a scene with ``"cells": N`` or ``"chain": [...]``) go through
:func:`simulate`, :func:`sweep` (every solver), :func:`orbit` with a signature (an impact
sequence of the chain's pairs, ``"0+ 1- 0- 1+"``: :class:`ChainOrbits`),
:func:`orbit_trajectory` (one row per cell), :func:`compare` (:class:`ChainComparison`) and
:func:`continue_branch` and :func:`boundary`, each as the command on the same chain;
:func:`orbit` without a signature takes a single unit and refuses a chain with a
:class:`ValueError` naming it.

Structures (a scene in the structure form: bodies, springs, dashpots, stops and forcing, with a
``structure`` field; :attr:`Scene.form` is ``"structure"``) go through :func:`simulate` (every
body's amplitude by name; the trajectory with a column per body and per stop; the Lyapunov
exponents), :func:`orbit` with a signature (an impact sequence of its stops:
:class:`StructureOrbits`), :func:`orbit_trajectory` (a column per body and per stop, as the
simulated trajectory's), :func:`compare` (:class:`StructureComparison`), :func:`sweep`
(every solver, whole or in parts), :func:`continue_branch` and :func:`boundary` (an impact
sequence of the stops, a parameter by its path such as ``"structure.stops[0].gap_plus"``),
:func:`map` over two of its numbers (``x=``, ``y=``) and :func:`basins` (over any two of its
bodies' displacements and velocities, ``x="u:NAME"``, ``y="v:NAME"``), each as the command on
the same structure. :func:`orbit` without a signature refuses a structure with a
:class:`ValueError` naming the function and the forms it takes, as the command refuses one;
:func:`map` without ``x`` and ``y`` asks for them.
"""

from . import _rattle

__all__ = [
    "Scene",
    "Record",
    "OrbitResult",
    "SignatureOrbits",
    "ChainOrbits",
    "StructureOrbits",
    "Simulation",
    "Comparison",
    "ChainComparison",
    "StructureComparison",
    "Sweep",
    "Table",
    "OrbitCycle",
    "Continuation",
    "orbit",
    "orbit_trajectory",
    "simulate",
    "compare",
    "sweep",
    "frequencies",
    "continue_branch",
    "boundary",
    "Boundary",
    "map",
    "basins",
    "merge",
    "Map",
    "Basins",
    "Response",
    "respond",
    "Transmission",
    "transmission",
    "TRANSMISSION_VARIABLES",
    "TRANSMISSION_SECONDS_PER_SAMPLE",
    "DEFAULTS",
    "CONTINUATION_DEFAULTS",
    "BOUNDARY_DEFAULTS",
    "SAMPLES_PER_PERIOD",
    "LYAPUNOV_PERIODS",
]

__version__ = _rattle.__version__

from ._defaults import (
    BOUNDARY_DEFAULTS,
    CONTINUATION_DEFAULTS,
    DEFAULTS,
    LYAPUNOV_PERIODS,
    SAMPLES_PER_PERIOD,
)
from ._records import (
    Boundary,
    ChainComparison,
    ChainOrbits,
    Comparison,
    Continuation,
    OrbitCycle,
    OrbitResult,
    Record,
    SignatureOrbits,
    Simulation,
    StructureComparison,
    StructureOrbits,
    Sweep,
    Table,
)
from ._scene import Scene
from ._signals import TRANSMISSION_VARIABLES, Response, Transmission, respond, transmission
from ._studies import (
    boundary,
    compare,
    continue_branch,
    frequencies,
    orbit,
    orbit_trajectory,
    simulate,
    sweep,
)

# Maps and basins, whole, in parts or on a Dask cluster (``_grids``); defined last, since
# ``map`` is this module's name for the command, not the builtin.
from ._grids import (  # noqa: E402
    TRANSMISSION_SECONDS_PER_SAMPLE,
    Basins,
    Map,
    basins,
    map,
    merge,
)
