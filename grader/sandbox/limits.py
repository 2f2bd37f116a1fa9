"""Resource limits for a sandboxed command and accounting of its process tree.

Limits are set with ``prlimit`` (util-linux) in front of the command, so they
are visible on the command line and inherited by every process the student
starts. The process-tree helpers read ``/proc`` of the host: the host sees the
real pids of every process in the sandbox, including those in a private pid
namespace or a new session.
"""

from __future__ import annotations

import os
import select
import signal
import time
from collections.abc import Iterable
from pathlib import Path
from typing import NamedTuple

__all__ = ["Process", "prlimit_prefix", "process", "process_tree", "pid_namespace", "hold_pid_namespace", "innermost_pid", "namespace_members", "status_bytes", "peak_rss_bytes", "kill_and_reap", "is_alive", "is_running"]


class Process(NamedTuple):
    """A host process, identified by pid and start time so that a recycled pid
    is never mistaken for it."""

    pid: int
    start_ticks: int


def prlimit_prefix(memory_bytes: int, cpu_seconds: int | None, file_bytes: int | None = None) -> list[str]:
    """Return the ``prlimit`` argv prefix that applies the sandbox's limits.

    Parameters
    ----------
    memory_bytes : int
        Address-space cap (``RLIMIT_AS``), soft and hard, in bytes.
    cpu_seconds : int or None
        CPU-time cap (``RLIMIT_CPU``) per process, in seconds; ``None`` for none.
    file_bytes : int or None
        Largest file a process may write (``RLIMIT_FSIZE``), so student code
        cannot fill the host's disk through the workdir; ``None`` for none.

    Returns
    -------
    list of str
        ``["prlimit", ..., "--"]``; append the command to run. Core dumps are
        disabled too, so a crashing student process cannot fill the workdir.
    """
    prefix = ["prlimit", f"--as={memory_bytes}", "--core=0"]
    if cpu_seconds is not None:
        prefix.append(f"--cpu={cpu_seconds}")
    if file_bytes is not None:
        prefix.append(f"--fsize={file_bytes}")
    return [*prefix, "--"]


def _stat_fields(pid: int) -> list[str] | None:
    """Fields of ``/proc/<pid>/stat`` after the command name (state first)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:  # the process has exited
        return None
    # The command name is in parentheses and may contain spaces or ")".
    return stat.rpartition(")")[2].split()


def process_tree(*roots: int | Process) -> list[Process]:
    """Return the root processes and all their live descendants.

    Parameters
    ----------
    *roots : int or Process
        Host pids of the roots. A :class:`Process` root counts only while its
        pid still belongs to it: a pid kept after its process was reaped may
        have been given to an unrelated process since.

    Returns
    -------
    list of Process
        ``(k,)`` processes, each once: the live roots in the order given, then
        their descendants breadth-first; empty if no root is alive.
    """
    parents, starts = {}, {}
    for entry in Path("/proc").iterdir():
        fields = _stat_fields(int(entry.name)) if entry.name.isdigit() else None
        if fields is not None:
            parents[int(entry.name)] = int(fields[1])
            starts[int(entry.name)] = int(fields[19])
    children: dict[int, list[int]] = {}
    for child, parent in parents.items():
        children.setdefault(parent, []).append(child)

    def pid_if_live(root: int | Process) -> int | None:
        if isinstance(root, Process):
            return root.pid if starts.get(root.pid) == root.start_ticks else None
        return root if root in parents else None

    tree = list(dict.fromkeys(p for p in map(pid_if_live, roots) if p is not None))
    seen = set(tree)
    for p in tree:  # the list grows while we walk it: breadth-first
        new = [c for c in children.get(p, []) if c not in seen]
        seen.update(new)
        tree.extend(new)
    return [Process(p, starts[p]) for p in tree]


def process(pid: int) -> Process | None:
    """The process that holds ``pid`` now, or ``None`` if none does.

    Parameters
    ----------
    pid : int
        Host pid.

    Returns
    -------
    Process or None
        With its start time, so that later calls can tell it from a process
        given the same pid after it is reaped.
    """
    fields = _stat_fields(pid)
    return None if fields is None else Process(pid, int(fields[19]))


def pid_namespace(pid: int) -> str | None:
    """The pid namespace of a host process, e.g. ``"pid:[4026532771]"``; ``None`` once it has exited.

    Parameters
    ----------
    pid : int
        Host pid.

    Returns
    -------
    str or None
        The kernel's name for the namespace, which no process can choose or forge.
    """
    try:
        return os.readlink(f"/proc/{pid}/ns/pid")
    except OSError:
        return None


def hold_pid_namespace(proc: Process) -> tuple[str, int] | None:
    """Open a descriptor on the pid namespace of ``proc``, which keeps its name from going to another.

    A namespace's name (its inode number) is free for the next namespace created once
    the last process in it has exited, and Linux hands out the lowest free one: a
    sandbox's name, remembered past its end, soon names another grader's sandbox. An
    open descriptor keeps the namespace, and so its name, alive.

    Parameters
    ----------
    proc : Process
        A host process (pid and start time).

    Returns
    -------
    (str, int) or None
        The name, as :func:`pid_namespace` gives it, and the descriptor (the caller
        closes it once it no longer kills by that name); ``None`` if ``proc`` has exited.
    """
    try:
        fd = os.open(f"/proc/{proc.pid}/ns/pid", os.O_RDONLY | os.O_CLOEXEC)
    except OSError:
        return None
    if not is_running(proc):  # the pid went to another process before the descriptor was open
        os.close(fd)
        return None
    return f"pid:[{os.fstat(fd).st_ino}]", fd


def namespace_members(namespace: str) -> list[int]:
    """Host pids of the live processes in a pid namespace.

    Parameters
    ----------
    namespace : str
        As :func:`pid_namespace` names it; held open (:func:`hold_pid_namespace`)
        unless another sandbox's processes may be among the members.

    Returns
    -------
    list of int
        ``(k,)`` host pids, ascending.
    """
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit() and pid_namespace(int(entry.name)) == namespace:
            found.append(int(entry.name))
    return sorted(found)


def innermost_pid(pid: int) -> int | None:
    """A host process's number in its own pid namespace (the last of ``NSpid``); ``None`` if it is gone.

    Parameters
    ----------
    pid : int
        Host pid.

    Returns
    -------
    int or None
        Set by the kernel: a process cannot choose it.
    """
    values = _status_field(pid, "NSpid")
    return int(values[-1]) if values else None


def _status_field(pid: int, key: str) -> list[str] | None:
    """The values of one field of ``/proc/<pid>/status``; ``None`` if the process or the field is missing."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return None
    for line in status.splitlines():
        if line.startswith(key + ":"):
            return line.split()[1:]
    return None


def status_bytes(pid: int, key: str) -> int | None:
    """A size field of ``/proc/<pid>/status`` (``VmHWM``, ``VmSize``, …) in bytes; ``None`` if unreadable.

    Parameters
    ----------
    pid : int
        Host pid.
    key : str
        The field's name.

    Returns
    -------
    int or None
    """
    values = _status_field(pid, key)
    try:
        return int(values[0]) * 1024 if values else None
    except ValueError:
        return None


def peak_rss_bytes(pids: Iterable[int]) -> int | None:
    """Return the largest peak resident set size among processes.

    Parameters
    ----------
    pids : iterable of int
        Host pids; processes that have exited are skipped.

    Returns
    -------
    int or None
        ``max(VmHWM)`` in bytes over the live processes, ``None`` if none is
        alive. ``VmHWM`` is each process's own high-water mark since it started,
        so sampling any time before it exits gives its true peak.
    """
    peaks = [b for b in (status_bytes(p, "VmHWM") for p in pids) if b is not None]
    return max(peaks) if peaks else None


def is_alive(pid: int) -> bool:
    """True while the process ``pid`` has not exited (a zombie has exited; it only awaits reaping).

    Parameters
    ----------
    pid : int
        Host pid.

    Returns
    -------
    bool
    """
    fields = _stat_fields(pid)
    return fields is not None and fields[0] != "Z"


def is_running(proc: Process) -> bool:
    """True while ``proc`` has not exited (a zombie has exited; it only awaits
    reaping) and its pid has not been recycled.

    Parameters
    ----------
    proc : Process

    Returns
    -------
    bool
    """
    fields = _stat_fields(proc.pid)
    return fields is not None and fields[0] != "Z" and int(fields[19]) == proc.start_ticks


def kill_and_reap(procs: Iterable[Process], timeout: float = 5.0) -> list[Process]:
    """SIGKILL processes and wait until they have exited.

    Parameters
    ----------
    procs : iterable of Process
        Processes to kill; those that have already exited are ignored.
    timeout : float
        Seconds to wait for them to exit.

    Returns
    -------
    list of Process
        Those still running after ``timeout`` (empty on success).
    """
    pending = [p for p in procs if is_running(p)]
    for proc in pending:
        try:
            os.kill(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    deadline = time.monotonic() + timeout
    while pending and (left := deadline - time.monotonic()) > 0:
        _wait_for_an_exit(pending, left)
        pending = [p for p in pending if is_running(p)]
    return pending


def _wait_for_an_exit(procs: list[Process], timeout: float) -> None:
    """Return once one of ``procs`` has exited, or after ``timeout`` seconds.

    Woken by the processes' pidfds, which become readable when they exit,
    rather than by polling (a sandbox's processes die a few milliseconds
    after SIGKILL; a 20 ms poll took a whole period per unit). Where pidfds
    are missing (Linux before 5.3), it sleeps a short period instead.
    """
    fds = []
    try:
        for proc in procs:
            try:
                fds.append(os.pidfd_open(proc.pid))
            except ProcessLookupError:
                return  # it exited since the caller looked
            except OSError:
                time.sleep(min(0.02, timeout))
                return
        # the pid may have been recycled before its pidfd was opened: that pidfd
        # would never wake us, so look again now that they are all open
        if not all(is_running(p) for p in procs):
            return
        poller = select.poll()
        for fd in fds:
            poller.register(fd, select.POLLIN)
        poller.poll(timeout * 1000)
    finally:
        for fd in fds:
            os.close(fd)
