"""The command-line entry point: commands load on first use, and each one is found."""

from __future__ import annotations

import importlib
import pkgutil
import subprocess
import sys

from click.testing import CliRunner

import rocking.cli as cli


def test_every_command_module_is_registered_under_its_commands_names():
    # the lazy table must list exactly the commands the modules define, each with its module
    found = {}
    for info in pkgutil.iter_modules(cli.__path__):
        if info.name.startswith("_"):
            continue
        mod = importlib.import_module(f"rocking.cli.{info.name}")
        for cmd in getattr(mod, "COMMANDS", ()):
            found[cmd.name] = info.name
    assert found == cli.COMMAND_MODULES


def test_help_lists_every_command_and_unknown_commands_fail_in_one_line():
    runner = CliRunner()
    out = runner.invoke(cli.main, ["--help"])
    assert out.exit_code == 0
    for name in cli.COMMAND_MODULES:
        assert f"  {name} " in out.output
    bad = runner.invoke(cli.main, ["no-such-command"])
    assert bad.exit_code != 0 and "No such command" in bad.output


def test_a_command_does_not_import_the_plotting_stack():
    # start-up time: `rocking simulate --help` must not load Matplotlib (the studies do)
    code = ("import sys; from rocking.cli import main\n"
            "try:\n    main(['simulate', '--help'])\nexcept SystemExit:\n    pass\n"
            "print('matplotlib' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip().splitlines()[-1] == "False"
