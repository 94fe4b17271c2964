"""mbgen from Python (docs/python.md).

    import mbgen
    robot = mbgen.load("robots/lola/lola.urdf", extras="robots/lola/lola.yaml", base="floating")
    qdd = robot.forward_dynamics(robot.assembled_q, vy, tau)     # the generic runtime
    report = mbgen.inspect("robots/lola/lola.urdf", extras=...)  # what `mbgen inspect --json` reports
    files = mbgen.generate("robots/lola/lola.urdf", out="gen", name="lola", python=True)

load() and the Robot it returns are the runtime's generic algorithms (the extension mbgen._runtime),
with the generated module's names and conventions. inspect() and generate() run the mbgen command
itself, so that they report and write exactly what the command does: the executable is
$MBGEN_EXECUTABLE, else the one this package was built with (mbgen/_paths.py), else the installed
one beside an installed package (<prefix>/bin/mbgen), else `mbgen` on PATH.
"""
import json
import os
import shutil
import subprocess

from ._runtime import DifferentialIk, LoadError, Robot, Simulator, WalkingPattern, load

__all__ = ["DifferentialIk", "LoadError", "Robot", "Simulator", "WalkingPattern", "load", "inspect", "generate", "executable", "CommandError"]


class CommandError(RuntimeError):
    """The mbgen command failed: its exit status and what it printed on stderr."""

    def __init__(self, arguments, status, stderr):
        super().__init__(f"mbgen {' '.join(arguments)} exited with status {status}:\n{stderr.strip()}")
        self.status = status
        self.stderr = stderr


def executable():
    """The mbgen command inspect() and generate() run."""
    chosen = os.environ.get("MBGEN_EXECUTABLE")
    if chosen:
        return chosen
    try:  # the build tree's (python/CMakeLists.txt writes it)
        from ._paths import MBGEN_EXECUTABLE
        if os.path.exists(MBGEN_EXECUTABLE):
            return MBGEN_EXECUTABLE
    except ImportError:
        pass
    # An install: <prefix>/lib/python3/dist-packages/mbgen beside <prefix>/bin/mbgen.
    installed = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", "..", "..", "..", "bin", "mbgen"))
    if os.path.exists(installed):
        return installed
    found = shutil.which("mbgen")
    if found is None:
        raise FileNotFoundError("no mbgen executable: set MBGEN_EXECUTABLE, or put mbgen on PATH")
    return found


def _description_arguments(description, extras, base, mimic):
    arguments = [os.fspath(description)]
    if extras is not None:
        arguments += ["--extras", os.fspath(extras)]
    if base is not None:
        if base not in ("floating", "fixed"):
            raise ValueError(f"base must be 'floating' or 'fixed', not {base!r}")
        arguments.append("--" + base)
    if mimic is not None:
        arguments += ["--mimic", mimic]
    return arguments


def _run(arguments):
    done = subprocess.run([executable()] + arguments, capture_output=True, text=True)
    if done.returncode != 0:
        raise CommandError(arguments, done.returncode, done.stderr)
    return done.stdout


def inspect(description, extras=None, base=None, mimic=None):
    """What `mbgen inspect --json` reports, as Python objects (dicts and lists)."""
    return json.loads(_run(["inspect"] + _description_arguments(description, extras, base, mimic) + ["--json"]))


def generate(description, out, name=None, extras=None, base=None, mimic=None, outputs=None, scalar=None,
             frames=None, batch=None, python=False):
    """Runs `mbgen generate` with these options (the command's, docs/extras.md) and returns the paths
    of the files now in `out`, the header first. outputs and frames: lists of names."""
    arguments = ["generate"] + _description_arguments(description, extras, base, mimic) + ["--out", os.fspath(out)]
    if name is not None:
        arguments += ["--name", name]
    if outputs is not None:
        arguments += ["--outputs", ",".join(outputs)]
    if scalar is not None:
        arguments += ["--scalar", scalar]
    if frames is not None:
        arguments += ["--frames", ",".join(frames)]
    if batch is not None:
        arguments += ["--batch", str(batch)]
    if python:
        arguments.append("--python")
    _run(arguments + ["--quiet"])
    files = sorted(os.path.join(out, f) for f in os.listdir(out))
    headers = [f for f in files if f.endswith((".hpp", ".h"))]
    return headers + [f for f in files if f not in headers]
