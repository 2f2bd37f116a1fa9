"""A cap on how many processes and threads one sandbox may hold at once.

``RLIMIT_NPROC`` cannot do this: it counts every process of the user, and the
kernel does not enforce it for root, which is how CI and many grading
machines run. A ``pids`` cgroup can: each sandbox gets its own, ``pids.max``
caps its tasks (processes and threads), ``fork`` and ``clone`` fail with
``EAGAIN`` beyond it, and ``pids.events`` counts the refusals. The sandboxed
command joins its cgroup before ``exec`` (:meth:`ProcessLimit.join_prefix`),
so everything it starts is inside from the first instruction.

Both cgroup versions work: v1 (a ``pids`` hierarchy, as in many containers)
and v2 (where the ``pids`` controller is enabled for this process's cgroup's
children). Where neither is writable, :func:`pids_parent` is ``None``.

A non-root user without a delegated cgroup (a TA's laptop) still gets a cap:
inside a user namespace of its own, ``RLIMIT_NPROC`` counts only the tasks of
that namespace, so :func:`namespace_cap_prefix`, run inside the sandbox, caps
one sandbox. Measured as an unprivileged user with 64 processes already
running: two sandboxes under ``--nproc=20`` each forked 18 children, while the
same limit outside a namespace refused the first fork. Refusals are not
counted there: the student's code sees ``EAGAIN`` but no event is recorded.
Root is exempt from ``RLIMIT_NPROC``, so root needs the cgroup.
"""

from __future__ import annotations

import functools
import os
import signal
import time
import uuid
from pathlib import Path

__all__ = ["DEFAULT_MAX_PROCESSES", "ProcessLimit", "namespace_cap_prefix", "pids_parent", "remove_stale_limits"]

#: Tasks per sandbox. An IPython kernel holds about 10 threads, and libigl's
#: parallel loops add one per core; 512 leaves room on large machines while a
#: fork bomb stays harmless.
DEFAULT_MAX_PROCESSES = 512

CGROUP_ROOT = Path("/sys/fs/cgroup")
_PREFIX = "deformlab-"


def namespace_cap_prefix(max_processes: int) -> list[str]:
    """The argv prefix that caps a command's tasks with ``RLIMIT_NPROC``.

    It caps one sandbox only when run inside a user namespace of the sandbox's
    own, by a user other than root (see the module docstring); outside one it
    counts every process of the user.

    Parameters
    ----------
    max_processes : int
        Largest number of processes and threads alive at once.

    Returns
    -------
    list of str
        ``["prlimit", "--nproc=<max_processes>", "--"]``; append the command.
    """
    if not isinstance(max_processes, int) or isinstance(max_processes, bool) or max_processes <= 0:
        raise ValueError(f"max_processes must be a positive int, got {max_processes!r}")
    return ["prlimit", f"--nproc={max_processes}", "--"]


def _own_cgroups(proc_cgroup: str) -> dict[str, str]:
    """``controller -> path`` from ``/proc/self/cgroup``; v2's single line is under ``""``."""
    found = {}
    for line in proc_cgroup.splitlines():
        _, controllers, path = line.split(":", 2)
        for controller in controllers.split(",") if controllers else [""]:
            found[controller] = path
    return found


def _candidates(root: Path, proc_cgroup: str) -> list[Path]:
    own = _own_cgroups(proc_cgroup)
    found = []
    if "pids" in own and (root / "pids").is_dir():  # v1
        found.append(root / "pids" / own["pids"].lstrip("/"))
    if "" in own:  # v2: children get the controller only if it is in our subtree_control
        here = root / own[""].lstrip("/")
        try:
            if "pids" in (here / "cgroup.subtree_control").read_text().split():
                found.append(here)
        except OSError:
            pass
    return found


def _can_create_children(parent: Path) -> bool:
    probe = parent / f"deformlab-probe-{os.getpid()}-{uuid.uuid4().hex[:8]}"
    try:
        probe.mkdir()
    except OSError:
        return False
    try:
        return (probe / "pids.max").is_file()
    finally:
        try:
            probe.rmdir()
        except OSError:
            pass


@functools.cache
def pids_parent(root: Path = CGROUP_ROOT) -> Path | None:
    """The cgroup under which this process can create per-sandbox ``pids`` cgroups.

    Parameters
    ----------
    root : Path
        Where the cgroup filesystems are mounted.

    Returns
    -------
    Path or None
        A writable cgroup directory whose children get a ``pids.max`` file,
        or ``None`` (no cgroup filesystem, no ``pids`` controller, or no right
        to create cgroups). Cached per process.
    """
    try:
        proc_cgroup = Path("/proc/self/cgroup").read_text()
    except OSError:
        return None
    for parent in _candidates(root, proc_cgroup):
        if _can_create_children(parent):
            return parent
    return None


class ProcessLimit:
    """One sandbox's ``pids`` cgroup, created on construction.

    Parameters
    ----------
    max_processes : int
        Largest number of tasks (processes and threads) alive at once in the
        cgroup; positive.
    parent : Path
        Where to create the cgroup: :func:`pids_parent`'s answer.

    Raises
    ------
    ValueError
        If ``max_processes`` is not a positive int.
    OSError
        If the cgroup cannot be created or configured (nothing is left behind).
    """

    def __init__(self, max_processes: int, parent: Path):
        if not isinstance(max_processes, int) or isinstance(max_processes, bool) or max_processes <= 0:
            raise ValueError(f"max_processes must be a positive int, got {max_processes!r}")
        self.max_processes = max_processes
        # The owner's pid in the name lets remove_stale_limits tell a dead grader's cgroups.
        self.path = Path(parent) / f"{_PREFIX}{os.getpid()}-{uuid.uuid4().hex[:12]}"
        self.path.mkdir()
        try:
            (self.path / "pids.max").write_text(str(max_processes))
        except OSError:
            self.path.rmdir()
            raise

    @classmethod
    def adopt(cls, path: Path) -> "ProcessLimit":
        """The existing cgroup at ``path`` (to remove one a dead grader left), without configuring it."""
        limit = cls.__new__(cls)
        limit.path = Path(path)
        limit.max_processes = None
        return limit

    def join_prefix(self) -> list[str]:
        """The argv prefix that moves the command into this cgroup, then execs it.

        Returns
        -------
        list of str
            ``["sh", "-c", ..., <cgroup.procs>]``; append the command. If the
            cgroup is gone the shell fails and the command never starts.
        """
        # $$ is the shell's pid, which exec hands on to the command.
        return ["/bin/sh", "-c", 'echo $$ > "$0" && exec "$@"', str(self.path / "cgroup.procs")]

    def pids(self) -> list[int]:
        """Host pids of the processes in the cgroup (empty once it is removed)."""
        try:
            return [int(p) for p in (self.path / "cgroup.procs").read_text().split()]
        except OSError:
            return []

    def refused(self) -> int:
        """How many times a new process or thread was refused for the cap."""
        try:
            events = (self.path / "pids.events").read_text().split()
        except OSError:
            return 0
        return int(events[events.index("max") + 1]) if "max" in events else 0

    def remove(self, timeout: float = 10.0) -> bool:
        """Kill everything in the cgroup and delete it.

        Parameters
        ----------
        timeout : float
            Seconds to keep killing (a process may fork while its siblings die).

        Returns
        -------
        bool
            ``True`` if the cgroup is gone.
        """
        deadline = time.monotonic() + timeout
        while self.path.exists():
            kill_file = self.path / "cgroup.kill"  # v2 since Linux 5.14: the whole cgroup at once
            if kill_file.exists():
                try:
                    kill_file.write_text("1")
                except OSError:
                    pass
            for pid in self.pids():
                try:
                    os.kill(pid, signal.SIGKILL)
                except OSError:
                    pass
            try:
                self.path.rmdir()  # fails with EBUSY while a process (even a zombie) remains
                return True
            except FileNotFoundError:
                return True
            except OSError:
                if time.monotonic() > deadline:
                    return False
                time.sleep(0.01)
        return True


def remove_stale_limits(parent: Path | None = None) -> list[Path]:
    """Remove the cgroups of graders that died without removing them (killed workers).

    Parameters
    ----------
    parent : Path, optional
        Where the cgroups were created; default :func:`pids_parent`.

    Returns
    -------
    list of Path
        The cgroups removed (their processes killed first).
    """
    parent = parent or pids_parent()
    removed: list[Path] = []
    if parent is None:
        return removed
    for path in parent.glob(f"{_PREFIX}*-*"):
        owner = path.name[len(_PREFIX):].split("-", 1)[0]
        if not owner.isdigit() or Path(f"/proc/{owner}").exists():
            continue
        if ProcessLimit.adopt(path).remove():
            removed.append(path)
    return removed
