"""The ``rocking`` command-line interface.

Each module of this package that defines a list ``COMMANDS`` of click commands or groups has them
registered on the main group, so command groups live beside each other without a central list.
Errors caused by the user's input are printed in one line (``Error: ...``) with exit status 1;
never a traceback.
"""

from __future__ import annotations

import importlib
import os
import pkgutil
import signal
import sys

import click

from ..errors import RockingError


def _one_line(exc: BaseException) -> str:
    msg = str(exc) or exc.__class__.__name__
    return " ".join(msg.split())


class _Main(click.Group):
    """Main group that turns input errors into one-line messages."""

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except BrokenPipeError:
            # the reader of our output went away (e.g. `| head`): stop quietly
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            raise SystemExit(1) from None
        except (RockingError, ValueError, OSError, KeyError) as exc:
            raise click.ClickException(_one_line(exc)) from None


@click.group(cls=_Main, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="rocking")
def main():
    """Rocking and overturning of free-standing rigid blocks under earthquakes."""
    # SIGTERM (a batch system's stop) unwinds like Ctrl-C, so that long runs record their
    # status as failed in run.json; finished chunks are already on disk.
    signal.signal(signal.SIGTERM, _terminate)


def _terminate(signum, frame):
    raise SystemExit(128 + signum)


def _register():
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        mod = importlib.import_module(f"{__name__}.{info.name}")
        for cmd in getattr(mod, "COMMANDS", ()):
            main.add_command(cmd)


_register()
