"""Command lines that run a student's code under bubblewrap with resource limits.

Inside the sandbox the student sees a read-only view of the Python environment
and the system (``/usr``, the ``/lib*`` and ``/bin`` links, a few files of
``/etc``), the course's read-only extras (``data/``, ``starter/``) and their own
writable working directory, each at its host path; ``/tmp`` is a private tmpfs,
``/proc`` and ``/dev`` are minimal, there is no network and no view of the rest
of the host (the repository's ``reference/``, other students, the gradebook),
no way to make a user namespace (which would hand the student's code every
capability over namespaces of its own), and the system calls that reach the
kernel's most exploited parts are refused (:mod:`grader.sandbox.seccomp`).
"""

from __future__ import annotations

import fcntl
import functools
import importlib.util
import logging
import os
import shutil
import subprocess
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from grader.sandbox.limits import prlimit_prefix
from grader.sandbox.process_limit import DEFAULT_MAX_PROCESSES
from grader.sandbox.seccomp import filter_program

__all__ = [
    "SandboxSpec",
    "bwrap_available",
    "user_namespaces_disabled",
    "system_calls_filtered",
    "wrap_command",
    "sandbox_env",
    "DEFAULT_MEMORY_BYTES",
    "DEFAULT_CPU_SECONDS",
]

log = logging.getLogger(__name__)

DEFAULT_MEMORY_BYTES = 4 * 2**30
DEFAULT_CPU_SECONDS = 3600
DEFAULT_FILE_BYTES = 2**30

# The engine, never importable by a student; every course pack adds its reference and hidden packages.
ENGINE_PACKAGES = ("grader",)


def hidden_packages() -> tuple[str, ...]:
    """Top-level packages the student must never import, masked wherever they are installed:
    the engine's and every course pack's reference and ``hidden_packages`` (a pack's own folder is never bound)."""
    from grader.course_pack import PACKAGE, packs

    names = set(ENGINE_PACKAGES)
    for course in packs().values():
        names |= {n for n in (*course.hidden_packages, *course.reference_packages()) if n != PACKAGE}
    return tuple(sorted(names))

# What Python, numpy, matplotlib and the shell tools need from /etc; the rest of
# /etc (package-manager credentials, ssh, shadow) stays out of sight.
ETC_ENTRIES = (
    "alternatives",
    "fonts",
    "group",
    "host.conf",
    "hosts",
    "ld.so.cache",
    "ld.so.conf",
    "ld.so.conf.d",
    "localtime",
    "mime.types",
    "nsswitch.conf",
    "os-release",
    "passwd",
    "timezone",
)

# Merged-/usr systems make these symlinks into /usr; older ones have real directories.
ROOT_LINKS = ("bin", "sbin", "lib", "lib32", "lib64", "libx32")


@dataclass
class SandboxSpec:
    """What one sandboxed run may see and use.

    Parameters
    ----------
    workdir : Path
        Existing directory, the only writable place (besides the private
        ``/tmp``); also ``HOME`` and the working directory.
    readonly : list of Path
        Existing extra paths bound read-only at the same path (course
        ``data/``, the ``starter/`` package).
    hide : list of Path
        Paths masked (by an empty tmpfs, or ``/dev/null`` for a file) if they
        lie inside a tree the sandbox binds; the ``reference`` and ``grader``
        packages are always masked.
    memory_bytes : int
        Address-space limit (``RLIMIT_AS``) of every process, in bytes.
    cpu_seconds : int or None
        CPU-time limit (``RLIMIT_CPU``) of every process, a backstop behind the
        executor's per-cell timeout; ``None`` for none.
    env : dict of str to str
        Extra environment variables, applied over the sandbox's clean defaults.
    file_bytes : int
        Largest file a process may write (``RLIMIT_FSIZE``), and the size of
        the private ``/tmp`` (which lives in the host's memory).
    max_processes : int or None
        Largest number of processes and threads alive at once, enforced by a
        ``pids`` cgroup or, failing that, by ``RLIMIT_NPROC`` inside the
        sandbox's own user namespace (:mod:`grader.sandbox.process_limit`);
        ``None`` for no cap.

    Paths are made absolute and resolved (symlinks followed) on construction.
    """

    workdir: Path
    readonly: list[Path] = field(default_factory=list)
    hide: list[Path] = field(default_factory=list)
    memory_bytes: int = DEFAULT_MEMORY_BYTES
    cpu_seconds: int | None = DEFAULT_CPU_SECONDS
    env: dict[str, str] = field(default_factory=dict)
    file_bytes: int = DEFAULT_FILE_BYTES
    max_processes: int | None = DEFAULT_MAX_PROCESSES

    def __post_init__(self):
        self.workdir = Path(self.workdir).resolve()
        if not self.workdir.is_dir():
            raise ValueError(f"workdir must be an existing directory, got {str(self.workdir)!r}")
        self.readonly = [Path(p).resolve() for p in self.readonly]
        missing = [str(p) for p in self.readonly if not p.exists()]
        if missing:
            raise ValueError(f"readonly must list existing paths, missing: {missing}")
        self.hide = [Path(p).resolve() for p in self.hide]
        if not _is_positive_int(self.file_bytes):
            raise ValueError(f"file_bytes must be a positive int, got {self.file_bytes!r}")
        if not _is_positive_int(self.memory_bytes):
            raise ValueError(f"memory_bytes must be a positive int, got {self.memory_bytes!r}")
        if self.max_processes is not None and not _is_positive_int(self.max_processes):
            raise ValueError(f"max_processes must be None or a positive int, got {self.max_processes!r}")
        if self.cpu_seconds is not None and not _is_positive_int(self.cpu_seconds):
            raise ValueError(f"cpu_seconds must be None or a positive int, got {self.cpu_seconds!r}")
        if not isinstance(self.env, dict):
            raise ValueError(f"env must be a dict of str to str, got {type(self.env).__name__}")
        bad = [k for k, v in self.env.items() if not (_is_env_name(k) and isinstance(v, str))]
        if bad:
            raise ValueError(f"env must map variable names (non-empty, no '=') to str values, bad keys: {bad!r}")
        self.env = dict(self.env)


def _is_positive_int(x) -> bool:
    return isinstance(x, int) and not isinstance(x, bool) and x > 0


def _is_env_name(x) -> bool:
    return isinstance(x, str) and x != "" and "=" not in x


# A trial sandbox mounts the same kernel filesystems as a real one: containers
# often allow the namespaces but refuse to mount /proc.
_TRIAL_MOUNTS = ("--ro-bind", "/", "/", "--proc", "/proc", "--dev", "/dev", "--tmpfs", "/tmp")


def _trial(*command: str, isolation: Sequence[str] | None = None, filtered: bool = False) -> subprocess.CompletedProcess | None:
    """Run ``command`` in a trial sandbox with the real namespaces (or ``isolation``); ``None`` if it cannot start.

    ``filtered``: under the seccomp filter too (``None`` where this machine has none).
    """
    exe = shutil.which("bwrap")
    if exe is None:
        return None
    isolation = _isolation_args() if isolation is None else isolation
    argv = [exe, *isolation, *_TRIAL_MOUNTS, *command]
    if filtered:
        argv = _under_filter(argv)
        if argv is None:
            return None
    try:
        return subprocess.run(argv, capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return None


@functools.cache
def _filter_fd() -> int | None:
    """A sealed memfd with the seccomp filter, open for this process's life; ``None`` where there is no filter."""
    program = filter_program()
    if program is None:
        return None
    try:
        fd = os.memfd_create("deformlab-seccomp", os.MFD_CLOEXEC | os.MFD_ALLOW_SEALING)
    except OSError as exc:
        log.warning("cannot hold the seccomp filter in memory (memfd_create: %s)", exc)
        return None
    os.write(fd, program)
    fcntl.fcntl(fd, fcntl.F_ADD_SEALS, fcntl.F_SEAL_SEAL | fcntl.F_SEAL_SHRINK | fcntl.F_SEAL_GROW | fcntl.F_SEAL_WRITE)
    return fd


def _under_filter(bwrap: list[str]) -> list[str] | None:
    """``bwrap`` (its argv, the executable first) run under the seccomp filter; ``None`` where there is none.

    A shell opens the grader's memfd through ``/proc`` as fd 3 and execs
    ``bwrap --seccomp 3``: nothing on disk to clean up or swap, and the
    launched process keeps the launcher's pid. bwrap closes fd 3 before the
    sandboxed command starts.
    """
    fd = _filter_fd()
    if fd is None:
        return None
    return ["/bin/sh", "-c", 'exec "$@" 3<"$0"', f"/proc/{os.getpid()}/fd/{fd}", bwrap[0], "--seccomp", "3", *bwrap[1:]]


@functools.cache
def system_calls_filtered() -> bool:
    """Whether sandboxes here run under the seccomp filter of :mod:`grader.sandbox.seccomp`.

    Returns
    -------
    bool
        ``True`` if this architecture has a filter and a trial sandbox runs
        under it. Cached per process.
    """
    trial = _trial("true", filtered=True) if bwrap_available() else None
    return trial is not None and trial.returncode == 0


@functools.cache
def bwrap_available() -> bool:
    """Whether bubblewrap is installed and can create namespaces here.

    Returns
    -------
    bool
        ``True`` if ``bwrap`` is on ``PATH`` and a trial sandbox with every
        namespace unshared runs ``true`` successfully. Cached per process.
    """
    trial = _trial("true")
    return trial is not None and trial.returncode == 0


@functools.cache
def sandbox_user_namespace() -> bool:
    """Whether each sandbox gets a user namespace of its own.

    There, ``RLIMIT_NPROC`` set inside counts only the sandbox's own tasks
    (the kernel keeps one count per user namespace, checked against the
    limits of every level), so it caps one sandbox, not all of a user's
    processes; :class:`grader.sandbox.kernel.SandboxedKernelManager` uses it
    where no ``pids`` cgroup is writable.

    Returns
    -------
    bool
        ``True`` if bubblewrap works here and a trial sandbox reports another
        user namespace than this process's. Cached per process.
    """
    trial = _trial("readlink", "/proc/self/ns/user") if bwrap_available() else None
    return trial is not None and trial.returncode == 0 and trial.stdout.strip() not in ("", os.readlink("/proc/self/ns/user"))


@functools.cache
def _warn_user_namespaces_allowed() -> None:
    log.warning(
        "bubblewrap here cannot stop student code from creating user namespaces (--disable-userns needs "
        "bubblewrap 0.8 or newer and a user namespace for the sandbox): kernel exploits that start there stay within reach"
    )


@functools.cache
def _warn_unfiltered() -> None:
    log.warning("no seccomp filter for this machine: sandboxed code may call io_uring, keyctl, perf_event_open and bpf")


@functools.cache
def _warn_without_bwrap() -> None:
    log.warning("bubblewrap not available: grading without filesystem/network isolation")


def sandbox_env(spec: SandboxSpec) -> dict[str, str]:
    """The complete environment of the sandboxed command.

    Parameters
    ----------
    spec : SandboxSpec

    Returns
    -------
    dict of str to str
        A clean, minimal environment (nothing inherited from the grader) with
        ``spec.env`` applied last.
    """
    # Caches and IPython's profile go to the private /tmp so the workdir holds
    # only what the student writes.
    env = {
        "PATH": os.pathsep.join([str(Path(sys.executable).parent), "/usr/local/bin", "/usr/bin", "/bin"]),
        "HOME": str(spec.workdir),
        "LANG": "C.UTF-8",
        "TMPDIR": "/tmp",
        "MPLBACKEND": "Agg",
        "MPLCONFIGDIR": "/tmp/matplotlib",
        "IPYTHONDIR": "/tmp/ipython",
        "XDG_CACHE_HOME": "/tmp/cache",
        "DEFORMLAB_NO_PLOTS": "1",
        # what importing starter.plotting sets, so that a kernel that imported it before it
        # started (forked from the template) has the environment of one that imports it later
        "VTK_DEFAULT_OPENGL_WINDOW": "vtkEGLRenderWindow",
        "OMP_NUM_THREADS": "1",
        "OPENBLAS_NUM_THREADS": "1",
        "MKL_NUM_THREADS": "1",
        "PYTHONDONTWRITEBYTECODE": "1",
    }
    env.update(spec.env)
    return env


def _python_trees() -> list[Path]:
    """Install trees the interpreter needs: the venv, its base and the real executable's."""
    candidates = {Path(p) for p in (sys.prefix, sys.exec_prefix, sys.base_prefix, sys.base_exec_prefix)}
    candidates.add(Path(sys.executable).resolve().parent.parent)
    return sorted({p.resolve() for p in candidates} | candidates)


def _is_within(path: Path, root: Path) -> bool:
    return path == root or root in path.parents


def _hidden_paths(spec: SandboxSpec) -> list[Path]:
    """``spec.hide`` plus where the hidden packages are installed."""
    hidden = list(spec.hide)
    for name in hidden_packages():
        found = importlib.util.find_spec(name)
        if found is None:
            continue
        if found.submodule_search_locations:
            hidden.extend(Path(p).resolve() for p in found.submodule_search_locations)
        elif found.origin:
            hidden.append(Path(found.origin).resolve())
    return hidden


_NAMESPACES = (
    "--unshare-all",  # user (if possible), network, pid, ipc, uts and (if possible) cgroup namespaces
    "--die-with-parent",
    "--new-session",
)
# Without these, student code can unshare(CLONE_NEWUSER | CLONE_NEWNET) and hold
# every capability over a network namespace of its own: the way in for most
# kernel exploits (nf_tables and the like) that climb out of a container.
_NO_USER_NAMESPACES = ("--unshare-user", "--disable-userns")


@functools.cache
def user_namespaces_disabled() -> bool:
    """Whether sandboxed code here is kept from creating user namespaces of its own.

    bubblewrap 0.8 does it (``--disable-userns``) where it can give the
    sandbox a user namespace; elsewhere student code may create them if the
    kernel lets this user, and a warning says so once per process.

    Returns
    -------
    bool
        ``True`` if a trial sandbox with ``--disable-userns`` runs. Cached per process.
    """
    trial = _trial("true", isolation=[*_NAMESPACES, *_NO_USER_NAMESPACES])
    return trial is not None and trial.returncode == 0


def _isolation_args() -> list[str]:
    """bubblewrap's namespace and process options."""
    args = list(_NAMESPACES)
    if user_namespaces_disabled():
        args += _NO_USER_NAMESPACES
    if os.geteuid() == 0:
        args += ["--cap-drop", "ALL"]
    return args


def _bwrap_args(spec: SandboxSpec, binds: Sequence[tuple[str, Path]] = (), pid_1: bool = False) -> list[str]:
    """bubblewrap options for ``spec`` and extra ``(option, path)`` binds, mounts in an order where later ones win."""
    # /tmp first, so that a venv or course folder under /tmp is bound on top of it.
    args = [*_isolation_args(), *(["--as-pid-1"] if pid_1 else []), "--proc", "/proc", "--dev", "/dev", "--size", str(spec.file_bytes), "--tmpfs", "/tmp"]
    mounted = [Path("/usr")]
    args += ["--ro-bind", "/usr", "/usr"]
    for name in ROOT_LINKS:
        path = Path("/") / name
        if path.is_symlink():
            args += ["--symlink", os.readlink(path), str(path)]
        elif path.is_dir():
            args += ["--ro-bind", str(path), str(path)]
            mounted.append(path)
    for name in ETC_ENTRIES:
        path = Path("/etc") / name
        if path.exists():
            args += ["--ro-bind", str(path), str(path)]
            mounted.append(path)
    for tree in _python_trees():
        if not any(_is_within(tree, m) for m in mounted):
            args += ["--ro-bind", str(tree), str(tree)]
            mounted.append(tree)
    # Parents before children, so a writable workdir inside a read-only extra
    # (or the reverse) keeps its own mode.
    user_binds = [(spec.workdir, "--bind"), *((p, "--ro-bind") for p in spec.readonly)]
    user_binds.sort(key=lambda bind: len(bind[0].parts))
    for path, how in user_binds:
        args += [how, str(path), str(path)]
        mounted.append(path)
    for how, path in binds:
        args += [how, str(path), str(path)]
    for path in _hidden_paths(spec):
        if not path.exists() or not any(_is_within(path, m) for m in mounted):
            continue
        if path.is_dir():
            args += ["--tmpfs", str(path), "--remount-ro", str(path)]
        else:
            args += ["--ro-bind", "/dev/null", str(path)]
    args += ["--chdir", str(spec.workdir), "--clearenv"]
    for key, value in sandbox_env(spec).items():
        args += ["--setenv", key, value]
    return args


# Without bwrap: die with the grader's launching thread (what --die-with-parent does; it survives
# exec), start a new session (unless the launcher already made this process a session leader, as
# jupyter_client does), enter the workdir, exec.
_SESSION_LAUNCHER = (
    "import ctypes, os, sys\n"
    "if ctypes.CDLL(None, use_errno=True).prctl(1, 9, 0, 0, 0) != 0 or os.getppid() != int(sys.argv[1]):\n"
    "    os._exit(1)\n"
    "if os.getsid(0) != os.getpid():\n"
    "    os.setsid()\n"
    "os.chdir(sys.argv[2])\n"
    "os.execvp(sys.argv[3], sys.argv[3:])\n"
)


def wrap_command(argv: list[str], spec: SandboxSpec, binds: Sequence[tuple[str, Path]] = (), pid_1: bool = False) -> list[str]:
    """Return the command line that runs ``argv`` inside the sandbox.

    Parameters
    ----------
    argv : list of str
        The command to sandbox (non-empty).
    spec : SandboxSpec
        What the command may see and use.
    binds : sequence of (str, Path)
        Extra host paths the command needs at the same path, each with
        ``"--bind"`` (read-write) or ``"--ro-bind"``: the kernel's connection
        file and sockets. Without bubblewrap they are simply where they are.
    pid_1 : bool
        Run ``argv`` as the sandbox's pid 1 (``--as-pid-1``), which must then
        reap orphans; the sandbox ends when it exits. Needs bubblewrap.

    Returns
    -------
    list of str
        ``prlimit ... -- sh -c ... bwrap --seccomp 3 ... -- argv`` when
        bubblewrap works here (the shell hands bwrap the seccomp filter;
        without one for this machine, ``prlimit ... -- bwrap ... -- argv``).
        Otherwise a command that applies the same limits, clean environment
        and working directory and runs ``argv`` in its own session, but with no
        filesystem or network isolation; a warning says so once per process.
    """
    if not argv or not all(isinstance(a, str) for a in argv):
        raise ValueError(f"argv must be a non-empty list of str, got {argv!r}")
    bad = [b for b in binds if not (isinstance(b, tuple) and len(b) == 2 and b[0] in ("--bind", "--ro-bind"))]
    if bad:
        raise ValueError(f"binds must be (\"--bind\" or \"--ro-bind\", path) pairs, got {bad!r}")
    limits = prlimit_prefix(spec.memory_bytes, spec.cpu_seconds, spec.file_bytes)
    if bwrap_available():
        if not user_namespaces_disabled():
            _warn_user_namespaces_allowed()
        bwrap = [shutil.which("bwrap"), *_bwrap_args(spec, binds, pid_1), "--", *argv]
        if system_calls_filtered():
            return [*limits, *_under_filter(bwrap)]
        _warn_unfiltered()
        return [*limits, *bwrap]
    if pid_1:
        raise ValueError("pid_1 needs bubblewrap, which is not available here")
    _warn_without_bwrap()
    env = [f"{k}={v}" for k, v in sandbox_env(spec).items()]
    launcher = [sys.executable, "-I", "-S", "-c", _SESSION_LAUNCHER, str(os.getpid()), str(spec.workdir)]
    return ["env", "-i", *env, *limits, *launcher, *argv]
