"""Parameters of the studies: fidelity presets and their override by a TOML file or ``--set``.

A configuration is a nested mapping ``{section: {key: value}}``. :data:`PRESETS` holds two:
``"paper"`` (the paper's ensemble sizes, dt = 1/400 s, the 72 bodies) and ``"quick"`` (small
ensembles, dt = 1/200 s, coarse A_gx grids, a 3 × 3 subset of the bodies: a check of every
section in a fraction of the paper's cost; the tutorial on reproducing the paper gives run
times). A TOML file given with ``--config`` replaces any of the keys below (a key it does not
name keeps the preset's value); ``--set section.key=VALUE`` (VALUE in
TOML syntax) does the same from the command line and wins over the file;
``rocking reproduce all --show-config`` prints the result as TOML. :func:`validate` checks the
values (bodies, frames, envelopes, motion numbers, and every number against its range: sizes
within :data:`rocking.core.checks.LIMITS`, seeds, accelerations in g up to
:data:`rocking.core.checks.MAX_G`, restitution in (0, 1], every other number finite and > 0)
before a run starts.

Keys (units in brackets; "No. k" motion numbers count from 1 as in the paper; body lists are
``[[R, gamma], ...]`` [m, -], the string ``"paper"`` for the 72 bodies of Tables 1–3, or the path
of a CSV file read by :func:`rocking.assessment.bodies.read_bodies`; frames are preset names of
:data:`rocking.structures.frames.PRESETS` or paths of frame TOML files, see
:meth:`rocking.structures.frames.ShearFrame.from_toml`):

``[common]`` — motions of Sections 4, 5, 7 and 8 (RG 1.60 target):
    ``dt`` [s] time step of motions and rocking solver; ``e`` [-] coefficient of restitution;
    ``envelope`` ("boxcar", "trapezoidal", "compound"); ``duration`` [s];
    ``envelope_params`` (table, e.g. ``{t1 = 2.0, t2 = 12.0, c = 0.25}`` [s, s, 1/s]; empty: the
    duration rule of :mod:`rocking.motions.envelopes`); ``iterations`` [-] spectral-matching
    iterations
    of :func:`rocking.motions.synthesis.generate` (the paper: 0).
``[sec4]`` baseline correction (Figs. 3–4): ``seed``; ``motion`` (No.); ``R`` [m]; ``gammas``;
    ``agx`` [g] (the motion's own PGA); ``n_check`` [-] motions over which the share of changed
    outcomes is counted.
``[sec5]`` sensitivity (Figs. 5–8): ``seed``; ``n`` (ensemble size, ≥ every motion No.);
    ``R``, ``gamma``, ``agx`` (Fig. 5 body and PGA); ``motions`` (Fig. 5 Nos.);
    ``scale_motion``, ``scales`` [g] (Fig. 6); ``size_motion``, ``size_agx`` [g], ``sizes`` [m],
    ``size_gamma`` (Fig. 7); ``e_R`` [m], ``e_values`` [-] (Fig. 8, motion and PGA as Fig. 7);
    ``gammas`` (slenderness sweep with R = ``e_R``, motion and PGA of Fig. 7).
``[sec6]`` duration and intensity function (Figs. 9–10): ``seed``; ``n``; ``durations`` [s];
    ``envelopes``; ``bodies`` (one Fig. 9 per body; Fig. 10 for the first); ``agx`` [g] grid;
    ``fig10_durations`` [s].
``[sec7]`` floors (Figs. 11–12): ``seed``; ``n``; ``frames``; ``bodies``; ``agx`` [g] grid;
    ``spectra_agx`` [g] (Fig. 12); ``n_freq`` [-] frequencies of the Fig. 12 spectra;
    ``fig11_body`` ([R, gamma] of the Fig. 11 curves; the first body if it is not run).
``[sec8]`` energy balance (Figs. 13–16, Tables 1–3): ``seed``; ``n``; ``bodies``; ``frame``;
    ``floor``; ``resolution`` [g] and ``agx_max`` [g] of the A_gx50 search; ``fig13_agx`` [g]
    grid of the Fig. 13 curve; ``examples`` (bodies of the worked examples); ``example_agx`` [g];
    ``band_hz`` [Hz].
``[soundness]`` numerical and statistical soundness (issue 17, :mod:`.soundness`): ``seed``;
    ``n`` (ground motions of the bootstrap, strength and floor parts); ``bodies``;
    ``resolution`` and ``agx_max`` [g] of the A_gx50 searches; ``band_hz`` [Hz];
    ``dts`` [s] (time steps of the convergence part, each a whole multiple of the smallest);
    ``convergence_n``, ``convergence_bodies``, ``convergence_resolution`` [g];
    ``bootstrap`` (resamples), ``bootstrap_seed``, ``grid_span`` [-] and ``grid_levels`` (the
    A_gx grid of the bootstrap, (1 ± span)·A_gx50), ``target_g`` [g] (half-width asked of
    A_gx50); ``variant_bodies`` (bodies of the strength part); ``floor_frame``,
    ``floor_periods`` [s], ``floor_dampings`` [-], ``floor_agx`` [g] (the frame scan).
``[friction]`` beyond the paper: Section 8's A_gx50 and Table 3 with friction (issue 45,
    :mod:`.friction`): ``seed``; ``n``; ``bodies``; ``mu`` [-] (static friction coefficients;
    infinite friction is always added); ``kinetic_ratio`` [-] (μ_k/μ, in (0, 1]; 1: kinetic =
    static); ``resolution`` [g] and ``agx_max`` [g] of the A_gx50 searches; ``band_hz`` [Hz].
"""

from __future__ import annotations

import copy
import hashlib
import json
import os
import tomllib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..core import checks
from ..core.checks import in_range, read_toml, restitution
from ..defaults import BAND_HZ, DEFAULT_E, DT
from ..dynamics.body import FOOT, Block, paper_bodies
from ..dynamics.physics import Physics
from ..errors import InputError
from ..structures.frames import PRESETS as FRAME_PRESETS
from ..structures.frames import ShearFrame

if TYPE_CHECKING:
    from ..core.progress import Reporter
    from ..montecarlo.backends import Backend
    from ..motions.ensemble import Ensemble


def _ft(*feet: float) -> list[float]:
    """Sizes given in whole feet as metres (the paper prints 4 ft as 1.22 m)."""
    return [round(f * FOOT, 10) for f in feet]


def _grid(lo: float, hi: float, step: float) -> list[float]:
    n = round((hi - lo) / step)
    return [round(lo + i * step, 10) for i in range(n + 1)]


_R4, _R8, _R12 = _ft(4, 8, 12)

PAPER: dict = {
    "common": {
        "dt": DT,
        "e": DEFAULT_E,
        "envelope": "compound",
        "duration": 20.0,
        "envelope_params": {},
        "iterations": 0,
    },
    "sec4": {
        "seed": 1,
        "motion": 1,
        "R": _ft(10)[0],
        "gammas": [3.75, 4.0, 5.0, 6.0],
        "agx": 0.6,
        "n_check": 100,
    },
    "sec5": {
        "seed": 1,
        "n": 25,
        "R": _R12,
        "gamma": 5.0,
        "agx": 0.6,
        "motions": [10, 12, 19, 23],
        "scale_motion": 25,
        "scales": [0.35, 0.45, 0.6, 0.75],
        "size_motion": 1,
        "size_agx": 0.5,
        "sizes": _ft(5, 10, 12, 14),
        "size_gamma": 5.0,
        "e_R": _ft(10)[0],
        "e_values": [0.80, 0.88, 0.92, 0.93],
        "gammas": [3.75, 4.0, 5.0, 6.0],
    },
    "sec6": {
        "seed": 6,
        "n": 500,
        "durations": [10.0, 15.0, 20.0, 25.0, 30.0],
        "envelopes": ["boxcar", "trapezoidal", "compound"],
        "bodies": [[_R4, 4.0], [_R12, 4.0]],
        "agx": _grid(0.1, 1.5, 0.1),
        "fig10_durations": [15.0, 20.0, 25.0, 30.0],
    },
    "sec7": {
        "seed": 7,
        "n": 500,
        "frames": ["paper-2.0", "paper-1.5", "paper-1.0", "paper-0.5"],
        "bodies": [[r, g] for r in (_R4, _R8, _R12) for g in (3.0, 4.0)],
        "agx": _grid(0.3, 0.8, 0.05),
        "spectra_agx": 0.6,
        "n_freq": 150,
        "fig11_body": [_R4, 4.0],
    },
    "sec8": {
        "seed": 8,
        "n": 200,
        "bodies": "paper",
        "frame": "paper-2.0",
        "floor": 1,
        "resolution": 0.01,
        "agx_max": 5.0,
        "fig13_agx": _grid(0.5, 1.6, 0.05),
        "examples": [[_R4, 2.0], [_R4, 4.0]],
        "example_agx": 0.6,
        "band_hz": list(BAND_HZ),
    },
    "soundness": {
        "seed": 8,
        "n": 200,
        "bodies": "paper",
        "resolution": 0.01,
        "agx_max": 5.0,
        "band_hz": list(BAND_HZ),
        "dts": [2 * DT, DT, DT / 2, DT / 4],  # 1/200 … 1/1600 s, exactly
        "convergence_n": 200,
        "convergence_bodies": "paper",
        "convergence_resolution": 0.001,
        "bootstrap": 1000,
        "bootstrap_seed": 17,
        "grid_span": 0.3,
        "grid_levels": 61,
        "target_g": 0.01,
        "variant_bodies": [[r, g] for r in _ft(4, 7, 10) for g in (2.0, 4.0, 6.0)],
        "floor_frame": "paper-2.0",
        "floor_periods": [0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0],
        "floor_dampings": [0.02, 0.05, 0.1, 0.2],
        "floor_agx": 0.6,
    },
    "friction": {
        "seed": 8,
        "n": 200,
        "bodies": "paper",
        "mu": [0.3, 0.4, 0.5, 0.6, 0.7, 0.8],
        "kinetic_ratio": 1.0,
        "resolution": 0.01,
        "agx_max": 5.0,
        "band_hz": list(BAND_HZ),
    },
}

QUICK: dict = copy.deepcopy(PAPER)
QUICK["common"]["dt"] = 1 / 200
QUICK["sec4"]["n_check"] = 25
QUICK["sec6"].update(
    n=40, agx=_grid(0.2, 1.4, 0.3), durations=[10.0, 20.0, 25.0, 30.0], fig10_durations=[20.0, 30.0]
)
QUICK["sec7"].update(
    n=30, agx=[0.3, 0.55, 0.8], n_freq=40, bodies=[[_R4, 3.0], [_R4, 4.0], [_R12, 4.0]]
)
QUICK["sec8"].update(
    n=40,
    bodies=[[r, g] for r in _ft(4, 7, 10) for g in (2.0, 4.0, 6.0)],
    resolution=0.02,
    fig13_agx=_grid(0.6, 1.4, 0.2),
)
# the friction study runs seven A_gx50 searches (six μ and infinite friction): three bodies of
# B/H = 1/2, 1/4 and 1/6 (one below, one inside and one above the μ range) and few motions
QUICK["friction"].update(
    n=20, bodies=[[_R4, 2.0], [_R4, 4.0], [_R4, 6.0]], resolution=0.05, agx_max=3.0
)
QUICK["soundness"].update(
    n=40,
    bodies=[[r, g] for r in _ft(4, 10) for g in (2.0, 4.0)],
    convergence_n=40,
    convergence_bodies=[[_R4, 2.0], [_R4, 4.0], [_ft(10)[0], 4.0]],
    convergence_resolution=0.005,
    bootstrap=200,
    grid_span=0.4,
    grid_levels=21,
    variant_bodies=[[_R4, 2.0], [_R4, 4.0]],
    floor_periods=[0.75, 1.0, 1.5, 2.0],
    floor_dampings=[0.05, 0.2],
)

#: Fidelity presets by name.
PRESETS = {"quick": QUICK, "paper": PAPER}
#: Sections and their keys (those of the presets).
SECTIONS = tuple(PAPER)


def load_config(
    fidelity: str = "quick",
    path: str | os.PathLike[str] | None = None,
    sets: Sequence[str] = (),
) -> dict:
    """The configuration of a run: a preset, then a TOML file, then ``section.key=VALUE`` sets.

    Parameters
    ----------
    fidelity : str
        Preset name: "quick" or "paper".
    path : str or Path, optional
        TOML file with ``[section]`` tables of keys to replace (see the module docstring).
    sets : sequence of str
        Overrides ``"section.key=VALUE"`` (VALUE in TOML syntax, e.g. ``sec8.n=100``,
        ``sec7.frames=["paper-0.5"]``, ``common.envelope="boxcar"``).

    Returns
    -------
    dict
        ``{section: {key: value}}`` with every key of the preset.
    """
    if fidelity not in PRESETS:
        raise InputError(f"unknown fidelity {fidelity!r}; choose one of {', '.join(PRESETS)}")
    cfg = copy.deepcopy(PRESETS[fidelity])
    if path is not None:
        path = Path(path)
        data = read_toml(path, f"config {path}")
        for section, table in data.items():
            if not isinstance(table, dict):
                raise InputError(
                    f"config {path}: {section!r} must be a [section] table of "
                    f"keys; sections are {', '.join(SECTIONS)}"
                )
            for key, value in table.items():
                _override(cfg, section, key, value, f"config {path}")
    for item in sets:
        name, sep, text = str(item).partition("=")
        section, dot, key = name.strip().partition(".")
        if not sep or not dot:
            raise InputError(f"--set {item!r}: expected section.key=VALUE, e.g. sec8.n=100")
        try:
            value = tomllib.loads(f"v = {text.strip()}")["v"]
        except tomllib.TOMLDecodeError:
            raise InputError(
                f"--set {item!r}: VALUE must be written in TOML syntax (numbers, "
                '"strings", [lists])'
            ) from None
        _override(cfg, section, key.strip(), value, "--set")
    return cfg


def to_toml(cfg: dict) -> str:
    """The configuration as a TOML file that :func:`load_config` reads back unchanged
    (``--show-config`` prints it: a starting point for a ``--config`` file)."""
    lines = []
    for section, table in cfg.items():
        lines.append(f"[{section}]")
        lines += [f"{key} = {_toml_value(value)}" for key, value in table.items()]
        lines.append("")
    return "\n".join(lines)


def _toml_value(value: object) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)  # shortest round-trip form of a float
    if isinstance(value, str):
        return json.dumps(value)  # a JSON string is a valid TOML basic string
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_toml_value(v)}" for k, v in value.items()) + "}"
    raise InputError(f"cannot write {value!r} as TOML")


def _override(cfg: dict, section: str, key: str, value: object, where: str) -> None:
    """Replace ``cfg[section][key]`` by ``value`` after checking the name and the type."""
    if section not in cfg:
        raise InputError(
            f"{where}: unknown section [{section}]; sections are {', '.join(SECTIONS)}"
        )
    if key not in cfg[section]:
        raise InputError(
            f"{where}: unknown key {key!r} in [{section}]; keys are {', '.join(cfg[section])}"
        )
    old = cfg[section][key]
    if not _same_kind(old, value):
        raise InputError(f"{where}: [{section}] {key} must be {_kind(old)}, got {value!r}")
    cfg[section][key] = value


def _same_kind(old: object, new: object) -> bool:
    if key_is_bodies(old):  # body lists: "paper", a CSV path or [[R, gamma], ...]
        return isinstance(new, str) or (
            isinstance(new, list)
            and all(
                isinstance(p, list) and len(p) == 2 and all(_is_number(x) for x in p) for p in new
            )
        )
    if isinstance(old, bool) or isinstance(new, bool):
        return type(old) is type(new)
    if isinstance(old, float):
        return _is_number(new)
    if isinstance(old, list):
        return (
            isinstance(new, list)
            and bool(new)
            and all(_same_kind(old[0], x) if old else True for x in new)
        )
    return type(old) is type(new)


def key_is_bodies(value: object) -> bool:
    """True if a preset value is a body list (``"paper"`` or ``[[R, gamma], ...]``)."""
    return value == "paper" or (
        isinstance(value, list) and bool(value) and isinstance(value[0], list)
    )


def _is_number(x: object) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _kind(old: object) -> str:
    if key_is_bodies(old):
        return '"paper", a CSV path or a list of [R, gamma] pairs'
    if isinstance(old, list):
        return f"a non-empty list of {_kind(old[0])}s" if old else "a list"
    return {
        float: "a number",
        int: "an integer",
        str: "a string",
        dict: "a table",
        bool: "true or false",
    }.get(type(old), type(old).__name__)


def resolve_bodies(value: str | Sequence[Sequence[float]], where: str) -> list[Block]:
    """Blocks of a body-list value (``"paper"``, a CSV path or ``[[R, gamma], ...]``);
    ``where`` (e.g. ``"sec8.bodies"``) names the key in error messages."""
    if value == "paper":
        return paper_bodies()
    if isinstance(value, str):
        from ..assessment.bodies import read_bodies

        return read_bodies(value)
    try:
        return [Block(r, g) for r, g in value]
    except (InputError, TypeError, ValueError) as exc:
        raise InputError(f"{where}: {exc}") from None


def resolve_frame(name: str) -> ShearFrame:
    """A frame preset by name, or a frame TOML file by path (``*.toml``)."""
    if name in FRAME_PRESETS or not str(name).endswith(".toml"):
        return ShearFrame.preset(name)
    return ShearFrame.from_toml(name)


#: Keys whose values are sizes: the kind of :data:`rocking.core.checks.LIMITS` and the least value.
_COUNTS = {
    "n": ("motions", 1),
    "convergence_n": ("motions", 1),
    "n_check": ("motions", 1),
    "bootstrap": ("bootstrap resamples", 1),
    "grid_levels": ("levels", 3),
    "n_freq": ("frequencies", 2),
    "iterations": ("iterations", 0),
}
#: Keys whose values are accelerations [g] (A_gx, PGA, resolutions of A_gx).
_G_KEYS = {
    *("agx", "scales", "size_agx", "spectra_agx", "fig13_agx", "example_agx", "agx_max"),
    *("floor_agx", "resolution", "convergence_resolution", "target_g"),
}
#: Keys whose values are motion numbers (from 1) or floors (from 0: the ground).
_NUMBERS = {"motion": 1, "motions": 1, "scale_motion": 1, "size_motion": 1, "floor": 0}


def _check_number(key: str, where: str, x: object) -> None:
    """Check one number ``x`` of the key ``key`` (``where``: section.key) against its range."""
    if key in _COUNTS:
        kind, least = _COUNTS[key]
        checks.count(where, x, kind, least)
    elif key.endswith("seed"):
        checks.seed(where, x)
    elif key in _NUMBERS:
        if not isinstance(x, int) or x < _NUMBERS[key]:
            raise InputError(f"{where} must be an integer >= {_NUMBERS[key]}, got {x!r}")
    elif key in _G_KEYS:
        checks.intensity_g(where, x)  # type: ignore[arg-type]
    elif key in ("e", "e_values"):
        restitution(x, where)  # type: ignore[arg-type]
    elif key == "floor_dampings":
        in_range(where, x, 0.0, 1.0, lo_open=True, hi_open=True, unit="-")  # type: ignore[arg-type]
    else:
        checks.positive(where, x)  # type: ignore[arg-type]


def _check_numbers(cfg: dict) -> None:
    """Every number of the configuration (except the bodies and the envelope parameters, which
    their own checks judge) against the range of its key."""
    for section, table in cfg.items():
        for key, value in table.items():
            if key_is_bodies(value) or isinstance(value, (str, dict)):
                continue
            for x in value if isinstance(value, list) else [value]:
                if not isinstance(x, str):
                    _check_number(key, f"{section}.{key}", x)


def validate(cfg: dict) -> None:
    """Check the values that only the library can judge (bodies, frames, envelopes, motion
    numbers, the range of every number) before any work starts; errors name the key, e.g.
    ``sec7.frames: ...``."""
    from ..motions.envelopes import make_envelope

    _check_numbers(cfg)
    c = cfg["common"]
    checks: dict[str, Callable[[], object]] = {
        "common.envelope_params": lambda: make_envelope(
            c["envelope"], c["duration"], **c["envelope_params"]
        ),
        "sec6.envelopes": lambda: [
            make_envelope(env, dur)
            for env in cfg["sec6"]["envelopes"]
            for dur in cfg["sec6"]["durations"]
        ],
        "sec7.frames": lambda: [resolve_frame(f) for f in cfg["sec7"]["frames"]],
        "sec8.frame": lambda: resolve_frame(cfg["sec8"]["frame"]),
        "soundness.floor_frame": lambda: resolve_frame(cfg["soundness"]["floor_frame"]),
        "sec7.fig11_body": lambda: Block(*cfg["sec7"]["fig11_body"]),
    }
    checks.update(
        {
            f"{sec}.{key}": partial(resolve_bodies, cfg[sec][key], f"{sec}.{key}")
            for sec, key in (
                ("sec6", "bodies"),
                ("sec7", "bodies"),
                ("sec8", "bodies"),
                ("sec8", "examples"),
                ("soundness", "bodies"),
                ("soundness", "convergence_bodies"),
                ("soundness", "variant_bodies"),
                ("friction", "bodies"),
            )
        }
    )
    for where, check in checks.items():
        try:
            check()
        except (InputError, OSError, TypeError) as exc:
            msg = str(exc)
            raise InputError(msg if msg.startswith(where) else f"{where}: {msg}") from None
    stories = {resolve_frame(f).n_stories for f in cfg["sec7"]["frames"]}
    if len(stories) > 1:
        raise InputError(
            f"sec7.frames: the frames must have the same number of stories "
            f"(their floors are compared side by side), got {sorted(stories)}"
        )
    p = cfg["sec5"]
    numbers = p["motions"] + [p["scale_motion"], p["size_motion"]]
    if min(numbers) < 1 or max(numbers) > p["n"]:
        raise InputError(
            f"sec5: motion numbers must lie in 1..n = {p['n']} (the ensemble "
            f"size); got {sorted(numbers)}"
        )
    dts, duration = sorted(cfg["soundness"]["dts"]), c["duration"]
    if (
        len(dts) < 3
        or dts[0] <= 0
        or not all(_whole(d / dts[0]) and _whole(duration / d) for d in dts)
    ):
        raise InputError(
            "soundness.dts: give at least three positive time steps, each a whole multiple "
            f"of the smallest and dividing the duration ({duration:g} s) into whole steps, "
            f"got {cfg['soundness']['dts']}"
        )
    span, levels = cfg["soundness"]["grid_span"], cfg["soundness"]["grid_levels"]
    if not (0.0 < span < 1.0 and isinstance(levels, int) and levels >= 3):
        raise InputError(
            "soundness: grid_span must lie in (0, 1) (the bootstrap grid spans A_gx50 × "
            f"(1 ± grid_span), above 0 g) and grid_levels be an integer >= 3, got {span!r} "
            f"and {levels!r}"
        )
    friction_coefficients(cfg["friction"]["mu"], "friction.mu")
    in_range("friction.kinetic_ratio", cfg["friction"]["kinetic_ratio"], 0.0, 1.0, lo_open=True)
    if cfg["sec4"]["motion"] < 1 or cfg["sec4"]["n_check"] < 1:
        raise InputError("sec4: motion (No., from 1) and n_check must be ≥ 1")


def friction_coefficients(mus: Sequence[float], name: str) -> list[float]:
    """The static friction coefficients [-] of the friction study as floats, checked: at least
    one, each once (:class:`InputError` naming the parameter ``name``)."""
    values = [float(m) for m in mus]
    if not values or len(set(values)) < len(values):
        raise InputError(
            f"{name} must hold at least one friction coefficient, each once, got {list(mus)}"
        )
    return values


def _whole(x: float) -> bool:
    return abs(x - round(x)) <= 1e-9 * max(1.0, abs(x))


@dataclass(frozen=True)
class RunContext:
    """What every study needs besides its parameters.

    Attributes
    ----------
    cfg : dict
        The configuration (:func:`load_config`).
    fidelity : str
        Preset name the configuration started from.
    modified : bool
        True if a config file or ``--set`` changed the preset.
    backend : Backend or None
        Backend of :mod:`rocking.montecarlo.probability` (None: local).
    progress : bool, None or rocking.core.progress.Reporter
        Progress of the Monte Carlo runs (:func:`rocking.core.progress.resolve`; None: bars
        only when writing to a terminal).
    chunks : Path or None
        Folder of finished Monte Carlo chunks (None: keep nothing on disk).
    """

    cfg: dict
    fidelity: str = "quick"
    modified: bool = False
    backend: Backend | None = None
    progress: bool | Reporter | None = False
    chunks: Path | None = None

    @property
    def physics(self) -> Physics:
        """The physics of every simulation of the run (the common restitution ``e``)."""
        return Physics(e=self.cfg["common"]["e"])

    def store(self, section: str, name: str) -> Path | None:
        """Chunk folder of one Monte Carlo call, ``chunks/<section>-<hash>/<name>``: the hash
        covers the section's and the common parameters, so changed parameters never meet the
        chunks of an earlier run (see :class:`rocking.montecarlo.store.ChunkStore`)."""
        if self.chunks is None:
            return None
        text = json.dumps(
            {"common": self.cfg["common"], section: self.cfg[section]}, sort_keys=True
        )
        return self.chunks / f"{section}-{hashlib.sha256(text.encode()).hexdigest()[:10]}" / name

    def label(self, **counts: object) -> str:
        """Fidelity note for titles and captions, e.g. "quick fidelity: n=40, dt=1/200 s"."""
        parts = [f"{k}={v}" for k, v in counts.items()]
        parts.append(f"dt=1/{1 / self.cfg['common']['dt']:.0f} s")
        mod = " (modified by config)" if self.modified else ""
        return f"{self.fidelity} fidelity{mod}: {', '.join(parts)}"

    def motions(self, section: str, n: int, **changes: Any) -> Ensemble:
        """``n`` simulated motions with the common settings and the section's seed
        (:func:`rocking.motions.synthesis.generate`); ``changes`` override generate()'s
        arguments."""
        from ..motions.synthesis import generate

        c = self.cfg["common"]
        kwargs = dict(
            duration=c["duration"],
            dt=c["dt"],
            envelope=c["envelope"],
            envelope_params=c["envelope_params"] or None,
            iterations=c["iterations"],
            seed=self.cfg[section]["seed"],
        )
        kwargs.update(changes)
        return generate(n, **kwargs)
