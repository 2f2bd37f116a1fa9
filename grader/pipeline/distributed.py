"""Grading on a Dask cluster: units run on other machines, results come back here.

``deformlab grade … --scheduler tcp://HOST:8786`` submits every unit to a
``dask.distributed`` scheduler; ``--scheduler local:N`` starts a cluster of N
worker processes on this machine. A ``UnitSpec`` is self-contained (submitted
bytes, instructor notebook, seed, limits), so a worker needs only the installed
kit; each worker still runs every notebook in its own sandbox and refuses units
when it has no bubblewrap, unless the TA opts out (``--allow-unsandboxed``).
Results stream back in order of completion to the one process
that records them (``grader.pipeline.run``). A worker that dies mid-unit costs
nothing: the scheduler runs its units again elsewhere, and only a unit that kills
workers repeatedly is recorded as a grader error.

A Dask worker runs its tasks in threads, where the grader's own limits on
verification and feedback (``grader.pipeline.guard.grader_limits``: an
address-space cap and an alarm) cannot work: both are per process and the alarm
reaches the main thread only. So each worker thread hands its units to a
*grading process* of its own (``GradingProcess``), a child that grades one unit
at a time in its main thread, as a pool worker does, and keeps what a pool
worker keeps between units (the kernel template, the next unit's sandbox, the
reference's outputs). A child that dies is replaced and the unit graded again in
the new one; a unit whose grading process dies twice is a grader error that says so.
A grading process dies with its worker, however the worker ends (SIGKILL included),
and its kernels and sandboxes with it (:mod:`grader.pipeline.workers`); start
``dask worker`` with ``--death-timeout`` so that a worker whose scheduler is gone
closes instead of waiting for it forever.
"""

from __future__ import annotations

import os
import pickle
import re
import struct
import subprocess
import sys
import threading
import time
import uuid
from collections.abc import Callable, Iterator

from grader.pipeline.unit import UnitSpec, grade_unit

_TCP = re.compile(r"^(tcp|tls)://[^\s/:]+:\d{1,5}$")
_LOCAL = re.compile(r"^local:(\d+)$")
#: Units in flight per worker thread: enough to keep workers busy between results,
#: few enough that a class's submitted bytes never sit all in this process's memory.
IN_FLIGHT_PER_THREAD = 3
#: Seconds between checks that the units in flight can still run somewhere.
WATCH_SECONDS = 5.0
#: Seconds units may wait with no worker able to grade them before they are given up.
STALL_SECONDS = 120.0
NO_SANDBOX = (
    "no Dask worker can sandbox notebooks (bubblewrap missing or unable to create namespaces there): "
    "install bubblewrap on the workers, or pass --allow-unsandboxed to grade without isolation"
)
NO_WORKER = (
    "no Dask worker able to grade was left in the cluster (the sandboxing workers died or left): "
    "start workers and grade again; units already graded are kept"
)


class SandboxUnavailable(RuntimeError):
    """Raised by a worker that has no working bubblewrap and was not told to grade without it."""

    def __init__(self, worker: str):
        super().__init__(f"worker {worker} has no working bubblewrap sandbox")
        self.worker = worker


def parse_scheduler(text: str) -> tuple[str, int | None]:
    """``("tcp://HOST:PORT", None)`` or ``("local", N)``.

    Raises
    ------
    ValueError
        If ``text`` is neither ``tcp://HOST:PORT`` (or ``tls://``) nor ``local:N`` with N ≥ 1.
    """
    if _TCP.match(text):
        return text, None
    local = _LOCAL.match(text)
    if local and int(local.group(1)) >= 1:
        return "local", int(local.group(1))
    raise ValueError(f"--scheduler must be tcp://HOST:PORT (a running `dask scheduler`) or local:N (N ≥ 1 worker processes here), got {text!r}")


def _sandbox_ready(allow_unsandboxed: bool) -> bool:
    from grader.sandbox import bwrap_available

    return allow_unsandboxed or bwrap_available()


class GradingProcessDied(RuntimeError):
    """The grading process of a Dask worker died while grading a unit (not the student's kernel: the grader itself)."""


class GradingProcess:
    """A child process that runs calls in its main thread, one at a time (``python -m grader.pipeline.distributed``).

    Calls and answers cross its standard input and output as length-prefixed
    pickles (``cloudpickle`` for the call, so a function may be defined anywhere);
    whatever the grading code prints goes to the worker's standard error.
    """

    def __init__(self):
        # It dies with the worker thread that starts it, however the worker ends (grader.pipeline.workers).
        self.process = subprocess.Popen([sys.executable, "-m", "grader.pipeline.distributed", str(os.getpid())],
                                        stdin=subprocess.PIPE, stdout=subprocess.PIPE)

    def call(self, fn: Callable, *args):
        """``fn(*args)`` in the child's main thread; its exception is raised here.

        Raises
        ------
        GradingProcessDied
            If the child exits before it answers.
        """
        import cloudpickle

        try:
            _send(self.process.stdin, cloudpickle.dumps((fn, args)))
            ok, value = pickle.loads(_receive(self.process.stdout))
        except (EOFError, BrokenPipeError) as exc:
            self.close()
            raise GradingProcessDied(f"the grading process died while grading this notebook (exit status {self.process.returncode})") from exc
        if not ok:
            raise value
        return value

    def close(self) -> None:
        """End the child (closing its input ends its loop) and reap it."""
        for stream in (self.process.stdin, self.process.stdout):
            try:
                stream.close()
            except OSError:
                pass
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()


def _send(stream, payload: bytes) -> None:
    stream.write(struct.pack("<Q", len(payload)))
    stream.write(payload)
    stream.flush()


def _receive(stream) -> bytes:
    def exactly(n: int) -> bytes:
        data = stream.read(n)
        if data is None or len(data) < n:
            raise EOFError("the other side closed the pipe")
        return data

    return exactly(struct.unpack("<Q", exactly(8))[0])


_thread_local = threading.local()


def on_grading_process(fn: Callable, *args):
    """``fn(*args)`` in the main thread of this thread's grading process (started on first use)."""
    grading = getattr(_thread_local, "grading", None)
    if grading is None or grading.process.poll() is not None:
        grading = _thread_local.grading = GradingProcess()
    try:
        return grading.call(fn, *args)
    except GradingProcessDied:
        _thread_local.grading = None
        raise


def grade_unit_on_worker(spec: UnitSpec, allow_unsandboxed: bool = False, grade: Callable = grade_unit) -> dict:
    """The Dask task: ``grade(spec)`` in this worker's grading process, sandboxed, under the grader's own limits.

    Parameters
    ----------
    spec : UnitSpec
    allow_unsandboxed : bool, optional
        Grade even where bubblewrap is missing.
    grade : callable, optional
        ``UnitSpec -> dict``; ``grade_unit``.

    Raises
    ------
    SandboxUnavailable
        If this worker cannot sandbox notebooks and ``allow_unsandboxed`` is False.
    GradingProcessDied
        If the grading process died twice while grading this unit (recorded as its grader error).
    """
    from distributed import get_worker

    if not _sandbox_ready(allow_unsandboxed):
        raise SandboxUnavailable(get_worker().address)
    try:
        return on_grading_process(grade, spec)
    except GradingProcessDied:
        # Once more in a new grading process: something else may have killed the first one
        # (the kernel's OOM killer picks by size); a unit that kills it again is the culprit.
        try:
            return on_grading_process(grade, spec)
        except GradingProcessDied as exc:
            raise GradingProcessDied(f"{exc}, twice") from None


def _serve(worker: int) -> None:
    """The grading process's loop: each call in this main thread, until the worker (pid ``worker``) closes the pipe or dies."""
    from grader.pipeline.workers import init_worker

    calls = os.fdopen(os.dup(0), "rb")
    answers = os.fdopen(os.dup(1), "wb")
    # Nothing else reads the worker's pipe or writes to it: prints go to standard error.
    devnull = os.open(os.devnull, os.O_RDONLY)
    os.dup2(devnull, 0)
    os.close(devnull)
    os.dup2(2, 1)
    init_worker(worker)
    _sweep()
    while True:
        try:
            fn, args = pickle.loads(_receive(calls))
        except EOFError:
            return
        try:
            answer = (True, fn(*args))
        except Exception as exc:  # noqa: BLE001 - the worker raises it as the task's error
            answer = (False, exc)
        try:
            payload = pickle.dumps(answer)
        except Exception as exc:  # noqa: BLE001 - an exception that does not pickle is sent as its text
            payload = pickle.dumps((False, RuntimeError(f"{type(exc).__name__}: {exc}")))
        try:
            _send(answers, payload)
        except BrokenPipeError:  # the worker is gone
            return


def _sweep() -> None:
    """What a killed grader left on this machine (work folders with hidden inputs, cgroups): once per grading process."""
    from grader.sandbox.process_limit import remove_stale_limits
    from grader.sandbox.workspace import remove_stale_workspaces

    remove_stale_workspaces()
    remove_stale_limits()


def connect(scheduler: str):
    """A ``distributed.Client`` on the cluster ``scheduler`` names, and the local cluster to close (or None)."""
    address, n_local = parse_scheduler(scheduler)
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise ValueError('--scheduler needs Dask: pip install "deformlab[dask]" (with -c constraints.txt)') from None
    if n_local is not None:
        import dask

        # One thread per worker process: a unit is one kernel; N processes grade N notebooks at once.
        # No statistical profiler (it samples each worker's stack every 10 ms for a dashboard this
        # cluster does not serve) and no GIL monitor: the workers inherit this configuration.
        with dask.config.set({"distributed.worker.profile.enabled": False, "distributed.admin.system-monitor.gil.enabled": False}):
            # Its worker processes exit with this one (distributed watches their parent), and a worker that
            # lost its scheduler for a minute closes rather than waiting for it forever.
            cluster = LocalCluster(n_workers=n_local, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None,
                                   death_timeout=60)
        return Client(cluster), cluster
    try:
        return Client(address, timeout="20s"), None
    except (OSError, TimeoutError) as exc:
        raise ValueError(f"cannot reach the Dask scheduler at {address}: {exc}") from None


def grade_on_dask(
    todo: list,
    spec_of: Callable[[object], UnitSpec],
    error_of: Callable[[object, str], dict],
    scheduler: str,
    allow_unsandboxed: bool = False,
    stall_seconds: float | None = None,
) -> Iterator[tuple[object, dict]]:
    """Grade ``todo`` on the cluster; yield ``(unit, result)`` in order of completion.

    Parameters
    ----------
    todo : list
        Planned units (``grader.pipeline.plan.PlannedUnit``).
    spec_of : callable
        ``unit -> UnitSpec``; called just before the unit is submitted.
    error_of : callable
        ``(unit, reason) -> result`` of a unit the cluster could not grade.
    scheduler : str
        ``tcp://HOST:PORT`` or ``local:N``.
    stall_seconds : float, optional
        How long units may wait without any worker able to grade them (all
        sandboxing workers gone) before they are recorded as grader errors;
        default ``STALL_SECONDS``.
    """
    from distributed import wait
    from distributed.scheduler import KilledWorker

    stall_seconds = STALL_SECONDS if stall_seconds is None else stall_seconds
    client, cluster = connect(scheduler)
    try:
        ready = client.run(_sandbox_ready, allow_unsandboxed)
        refusing = {w for w, ok in ready.items() if not ok}
        if refusing:
            print(f"warning: {len(refusing)} Dask worker(s) without bubblewrap get no units: {', '.join(sorted(refusing))}", file=sys.stderr)
        queue = list(todo)
        in_flight: dict = {}  # future -> (unit, the workers it may run on; None: any)

        def allowed() -> list[str] | None:
            if not refusing:
                return None
            return [w for w in client.nthreads() if w not in refusing]

        def submit(unit) -> bool:
            workers = allowed()
            if workers == []:
                return False
            future = client.submit(
                grade_unit_on_worker,
                spec_of(unit),
                allow_unsandboxed,
                key=f"grade-{unit.student_id}-{unit.notebook}-{uuid.uuid4().hex}",
                workers=workers,
                allow_other_workers=False,
            )
            in_flight[future] = (unit, workers)
            return True

        def drop(future):
            future.release()
            return in_flight.pop(future)[0]

        def take_back(future) -> None:
            """Cancel a unit in flight and queue it first again."""
            future.cancel()
            queue.insert(0, drop(future))

        def refill() -> None:
            limit = IN_FLIGHT_PER_THREAD * max(1, sum(client.nthreads().values()))
            while queue and len(in_flight) < limit and submit(queue[0]):
                queue.pop(0)

        if allowed() == []:  # no worker of this cluster can sandbox a notebook
            for unit in queue:
                yield unit, error_of(unit, NO_SANDBOX)
            return
        refill()
        stalled_since = None
        while in_flight or queue:
            try:
                done, _ = wait(list(in_flight), timeout=WATCH_SECONDS, return_when="FIRST_COMPLETED") if in_flight else (set(), None)
            except TimeoutError:
                done = set()
            if not done:
                # Nothing finished for a while: can the units still run? A unit pinned to
                # sandboxing workers that all died would wait in the scheduler forever.
                alive = set(client.nthreads()) - refusing
                for future in [f for f, (_, workers) in in_flight.items() if workers is not None and not alive & set(workers)]:
                    take_back(future)
                refill()
                if alive:
                    stalled_since = None
                    if not in_flight:
                        time.sleep(WATCH_SECONDS)
                    continue
                stalled_since = stalled_since or time.monotonic()
                if time.monotonic() - stalled_since < stall_seconds:
                    time.sleep(0 if in_flight else WATCH_SECONDS)
                    continue
                for future in list(in_flight):
                    take_back(future)
                for unit in queue:
                    yield unit, error_of(unit, NO_WORKER)
                return
            stalled_since = None
            for future in done:
                unit = in_flight[future][0]
                try:
                    result = future.result()
                except SandboxUnavailable as exc:
                    refusing.add(exc.worker)
                    print(f"warning: Dask worker {exc.worker} has no bubblewrap: it gets no more units", file=sys.stderr)
                    queue.insert(0, unit)
                    continue
                except KilledWorker:
                    result = error_of(unit, "Dask workers died repeatedly while grading this notebook")
                except Exception as exc:  # noqa: BLE001 - whatever one unit raised, the others are graded
                    result = error_of(unit, f"grader error: {type(exc).__name__}: {exc}")
                finally:
                    drop(future)
                yield unit, result
            refill()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


if __name__ == "__main__":
    _serve(int(sys.argv[1]))
