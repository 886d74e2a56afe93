"""The ``rocking`` command-line interface.

Each module of this package defines a list ``COMMANDS`` of click commands or groups;
``COMMAND_MODULES`` names the module of each command, which is imported only when the command runs
(start-up time: the studies import Matplotlib, which most commands do not need).
Errors caused by the user's input are printed in one line (``Error: ...``) with exit status 1;
never a traceback.
"""

from __future__ import annotations

import importlib
import os
import signal
import sys

import click

from ..errors import RockingError


def _one_line(exc: BaseException) -> str:
    msg = str(exc) or exc.__class__.__name__
    return " ".join(msg.split())


#: Command name → module of this package that defines it (tests/test_cli.py checks that this
#: matches the modules' COMMANDS).
COMMAND_MODULES = {
    "agx50": "fragility", "assess": "fragility", "fragility": "fragility", "frame": "frame",
    "motions": "motions", "reproduce": "reproduce", "screen": "screen", "simulate": "simulate",
    "spectrum": "spectrum", "table1": "body",
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
