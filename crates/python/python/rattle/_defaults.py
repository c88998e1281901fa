"""The commands' defaults, read from the Rust library so that Python and the command agree."""

from . import _rattle

#: The simulator's default accuracy knobs, as the command's: ``tol`` (relative tolerance of
#: contact times), ``steady_tol`` (of the periodicity test), ``max_periods`` (cap on forcing
#: periods), ``max_oscillations`` (cap on free oscillations of the fastest mode).
DEFAULTS = dict(_rattle.defaults())

_TOL = DEFAULTS["tol"]
_STEADY_TOL = DEFAULTS["steady_tol"]
_MAX_PERIODS = DEFAULTS["max_periods"]
_MAX_OSCILLATIONS = DEFAULTS["max_oscillations"]

#: The continuation's default settings, as the command's: ``max_step`` (largest step along a
#: branch, in α, impact phases and ω together), ``max_branches`` (cap on the branches
#: followed per start orbit) and ``max_depth`` (switching depth).
CONTINUATION_DEFAULTS = dict(_rattle.continuation_defaults())

#: The boundary's default settings, as the command's: ``omega_min`` and ``omega_max`` (the
#: frequency range of the event search and of the curve) and ``max_step`` (largest step along
#: the curve, in α, impact phases, ω and the parameter together).
BOUNDARY_DEFAULTS = dict(_rattle.boundary_defaults())

#: Uniform samples per forcing period of a trajectory by default, as the command's
#: ``--samples-per-period``.
SAMPLES_PER_PERIOD = 200

#: Forcing periods of the Lyapunov exponents' run by default, as the command's
#: ``--lyapunov-periods``.
LYAPUNOV_PERIODS = _rattle.LYAPUNOV_PERIODS
