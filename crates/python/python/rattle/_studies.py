"""The periodic studies: orbits, simulation, comparison, sweeps, continuation and boundaries."""

import json as _json

import numpy as _np

from . import _rattle
from ._defaults import (
    _MAX_OSCILLATIONS,
    _MAX_PERIODS,
    _STEADY_TOL,
    _TOL,
    BOUNDARY_DEFAULTS,
    CONTINUATION_DEFAULTS,
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
    SignatureOrbits,
    Simulation,
    StructureComparison,
    StructureOrbits,
    Sweep,
    Table,
)
from ._scene import _native_scene


def orbit(scene, omega, signature=None, period=1, symmetric_only=False):
    """The analytic solver at one frequency, as ``rattle orbit --json``.

    Without ``signature``: the linear steady state and every two-impact orbit (symmetric
    branches 0 and 1, then the asymmetric ones unless ``symmetric_only``), each with its
    viability and Floquet stability; returns an :class:`OrbitResult`.

    With ``signature`` (the stops hit over one cycle in time order, ``+`` side 1, ``-`` side 2,
    any rotation, e.g. ``"+-"``, ``"++--"``) and ``period`` (forcing periods per cycle, 1 to 8):
    every orbit of that signature; returns :class:`SignatureOrbits`.

    On a chain of cells, ``signature`` is an impact sequence of the chain's pairs in time
    order, ``<pair><side>`` tokens with pairs numbered from 0 at the base (``"0+ 1- 0- 1+"``;
    a signature without numbers is pair 0's alone), as ``rattle orbit CHAIN --signature``;
    returns :class:`ChainOrbits`. Without a signature a chain is refused (the two-impact
    orbits are a single unit's).

    On a structure, ``signature`` is an impact sequence of its stops, ``<stop><side>`` tokens
    with stops numbered from 0 in file order (with one stop the sides alone, ``"+-"``), as
    ``rattle orbit STRUCTURE --signature``; returns :class:`StructureOrbits`. Without a
    signature a structure is refused by name.

    ``omega`` is the angular frequency of the forcing in rad/s (finite, > 0).
    """
    text = _rattle.orbit(_native_scene(scene), float(omega), signature, period, symmetric_only)
    data = _json.loads(text)
    if data.get("form") == "structure":
        return StructureOrbits(data)
    if "sequence" in data:
        return ChainOrbits(data)
    return SignatureOrbits(data) if signature is not None else OrbitResult(data)


def simulate(
    scene,
    omega,
    periods=None,
    tol=_TOL,
    steady_tol=_STEADY_TOL,
    max_periods=_MAX_PERIODS,
    max_oscillations=_MAX_OSCILLATIONS,
    trajectory=False,
    samples_per_period=SAMPLES_PER_PERIOD,
    lyapunov=False,
    lyapunov_periods=LYAPUNOV_PERIODS,
    sampled_periods=None,
):
    """The event-driven simulator from rest, as ``rattle simulate --json``.

    Runs until the motion is periodic (or a cap), or exactly ``periods`` forcing periods.
    ``tol`` is the relative tolerance of contact times (1e-15 to 1e-2), ``steady_tol`` that of
    the periodicity test (1e-14 to 1e-2), ``max_periods`` and ``max_oscillations`` the caps of
    a run until steady. Returns a :class:`Simulation`.

    With ``trajectory=True`` the result also carries, as :class:`Table`, what
    ``rattle simulate --trajectory F.csv --impacts I.csv --samples-per-period N`` writes:
    ``trajectory``, the final cycle sampled from the closed form (its ``period`` forcing
    periods; for a motion that is not periodic, the run's observed final stretch), with
    ``samples_per_period`` uniform samples per forcing period (1 to 100000, both ends of the
    stretch included) and each impact as two rows, before and after (columns ``t, kind, cell,
    base, u_o, u_i, v_o, v_i, r``; ``t`` in s with the base at ``u_g cos ωt``, ``kind`` one
    of ``sample``, ``before_impact``, ``after_impact``, ``after_stick``; a chain has one row
    per cell at each time, ``cell`` numbered from 0 at the base, 0 for the unit), and
    ``impact_table``, every impact of that stretch (``t, pair, side,
    relative_velocity_before, u_o, u_i, v_o_before, v_i_before``, displacements and
    velocities of the pair's cell). With ``sampled_periods=N`` (``--sampled-periods N``) the
    tables hold ``N`` forcing periods continued from where the run ended instead of the final
    cycle: with ``samples_per_period=1`` the ``sample`` rows are the stroboscopic (Poincaré)
    section at ``t = kT`` and ``impact_table`` the impact map, for a motion periodic or not
    (``N`` ≥ 1, ``N × samples_per_period`` ≤ 10 000 000).

    With ``lyapunov=True``, as ``rattle simulate --lyapunov --lyapunov-periods N``: after the
    run, the Lyapunov exponents over ``lyapunov_periods`` more forcing periods (at least 10;
    ignored without ``lyapunov``), from the simulator's exact tangent flow, in the result:
    ``lyapunov_exponents`` (the finite ones, descending, 1/s), ``lyapunov_uncertainty`` (of
    the largest, 1/s), ``lyapunov_uncertainties`` (of each), ``lyapunov_collapsed``
    (directions contracted by sticking, exponents −∞, not listed), ``lyapunov_periods`` and
    ``lyapunov_regime`` (``chaotic``, ``quasi-periodic`` or ``unsettled`` for a motion that
    did not repeat, ``None`` for a periodic one). The same numbers as the command, bit for bit.

    On a structure (``scene.form == "structure"``), as ``rattle simulate STRUCTURE``: the run
    from the structure's rest state, the record with ``form``, ``observed`` and every body's
    amplitude by name (``body_amplitudes``, from the polished cycle when ``amplitudes_of`` is
    ``"polished"``), ``pair_impacts_per_period`` and ``pair_signatures`` per stop; its
    ``trajectory`` has a column per body and per stop (``t, kind, base, u_NAME…, v_NAME…,
    r_K…``) and its ``impact_table`` the columns ``t, stop, side, relative_velocity_before,
    u_NAME…, v_NAME_before…``; with ``lyapunov=True``, two exponents per body.
    """
    text, tables = _rattle.simulate(
        _native_scene(scene),
        float(omega),
        periods,
        float(tol),
        float(steady_tol),
        max_periods,
        float(max_oscillations),
        samples_per_period if trajectory else None,
        lyapunov_periods if lyapunov else None,
        sampled_periods if trajectory else None,
    )
    if tables is None:
        return Simulation(_json.loads(text))
    rows, impacts = tables
    return Simulation(_json.loads(text), Table(rows), Table(impacts))


def orbit_trajectory(
    scene, omega, signature, period=1, orbit=0, samples_per_period=SAMPLES_PER_PERIOD
):
    """One analytic orbit's cycle sampled from the closed form, as
    ``rattle orbit --signature SIG --period P --orbit K --trajectory F.csv --impacts I.csv``.

    ``signature`` and ``period`` as in :func:`orbit`; ``orbit`` is which orbit of the signature
    (numbered from 0, in the order ``orbit(scene, omega, signature, period).orbits`` lists
    them); ``samples_per_period`` uniform samples per forcing period (1 to 100000), each impact
    adding two rows (before and after). The tables have the columns of
    ``simulate(..., trajectory=True)``, so the two solvers' cycles overlay directly. Returns
    an :class:`OrbitCycle`; an ``orbit`` out of range is a :class:`ValueError` naming
    ``orbit`` and how many orbits there are.

    On a chain of cells ``signature`` is an impact sequence of its pairs (e.g. ``"0+ 1- 0- 1+"``),
    as ``rattle orbit CHAIN --signature SEQUENCE --orbit K --trajectory F.csv``: ``orbits`` is
    then the :class:`ChainOrbits` of that sequence, the trajectory has one row per cell at each
    time (``cell`` numbered from 0 at the base) and each impact names its ``pair``.

    A function of its own rather than ``orbit(..., trajectory=True)``: it needs a signature
    and picks one orbit, where :func:`orbit` lists them all, with or without a signature; and
    its result has one type whatever the arguments.

    On a structure ``signature`` is an impact sequence of its stops (with one stop the sides
    alone, ``"+-"``), as ``rattle orbit STRUCTURE --signature SEQUENCE --orbit K --trajectory
    F.csv``: ``orbits`` is then the :class:`StructureOrbits` of that sequence, and the tables
    have the columns of a structure's ``simulate(..., trajectory=True)``, a column per body and
    per stop (``t, kind, base, u_NAME…, v_NAME…, r_K…``; the impacts ``t, stop, side,
    relative_velocity_before, u_NAME…, v_NAME_before…``).
    """
    native = _native_scene(scene)
    text, rows, impacts = _rattle.orbit_trajectory(
        native, float(omega), signature, period, orbit, samples_per_period
    )
    doc = _json.loads(text)
    if doc.get("form") == "structure":
        orbits = StructureOrbits(doc)
    elif "sequence" in doc:
        orbits = ChainOrbits(doc)
    else:
        orbits = SignatureOrbits(doc)
    return OrbitCycle(orbits, orbit, Table(rows), Table(impacts))


def compare(
    scene,
    omega,
    tol=_TOL,
    steady_tol=_STEADY_TOL,
    max_periods=_MAX_PERIODS,
    max_oscillations=_MAX_OSCILLATIONS,
):
    """Both solvers on the motion the unit settles on, as ``rattle compare --json``.

    The simulator runs from rest and polishes its cycle; the analytic orbit of that impact
    signature is solved from the simulated phases; the verdict says whether they agree.
    Accuracy knobs as :func:`simulate`. Returns a :class:`Comparison`.

    On a chain of cells: the simulated cycle's impacts, pair by pair in time order, are the
    impact sequence the analytic solver solves from the simulated impact times, as
    ``rattle compare CHAIN``; returns a :class:`ChainComparison`.

    On a structure: the same, every body compared (the stops' impacts are the sequence), as
    ``rattle compare STRUCTURE``; returns a :class:`StructureComparison`.
    """
    text = _rattle.compare(
        _native_scene(scene),
        float(omega),
        float(tol),
        float(steady_tol),
        max_periods,
        float(max_oscillations),
    )
    data = _json.loads(text)
    if data.get("form") == "structure":
        return StructureComparison(data)
    return ChainComparison(data) if "cells" in data else Comparison(data)


def sweep(
    scene,
    omegas,
    solver="both",
    tol=_TOL,
    steady_tol=_STEADY_TOL,
    max_periods=_MAX_PERIODS,
    max_oscillations=_MAX_OSCILLATIONS,
    shard=None,
):
    """A frequency sweep with one solver or both, in parallel, as ``rattle sweep``.

    ``omegas``: the frequencies, rad/s, any 1-D sequence (each finite, > 0 and within the
    scene's bounds, see the module's docstring); use
    :func:`frequencies` for the command's evenly spaced axis. ``solver``: ``"analytic"``
    (linear steady state and symmetric orbits), ``"event"`` (simulator from rest) or
    ``"both"`` (also the simulator started on every viable orbit, and a verdict). A frequency
    that fails gives a row with its ``error``, as in the command. Returns a :class:`Sweep`.

    On a chain of cells: ``"analytic"`` is the linear chain, ``"event"`` the chain from rest,
    ``"both"`` the linear chain and, at each frequency, the verdict of :func:`compare` on the
    chain; ``outer_amplitude`` and ``transmittance_db`` columns are the last cell's, the list
    columns hold every cell and pair.

    On a structure, as ``rattle sweep STRUCTURE``: ``"analytic"`` is the linear steady
    state, ``"event"`` the structure from rest (amplitudes from its polished cycle),
    ``"both"`` also the verdict of :func:`compare`; the rows have a structure's columns
    (``linear_outer_amplitude`` and ``simulated_outer_amplitude`` of the observed body,
    ``linear_body_amplitudes`` and ``simulated_body_amplitudes`` with every body's amplitude
    in the scene's order, ``simulated_pair_signatures`` per stop…; see :class:`Sweep`);
    ``shard`` cuts it as it cuts a unit's sweep.

    ``shard=(K, N)``: part ``K`` of ``N`` only (a contiguous block of ``omegas``), as
    ``rattle sweep --shard K/N``; :func:`merge` joins the parts into the whole sweep (a
    :class:`Sweep` equal to the one computed whole).
    """
    omegas = _np.ascontiguousarray(omegas, dtype=_np.float64)
    if omegas.ndim != 1:
        raise ValueError(f"omegas must be one-dimensional, not of shape {omegas.shape}")
    native = _rattle.sweep(
        _native_scene(scene),
        omegas,
        str(solver),
        float(tol),
        float(steady_tol),
        max_periods,
        float(max_oscillations),
        None if shard is None else tuple(shard),
    )
    return Sweep(native)


def frequencies(omega_min, omega_max, points):
    """``points`` evenly spaced frequencies from ``omega_min`` to ``omega_max``, ends included:
    the axis of ``rattle sweep --omega-min … --omega-max … --points …``, value for value
    (a ``float64`` array)."""
    return _rattle.frequencies(float(omega_min), float(omega_max), points)


def continue_branch(
    scene,
    signature,
    omega,
    omega_min,
    omega_max,
    period=1,
    orbit=None,
    switch=True,
    max_step=CONTINUATION_DEFAULTS["max_step"],
    max_branches=CONTINUATION_DEFAULTS["max_branches"],
    max_depth=CONTINUATION_DEFAULTS["max_depth"],
):
    """The branches through the orbits of a signature, followed in frequency, as
    ``rattle continue --json``.

    Every orbit of ``signature`` (over ``period`` forcing periods, as in :func:`orbit`) found
    at ``omega`` (or only the ``orbit``-th, numbered from 0 as :func:`orbit` lists them) is
    followed both ways within ``[omega_min, omega_max]`` (``omega`` inside it), its stability
    and viability tracked, and its events (branch points, period doublings, grazings…)
    located; with ``switch`` (the command without ``--no-switch``) the branches leaving at
    them are followed too. ``max_step`` is the largest step along a branch (in α, impact
    phases and ω together, ≥ 1e-9), ``max_branches`` the cap on the branches per start
    orbit (≥ 1), ``max_depth`` the switching depth (≥ 0; a start's branch has depth 0, one
    switched onto from a branch of depth d has d + 1; where the depth cuts, a branch without
    points ends ``max-depth``; the branches still queued once ``max_branches`` have been
    followed end ``branch-cap``). Each branch is followed once: one that runs onto a branch
    already followed, or onto its mirror image, ends ``joins`` with that branch. Returns a
    :class:`Continuation`.

    On a chain scene ``signature`` is an impact sequence of its pairs, ``"0+ 1- 0- 1+"``
    (pair index from 0 at the base, then the side), as in :func:`orbit`; the same
    continuation runs on the chain's equations (grazing and vanishing impact per pair), and
    the document gains ``cells`` and each point ``cell_outer_amplitudes`` (every cell's
    outer amplitude from the base out, the last being ``outer_amplitude``), as
    ``rattle continue CHAIN --json``. On a structure ``signature`` is an impact sequence of
    its stops (``"0+ 1-"``; with one stop ``"+-"`` reads as ``"0+ 0-"``), and each point
    gains ``body_amplitudes`` (:meth:`Continuation.body_amplitudes`), its
    ``outer_amplitude`` and ``transmittance_db`` being the observed body's.

    A bad argument is a :class:`ValueError` naming it (``omega_min``, ``max_step``,
    ``orbit``, a pair the chain lacks…); no orbit of the signature at ``omega`` a
    :class:`RuntimeError`.
    """
    text = _rattle.continue_branch(
        _native_scene(scene),
        signature,
        float(omega),
        float(omega_min),
        float(omega_max),
        period,
        orbit,
        bool(switch),
        float(max_step),
        max_branches,
        max_depth,
    )
    return Continuation(_json.loads(text))


def boundary(
    scene,
    signature,
    event,
    omega,
    param,
    min,
    max,
    period=1,
    at=None,
    omega_min=BOUNDARY_DEFAULTS["omega_min"],
    omega_max=BOUNDARY_DEFAULTS["omega_max"],
    max_step=BOUNDARY_DEFAULTS["max_step"],
):
    """A regime boundary: the curve of one event of a signature's orbits in (frequency, a
    scene parameter), as ``rattle boundary --json``.

    The event of kind ``event`` (``"fold"``, ``"branch-point"``, ``"period-doubling"``,
    ``"neimark-sacker"``, ``"grazing"`` or ``"vanishing-impact"``) nearest ``omega`` on the
    branches of the ``signature`` orbits (over ``period`` forcing periods, as in
    :func:`orbit`; on a chain an impact sequence of its pairs, ``"0+ 1- 0- 1+"``) found at
    ``omega``, continued in frequency within
    ``[omega_min, omega_max]`` at the scene's own value of ``param``, is followed in
    (ω, ``param``) both ways within ``[min, max]``, through turning points. ``param`` is a
    scene field by its JSON path (``"stops.gap"``, ``"stops.restitution"``,
    ``"unit.inner_stiffness"``, ``"damping.outer"``…; on a chain the whole chain's field or
    one cell's, ``"chain[1].stops.gap"``; on a structure a field of the structure form,
    ``"structure.stops[0].gap_plus"``, ``"structure.bodies[1].mass"``,
    ``"structure.springs[0].stiffness"``, ``"forcing.forces[0].amplitude"``…, the signature
    then an impact sequence of its stops, each point's ``outer_amplitude`` the observed
    body's); ``min`` and ``max`` lie in its physical range. ``at`` (values in ``[min, max]``) asks for the curve's ω solved exactly at those
    parameter values (one entry per crossing). ``max_step`` is the largest step along the
    curve. Returns a :class:`Boundary` (numpy columns from its ``*_columns`` methods).

    The record holds the points, the ``at`` entries, the ends and the special points (turning
    points, grazing and vanishing impact of the curve's orbit, strong resonances, crossings
    of other event curves), as the command's document. A bad argument is a
    :class:`ValueError` with the command's message naming it as this function's parameter (``event``, ``param``, ``min``, ``max``, ``at``, ``omega``,
    ``omega_min``, ``signature``, ``period``…, or the scene field out of its range); no orbit
    of the signature at ``omega``, no event of the kind on its branches, or a start that does
    not converge a :class:`RuntimeError` (``numerical failure: …``, the command's words). The
    computation releases the GIL.
    """
    text = _rattle.boundary(
        _native_scene(scene),
        {
            "signature": signature,
            "period": period,
            "event": event,
            "omega": float(omega),
            "param": param,
            "min": float(min),
            "max": float(max),
            "at": [] if at is None else [float(v) for v in at],
            "omega_min": float(omega_min),
            "omega_max": float(omega_max),
            "max_step": float(max_step),
        },
    )
    return Boundary(_json.loads(text))
