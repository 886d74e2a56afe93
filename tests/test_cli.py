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


def test_help_of_every_command_exits_zero():
    # `rocking simulate --help` printed its help, then called itself an internal error (exit 70):
    # the help option ends by raising click's Exit, which the main group took for a bug
    runner = CliRunner()
    for name in cli.COMMAND_MODULES:
        out = runner.invoke(cli.main, [name, "--help"])
        assert out.exit_code == 0, (name, out.output)
        assert out.output.startswith(f"Usage: main {name} "), (name, out.output)
        assert "internal error" not in out.output, name
    nested = runner.invoke(cli.main, ["motions", "generate", "--help"])
    assert nested.exit_code == 0 and "--n INTEGER" in nested.output, nested.output


def test_python_m_rocking_is_the_rocking_command():
    # `python -m rocking` used to fail (no rocking/__main__.py); it must run the command line,
    # its errors in one line and a non-zero status included
    for module in ("rocking", "rocking.cli"):
        ok = subprocess.run(
            [sys.executable, "-m", module, "--help"], capture_output=True, text=True, check=True
        )
        assert "Commands:" in ok.stdout and "  simulate " in ok.stdout
        bad = subprocess.run(
            [sys.executable, "-m", module, "no-such-command"], capture_output=True, text=True
        )
        assert bad.returncode != 0 and "No such command" in bad.stderr
        assert "Traceback" not in bad.stderr


def test_a_command_does_not_import_the_plotting_stack():
    # start-up time: `rocking simulate --help` must not load Matplotlib (the studies do)
    code = (
        "import sys; from rocking.cli import main\n"
        "try:\n    main(['simulate', '--help'])\nexcept SystemExit:\n    pass\n"
        "print('matplotlib' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip().splitlines()[-1] == "False"


HEAVY = ("numpy", "numba", "scipy", "xarray", "pandas", "matplotlib", "dask")


def test_help_and_option_errors_load_no_numerical_library():
    # start-up time (issue 14: `rocking --help` and any command's argument errors in < 0.5 s):
    # listing the commands imports every command module, so none may import the numerical stack
    code = (
        "import sys\nfrom rocking.cli import main\n"
        "for args in (['--help'], ['fragility', '--bogus'], ['simulate', '--R', '1'],\n"
        "             ['screen', '--help'], ['reproduce', '9']):\n"
        "    try:\n        main(args)\n    except SystemExit:\n        pass\n"
        f"print(sorted(m for m in {HEAVY!r} if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip().splitlines()[-1] == "[]"


def test_the_light_name_lists_match_the_library():
    # the command line takes these names from rocking.defaults so as not to import the modules
    # that define them; they must stay the same lists
    from rocking import defaults
    from rocking.motions.envelopes import ENVELOPES
    from rocking.structures.frames import PRESETS
    from rocking.studies import STUDIES

    assert sorted(defaults.ENVELOPE_NAMES) == sorted(ENVELOPES)
    assert list(defaults.FRAME_PRESETS) == list(PRESETS)
    assert list(defaults.STUDY_SECTIONS) == list(STUDIES)


def test_binary_files_where_text_is_expected_are_one_line_input_errors(tmp_path):
    # Issue 49: each of these ended as "internal error ... UnicodeDecodeError" (exit 70). A PNG
    # header (binary, not UTF-8) is given where a CSV or TOML file is read.
    binary = tmp_path / "binary.csv"
    binary.write_bytes(b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR\xff\xfe")
    toml = tmp_path / "binary.toml"
    toml.write_bytes(binary.read_bytes())
    cases = {
        "assess": ["assess", "--bodies", "paper", "--spectrum", binary],
        "screen": ["screen", "example", "--spectrum", binary, "--out", tmp_path / "s"],
        "generate": ["motions", "generate", "--target", binary, "--out", tmp_path / "g.nc"],
        "import": ["motions", "import", "--manifest", binary, "--out", tmp_path / "i.nc"],
        "frame": ["frame", "show", "--frame-file", toml],
        "reproduce": ["reproduce", "4", "--config", toml, "--out", tmp_path / "r"],
    }
    for name, args in cases.items():
        out = CliRunner().invoke(cli.main, [str(a) for a in args])
        assert out.exit_code == 1, (name, out.output)
        assert out.output.count("\n") == 1 and out.output.startswith("Error: "), (name, out.output)
        assert "binary." in out.output and "not a text file" in out.output, (name, out.output)
