"""The ``rocking`` command-line interface.

Each module of this package defines a list ``COMMANDS`` of click commands or groups;
``COMMAND_MODULES`` names the module of each command, which is imported only when the command runs
(start-up time: the studies import Matplotlib, which most commands do not need).
Errors are printed in one line, never as a traceback:

* the user's input (:class:`rocking.errors.InputError`), the machine (a file that cannot be read or
  written: ``OSError``) or the computing backend (:class:`rocking.errors.BackendError`):
  ``Error: ...``, exit status 1;
* anything else is a bug in ``rocking``: the message says so, the traceback is saved to a file
  whose path is printed (for a bug report), exit status 70 (``EX_SOFTWARE``).
"""

from __future__ import annotations

import datetime
import importlib
import os
import signal
import sys
import traceback
from pathlib import Path

import click

from ..errors import RockingError


def _one_line(exc: BaseException) -> str:
    msg = str(exc) or exc.__class__.__name__
    return " ".join(msg.split())


#: Command name → module of this package that defines it (tests/test_cli.py checks that this
#: matches the modules' COMMANDS).
COMMAND_MODULES = {
    "agx50": "fragility",
    "assess": "fragility",
    "fragility": "fragility",
    "frame": "frame",
    "motions": "motions",
    "pulse-spectrum": "pulse_spectrum",
    "reproduce": "reproduce",
    "risk": "risk",
    "screen": "screen",
    "simulate": "simulate",
    "spectrum": "spectrum",
    "table1": "body",
}


class _Main(click.Group):
    """Main group that loads its commands on first use and turns input errors into one-line
    messages (click's lazily loaded subcommands pattern)."""

    def list_commands(self, ctx):
        return sorted(COMMAND_MODULES)

    def get_command(self, ctx, cmd_name):
        module = COMMAND_MODULES.get(cmd_name)
        if module is None:
            return None
        mod = importlib.import_module(f"{__name__}.{module}")
        return next(cmd for cmd in mod.COMMANDS if cmd.name == cmd_name)

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except BrokenPipeError:
            # the reader of our output went away (e.g. `| head`): stop quietly
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            raise SystemExit(1) from None
        except RockingError as exc:
            raise click.ClickException(_one_line(exc)) from None
        except OSError as exc:
            raise click.ClickException(_os_error(exc)) from None
        except (click.ClickException, click.exceptions.Exit, click.Abort):
            raise  # click's own messages and control flow (--help and --version end with Exit)
        except Exception as exc:
            raise _Bug(exc) from None


class _Bug(click.ClickException):
    """An exception that is not the user's: a bug in rocking, reported as such."""

    exit_code = 70

    def __init__(self, exc: Exception):
        from ..core.version import package_version

        where = _save_traceback(exc)
        super().__init__(
            f"internal error in rocking {package_version()} (a bug, not a problem with "
            f"your input): {type(exc).__name__}: {_one_line(exc)}. The traceback "
            f"is in {where}; please report it."
        )


def _save_traceback(exc: Exception) -> str:
    """Write the traceback of ``exc`` to a new file in the user's log folder (or the temporary
    folder); return its path."""
    text = "".join(traceback.format_exception(exc))
    stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
    name = f"crash-{stamp}-{os.getpid()}.txt"
    folders = []
    try:
        import platformdirs

        folders.append(Path(platformdirs.user_log_dir("rocking")))
    except ImportError:
        pass
    import tempfile

    folders.append(Path(tempfile.gettempdir()))
    for folder in folders:
        try:
            folder.mkdir(parents=True, exist_ok=True)
            path = folder / name
            path.write_text(" ".join(sys.argv) + "\n\n" + text)
            return str(path)
        except OSError:
            continue
    return "(nowhere: no writable folder)"


def _os_error(exc: OSError) -> str:
    """One line for a failed file operation, naming the file."""
    what = exc.strerror or _one_line(exc)
    if exc.filename is not None:
        return f"{exc.filename}: {what}"
    return what


@click.group(cls=_Main, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="rocking")
def main() -> None:
    """Rocking and overturning of free-standing rigid blocks under earthquakes."""
    from ..core.process import configure_process

    configure_process()  # before any parallel kernel runs
    # SIGTERM (a batch system's stop) unwinds like Ctrl-C, so that long runs record their
    # status as failed in run.json; finished chunks are already on disk.
    signal.signal(signal.SIGTERM, _terminate)
    # A local Dask cluster's own log lines (lost workers, recomputed tasks) would drown the
    # one-line error that reports such a failure (rocking.errors.BackendError).
    import logging

    logging.getLogger("distributed").setLevel(logging.CRITICAL)


def _terminate(signum, frame):
    raise SystemExit(128 + signum)
