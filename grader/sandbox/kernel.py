"""A Jupyter kernel manager whose kernel runs inside the grading sandbox.

The kernel talks over ``ipc`` (Unix sockets): TCP cannot cross the sandbox's
private network namespace. The connection file and the sockets live in a
hidden folder of the workdir, which the sandbox binds at the same absolute
path, so the paths in the connection file mean the same thing on both sides.
"""

from __future__ import annotations

import dataclasses
import functools
import logging
import os
import sys

from jupyter_client import BlockingKernelClient, KernelManager
from jupyter_client.kernelspec import KernelSpec
from jupyter_core.utils import run_sync
from traitlets import DottedObjectName

from grader.sandbox.bwrap import SandboxSpec, sandbox_user_namespace, wrap_command
from grader.sandbox.limits import Process, kill_and_reap, peak_rss_bytes, process, process_tree, processes_with_argument
from grader.sandbox.process_limit import ProcessLimit, namespace_cap_prefix, pids_parent

__all__ = ["SandboxedKernelManager", "peak_memory_bytes", "KERNEL_DIR_NAME"]

log = logging.getLogger(__name__)

KERNEL_DIR_NAME = ".sandbox-kernel"

# sun_path holds 108 bytes including the terminating NUL.
_MAX_SOCKET_PATH = 107


class SandboxedKernelManager(KernelManager):
    """Kernel manager for an IPython kernel confined by a :class:`SandboxSpec`.

    Parameters
    ----------
    spec : SandboxSpec
        The sandbox; ``spec.workdir`` becomes the kernel's working directory
        and holds its connection file and sockets (in ``.sandbox-kernel/``).
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
    ``AsyncKernelClient``, which is what nbclient needs: with a blocking client
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
    namespace_cap: int | None = None  # RLIMIT_NPROC applied inside the sandbox, when no cgroup caps it

    client_class = DottedObjectName("jupyter_client.asynchronous.AsyncKernelClient", config=True)

    def __init__(self, spec: SandboxSpec, **kw):
        if not isinstance(spec, SandboxSpec):
            raise ValueError(f"spec must be a SandboxSpec, got {type(spec).__name__}")
        fixed = sorted({"transport", "ip", "connection_file"} & kw.keys())
        if fixed:
            raise ValueError(f"kw must not set {fixed}: the sandbox fixes them")
        kernel_dir = spec.workdir / KERNEL_DIR_NAME
        ip = str(kernel_dir / "kernel-ipc")
        if len(ip) + len("-99999") > _MAX_SOCKET_PATH:
            raise ValueError(
                f"workdir is too long for Unix socket paths ({len(ip)} characters in {ip!r}); use a shorter workdir"
            )
        super().__init__(transport="ipc", ip=ip, connection_file=str(kernel_dir / "kernel.json"), **kw)
        self.sandbox_spec = spec

    @property
    def kernel_spec(self) -> KernelSpec:
        """The sandboxed IPython kernel's spec (never looked up by name)."""
        return KernelSpec(
            # No history database: nothing reads it, and a student who fills the
            # size-capped /tmp would otherwise get sqlite warnings in their output.
            argv=[sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}", "--HistoryManager.enabled=False"],
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
        # Inside the pid namespace the kernel's parent is bwrap's pid 1; saying so
        # keeps ipykernel from polling a parent pid it cannot see and from
        # printing its "ipython kernel entry point" note on the grader's stdout.
        spec = dataclasses.replace(self.sandbox_spec, env={"JPY_PARENT_PID": "1", **self.sandbox_spec.env})
        kernel = super().format_kernel_cmd(extra_arguments)
        if self.namespace_cap is not None:
            kernel = [*namespace_cap_prefix(self.namespace_cap), *kernel]
        command = wrap_command(kernel, spec)
        if self.process_limit is not None:
            command = [*self.process_limit.join_prefix(), *command]
        return command

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
        (self.sandbox_spec.workdir / KERNEL_DIR_NAME).mkdir(mode=0o700, exist_ok=True)
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
        return await super()._async_pre_start_kernel(**kw)

    pre_start_kernel = run_sync(_async_pre_start_kernel)

    async def _async_launch_kernel(self, kernel_cmd: list[str], **kw) -> None:
        await super()._async_launch_kernel(kernel_cmd, **kw)
        # Remember the launcher with its start time: once jupyter_client has
        # reaped it, its pid may go to any process on the host.
        self.launcher = process(self.provisioner.pid)

    _launch_kernel = run_sync(_async_launch_kernel)

    def _sandbox_processes(self):
        # Every process carrying the connection file in its argv is this
        # sandbox's launcher, bwrap or kernel: that also finds a sandbox whose
        # launcher died during setup, leaving bwrap's init orphaned.
        roots = processes_with_argument(os.path.realpath(self.connection_file))
        return process_tree(*([self.launcher] if self.launcher is not None else []), *roots)

    async def _async_kill_kernel(self, restart: bool = False) -> None:
        # The whole tree at once, before the launcher dies and orphans it.
        kill_and_reap(self._sandbox_processes())
        await super()._async_kill_kernel(restart=restart)

    _kill_kernel = run_sync(_async_kill_kernel)

    async def _async_shutdown_kernel(self, now: bool = False, restart: bool = False) -> None:
        # A polite shutdown lets the kernel exit on its own; whatever it started
        # (in the no-bwrap fallback, where no pid namespace reaps it) is killed after.
        tree = self._sandbox_processes()
        try:
            await super()._async_shutdown_kernel(now=now, restart=restart)
        finally:
            kill_and_reap(tree)
            self._remove_process_limit()

    shutdown_kernel = run_sync(_async_shutdown_kernel)

    async def _async_cleanup_resources(self, restart: bool = False) -> None:
        await super()._async_cleanup_resources(restart=restart)
        if not restart:
            # Leave the workdir as the student left it; the folder is empty
            # once the connection file and sockets are gone.
            try:
                (self.sandbox_spec.workdir / KERNEL_DIR_NAME).rmdir()
            except OSError:
                pass

    cleanup_resources = run_sync(_async_cleanup_resources)

    def _remove_process_limit(self) -> None:
        if self.process_limit is not None:
            if not self.process_limit.remove():
                log.warning("could not remove the sandbox's pids cgroup %s", self.process_limit.path)
            self.process_limit = None


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
    return peak_rss_bytes(p.pid for p in km._sandbox_processes())
