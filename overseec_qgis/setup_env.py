"""The dock's "Set up environment" action: make the worker's venv and pip-install overseec into it.

An analyst who installed the plugin from its zip has no checkout and no ``make``; this does what
``make setup`` does for a developer, from QGIS, in a background task:

1. ``<python> -m venv --system-site-packages <venv>`` from QGIS's own interpreter (same version,
   so QGIS can borrow the venv's packages and the venv sees QGIS's numpy and GDAL bindings);
   skipped when ``<venv>`` already holds a Python;
2. ``<venv python> -m pip install <target>``, where the target is the source the plugin knows
   (a checkout beside the plugin, installed editable with its ``constraints.txt``; or an sdist,
   wheel or folder named in the settings) with the ``[models]`` extra, else the package name
   ``overseec[models]``. pip's own configuration applies, so an offline machine installs from a
   wheelhouse with ``PIP_NO_INDEX=1 PIP_FIND_LINKS=/path/to/wheels``.

Every line pip prints goes to the log as it comes, a rough progress follows pip's phases
(collecting, building, installing), and cancelling terminates pip; a venv this task created is
then removed again, so a cancelled or failed set-up leaves no half-made environment behind.
Commands are argv lists, never shell strings. Last, the new environment is asked which planner
it has (the compiled kernel, or the scikit-image fallback where pip could not compile the kernel:
no C compiler), and the answer is logged and kept in the result.
"""

from __future__ import annotations

import os
import queue
import shutil
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from overseec_core.errors import Cancelled, OverseecError

from . import venvs
from .task import _BaseTask, log
from .worker import CANCEL_GRACE_S, worker_env

#: The package and extra the worker needs (pyproject.toml's [project.optional-dependencies]).
PACKAGE = "overseec"
EXTRA = "models"


class SetupError(OverseecError, RuntimeError):
    """The environment could not be made; the message says what to do."""


@dataclass(frozen=True)
class InstallTarget:
    """What pip installs: a requirement or a local source, with the models extra."""

    requirement: str
    editable: bool = False
    constraints: Path | None = None

    def pip_args(self) -> list[str]:
        args = ["-c", str(self.constraints)] if self.constraints is not None else []
        return args + (["-e", self.requirement] if self.editable else [self.requirement])


def checkout_of(plugin_dir: str | os.PathLike | None) -> Path | None:
    """The source checkout the plugin runs from (a developer's symlinked plugin), if any:
    the nearest parent with ``pyproject.toml`` and ``overseec_core/``."""
    if plugin_dir is None:
        return None
    for parent in list(Path(plugin_dir).resolve().parents)[:3]:
        if (parent / "pyproject.toml").is_file() and (parent / "overseec_core").is_dir():
            return parent
    return None


def install_target(source: str = "", plugin_dir: str | os.PathLike | None = None) -> InstallTarget:
    """The pip target: ``source`` (a checkout folder, sdist or wheel) when given, else the
    checkout the plugin runs from, else the package name; each with the models extra."""
    if source:
        path = Path(source).expanduser()
        if not path.exists():
            raise SetupError(f"the install source {path} does not exist; choose a checkout, sdist or wheel")
        if path.is_dir():
            constraints = path / "constraints.txt"
            return InstallTarget(f"{path.resolve()}[{EXTRA}]", False, constraints if constraints.is_file() else None)
        return InstallTarget(f"{path.resolve()}[{EXTRA}]")
    checkout = checkout_of(plugin_dir)
    if checkout is not None:
        constraints = checkout / "constraints.txt"
        return InstallTarget(f"{checkout}[{EXTRA}]", True, constraints if constraints.is_file() else None)
    return InstallTarget(f"{PACKAGE}[{EXTRA}]")


def default_venv(plugin_dir: str | os.PathLike | None, profile_dir: str | os.PathLike) -> Path:
    """Where a new environment goes: the checkout's ``.venv`` (as ``make setup`` makes it) when
    the plugin runs from one, else ``overseec/venv`` in the QGIS profile folder."""
    checkout = checkout_of(plugin_dir)
    return checkout / ".venv" if checkout is not None else Path(profile_dir) / "overseec" / "venv"


def _python_version(python: Path) -> tuple[int, int] | None:
    try:
        out = subprocess.run(
            [str(python), "-I", "-c", "import sys; print(*sys.version_info[:2])"],
            capture_output=True,
            text=True,
            timeout=60,
            env=worker_env(),
        )
        major, minor = out.stdout.split()
        return int(major), int(minor)
    except (OSError, subprocess.SubprocessError, ValueError):
        return None


def base_python() -> Path:
    """An interpreter of QGIS's own Python version to make the venv from.

    Inside QGIS ``sys.executable`` may be QGIS itself, or whatever ``python3`` comes first on
    PATH; so the candidates (this process's base interpreter, the Python of ``sys.base_prefix``,
    ``pythonX.Y`` on PATH) are each asked their version, and the first that matches is used.
    """
    major, minor = sys.version_info[:2]
    names = (f"python{major}.{minor}", f"python{major}", "python", "python.exe")
    candidates: list[Path] = []
    for exe in (getattr(sys, "_base_executable", ""), sys.executable):
        if exe and Path(exe).name.lower().startswith("python"):
            candidates.append(Path(exe))
    for prefix in dict.fromkeys((sys.base_prefix, sys.base_exec_prefix)):
        candidates += [Path(prefix) / sub / name for sub in ("bin", "") for name in names]
    which = shutil.which(f"python{major}.{minor}")
    if which:
        candidates.append(Path(which))
    for cand in dict.fromkeys(candidates):
        if cand.is_file() and _python_version(cand) == (major, minor):
            return cand
    raise SetupError(
        f"no Python {major}.{minor} interpreter found to make the environment from "
        f"(looked in {sys.base_prefix}); install Python {major}.{minor} or make the venv by hand"
    )


class PipProgress:
    """A rough overall fraction from pip's output: each requirement collected moves the bar
    towards the build phase, then building, installing and the final line."""

    def __init__(self, start: float = 0.15) -> None:
        self.start = start
        self.collected = 0
        self.fraction = start

    def update(self, line: str) -> float:
        text = line.strip()
        if text.startswith(("Collecting ", "Processing ", "Obtaining ", "Requirement already satisfied")):
            self.collected += 1
            self.fraction = max(self.fraction, self.start + 0.55 * (1.0 - 0.85**self.collected))
        elif text.startswith(("Building wheel", "Building editable", "Preparing metadata", "Getting requirements")):
            self.fraction = max(self.fraction, 0.72)
        elif text.startswith("Installing collected packages"):
            self.fraction = max(self.fraction, 0.85)
        elif text.startswith("Successfully installed"):
            self.fraction = 1.0
        return self.fraction


def run_streaming(
    argv: Sequence[str],
    on_line: Callable[[str], None],
    is_cancelled: Callable[[], bool],
    env: dict[str, str] | None = None,
    poll_s: float = 0.1,
    grace_s: float = CANCEL_GRACE_S,
) -> tuple[int, bool, list[str]]:
    """Run ``argv`` (no shell) with stderr merged into stdout, hand each line to ``on_line`` as
    it comes, terminate (then kill) on cancel. Returns (exit status, cancelled, last lines)."""
    proc = subprocess.Popen(
        list(argv),
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        stdin=subprocess.DEVNULL,
        text=True,
        encoding="utf-8",
        errors="replace",
        bufsize=1,
        env=env,
    )
    lines: queue.Queue[str | None] = queue.Queue()

    def pump() -> None:
        assert proc.stdout is not None
        try:
            for line in iter(proc.stdout.readline, ""):
                lines.put(line.rstrip("\n"))
        finally:
            lines.put(None)

    reader = threading.Thread(target=pump, daemon=True)
    reader.start()
    stopper = _Stopper(proc, is_cancelled, grace_s)
    tail: list[str] = []
    while True:
        stopper.poll()
        try:
            line = lines.get(timeout=poll_s)
        except queue.Empty:
            continue
        if line is None:
            break
        if line.strip():
            tail = (tail + [line])[-20:]
            on_line(line)
    returncode = proc.wait()
    reader.join(timeout=1.0)
    if proc.stdout is not None:
        proc.stdout.close()
    return returncode, stopper.cancelled, tail


class _Stopper:
    """Terminates a process once ``is_cancelled()`` turns true, and kills it ``grace_s`` later."""

    def __init__(self, proc: subprocess.Popen, is_cancelled: Callable[[], bool], grace_s: float) -> None:
        self.proc, self.is_cancelled, self.grace_s = proc, is_cancelled, grace_s
        self.cancelled = False
        self._kill_at: float | None = None

    def poll(self) -> None:
        if not self.cancelled and self.is_cancelled():
            self.cancelled = True
            if self.proc.poll() is None:
                self.proc.terminate()
            self._kill_at = time.monotonic() + self.grace_s
        if self._kill_at is not None and time.monotonic() >= self._kill_at and self.proc.poll() is None:
            self.proc.kill()
            self._kill_at = None


@dataclass(frozen=True)
class SetupResult:
    """A finished set-up: the venv and its ``overseec`` command."""

    venv: Path
    worker: Path
    created: bool
    #: Which planner the environment has ("compiled kernel (...)" or "fallback (...): why"; "" unknown).
    planner: str = ""


def _last_error(tail: Sequence[str]) -> str:
    for line in reversed(tail):
        if line.strip().startswith(("ERROR:", "error:")):
            return line.strip()
    return tail[-1].strip() if tail else ""


def set_up(
    venv: str | os.PathLike,
    target: InstallTarget,
    on_line: Callable[[str], None] = log,
    set_progress: Callable[[float], None] = lambda _p: None,
    is_cancelled: Callable[[], bool] = lambda: False,
    python: Path | None = None,
    pip_args: Sequence[str] = (),
) -> SetupResult:
    """Make ``venv`` (unless it has a Python already) and pip-install ``target`` into it.

    Raises :class:`Cancelled` when cancelled and :class:`SetupError` when a step fails; either
    way a venv this call created is removed again.
    """
    venv = Path(venv).expanduser().resolve()
    created = not venvs.python(venv).is_file()
    existed = venv.exists()
    if created and existed and any(venv.iterdir()):
        raise SetupError(f"{venv} exists and is not a Python environment; choose an empty or new folder")
    env = worker_env()
    try:
        if created:
            _create_venv(venv, python or base_python(), on_line, set_progress, is_cancelled, env)
        worker = _pip_install(venv, target, pip_args, on_line, set_progress, is_cancelled, env, created)
    except BaseException:
        if created:  # back to how it was: no folder, or the empty folder the user chose
            shutil.rmtree(venv, ignore_errors=True)
            if existed:
                venv.mkdir(exist_ok=True)
        raise
    planner = planner_of(venv, env)
    if planner:
        on_line(f"planner: {planner}")
    set_progress(100.0)
    return SetupResult(venv=venv, worker=worker, created=created, planner=planner)


#: Run by the new environment's interpreter: which planner it has (a fixed program, no user text).
_PLANNER_PROBE = "from overseec_core.plan import planner_backend; print(planner_backend().describe())"


def planner_of(venv: Path, env: dict[str, str] | None = None, timeout_s: float = 120.0) -> str:
    """The planner ``venv`` plans with, as :meth:`PlannerBackend.describe` words it ("" when it
    cannot tell: an older overseec, or a core that does not import)."""
    try:
        done = subprocess.run(
            [str(venvs.python(venv)), "-I", "-c", _PLANNER_PROBE],
            capture_output=True,
            text=True,
            timeout=timeout_s,
            env=env,
        )
    except (OSError, subprocess.SubprocessError):
        return ""
    lines = done.stdout.strip().splitlines()
    return lines[-1].strip() if done.returncode == 0 and lines else ""


def _create_venv(venv: Path, interpreter: Path, on_line, set_progress, is_cancelled, env) -> None:
    on_line(f"creating {venv} from {interpreter}")
    set_progress(2.0)
    argv = [str(interpreter), "-m", "venv", "--system-site-packages", str(venv)]
    code, cancelled, tail = run_streaming(argv, on_line, is_cancelled, env)
    if cancelled:
        raise Cancelled("set-up cancelled; the new environment was removed")
    if code != 0 or not venvs.python(venv).is_file():
        raise SetupError(
            f"cannot create the environment {venv}: {_last_error(tail) or f'exit status {code}'}"
            " (on Debian/Ubuntu: apt install python3-venv)"
        )


def _pip_install(venv: Path, target, pip_args, on_line, set_progress, is_cancelled, env, created: bool) -> Path:
    """pip install ``target`` into ``venv``; returns the venv's ``overseec`` command."""
    pip = PipProgress(0.15)
    set_progress(100.0 * pip.fraction)

    def line_in(line: str) -> None:
        on_line(line)
        set_progress(100.0 * pip.update(line))

    argv = [str(venvs.python(venv)), "-m", "pip", "install", "--disable-pip-version-check", "--progress-bar", "off"]
    argv += [*pip_args, *target.pip_args()]
    on_line("running: " + " ".join(argv))
    code, cancelled, tail = run_streaming(argv, line_in, is_cancelled, env)
    if cancelled:
        raise Cancelled(
            "set-up cancelled"
            + ("; the new environment was removed" if created else f"; {venv} was left as pip left it")
        )
    if code != 0:
        raise SetupError(f"pip could not install {target.requirement}: {_last_error(tail) or f'exit status {code}'}")
    worker = venvs.executable(venv, "overseec")
    if not worker.is_file():
        raise SetupError(f"pip installed {target.requirement} but {worker} is missing")
    return worker


class SetupEnvTask(_BaseTask):
    """:func:`set_up` as a cancellable QgsTask: pip's lines to the log panel (and ``line``),
    progress to the task manager; ``succeeded(SetupResult)`` or ``failed(message, details)``."""

    def __init__(
        self,
        venv: str | os.PathLike,
        target: InstallTarget,
        python: Path | None = None,
        pip_args: Sequence[str] = (),
    ) -> None:
        super().__init__(f"overseec: set up the environment in {venv}")
        self.venv, self.target, self.python, self.pip_args = Path(venv), target, python, tuple(pip_args)
        self.lines: list[str] = []

    def _line(self, line: str) -> None:
        self.lines.append(line)
        log(line)

    def run(self) -> bool:  # task thread
        try:
            self.result = set_up(
                self.venv,
                self.target,
                on_line=self._line,
                set_progress=self.setProgress,
                is_cancelled=self.isCanceled,
                python=self.python,
                pip_args=self.pip_args,
            )
            return True
        except Cancelled as exc:
            self.error, self._cancelled = str(exc), True
        except (OverseecError, OSError) as exc:
            self.error = str(exc)
            self.details = "\n".join(self.lines[-20:])
        return False
