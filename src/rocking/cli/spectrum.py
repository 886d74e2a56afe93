"""``rocking spectrum``: response spectra of recorded ground motions."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import click

from ..defaults import G
from ..errors import InputError
from ..motions.units import UNITS_TEXT, acceleration_unit
from ._options import count, figure_file, option_group, reporter, writable_file

if TYPE_CHECKING:
    import numpy as np

    from ..motions.records import Record
    from ..motions.response import ResponseSpectrum

#: ``--units`` of the commands that read records (``spectrum``, ``motions import``).
units_option = click.option(
    "--units",
    default=None,
    metavar="UNIT",
    help=f"Units of the values in record files that do not state theirs: {UNITS_TEXT} (usual "
    "spellings such as cm/sec/sec or m/s^2 too); a file that states other units is refused; "
    "required for SAC and miniSEED files (with --calibration for counts) [default: as each "
    "file states, else g]",
)
#: ``--calibration`` of the commands that read records: SAC and miniSEED values per unit.
calibration_option = click.option(
    "--calibration",
    type=click.FloatRange(0.0, min_open=True),
    default=None,
    metavar="FACTOR",
    help="Units (--units) per count of SAC and miniSEED files, which hold counts: their values "
    "are multiplied by it [default: 1, the values are in --units]; refused for other files.",
)
#: ``--record-dt`` of the commands that read records, and ``--dt``, its old name in
#: ``spectrum`` (hidden; kept for one release, with a warning).
record_dt_option = click.option(
    "--record-dt",
    type=click.FloatRange(0.0, min_open=True),
    default=None,
    help="Time step [s] of a one-column text file (which does not state it); several "
    "one-column files need a step each (motions import: a manifest's dt column).",
)
_old_dt_option = click.option(
    "--dt", "old_dt", type=click.FloatRange(0.0, min_open=True), default=None, hidden=True
)


def checked_units(units: str | None) -> str | None:
    """``--units`` as a name of :data:`rocking.motions.units.ACCELERATION_UNITS` (None: not
    given); a unit that is not understood is refused, naming it."""
    return None if units is None else acceleration_unit(units, "--units")


#: Highest frequency [Hz] of the spectra unless a record's Nyquist frequency is lower.
_DEFAULT_FMAX = 50.0
#: Frequencies [Hz] shown in the printed table (the nearest computed ones within the range).
_TABLE_FREQS = (0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0)


def _table_rows(freqs: np.ndarray) -> np.ndarray:
    import numpy as np

    from ..core import portable

    wanted = [f for f in _TABLE_FREQS if freqs[0] <= f <= freqs[-1]] or [freqs[0], freqs[-1]]
    return np.unique([int(np.argmin(np.abs(portable.log(freqs / f)))) for f in wanted])


@dataclass(frozen=True)
class _Frequencies:
    """--fmin, --fmax (None: by default) [Hz] and --n of ``rocking spectrum``."""

    fmin: float
    fmax: float | None
    n: int


def _frequencies(fmin: float, fmax: float | None, n: int) -> _Frequencies:
    if fmax is not None and not fmin < fmax:
        raise InputError(f"--fmin ({fmin:g} Hz) must be below --fmax ({fmax:g} Hz)")
    return _Frequencies(fmin, fmax, n)


_frequency_options = option_group(
    "frequencies",
    _frequencies,
    click.option(
        "--fmin",
        type=click.FloatRange(0.0, min_open=True),
        default=0.1,
        show_default=True,
        help="Lowest frequency [Hz].",
    ),
    click.option(
        "--fmax",
        type=click.FloatRange(0.0, min_open=True),
        default=None,
        help="Highest frequency [Hz], at most the Nyquist frequency 1/(2 dt) of every "
        "record  [default: 50 Hz or the lowest Nyquist frequency of the records, "
        "whichever is lower]",
    ),
    click.option(
        "--n",
        "n_freq",
        type=count("frequencies", 2),
        default=100,
        show_default=True,
        help="Number of frequencies, log-spaced from fmin to fmax.",
    ),
)


@click.command("spectrum")
@click.argument("files", nargs=-1, required=True, metavar="RECORD...")
@click.option(
    "--damping",
    type=click.FloatRange(0.0, 1.0, max_open=True),
    default=0.05,
    show_default=True,
    help="Damping ratio [-].",
)
@_frequency_options
@units_option
@calibration_option
@record_dt_option
@_old_dt_option
@click.option(
    "--plot",
    "plot_path",
    type=click.Path(dir_okay=False, writable=True),
    help="Save a figure of PSA against frequency (e.g. out.png).",
)
@click.option(
    "--csv",
    "csv_path",
    type=click.Path(dir_okay=False, writable=True),
    help="Save every spectrum to a CSV file.",
)
def spectrum(
    files: tuple[str, ...],
    damping: float,
    frequencies: _Frequencies,
    units: str | None,
    calibration: float | None,
    record_dt: float | None,
    old_dt: float | None,
    plot_path: str | None,
    csv_path: str | None,
) -> None:
    """Response spectra of ground-acceleration records (PEER .AT2, text, K-NET/KiK-net,
    ESM/ITACA, COSMOS V1/V2, SAC or miniSEED, told by their headers; folders allowed; 'example'
    is the shipped record El Centro 1940 NS).

    Prints PSA [g], PSV [cm/s] and SD [cm] at a few frequencies for each record; --csv saves
    all frequencies, --plot draws PSA against frequency.
    """
    fmin, fmax, n_freq = frequencies.fmin, frequencies.fmax, frequencies.n
    if old_dt is not None:
        if record_dt is not None:
            raise InputError("--dt is the old name of --record-dt: give --record-dt only")
        click.echo(
            "warning: --dt of 'rocking spectrum' is renamed --record-dt (as in 'rocking "
            "motions import'); --dt will be removed in the next release",
            err=True,
        )
        record_dt = old_dt
    units = checked_units(units)
    writable_file(csv_path, "--csv")
    figure_file(plot_path, "--plot")

    from ..core import portable
    from ..motions.records import read_records
    from ..motions.response import response_spectrum

    records = read_records(files, dt=record_dt, units=units, calibration=calibration)
    freqs = portable.geomspace(fmin, _highest_frequency(records, fmin, fmax), n_freq)
    with reporter():
        spectra = [response_spectrum(r.acc, r.dt, freqs, damping) for r in records]
    _print_spectra(records, spectra, freqs, damping)
    if csv_path:
        _write_csv(csv_path, records, spectra, freqs)
        click.echo(f"wrote {csv_path}")
    if plot_path:
        from ..core.files import save_figure
        from ..plots.spectra import plot_spectra  # matplotlib only when a figure is asked for

        fig = plot_spectra(
            freqs,
            [sp.psa / G for sp in spectra],
            [r.name for r in records],
            damping=damping,
            title="Response spectra",
        )
        save_figure(fig, plot_path)
        click.echo(f"wrote {plot_path}")


def _highest_frequency(records: list[Record], fmin: float, fmax: float | None) -> float:
    """``--fmax`` [Hz], checked against the lowest Nyquist frequency of the records, or by
    default the lower of 50 Hz and that Nyquist frequency (said on standard output)."""
    # Above the Nyquist frequency a record holds no information (its samples cannot tell what
    # happens between them); the spectrum there would only show the interpolation.
    coarsest = max(records, key=lambda r: r.dt)  # its Nyquist frequency is the lowest
    nyquist = 0.5 / coarsest.dt
    if fmax is None:
        fmax = min(_DEFAULT_FMAX, nyquist)
        if not fmin < fmax:
            raise InputError(
                f"--fmin ({fmin:g} Hz) must be below the Nyquist frequency "
                f"{fmax:g} Hz of {coarsest.name} (dt = {coarsest.dt:g} s)"
            )
        if fmax < _DEFAULT_FMAX:
            click.echo(
                f"fmax = {fmax:g} Hz: the Nyquist frequency 1/(2 dt) of {coarsest.name} "
                f"(dt = {coarsest.dt:g} s)"
            )
    elif fmax > nyquist * (1.0 + 1e-9):
        raise InputError(
            f"--fmax {fmax:g} Hz is above the Nyquist frequency 1/(2 dt) = "
            f"{nyquist:g} Hz of {coarsest.name} (dt = {coarsest.dt:g} s)"
        )
    return fmax


def _print_spectra(
    records: list[Record], spectra: list[ResponseSpectrum], freqs: np.ndarray, damping: float
) -> None:
    """Print PSA [g], PSV [cm/s] and SD [cm] of each record at the table's frequencies."""
    rows = _table_rows(freqs)
    for rec, sp in zip(records, spectra):
        click.echo(
            f"{rec.name}: {rec.acc.size} samples at {rec.dt:g} s, PGA {rec.pga:.4g} g, "
            f"{100 * damping:g} % damping"
        )
        click.echo(f"{'f [Hz]':>9} {'PSA [g]':>10} {'PSV [cm/s]':>11} {'SD [cm]':>10}")
        for i in rows:
            click.echo(
                f"{freqs[i]:9.3g} {sp.psa[i] / G:10.4g} {100 * sp.psv[i]:11.4g} "
                f"{100 * sp.sd[i]:10.4g}"
            )


def _write_csv(
    csv_path: str, records: list[Record], spectra: list[ResponseSpectrum], freqs: np.ndarray
) -> None:
    """Save every spectrum at every frequency to ``csv_path``."""
    import pandas as pd

    from ..core.files import atomic_write

    table = pd.concat(
        [
            pd.DataFrame(
                {
                    "record": rec.name,
                    "freq_hz": freqs,
                    "psa_g": sp.psa / G,
                    "psv_cm_s": 100 * sp.psv,
                    "sd_cm": 100 * sp.sd,
                }
            )
            for rec, sp in zip(records, spectra)
        ]
    )
    atomic_write(csv_path, table.to_csv(index=False, float_format="%.6g"))


COMMANDS = [spectrum]
