"""Make the shipped Ridgecrest 2019 records (src/rocking/data/records/Ridgecrest2019_*.AT2).

Source: the uncorrected accelerograms (CSMIP "V1" format, 100 samples/s, in g) of the 2019-07-06
M7.1 Ridgecrest earthquake (USGS event ci38457511) at the SCSN stations CI.CCC, CI.CLC and CI.TOW2,
as shipped in the demo data of the USGS package gmprocess 2.8.0 (PyPI wheel,
gmprocess/data/demo/ci38457511/raw/; public domain in the US, CC0 worldwide).

Run once by hand, not by the package or its tests:

    python tools/ridgecrest_records.py path/to/gmprocess/data/demo/ci38457511/raw

Each channel is processed as stated in src/rocking/data/records/README.md: the mean of a
pre-event window removed, a 30 s window around the strong motion cut, a 1 s cosine taper at each
end, a 4-pole Butterworth high-pass at 0.1 Hz run forwards and backwards (zero phase,
scipy.signal.sosfiltfilt, 20 s of zeros padded on each side) against the drift of uncorrected
records. The result is written as a PEER-style .AT2 file in g.
"""

import sys
from pathlib import Path

import numpy as np
from scipy import signal

DT = 0.01  # s, 100 samples/s in every source file
WINDOW = 30.0  # s
TAPER = 1.0  # s at each end
HIGHPASS = 0.1  # Hz
PAD = 20.0  # s of zeros on each side for the zero-phase filter
# file, station code, station name, pre-event window [s], start of the window [s] (the M7.1's
# strong motion: 5-95 % of the Arias intensity lies inside; CI.CLC's file starts at a foreshock)
STATIONS = [
    ("CICCC.RAW", "CCC", "China Lake NWC Christmas Canyon Rd (CI.CCC)", (0.0, 15.0), 25.0),
    ("CICLC.v1", "CLC", "China Lake G2 Tower Rd (CI.CLC)", (185.0, 215.0), 222.0),
    ("CITOW2.RAW", "TOW2", "Tower 2 (CI.TOW2)", (0.0, 15.0), 22.0),
]
COMPONENTS = {"90 Deg": "090", "360 Deg": "360", "Up": "UP"}


def channels(path: Path):
    """(component, accelerations [g]) of each channel of a CSMIP V1 file (8f9.6 values)."""
    lines = path.read_text().splitlines()
    i = 0
    while i < len(lines):
        if "Accelerogram points" not in lines[i]:
            i += 1
            continue
        n = int(lines[i].split()[0])
        comp = lines[i - 21].split(":", 1)[1].strip()  # "Chan  1:  90 Deg"
        values: list[float] = []
        i += 1
        while len(values) < n:
            row = lines[i].rstrip()
            values += [float(row[k : k + 9]) for k in range(0, len(row), 9)]
            i += 1
        yield COMPONENTS[comp], np.array(values[:n])


def process(acc, pre, start):
    n = round(WINDOW / DT)
    a = acc - acc[round(pre[0] / DT) : round(pre[1] / DT)].mean()
    seg = a[round(start / DT) : round(start / DT) + n] * signal.windows.tukey(n, 2 * TAPER / WINDOW)
    sos = signal.butter(4, HIGHPASS, "highpass", fs=1 / DT, output="sos")
    pad = np.zeros(round(PAD / DT))
    return signal.sosfiltfilt(sos, np.concatenate([pad, seg, pad]))[pad.size : -pad.size]


def main(folder: Path, out: Path) -> None:
    for name, code, station, pre, start in STATIONS:
        for comp, acc in channels(folder / name):
            a = process(acc, pre, start)
            lines = [
                "PEER-STYLE ACCELERATION TIME SERIES (processed from CSMIP V1, see README.md)",
                f"Ridgecrest 2019 M7.1, 7/6/2019, {station}, {comp}",
                "ACCELERATION TIME SERIES IN UNITS OF G",
                f"NPTS= {a.size:6d}, DT= {DT:.4f} SEC",
            ]
            lines += ["".join(f"{v:11.7f}" for v in a[k : k + 8]) for k in range(0, a.size, 8)]
            (out / f"Ridgecrest2019_{code}_{comp}.AT2").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(Path(sys.argv[1]), Path(__file__).parents[1] / "src/rocking/data/records")
