"""A Jupyter kernel manager whose kernel runs inside the grading sandbox.

The kernel talks over ``ipc`` (Unix sockets): TCP cannot cross the sandbox's
private network namespace. Its connection file and sockets live in a runtime
folder of the grader's own, outside the student's workdir: the connection file
is bound read-only into the sandbox (the kernel can neither change, move nor
replace it), the sockets' folder is bound read-write at the same absolute path
so the kernel can create its sockets, and, where the grader is root, is handed
to another owner as soon as they exist, so student code cannot swap a socket
for a link to another one. Nothing of either is in the workdir.

The sandbox's processes are found by what student code cannot forge: the
launcher's process tree (pid and start time), the sandbox's pid namespace and,
where there is one, its ``pids`` cgroup. Never by command lines or paths.
"""

from __future__ import annotations

import asyncio
import dataclasses
import functools
import importlib.util
import logging
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import BinaryIO, NamedTuple

from jupyter_client import BlockingKernelClient, KernelManager
from jupyter_client.kernelspec import KernelSpec
from jupyter_core.utils import run_sync
from traitlets import DottedObjectName

from grader.sandbox import bwrap, fork_server
from grader.sandbox.bwrap import SandboxSpec, sandbox_env, sandbox_user_namespace, wrap_command
from grader.sandbox.kernel_client import SandboxedKernelClient
from grader.sandbox.limits import (
    Process, hold_pid_namespace, innermost_pid, is_running, kill_and_reap, namespace_members, peak_rss_bytes, pid_namespace, process,
    process_tree,
)
from grader.sandbox.seccomp import filter_program
from grader.sandbox.process_limit import ProcessLimit, namespace_cap_prefix, pids_parent

__all__ = ["SandboxedKernelManager", "SandboxedKernelClient", "peak_memory_bytes"]

log = logging.getLogger(__name__)

# sun_path holds 108 bytes including the terminating NUL.
_MAX_SOCKET_PATH = 107
# Owner of a sealed sockets folder: not the sandbox's user, so its code cannot write there.
_SEALED_UID = 65534
# How long start-up waits for the kernel's sockets before sealing what is there.
_SOCKETS_TIMEOUT = 60.0
# How a fresh kernel is started; its arguments follow.
_KERNEL_LAUNCHER = [sys.executable, "-m", "ipykernel_launcher"]
#: the IPython extension every grading kernel loads before any cell (``starter/library_policy.py``)
POLICY_EXTENSION = "starter.library_policy"


class _PendingFork(NamedTuple):
    """A sandbox launched for a kernel not yet forked into it (``launch(defer_fork=True)``)."""

    from_waiter: BinaryIO  # the waiter's stdout: one byte once bubblewrap has built the sandbox
    to_waiter: BinaryIO  # the waiter's stdin: the kernel's pid in the sandbox, once it is there
    kw: dict  # the launch's options, for the kernel's arguments or a fresh start instead


class SandboxedKernelManager(KernelManager):
    """Kernel manager for an IPython kernel confined by a :class:`SandboxSpec`.

    Parameters
    ----------
    spec : SandboxSpec
        The sandbox; ``spec.workdir`` becomes the kernel's working directory.
    runtime_root : path-like, optional
        A folder of the grader's, never bound into any sandbox, in which the
        manager creates its runtime folder (connection file and sockets);
        default the system's temporary folder. The runtime folder is deleted
        when the kernel is shut down for good.
    **kw
        Passed to :class:`jupyter_client.KernelManager`; ``transport``,
        ``ip`` and ``connection_file`` are fixed by the sandbox.

    Notes
    -----
    The kernel is the grader's own interpreter (``sys.executable``) running
    ``-m ipykernel_launcher``. Interrupts travel as control messages, because a
    signal to the launcher would stop bwrap rather than reach the kernel.
    Shutting down (``now=True`` or not) ends with SIGKILL to every process of
    the sandbox, so a kernel that ignores SIGINT/SIGTERM or a student process
    in its own session cannot outlive it.

    The manager's own methods are synchronous, but :meth:`client` returns an
    ``AsyncKernelClient`` (:class:`SandboxedKernelClient`), which is what nbclient needs: with a blocking client
    nbclient's wait for a hung cell's output blocks its event loop, so its
    cell timeout never fires. Use :meth:`blocking_client` to drive the kernel
    from synchronous code.

    Start the kernel from a thread that outlives it (nbclient does): bwrap's
    ``--die-with-parent`` ties the sandbox to the starting *thread*.

    Each start creates a ``pids`` cgroup capping the sandbox at
    ``spec.max_processes`` tasks (:mod:`grader.sandbox.process_limit`), and
    each shutdown removes it. Where the host has no writable ``pids`` cgroup,
    a user other than root is capped by ``RLIMIT_NPROC`` inside the sandbox's
    own user namespace (refusals are then not counted); failing both, the
    kernel runs uncapped and a warning says so once.
    """

    process_limit: ProcessLimit | None = None
    launcher: Process | None = None
    _pending_fork: _PendingFork | None = None  # a deferred launch's sandbox, waiting for its kernel
    namespace_cap: int | None = None  # RLIMIT_NPROC applied inside the sandbox, when no cgroup caps it

    client_class = DottedObjectName("grader.sandbox.kernel_client.SandboxedKernelClient", config=True)

    pid_namespace: str | None = None  # the sandbox's, e.g. "pid:[4026532771]", once seen; held by _namespace_fd
    _namespace_fd: int | None = None  # keeps pid_namespace's name from going to another sandbox
    forked: bool = False  # this start forks the kernel from the template (grader.sandbox.fork_server)

    def __init__(self, spec: SandboxSpec, runtime_root: str | Path | None = None, **kw):
        if not isinstance(spec, SandboxSpec):
            raise ValueError(f"spec must be a SandboxSpec, got {type(spec).__name__}")
        fixed = sorted({"transport", "ip", "connection_file"} & kw.keys())
        if fixed:
            raise ValueError(f"kw must not set {fixed}: the sandbox fixes them")
        runtime = Path(tempfile.mkdtemp(prefix="kernel-", dir=runtime_root))
        ip = str(runtime / "sockets" / "k")
        if len(ip) + len("-99999") > _MAX_SOCKET_PATH:
            shutil.rmtree(runtime)
            raise ValueError(
                f"runtime_root is too long for Unix socket paths ({len(ip)} characters in {ip!r}); use a shorter one"
            )
        super().__init__(transport="ipc", ip=ip, connection_file=str(runtime / "kernel.json"), **kw)
        self.sandbox_spec = spec
        self.runtime_dir = runtime

    @property
    def sockets_dir(self) -> Path:
        """The folder of the kernel's sockets, the only runtime path the sandbox may write."""
        return self.runtime_dir / "sockets"

    @property
    def kernel_spec(self) -> KernelSpec:
        """The sandboxed IPython kernel's spec (never looked up by name)."""
        return KernelSpec(
            # No history database: nothing reads it, and a student who fills the
            # size-capped /tmp would otherwise get sqlite warnings in their output.
            # No 0.5 ms sleep before each execute_reply: ipykernel keeps it for front ends that
            # stop at the reply, but nbclient reads outputs until the kernel says it is idle.
            # The library-call policy's recorder is an IPython extension: loaded before the first
            # cell whether the kernel is forked from the template (which installed it already) or fresh.
            argv=[*_KERNEL_LAUNCHER, "-f", "{connection_file}", "--HistoryManager.enabled=False", "--IPythonKernel._execute_sleep=0",
                  f"--IPKernelApp.extensions={POLICY_EXTENSION}"],
            display_name="Python 3 (sandboxed)",
            language="python",
            interrupt_mode="message",
        )

    def format_kernel_cmd(self, extra_arguments: list[str] | None = None) -> list[str]:
        """The kernel command, wrapped in the sandbox.

        Parameters
        ----------
        extra_arguments : list of str, optional
            Appended to the kernel's own arguments.

        Returns
        -------
        list of str
            :func:`grader.sandbox.bwrap.wrap_command` of
            ``python -m ipykernel_launcher -f <connection file> ...``.
        """
        spec = self._kernel_sandbox()
        kernel = [sys.executable, "-I", "-S", "-c", fork_server.WAITER] if self.forked else super().format_kernel_cmd(extra_arguments)
        if self.namespace_cap is not None:
            kernel = [*namespace_cap_prefix(self.namespace_cap), *kernel]
        binds = [("--ro-bind", Path(self.connection_file)), ("--bind", self.sockets_dir)]
        command = wrap_command(kernel, spec, binds, pid_1=self.forked)
        if self.process_limit is not None:
            command = [*self.process_limit.join_prefix(), *command]
        return command

    def _kernel_sandbox(self) -> SandboxSpec:
        """``sandbox_spec`` as the kernel runs in it."""
        # Inside the pid namespace the kernel's parent is bwrap's pid 1; saying so
        # keeps ipykernel from polling a parent pid it cannot see and from
        # printing its "ipython kernel entry point" note on the grader's stdout.
        return dataclasses.replace(
            self.sandbox_spec,
            env={"JPY_PARENT_PID": "1", **self.sandbox_spec.env},
            hide=[*self.sandbox_spec.hide, *_debugger_paths()],
        )

    def processes_refused(self) -> int:
        """How many new processes or threads the kernel's cap has refused since it started.

        Returns
        -------
        int
            0 also when no cap is in force or the cap is ``RLIMIT_NPROC``, which counts nothing.
        """
        return self.process_limit.refused() if self.process_limit is not None else 0

    def blocking_client(self) -> BlockingKernelClient:
        """A synchronous client connected to this kernel.

        Returns
        -------
        jupyter_client.BlockingKernelClient
        """
        info = self.get_connection_info(session=True)
        return BlockingKernelClient(**info, connection_file=self.connection_file, parent=self)

    async def _async_pre_start_kernel(self, **kw):
        # A fresh sockets folder per start: a restart never reuses what the last kernel could write.
        shutil.rmtree(self.sockets_dir, ignore_errors=True)
        self.sockets_dir.mkdir(mode=0o700)
        self._release_pid_namespace()
        self._remove_process_limit()
        self.namespace_cap = None
        cap = self.sandbox_spec.max_processes
        parent = pids_parent() if cap is not None else None
        if parent is not None:
            try:
                self.process_limit = ProcessLimit(cap, parent)
            except OSError as exc:  # e.g. the parent's own cgroup count is exhausted
                log.warning("kernel starts without a process cap: cannot create its pids cgroup: %s", exc)
        elif cap is not None and os.geteuid() != 0 and sandbox_user_namespace():
            self.namespace_cap = cap
        elif cap is not None:
            _warn_without_process_limit()
        # looked up in bwrap's module each time, so that a test can take bubblewrap away
        self.forked = fork_server.enabled() and bwrap.bwrap_available()
        return await super()._async_pre_start_kernel(**kw)

    pre_start_kernel = run_sync(_async_pre_start_kernel)

    def launch(self, defer_fork: bool = False, **kw) -> None:
        """Start the kernel's process and return at once, without waiting for it to boot.

        :meth:`finish_start` completes the start (waits for the sockets, seals them, connects
        the control socket); until then no client should talk to the kernel. ``start_kernel``
        is ``launch`` then ``finish_start``. A kernel launched ahead of time boots while the
        grader does other work (``grader.pipeline.unit`` pre-starts the next unit's sandbox).

        With ``defer_fork``, a kernel to be forked from the template gets only its sandbox:
        bubblewrap builds it (about 20 ms, much of it waiting on the host's kernel) while the
        grader works on, and :meth:`complete_launch` forks the kernel into it.
        """
        self._attempted_start = True
        kernel_cmd, kw = self.pre_start_kernel(**kw)
        self._launch_kernel(kernel_cmd, defer_fork=defer_fork, **kw)
        self._launch_kw = kw

    def finish_start(self) -> None:
        """Complete a :meth:`launch`: fork the kernel if that was deferred, wait for its sockets and seal them."""
        self.complete_launch()
        self.post_start_kernel(**self._launch_kw)

    async def _async_launch_kernel(self, kernel_cmd: list[str], defer_fork: bool = False, **kw) -> None:
        # Nothing in the sandbox holds the grader's stdout or stderr (a terminal, a log):
        # student code would write to them, escape sequences included. Its output is the
        # notebook's, read from IOPub.
        kw = {**kw, "stdin": subprocess.DEVNULL, "stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
        if not self.forked:
            await self._launch_fresh(kw, kernel_cmd)
            return
        try:
            await self._launch_sandbox_for_fork(kernel_cmd, kw)
        except Exception as exc:  # noqa: BLE001 - the kernel starts fresh instead
            await self._launch_fresh_instead(exc, kw)
            return
        if not defer_fork:
            await self._async_complete_launch()

    _launch_kernel = run_sync(_async_launch_kernel)

    async def _launch_fresh(self, kw: dict, kernel_cmd: list[str] | None = None) -> None:
        kernel_cmd = kernel_cmd or self.format_kernel_cmd(kw.get("extra_arguments"))
        await super()._async_launch_kernel(kernel_cmd, **kw)
        # Remember the launcher with its start time: once jupyter_client has
        # reaped it, its pid may go to any process on the host.
        self.launcher = process(self.provisioner.pid)

    async def _launch_fresh_instead(self, exc: Exception, kw: dict) -> None:
        """After a failed fork: kill the half-built sandbox, say why, and start the kernel fresh."""
        kill_and_reap(self._sandbox_processes())
        self._release_pid_namespace()  # that sandbox's: the fresh kernel's is another
        fork_server.failed(f"it could not be forked from the template ({exc})")
        self.forked = False
        await self._launch_fresh(kw)

    async def _launch_sandbox_for_fork(self, kernel_cmd: list[str], kw: dict) -> None:
        """Launch the sandbox with the waiter as its pid 1; :meth:`complete_launch` forks the kernel into it."""
        to_waiter, waiter_reads = os.pipe()[::-1]
        try:
            await super()._async_launch_kernel(kernel_cmd, **{**kw, "stdin": waiter_reads, "stdout": subprocess.PIPE})
        except BaseException:
            os.close(to_waiter)
            raise
        finally:
            os.close(waiter_reads)
        self.launcher = process(self.provisioner.pid)
        self._pending_fork = _PendingFork(self.provisioner.process.stdout, os.fdopen(to_waiter, "wb"), kw)

    async def _async_complete_launch(self) -> None:
        """Fork the kernel into the sandbox a deferred launch built (nothing to do otherwise)."""
        pending, self._pending_fork = self._pending_fork, None
        if pending is None:
            return
        try:
            with pending.from_waiter, pending.to_waiter:
                # what a fresh kernel would be started with, less the interpreter and the launcher module
                arguments = super().format_kernel_cmd(pending.kw.get("extra_arguments"))[len(_KERNEL_LAUNCHER):]
                await self._enter_waiter(pending.from_waiter, pending.to_waiter, arguments)
        except Exception as exc:  # noqa: BLE001 - the kernel starts fresh instead
            await self._launch_fresh_instead(exc, pending.kw)
            return
        fork_server.succeeded()

    complete_launch = run_sync(_async_complete_launch)

    async def _enter_waiter(self, from_waiter, to_waiter, arguments: list[str]) -> None:
        # The waiter's first byte: bubblewrap has built the sandbox and handed it the waiter.
        if not fork_server.readable(from_waiter.fileno(), _SOCKETS_TIMEOUT) or os.read(from_waiter.fileno(), 1) != b"r":
            raise RuntimeError("the sandbox's waiter did not start")
        found = self._first_in_sandbox()
        if found is None:
            raise RuntimeError("the sandbox's waiter is gone")
        waiter = found
        program = filter_program() if bwrap.system_calls_filtered() else None
        request = {
            "target": waiter.pid,
            "start": waiter.start_ticks,
            "cgroup": str(self.process_limit.path / "cgroup.procs") if self.process_limit is not None else None,
            "seccomp": program.hex() if program is not None else None,
            "workdir": str(self.sandbox_spec.workdir),
            "env": {**sandbox_env(self._kernel_sandbox()), "PWD": str(self.sandbox_spec.workdir)},  # bwrap's --chdir sets PWD
            "argv": arguments,
        }
        kernel = await asyncio.to_thread(fork_server.fork_kernel, request)
        inner = innermost_pid(kernel)
        if inner is None or pid_namespace(kernel) != self.pid_namespace:
            raise RuntimeError("the forked kernel is gone")
        to_waiter.write(f"{inner}\n".encode())

    async def _async_post_start_kernel(self, **kw) -> None:
        await super()._async_post_start_kernel(**kw)
        await self._seal_sockets()

    post_start_kernel = run_sync(_async_post_start_kernel)

    async def _seal_sockets(self) -> None:
        """Once the kernel has created its sockets, take their folder away from the sandbox's user.

        Only root can: elsewhere the sandbox's user owns the folder and could
        take it back. Also notes the sandbox's pid namespace on the way.
        """
        ports = [self.shell_port, self.iopub_port, self.stdin_port, self.control_port, self.hb_port]
        sockets = [Path(f"{self.ip}-{port}") for port in ports]
        deadline = time.monotonic() + _SOCKETS_TIMEOUT
        while time.monotonic() < deadline and self._launcher_running():
            self._note_pid_namespace()
            if all(p.exists() for p in sockets):
                break
            await asyncio.sleep(0.01)
        self._note_pid_namespace()
        if os.geteuid() == 0:
            os.chown(self.sockets_dir, _SEALED_UID, _SEALED_UID)
            os.chmod(self.sockets_dir, 0o755)

    def _launcher_running(self) -> bool:
        # One stat file, not a /proc scan: this runs every 10 ms while the kernel starts.
        return self.launcher is not None and is_running(self.launcher)

    def _note_pid_namespace(self) -> None:
        """Remember the pid namespace the sandbox's processes are in (bwrap gives it one of its own)."""
        if self.pid_namespace is None:
            self._first_in_sandbox()

    def _first_in_sandbox(self) -> Process | None:
        """The launcher's first descendant in a pid namespace other than the grader's; its namespace is held.

        The namespace is held open (:func:`~grader.sandbox.limits.hold_pid_namespace`) until
        the kernel is shut down: killing by a name the sandbox no longer holds would kill
        whichever sandbox was given that name next (another unit's, another grader's).
        """
        if self.launcher is None:
            return None
        own = pid_namespace(os.getpid())
        for proc in process_tree(self.launcher):
            ns = pid_namespace(proc.pid)
            if ns is None or ns == own:
                continue
            if self.pid_namespace is None and (held := hold_pid_namespace(proc)) is not None:
                self.pid_namespace, self._namespace_fd = held
            if self.pid_namespace == ns:
                return proc
        return None

    def _release_pid_namespace(self) -> None:
        """Forget the sandbox's pid namespace and let its name go (after its processes were killed)."""
        fd, self._namespace_fd, self.pid_namespace = self._namespace_fd, None, None
        if fd is not None:
            os.close(fd)

    def _sandbox_processes(self) -> list[Process]:
        # The launcher's tree, plus whatever is in the sandbox's pid namespace or
        # cgroup but was orphaned from that tree (a launcher dying during setup).
        self._note_pid_namespace()
        roots = [self.launcher] if self.launcher is not None else []
        if self.pid_namespace is not None:
            roots += namespace_members(self.pid_namespace)
        if self.process_limit is not None:
            roots += self.process_limit.pids()
        return process_tree(*roots)

    async def _async_kill_kernel(self, restart: bool = False) -> None:
        # The whole tree at once, before the launcher dies and orphans it.
        kill_and_reap(self._sandbox_processes())
        await super()._async_kill_kernel(restart=restart)
        self._release_pid_namespace()

    _kill_kernel = run_sync(_async_kill_kernel)

    async def _async_shutdown_kernel(self, now: bool = False, restart: bool = False) -> None:
        # A polite shutdown lets the kernel exit on its own; whatever it started
        # (in the no-bwrap fallback, where no pid namespace reaps it) is killed after.
        tree = self._sandbox_processes()
        try:
            if now and self.owns_kernel:
                await self._kill_now(restart)
            else:
                await super()._async_shutdown_kernel(now=now, restart=restart)
        finally:
            kill_and_reap(tree)
            self._release_pid_namespace()
            self._remove_process_limit()

    shutdown_kernel = run_sync(_async_shutdown_kernel)

    async def _kill_now(self, restart: bool) -> None:
        """``shutdown_kernel(now=True)`` as jupyter_client does it, less two costs of every unit.

        jupyter_client first sends the kernel an interrupt request (a control connection and a
        message, for a kernel killed right after), and its ``in_pending_state`` decorator sleeps
        10 ms "so tests can see the pending state". The sandbox's tree, listed once, is killed
        by the caller.
        """
        self.shutting_down = True  # the restarter must not revive it
        self.stop_restarter()
        await super()._async_kill_kernel(restart=restart)
        await self._async_cleanup_resources(restart=restart)

    async def _async_cleanup_resources(self, restart: bool = False) -> None:
        if self._pending_fork is not None:  # a sandbox shut down before its kernel was forked
            self._pending_fork.from_waiter.close()
            self._pending_fork.to_waiter.close()
            self._pending_fork = None
        await super()._async_cleanup_resources(restart=restart)
        if not restart:
            shutil.rmtree(self.runtime_dir, ignore_errors=True)  # never follows a link planted in sockets/

    cleanup_resources = run_sync(_async_cleanup_resources)

    def _remove_process_limit(self) -> None:
        if self.process_limit is not None:
            if not self.process_limit.remove():
                log.warning("could not remove the sandbox's pids cgroup %s", self.process_limit.path)
            self.process_limit = None


@functools.cache
def _debugger_paths() -> tuple[Path, ...]:
    """Where debugpy is installed: masked in every sandbox, so ipykernel starts without its debugger.

    Nothing in grading uses the debugger (no front end attaches, there is no network), and
    importing it is about a fifth of the kernel's start-up imports.
    """
    found = importlib.util.find_spec("debugpy")
    if found is None or not found.submodule_search_locations:
        return ()
    return tuple(Path(p).resolve() for p in found.submodule_search_locations)


@functools.cache
def _warn_without_process_limit() -> None:
    log.warning(
        "no writable pids cgroup (and, as root or without user namespaces, no RLIMIT_NPROC per sandbox): "
        "sandboxes run without a cap on their number of processes"
    )


def peak_memory_bytes(km: SandboxedKernelManager) -> int | None:
    """Peak resident memory of the sandboxed kernel, measured from the host.

    Parameters
    ----------
    km : SandboxedKernelManager
        A manager whose kernel is running.

    Returns
    -------
    int or None
        The largest peak RSS (``VmHWM``) in bytes among the sandbox's live
        processes (the kernel's own peak, unless a child it started peaked
        higher); ``None`` if no kernel is running. Call it before shutdown.
    """
    if km.process_limit is not None:
        # Every process of the sandbox is in its pids cgroup from its first instruction and cannot
        # leave it (no cgroup filesystem, no capabilities inside): one small read, not two /proc scans.
        return peak_rss_bytes(km.process_limit.pids())
    return peak_rss_bytes(p.pid for p in km._sandbox_processes())
