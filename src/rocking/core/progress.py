"""Progress of long stages, on a terminal and off it.

A :class:`Reporter` is what the long-running functions of the package take as ``progress``.  Each
stage (a Monte Carlo run, a spectral fit, a section of the paper's reproduction) opens a
:meth:`Reporter.stage`; what is shown depends on where the output goes:

* on a terminal, a tqdm progress bar (with the fraction done and the time left when the size of
  the stage is known);
* off a terminal (a log file, a batch system, CI), one short line every ``interval`` seconds, e.g.
  ``P(overturn): 45% (1.2M/2.7M sim, 00:12 elapsed, 00:15 left)``, and one when the stage ends;
* nothing for stages that end within ``delay`` seconds.

Stages nest: a stage opened while another is open on the same reporter reports into it (its
work adds to the outer count), so a section of ``rocking reproduce`` shows one line for all its
Monte Carlo calls instead of one bar per call.

While a reporter is active (``with reporter:``, or any open stage) it also says when Numba starts
compiling a kernel (the first run after installation; later runs load them from the cache): the
one long silence a new user would otherwise meet. It says which kernel (once per process and
kernel), and the open stage's line names it until the compilation ends, e.g.
``section 8 [compiling the rocking kernel]: 0 sim (00:12 elapsed)``, then counts again: a
notice printed once above a line that reads "0 sim" for half a minute looked like a stuck run.

tqdm draws the bars and formats the lines (rates, times); off a terminal its output is cut into
plain lines by :class:`_Lines`, because tqdm itself only knows how to redraw a line in place.
"""

from __future__ import annotations

import functools
import io
import math
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any, TextIO

#: Seconds between two progress lines off a terminal.
LINE_INTERVAL = 5.0
#: Stages shorter than this [s] show nothing.
DELAY = 2.0
#: What the kernels of the package's modules are (the longest prefix of a kernel's module
#: names it) and how long their first compilation takes, measured on 2 cores (27 s for the
#: rocking kernel, issue 48; the others take seconds); any other: "the numerical kernels".
_KERNELS = {
    "rocking.dynamics": ("the rocking kernel", ", ~30 s"),
    "rocking.motions.response": ("the response-spectrum kernel", ""),
    "rocking.motions": ("the ground-motion kernels", ""),
    "rocking.structures": ("the shear-frame kernels", ""),
}
_OTHER_KERNELS = ("the numerical kernels", "")


def compile_notice(what: str, took: str = "") -> str:
    """The line that says that ``what`` (e.g. "the rocking kernel") is being compiled."""
    return f"compiling {what} (first run only{took}; later runs reuse the compiled code)"


#: The notice of kernels that are not the package's own.
COMPILING = compile_notice(*_OTHER_KERNELS)

_FORMAT_KNOWN = (
    "{desc}: {percentage:3.0f}% ({n_fmt}/{total_fmt} {unit}, {elapsed} elapsed, {remaining} left)"
)
_FORMAT_OPEN = "{desc}: {n_fmt} {unit} ({elapsed} elapsed)"


class _Lines(io.TextIOBase):
    """A text stream for tqdm off a terminal: each redraw becomes one plain line."""

    def __init__(self, stream):
        self._stream = stream

    def write(self, text: str) -> int:
        line = text.replace("\r", "").strip()
        if line:
            self._stream.write(line + "\n")
            self._stream.flush()
        return len(text)

    def flush(self) -> None:
        self._stream.flush()


_said_compiling: set[str] = set()  # kernels announced in this process, by any reporter


def _kernel_of(ev) -> tuple[str, str]:
    """(what, how long) of the kernel whose compilation the Numba event ``ev`` starts."""
    func = getattr(ev.data.get("dispatcher"), "py_func", None)
    module = getattr(func, "__module__", "") or ""
    for prefix in sorted(_KERNELS, key=len, reverse=True):
        if module == prefix or module.startswith(prefix + "."):
            return _KERNELS[prefix]
    return _OTHER_KERNELS


@functools.cache
def _listener_class():
    """Numba event listener that tells its reporter when a kernel's compilation starts and
    ends (defined on first use: Numba is imported only by what runs the kernels). A kernel's
    compilation compiles the functions it calls inside it: the outermost one names it."""
    from numba.core import event

    class Compiling(event.Listener):
        def __init__(self, reporter):
            self._reporter = reporter
            self._depth = 0

        def on_start(self, ev) -> None:
            self._depth += 1
            if self._depth == 1:
                self._reporter._compiling(*_kernel_of(ev))

        def on_end(self, ev) -> None:
            self._depth -= 1
            if self._depth == 0:
                self._reporter._compiling(None)

    return Compiling


class Stage:
    """One open stage of a :class:`Reporter`: count work with :meth:`update`."""

    def __init__(self, bar: Any, parent: Stage | None, lines: bool = False):
        self._bar = bar
        self._parent = parent
        self._lines = lines  # bar drawn as lines (off a terminal)
        self._desc: str | None = None  # the description, while a compilation changes it

    def update(self, n: int = 1) -> None:
        """Count ``n`` more units of work done."""
        if self._parent is not None:
            self._parent.update(n)
        elif self._bar is not None:
            self._bar.update(n)

    def expect(self, n: int) -> None:
        """Announce that at least ``n`` more units of work are to come: the size of the stage
        becomes at least what is done plus ``n`` (a nested stage leaves its outer stage's size
        alone, which then shows counts and rates only)."""
        if self._parent is not None or self._bar is None:
            return
        bar = self._bar
        target = bar.n + n
        if bar.total is None or bar.total < target:
            if bar.total is None and self._lines:
                bar.bar_format = _FORMAT_KNOWN
            bar.total = target  # shown at the next update (a refresh now would break the delay)

    def compiling(self, what: str | None) -> None:
        """Name the kernel being compiled in the stage's line (None: the compilation ended)."""
        bar = self._bar
        if bar is None:
            return
        if self._desc is None:
            self._desc = bar.desc
        bar.set_description_str(
            self._desc if what is None else f"{self._desc} [compiling {what}]", refresh=False
        )

    def note(self, text: str) -> None:
        """Print one line of text without breaking the bar."""
        if self._parent is not None:
            self._parent.note(text)
        elif self._bar is not None:
            self._bar.write(text, file=self._bar.fp)


class Reporter:
    """Shows the progress of stages (see the module notes).

    Parameters
    ----------
    stream : text stream, optional
        Where to write (default ``sys.stderr`` at the time of writing).
    tty : bool, optional
        Draw bars (True) or write lines (False); default: whether ``stream`` is a terminal.
    interval : float
        Seconds between two lines off a terminal.
    delay : float
        Seconds before a stage shows anything.
    enabled : bool
        False shows nothing at all (a reporter that is quiet).
    """

    def __init__(
        self,
        stream: TextIO | None = None,
        *,
        tty: bool | None = None,
        interval: float = LINE_INTERVAL,
        delay: float = DELAY,
        enabled: bool = True,
    ):
        self._stream = stream
        self._tty = tty
        self.interval = float(interval)
        self.delay = float(delay)
        self.enabled = bool(enabled)
        self._open: list[Stage] = []
        self._listeners: list = []
        self._active = 0

    @property
    def stream(self) -> TextIO:
        return sys.stderr if self._stream is None else self._stream

    @property
    def tty(self) -> bool:
        if self._tty is not None:
            return self._tty
        isatty = getattr(self.stream, "isatty", None)
        return bool(isatty and isatty())

    def write(self, text: str) -> None:
        """Print one line now (e.g. what a command is about to do), unless disabled."""
        if not self.enabled:
            return
        if self._open:
            self._open[0].note(text)
        else:
            self.stream.write(text + "\n")
            self.stream.flush()

    def _compiling(self, what: str | None, took: str = "") -> None:
        """A kernel's compilation starts (``what`` it is) or ends (None): say it once per
        process and kernel, and name it in the open stage's line until it ends."""
        if what is not None and what not in _said_compiling:
            _said_compiling.add(what)
            self.write(compile_notice(what, took))
        if self._open and self._open[0]._bar is not None:
            self._open[0].compiling(what)

    def __enter__(self) -> Reporter:
        """Activate: from now until :meth:`__exit__`, say once when Numba starts compiling."""
        if self.enabled:
            if not self._listeners:
                from numba.core import event  # whatever compiles has loaded Numba anyway

                listener = _listener_class()(self)
                event.register("numba:compile", listener)
                self._listeners.append(listener)
            self._active += 1
        return self

    def __exit__(self, *exc: object) -> None:
        if self.enabled:
            self._active -= 1
            if self._active == 0:
                from numba.core import event

                for listener in self._listeners:
                    event.unregister("numba:compile", listener)
                self._listeners.clear()

    @contextmanager
    def stage(self, desc: str, total: int | None = None, unit: str = "sim") -> Iterator[Stage]:
        """Open a stage named ``desc`` of ``total`` units (None: unknown); yields a
        :class:`Stage`."""
        if not self.enabled:
            yield Stage(None, None)
            return
        if self._open:  # nested: report into the outer stage
            stage = Stage(None, self._open[-1])
            self._open.append(stage)
            try:
                yield stage
            finally:
                self._open.pop()
            return
        from tqdm.auto import tqdm

        if self.tty:
            bar = tqdm(
                total=total,
                desc=desc,
                unit=unit,
                delay=self.delay,
                file=self.stream,
                smoothing=0.1,
                dynamic_ncols=True,
            )
            every = 1.0
        else:  # lines come from the heartbeat only, every `interval` seconds
            bar = tqdm(
                total=total,
                desc=desc,
                unit=unit,
                delay=self.delay,
                file=_Lines(self.stream),
                mininterval=math.inf,
                smoothing=0.1,
                bar_format=_FORMAT_OPEN if total is None else _FORMAT_KNOWN,
            )
            every = self.interval
        stage = Stage(bar, None, lines=not self.tty)
        stop = threading.Event()
        beat = threading.Thread(
            target=_heartbeat,
            args=(bar, stop, self.delay, every),
            daemon=True,
            name="rocking-progress",
        )
        self._open.append(stage)
        beat.start()
        try:
            with self:
                yield stage
        finally:
            self._open.pop()
            stop.set()
            beat.join()
            if bar.total is not None and not self.tty:
                bar.total = max(bar.total, bar.n)
            bar.close()


def _heartbeat(bar, stop: threading.Event, delay: float, every: float) -> None:
    """Redraw ``bar`` every ``every`` seconds once ``delay`` has passed, until ``stop``: the
    elapsed time keeps moving (and a line is written off a terminal) even while one long piece
    of work, such as the first compilation, gives no update."""
    if stop.wait(delay):
        return
    while True:
        bar.refresh()
        # as tqdm's update() records its own redraws (close() then draws the final state)
        bar.last_print_t, bar.last_print_n = bar._time(), bar.n
        if stop.wait(every):
            return


#: A reporter that shows nothing.
QUIET = Reporter(enabled=False)


def resolve(progress: Reporter | bool | None) -> Reporter:
    """The :class:`Reporter` for a ``progress`` argument of the package's functions.

    ``True``: a reporter on standard error (bars on a terminal, lines otherwise); ``False``:
    nothing; ``None``: bars if standard error is a terminal, else nothing (the default of
    library calls: a script's log is not filled unless it asks); a :class:`Reporter`: itself.
    """
    if isinstance(progress, Reporter):
        return progress
    if progress is None:
        return Reporter() if sys.stderr.isatty() else QUIET
    if isinstance(progress, bool):
        return Reporter() if progress else QUIET
    from ..errors import InputError

    raise InputError(
        f"progress must be True, False, None or a rocking.core.progress.Reporter, got {progress!r}"
    )
