"""Kernels forked from a template that imported them once, each inside its own bubblewrap sandbox.

A fresh kernel spends most of its start importing: ipykernel, then numpy,
scipy and libigl in the notebook's first cells (about 0.4 CPU-s of a unit's
0.85). Here each grading process keeps one template
(:mod:`grader.sandbox.kernel_template`) that imported them once; every kernel
is a fork of it. The sandbox is still bubblewrap's, built exactly as for a
fresh kernel, one per unit: bubblewrap runs a small *waiter* as the sandbox's
pid 1 instead of the kernel, the template's child enters the waiter's
namespaces, cgroup and limits, and the kernel it forks there confines itself
as bubblewrap would (no capabilities, ``no_new_privs``, the seccomp filter).
The waiter reaps the sandbox's orphans and exits when the kernel does, which
ends the sandbox as the kernel's exit does for a fresh one.

The template runs no student code and holds nothing of any student's: a
request carries only the waiter's pid and start time, paths, limits, the
environment and the filter. Student code cannot reach it: it lives outside
every sandbox's pid namespace and shares no descriptor with one.

Set ``DEFORMLAB_KERNEL_TEMPLATE=off`` to start every kernel fresh. Where the
template cannot start or a fork fails, that kernel starts fresh and a warning
says why; after three failures in a row, every later kernel of the process does.
"""

from __future__ import annotations

import atexit
import functools
import json
import logging
import os
import select
import subprocess
import sys
import threading
import time
from pathlib import Path

__all__ = ["WAITER", "enabled", "fork_kernel", "start_template", "stop_template", "disable", "failed", "succeeded", "readable"]

log = logging.getLogger(__name__)

TEMPLATE = Path(__file__).with_name("kernel_template.py")
# How long the template may take to import everything, and then to answer one request.
_START_TIMEOUT = 60.0
_REPLY_TIMEOUT = 10.0
# A reply is one short JSON line.
_MAX_REPLY = 4096

# The sandbox's pid 1 (``bwrap --as-pid-1``). It says it runs (so bubblewrap
# has built the sandbox), reads the kernel's pid in the sandbox once the
# kernel has entered, then reaps orphans until the kernel exits. An empty or
# bad line ends it, and with it the sandbox.
WAITER = """\
import os, select, signal, sys
os.write(1, b"r")
os.close(1)
line = sys.stdin.buffer.readline(32)
os.close(0)
try:
    kernel = os.pidfd_open(int(line))
except (ValueError, OSError):
    os._exit(1)
signal.signal(signal.SIGCHLD, signal.SIG_IGN)  # pid 1: the orphans it inherits are reaped as they exit
select.select([kernel], [], [])
os._exit(0)
"""

_lock = threading.Lock()
_template: subprocess.Popen | None = None
_owner: int | None = None  # the pid that started _template: a forked grading process must not share it
_disabled: str | None = None
_failures = 0  # forks failed in a row
#: Forks that may fail in a row (each kernel then starts fresh) before every later kernel does.
FAILURES_BEFORE_OFF = 3


def enabled() -> bool:
    """Whether kernels here are forked from the template: not turned off, nor by ``FAILURES_BEFORE_OFF`` failed forks in a row."""
    return _disabled is None and os.environ.get("DEFORMLAB_KERNEL_TEMPLATE", "on").lower() not in ("off", "0", "no")


def disable(reason: str) -> None:
    """Start every later kernel of this process fresh; warn once with ``reason``."""
    global _disabled
    if _disabled is None:
        _disabled = reason
        log.warning("kernels start fresh from now on: %s", reason)
    stop_template()


def failed(reason: str) -> None:
    """A kernel could not be forked and starts fresh; after ``FAILURES_BEFORE_OFF`` in a row, every later one does."""
    global _failures
    _failures += 1
    log.warning("a kernel starts fresh: %s", reason)
    if _failures >= FAILURES_BEFORE_OFF:
        disable(f"{_failures} forks failed in a row, the last because {reason}")


def succeeded() -> None:
    """A kernel was forked: failures are counted afresh."""
    global _failures
    _failures = 0


def _template_env(env: dict[str, str]) -> dict[str, str]:
    # Import-time settings (threads, backends, caches) as every kernel will have them;
    # HOME and the working directory are each kernel's own and set after the fork.
    return {**{k: v for k, v in env.items() if k != "PWD"}, "HOME": "/nonexistent"}


def preloads() -> list[str]:
    """The modules every course pack's kernels import (``preload`` in its assignment.toml), for the template."""
    from grader.course_pack import packs

    return sorted({name for course in packs().values() for name in course.preload})


def _start(env: dict[str, str]) -> subprocess.Popen:
    proc = subprocess.Popen(
        # it exits when this process does, however it ends; it preloads what the course packs name
        [sys.executable, "-s", str(TEMPLATE), str(os.getpid()), json.dumps(preloads())],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        env=_template_env(env),
        cwd="/",
        start_new_session=True,  # the grader's ^C reaches the grader, which stops it
    )
    if _read_line(proc, _START_TIMEOUT) != {"ready": True}:
        _kill(proc)
        raise RuntimeError("the kernel template did not start")
    return proc


def readable(fd: int, timeout: float) -> bool:
    """Whether ``fd`` has data (or EOF) within ``timeout`` seconds.

    ``poll``, not ``select``: a grading process may hold descriptors past 1024, which
    ``select`` refuses.
    """
    poller = select.poll()
    poller.register(fd, select.POLLIN)
    return bool(poller.poll(max(0.0, timeout) * 1000))


def _read_line(proc: subprocess.Popen, timeout: float) -> dict | None:
    """One reply line of at most ``_MAX_REPLY`` bytes, or ``None`` on EOF, timeout or garbage."""
    fd = proc.stdout.fileno()
    deadline = time.monotonic() + timeout
    data = b""
    while not data.endswith(b"\n") and len(data) <= _MAX_REPLY:
        left = deadline - time.monotonic()
        if left <= 0 or not readable(fd, left):
            return None
        chunk = os.read(fd, _MAX_REPLY + 1 - len(data))
        if not chunk:
            return None
        data += chunk
    try:
        reply = json.loads(data)
    except ValueError:
        return None
    return reply if isinstance(reply, dict) else None


def _kill(proc: subprocess.Popen) -> None:
    proc.kill()
    proc.wait()
    for pipe in (proc.stdin, proc.stdout):
        pipe.close()


def stop_template() -> None:
    """Stop this process's template, if it runs (at exit, and when disabled)."""
    global _template
    with _lock:
        if _template is not None and _owner == os.getpid():
            _kill(_template)
        _template = None


@functools.cache
def _register_stop() -> None:
    import multiprocessing.util

    atexit.register(stop_template)
    multiprocessing.util.Finalize(None, stop_template, exitpriority=100)  # pool workers exit without atexit


def _ensure_template(env: dict[str, str]) -> None:
    global _template, _owner
    _register_stop()
    if _owner != os.getpid():
        _template = None  # the parent's, inherited through fork: its pipes are the parent's to use
    if _template is None or _template.poll() is not None:
        _template = _start(env)
        _owner = os.getpid()


def start_template(env: dict[str, str]) -> None:
    """Start this process's template now, if it does not run, rather than at the first kernel's start.

    Parameters
    ----------
    env : dict of str to str
        The sandbox's environment (:func:`grader.sandbox.bwrap.sandbox_env`).

    Raises
    ------
    RuntimeError
        If it does not start.
    """
    with _lock:
        _ensure_template(env)


def fork_kernel(request: dict) -> int:
    """Have the template fork a kernel into a sandbox; return the kernel's host pid.

    Parameters
    ----------
    request : dict
        As :mod:`grader.sandbox.kernel_template` reads it; a template started
        now gets its ``env`` (the sandbox's environment).

    Raises
    ------
    RuntimeError
        If the template cannot start, does not answer, or the fork failed; a
        template that did not answer is stopped (the next call starts another).
    """
    global _template
    line = json.dumps(request).encode() + b"\n"
    with _lock:
        _ensure_template(request["env"])
        try:
            _template.stdin.write(line)
            _template.stdin.flush()
        except OSError:
            reply = None
        else:
            reply = _read_line(_template, _REPLY_TIMEOUT)
        if reply is None:
            _kill(_template)
            _template = None
            raise RuntimeError("the kernel template stopped answering")
    if "error" in reply or not isinstance(reply.get("pid"), int):
        raise RuntimeError(f"the kernel template could not fork a kernel: {str(reply.get('error'))[:500]}")
    return reply["pid"]
