"""Options and input parsers shared by the commands, each parsed in one place.

This module imports nothing heavy (only click, the standard library and the light checks of
:mod:`rocking.core.checks`; NumPy and the numerical modules inside the functions that need them),
so that the command line answers ``--help`` and a mistyped option at once.

Every size a user can type (numbers of motions, levels, frequencies, iterations, resamples) is a
:func:`count` option, bounded by :data:`rocking.core.checks.LIMITS`; every acceleration in g a
:data:`G_LEVEL` option (at most :data:`rocking.core.checks.MAX_G`); every seed a :data:`SEED`
option; every figure file is checked by :func:`figure_file`; all of it before any work.
"""

from __future__ import annotations

import functools
import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click

from ..core import checks
from ..defaults import BAND_HZ, DEFAULT_E, FIGURE_FORMATS, FRAME_PRESETS, OVERTURN_ANGLE
from ..errors import InputError

if TYPE_CHECKING:
    import numpy as np

    from ..assessment.bodies import NamedBody
    from ..core.progress import Reporter
    from ..core.runs import RunFolder
    from ..dynamics.physics import Physics
    from ..montecarlo.backends import Compute
    from ..structures.frames import ShearFrame

#: A click command callback (what the option decorators take and return).
F = TypeVar("F", bound=Callable[..., Any])
#: An option decorator of this module (an option or a group of options).
Decorator = Callable[[Callable[..., Any]], Callable[..., Any]]

#: The paper's band of the available S_v (Section 8) as the --band text.
BAND_TEXT = f"{BAND_HZ[0]:g}:{BAND_HZ[1]:g}"


# --------------------------------------------------------------------------- parsers


def parse_range(text: str, option: str = "--agx", unit: str = "g") -> np.ndarray:
    """Values of ``start:stop:step`` [``unit``] (stop included when within 1e-9·step) or of one
    number, as a NumPy array; all must be > 0, at most :data:`rocking.core.checks.MAX_G` when
    ``unit`` is g, and their number at most the limit of levels (counted before the values are
    made).

    Values are rounded to 12 significant digits, so 0.1:0.3:0.1 gives 0.1, 0.2, 0.3 exactly as
    written rather than 0.30000000000000004.
    """
    import numpy as np

    parts = str(text).split(":")
    try:
        nums = [float(p) for p in parts]
    except ValueError:
        raise InputError(f"{option} must be start:stop:step or one number, got {text!r}") from None
    if len(nums) == 1:
        nums = [nums[0], nums[0], 1.0]
    if len(nums) != 3 or not all(math.isfinite(x) for x in nums):
        raise InputError(f"{option} must be start:stop:step (three finite numbers), got {text!r}")
    start, stop, step = nums
    if step <= 0.0:
        raise InputError(f"{option} {text}: step must be > 0, got {step:g}")
    if start <= 0.0:
        raise InputError(f"{option} {text}: values must be > 0 [{unit}], got start {start:g}")
    if stop < start:
        raise InputError(
            f"{option} {text} is an empty range: stop ({stop:g} {unit}) is below "
            f"start ({start:g} {unit})"
        )
    if unit == "g" and stop > checks.MAX_G:
        raise InputError(f"{option} {text}: " + checks.too_strong("the highest level", stop))
    n = checks.count(
        f"{option} {text}: the number of levels", _levels_in(start, stop, step), "levels"
    )
    values = start + step * np.arange(n, dtype=np.float64)
    return np.array([float(f"{v:.12g}") for v in values.tolist()])


def _levels_in(start: float, stop: float, step: float) -> int:
    """Number of values of start:stop:step (stop included when within 1e-9·step)."""
    return math.floor((stop - start) / step + 1e-9) + 1


def parse_band(text: str) -> tuple[float, float]:
    """``lo:hi`` [Hz] with 0 < lo < hi."""
    try:
        lo, hi = (float(p) for p in str(text).split(":"))
    except ValueError:
        raise InputError(f"--band must be LOW:HIGH in Hz, e.g. 0.04:0.6, got {text!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo < hi):
        raise InputError(f"--band {text}: need 0 < LOW < HIGH [Hz]")
    return lo, hi


def parse_e(text: str) -> float | str:
    """Restitution of ``--e``: a number in (0, 1] [-], or the word ``housner``."""
    from ..core.checks import restitution

    return restitution(text, "--e")


def load_bodies(spec: str) -> list[NamedBody]:
    """Bodies (:class:`rocking.assessment.bodies.NamedBody`) of ``--bodies``: a CSV file, the word
    ``paper`` for the paper's 72 bodies, or ``example`` for the shipped example file (unless a
    file of that name exists)."""
    from ..assessment.bodies import NamedBody, example_bodies_path, read_bodies_table
    from ..dynamics.body import paper_bodies

    if spec == "paper":
        return [NamedBody(b.label, b) for b in paper_bodies()]
    if spec == "example" and not Path(spec).exists():
        return read_bodies_table(example_bodies_path())
    return read_bodies_table(spec)


def frame_and_floor(frame_name: str | None, floor: int | None) -> tuple[ShearFrame | None, int]:
    """(ShearFrame or None, floor) of ``--frame`` and ``--floor`` (given together or not at all)."""
    if frame_name is None and floor is None:
        return None, 0
    if frame_name is None or floor is None:
        raise InputError("--floor and --frame go together: give both (floor 0 is the ground)")
    from ..structures.frames import ShearFrame

    if Path(frame_name).is_file():  # the user's own building: masses, stiffnesses, damping
        frame = ShearFrame.from_toml(frame_name)
    else:
        frame = ShearFrame.preset(frame_name)
    if not 0 <= floor <= frame.n_stories:
        raise InputError(
            f"--floor must be from 0 (ground) to {frame.n_stories} (roof of "
            f"{frame.name}), got {floor}"
        )
    return frame, floor


def writable_file(path: str | None, option: str) -> Path | None:
    """Check, before any work, that the file ``path`` of ``option`` can be written (its folder
    exists and is writable; it is not a folder)."""
    if path is None:
        return None
    p = Path(path)
    folder = p.parent if str(p.parent) else Path(".")
    if p.is_dir():
        raise InputError(f"{option} {path}: is a folder, not a file")
    if not folder.is_dir():
        raise InputError(f"{option} {path}: the folder {folder} does not exist")
    if not os.access(folder, os.W_OK) or (p.exists() and not os.access(p, os.W_OK)):
        raise InputError(f"{option} {path}: not writable")
    return p


def reporter(quiet: bool = False) -> Reporter:
    """The progress reporter of a command (:class:`rocking.core.progress.Reporter`); quiet: none."""
    from ..core.progress import Reporter

    return Reporter(enabled=not quiet)


def print_table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> None:
    """Print a table of text cells, columns aligned (the first to the left, the others to the
    right: numbers), ``header`` (with the units) first."""
    widths = [max(len(r[j]) for r in (header, *rows)) for j in range(len(header))]
    for r in (header, *rows):
        cells = [r[0].ljust(widths[0]), *(c.rjust(w) for c, w in zip(r[1:], widths[1:]))]
        click.echo("  ".join(cells).rstrip())


def figure_file(path: str | None, option: str) -> Path | None:
    """Check, before any work, that ``path`` of ``option`` names a figure Matplotlib can write
    (its extension one of :data:`rocking.defaults.FIGURE_FORMATS`, or none: PNG) in a writable
    folder."""
    if path is None:
        return None
    suffix = Path(path).suffix.lower().lstrip(".")
    if suffix and suffix not in FIGURE_FORMATS:
        raise InputError(
            f"{option} {path}: Matplotlib cannot write a figure as .{suffix}; use one of "
            f"{', '.join('.' + f for f in FIGURE_FORMATS)}"
        )
    return writable_file(path, option)


# --------------------------------------------------------------------------- option types


class _Count(click.ParamType):
    """An integer size of the kind ``kind`` of :data:`rocking.core.checks.LIMITS`, from
    ``minimum`` to its limit."""

    name = "integer"

    def __init__(self, kind: str, minimum: int = 1):
        self.kind, self.minimum = kind, minimum

    def convert(self, value, param, ctx):
        number = click.INT.convert(value, param, ctx)
        return checks.count(_name(param), number, self.kind, self.minimum)


class _Seed(click.ParamType):
    """A seed from 0 to :data:`rocking.core.checks.MAX_SEED`."""

    name = "integer"

    def convert(self, value, param, ctx):
        return checks.seed(_name(param), click.INT.convert(value, param, ctx))


class _Intensity(click.ParamType):
    """An acceleration [g] > 0 and at most :data:`rocking.core.checks.MAX_G`."""

    name = "float"

    def convert(self, value, param, ctx):
        return checks.intensity_g(_name(param), click.FLOAT.convert(value, param, ctx))


def _name(param: click.Parameter | None) -> str:
    return "value" if param is None else max(param.opts, key=len)


def count(kind: str, minimum: int = 1) -> click.ParamType:
    """The click type of an option that is a size of ``kind`` (a key of
    :data:`rocking.core.checks.LIMITS`: "motions", "levels", "frequencies", ...)."""
    return _Count(kind, minimum)


#: The click type of every seed option.
SEED = _Seed()
#: The click type of every option that is an acceleration in g (PGA, A_gx).
G_LEVEL = _Intensity()


# --------------------------------------------------------------------------- options

bodies_option = click.option(
    "--bodies",
    "bodies_spec",
    required=True,
    metavar="FILE|paper|example",
    help="Bodies CSV with columns R [m] and gamma [-], or H [m] and B [m], and optionally name "
    "and the friction coefficients mu and mu_k [-] of each body (in place of --mu, --mu-k); "
    "'paper' for the paper's 72 bodies (R = 4-11 ft, gamma = 2-6); 'example' for the "
    "shipped example file (the paper's two Section 8 blocks and five pieces of "
    "equipment).",
)
quiet_option = click.option("--quiet", is_flag=True, help="No progress bars or messages.")
R_option = click.option(
    "--R", "R", type=float, required=True, help="Size R = half the diagonal [m]."
)
gamma_option = click.option("--gamma", type=float, required=True, help="Slenderness H/B [-].")
scheduler_option = click.option(
    "--scheduler",
    default=None,
    metavar="ADDRESS",
    help="'local' (default: all cores here), 'dask-local' (a local Dask cluster) or a Dask "
    "scheduler address tcp://HOST:PORT.",
)
connect_timeout_option = click.option(
    "--connect-timeout",
    type=click.FloatRange(0.0, min_open=True),
    default=None,
    metavar="SECONDS",
    help="With --scheduler tcp://HOST:PORT: seconds to wait for the scheduler before giving up "
    "[default: 5 for a loopback or private address, 30 for others].",
)
overwrite_option = click.option(
    "--overwrite",
    is_flag=True,
    help="Replace the results of another run in --out (deleted once this run's inputs are "
    "checked); without it such a folder is refused. The same run resumes without it.",
)
e_option = click.option(
    "--e",
    "e_text",
    default=f"{DEFAULT_E:g}",
    show_default=True,
    metavar="E|housner",
    help="Coefficient of restitution [-] in (0, 1], or 'housner' (1 - 1.5 sin^2 alpha per body).",
)
frame_option = click.option(
    "--frame",
    "frame_name",
    default=None,
    metavar="FRAME",
    help=f"Shear frame: a preset ({', '.join(FRAME_PRESETS)}) or a TOML file of your building "
    "(masses_kg, stiffnesses_N_per_m, damping; see 'rocking frame show --help').",
)
band_option = click.option(
    "--band",
    "band_text",
    default=BAND_TEXT,
    show_default=True,
    metavar="LOW:HIGH",
    help="Frequency band [Hz] of the available S_v (max of the mean 5 %-damped PSV).",
)


def options(*opts: Callable[[F], F]) -> Callable[[F], F]:
    """Apply click options in the order given (first listed first in --help)."""

    def apply(func: F) -> F:
        for option in reversed(opts):
            func = option(func)
        return func

    return apply


# --------------------------------------------------------------------------- option groups


def option_group(
    name: str, build: Callable[..., Any], *opts: Decorator, reads: Sequence[str] = ()
) -> Decorator:
    """Options ``opts`` (listed in --help where the group is) that reach the command as one
    parameter ``name``: ``build`` of their values, in the order of ``opts``, then of the
    options named ``reads`` (declared elsewhere on the command).  Built when the command runs,
    before its own code: a bad value is refused before any work."""

    def probe() -> None: ...

    names = [p.name for p in getattr(options(*opts)(probe), "__click_params__", [])]
    names = [*reversed(names), *reads]  # click keeps the declarations last first

    def apply(func: Callable[..., Any]) -> Callable[..., Any]:
        @functools.wraps(func)
        def command(*args: Any, **kwargs: Any) -> Any:
            kwargs[name] = build(*(kwargs.pop(n) for n in names))
            return func(*args, **kwargs)

        return options(*opts)(command)

    return apply


#: --overturn-angle's choices: the paper's π/2 [rad], or the critical angle α.
OVERTURN_CHOICES: dict[str, float | str] = {"pi2": OVERTURN_ANGLE, "alpha": "alpha"}


mu_option = click.option(
    "--mu",
    "mu",
    type=float,
    default=None,
    metavar="MU",
    help="Static friction coefficient of the bases [-], > 0: the bodies may then slide, "
    "slide-rock and fly, not only rock [default: infinite friction, the paper's model]. A "
    "bodies CSV may give its own per body (column mu).",
)
mu_k_option = click.option(
    "--mu-k",
    "mu_k",
    type=float,
    default=None,
    metavar="MU_K",
    help="Kinetic friction coefficient [-], at most --mu [default: --mu].",
)


def _physics(
    e_text: str | None = None,
    overturn: str | None = None,
    mu: float | None = None,
    mu_k: float | None = None,
) -> Physics:
    from ..dynamics.physics import Physics

    fields: dict[str, Any] = {}
    if e_text is not None:
        fields["e"] = parse_e(e_text)
    if overturn is not None:
        fields["overturn_angle"] = OVERTURN_CHOICES[overturn]
    for option, value in (("--mu", mu), ("--mu-k", mu_k)):
        if value is not None:
            checks.positive(option, value, "-")
    checks.kinetic_friction(mu, mu_k, names=("--mu", "--mu-k"))
    return Physics(**fields, mu=mu, mu_k=mu_k)


resolution_option = click.option(
    "--resolution",
    type=click.FloatRange(1e-6),
    default=0.01,
    show_default=True,
    help="Resolution of the A_gx50 search [g], >= 1e-6.",
)
agx_max_option = click.option(
    "--agx-max",
    type=G_LEVEL,
    default=5.0,
    show_default=True,
    help="Upper end of the A_gx50 search [g], at most 10; beyond it A_gx50 is NaN.",
)


def physics_options(restitution: bool = True, overturn_angle: bool = False) -> Decorator:
    """The options of the physics of a command's simulations, as one parameter ``physics`` (a
    :class:`rocking.Physics`): --e, unless the command's bodies carry their own restitution
    (``restitution=False``), --mu and --mu-k (friction, issue 45), and with ``overturn_angle``
    the command's --overturn-angle (parameter ``overturn``, one of :data:`OVERTURN_CHOICES`,
    listed where the command lists it).  An option of the physics is added here, for every
    command that simulates."""

    def build(*values: Any) -> Physics:
        given = list(values)
        e_text = given.pop(0) if restitution else None
        mu, mu_k = given.pop(0), given.pop(0)
        return _physics(e_text, given.pop(0) if overturn_angle else None, mu, mu_k)

    return option_group(
        "physics",
        build,
        *([e_option] if restitution else []),
        mu_option,
        mu_k_option,
        reads=("overturn",) if overturn_angle else (),
    )


def friction_params(physics: Physics) -> dict:
    """What a command's run.json records about friction (``mu``, ``mu_k``: one value or one per
    body): nothing without it, as before issue 45."""
    if physics.mu is None and physics.mu_k is None:
        return {}
    return {"mu": physics.params()["mu"], "mu_k": physics.params()["mu_k"]}


def _compute(scheduler: str | None, connect_timeout: float | None, quiet: bool) -> Compute:
    from ..montecarlo.backends import Compute, get_backend

    return Compute(backend=get_backend(scheduler, connect_timeout), progress=reporter(quiet))


def compute_options(scheduler: Decorator | None = None) -> Decorator:
    """--scheduler (the command's own ``scheduler`` option, default :data:`scheduler_option`)
    and --connect-timeout, with --quiet (listed where the command lists it), as one parameter
    ``compute`` (a :class:`rocking.montecarlo.backends.Compute`: the backend, not yet
    connected, and the progress reporter)."""
    return option_group(
        "compute",
        _compute,
        scheduler or scheduler_option,
        connect_timeout_option,
        reads=("quiet",),
    )


@dataclass(frozen=True)
class OutFolder:
    """--out and --overwrite of a command: the folder its run writes."""

    path: str
    overwrite: bool = False

    def claim(self, command: str, params: dict, **more: Any) -> RunFolder:
        """The run folder (:class:`rocking.core.runs.RunFolder`) of ``command`` with its
        ``params`` (``more``: its other arguments, e.g. ``reads``)."""
        from ..core.runs import RunFolder

        return RunFolder(
            self.path, command=command, params=params, overwrite=self.overwrite, **more
        )


def run_folder_options(out: Decorator) -> Decorator:
    """The command's own --out option ``out`` and --overwrite, as one parameter ``folder`` (an
    :class:`OutFolder`)."""
    return option_group("folder", OutFolder, out, overwrite_option)
