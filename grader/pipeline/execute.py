"""Steps 2–3: execute a sanitized notebook in the sandbox and collect raw outputs.

The kernel runs the planned cells (definitions), then, for each graded function,
one collection cell that calls the student's function on the hidden fixtures and
writes the raw outputs. A cell that times out or kills the kernel costs only
itself: the kernel is killed and restarted, the definitions that ran are
replayed, and execution goes on with the next cell.
"""

from __future__ import annotations

import re
import functools
import gc
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellTimeoutError, DeadKernelError

from grader.output_caps import MAX_CELL_OUTPUT_CHARS, MAX_NOTEBOOK_OUTPUT_CHARS, MAX_OUTPUT_CHARS, MAX_OUTPUTS_PER_CELL
from grader.harness import kernel_side
from grader.sandbox import SandboxedKernelManager, SandboxSpec, peak_memory_bytes
from grader.sandbox.process_limit import DEFAULT_MAX_PROCESSES

KERNEL_SIDE_SOURCE = Path(kernel_side.__file__).read_text()
STARTUP_TIMEOUT = 120


@dataclass
class ExecuteOptions:
    timeout: float = 60.0  # per cell
    wall: float = 900.0  # per notebook, replays after restarts included
    memory_bytes: int = 4 * 2**30
    max_processes: int | None = DEFAULT_MAX_PROCESSES  # processes and threads alive at once
    readonly: list[Path] = field(default_factory=list)  # course data/ and starter/
    runtime_root: Path | None = None  # the grader's own folder for kernel connection files and sockets


@dataclass
class Execution:
    """What happened in the kernel.

    Attributes
    ----------
    nb : NotebookNode
        The notebook with the outputs of the cells that ran.
    cell_failures : dict
        Cell index -> reason, for cells that timed out, killed the kernel or raised.
    collection_failures : dict
        Function -> reason its outputs could not be collected (timeout, kernel died).
    events : list of str
        Kernel restarts and limits hit, in order.
    peak_rss_bytes : int or None
        Largest resident memory seen in the kernel.
    """

    nb: nbformat.NotebookNode
    cell_failures: dict[int, str] = field(default_factory=dict)
    collection_failures: dict[str, str] = field(default_factory=dict)
    events: list[str] = field(default_factory=list)
    peak_rss_bytes: int | None = None
    seconds: float = 0.0




def _output_chars(out) -> int:
    if "text" in out:
        return len(out["text"]) if isinstance(out["text"], str) else 0
    data = out.get("data") or {}
    size = sum(len(v) if isinstance(v, str) else len(str(v)) for v in data.values())
    return size + sum(len(line) for line in out.get("traceback") or [] if isinstance(line, str))


class _CappedClient(NotebookClient):
    """nbclient, keeping at most ``MAX_OUTPUTS_PER_CELL`` outputs and a character budget per cell and notebook."""

    notebook_chars = 0

    def output(self, outs, msg, display_id, cell_index):
        out = super().output(outs, msg, display_id, cell_index)
        if out is None or not outs or outs[-1] is not out:
            return out
        chars = _output_chars(out)
        cell_chars = sum(_output_chars(o) for o in outs[:-1])
        dropped = any(o.get("name") == "grader" for o in outs)
        if (
            len(outs) > MAX_OUTPUTS_PER_CELL
            or cell_chars + chars > MAX_CELL_OUTPUT_CHARS
            or self.notebook_chars + chars > MAX_NOTEBOOK_OUTPUT_CHARS
        ):
            outs.pop()
            if not dropped:
                outs.append(nbformat.v4.new_output("stream", name="grader", text="[further output of this cell was dropped by the grader]\n"))
            return None
        self.notebook_chars += chars
        return out


def _cap_outputs(cell) -> None:
    """Keep a huge print from bloating the autograded notebook and the result passed between processes."""
    for out in cell.get("outputs", []):
        if out.get("output_type") == "stream" and len(out.get("text", "")) > MAX_OUTPUT_CHARS:
            out["text"] = out["text"][:MAX_OUTPUT_CHARS] + f"\n[... output cut at {MAX_OUTPUT_CHARS} characters by the grader]\n"
        for mime, value in list(out.get("data", {}).items()):
            if isinstance(value, str) and len(value) > 10 * MAX_OUTPUT_CHARS:
                out["data"] = {"text/plain": f"[{mime} output of {len(value)} characters removed by the grader]"}
                break


#: IPython compiles each cell as a temporary file (``/tmp/ipykernel_7/2723624691.py``), which a student never sees.
_CELL_FILE = re.compile(r"\((?:[^()\s]*/)?\d+\.py, line (\d+)\)")


def _error_of(cell) -> str | None:
    for out in cell.get("outputs", []):
        if out.get("output_type") == "error":
            evalue = _CELL_FILE.sub(r"(line \1 of the cell)", str(out.get("evalue", "")))
            return f"{out.get('ename', 'Error')}: {evalue[:500]}"
    return None


#: The collector's file, next to the fixtures it reads.
COLLECTOR = "kernel_side.py"


def _collect_source(function: str, fixtures: Path, outputs: Path) -> str:
    # The definition and the call share one cell, so no student code runs between them. The
    # definition is read from a file: IPython tokenizes a cell in Python and ipykernel hashes it
    # character by character, which cost 10 ms per collection when the cell held the source.
    collector = str(fixtures / COLLECTOR)
    return (
        f"exec(compile(open({collector!r}).read(), {collector!r}, 'exec'))\n"
        f"__deformlab_collect__({function!r}, {str(fixtures)!r}, {str(outputs)!r})\n"
    )


def execute(
    nb: nbformat.NotebookNode,
    plan: list[int],
    functions: list[str],
    workdir: Path,
    fixtures: Path,
    outputs: Path,
    options: ExecuteOptions,
    kernel: SandboxedKernelManager | None = None,
) -> Execution:
    """Run ``plan`` then one collection per function, in a sandboxed kernel.

    Parameters
    ----------
    nb : NotebookNode
        Sanitized notebook (modified in place: outputs are stored).
    plan : list of int
        Code cells to run, in order.
    functions : list of str
        Contract functions whose fixtures are in ``fixtures``.
    workdir : Path
        The sandbox's private working directory (contains ``fixtures`` and ``outputs``).
    kernel : SandboxedKernelManager, optional
        A kernel :func:`prestart` launched for this ``workdir`` and ``options``, used for the
        first kernel life (later lives after a crash or timeout start their own); shut down
        like any other.
    """
    result = Execution(nb=nb)
    start = time.monotonic()
    items: list[tuple[str, object]] = [("cell", i) for i in plan] + [("collect", f) for f in functions]
    replay: list[int] = []  # definition cells that finished; re-run after a restart
    spec = sandbox_spec(workdir, options)
    if functions:
        fixtures.mkdir(parents=True, exist_ok=True)
        (fixtures / COLLECTOR).write_text(KERNEL_SIDE_SOURCE)

    deadline = start + options.wall
    notebook_chars = 0
    barren_lives = 0  # kernel lives in a row that finished nothing
    while items:
        if time.monotonic() >= deadline or barren_lives >= 3:
            reason = (
                f"not run: the notebook's wall-clock limit of {options.wall:.0f} s was reached"
                if barren_lives < 3
                else "not run: the kernel could not be started or kept alive"
            )
            for kind, what in items:
                (result.cell_failures if kind == "cell" else result.collection_failures)[what] = reason
            result.events.append(reason)
            break
        if kernel is not None:  # the first life's kernel was launched ahead of time, in this very sandbox
            km, kernel = kernel, None
        else:
            km = SandboxedKernelManager(spec, runtime_root=options.runtime_root)
        client = _CappedClient(
            nb,
            km=km,
            timeout=options.timeout,
            startup_timeout=STARTUP_TIMEOUT,
            allow_errors=True,
            interrupt_on_timeout=False,
            record_timing=False,
            kernel_name="python3",
            resources={"metadata": {"path": str(workdir)}},
        )
        client.notebook_chars = notebook_chars
        done_before = len(items)
        try:
            if km.has_kernel:
                km.finish_start()  # seals its sockets before any cell runs, as start_kernel does
            with client.setup_kernel():
                if not _replay(client, nb, replay, result, deadline, options.timeout):
                    continue
                while items and time.monotonic() < deadline:
                    kind, what = items[0]
                    # A cell never runs past the notebook's wall limit.
                    client.timeout = _cell_timeout(options.timeout, deadline)
                    if kind == "cell":
                        client.execute_cell(nb.cells[what], what)
                        _cap_outputs(nb.cells[what])
                        error = _error_of(nb.cells[what])
                        if error:
                            result.cell_failures[what] = error
                        replay.append(what)
                    else:
                        source = _collect_source(what, fixtures, outputs)
                        cell = nbformat.from_dict({"cell_type": "code", "metadata": {}, "source": source, "outputs": [], "execution_count": None})
                        nb.cells.append(cell)  # nbclient stores results in place; the slot is removed below
                        try:
                            client.execute_cell(cell, len(nb.cells) - 1, store_history=False)
                        finally:
                            nb.cells.pop()
                        error = _error_of(cell)
                        if error:
                            result.collection_failures[what] = f"collection failed: {error}"
                    items.pop(0)
                    peak = peak_memory_bytes(km)
                    if peak is not None:
                        result.peak_rss_bytes = max(result.peak_rss_bytes or 0, peak)
        except CellTimeoutError:
            if time.monotonic() >= deadline:
                continue  # the wall limit's own message is written at the top of the loop
            _fail_first(result, items, f"timed out after {options.timeout:.0f} s; the kernel was killed")
        except DeadKernelError:
            _fail_first(result, items, "the kernel died (crash, os._exit, or the memory limit); it was restarted")
        except RuntimeError as exc:  # the kernel failed to start, or vanished mid-message
            result.events.append(f"kernel stopped: {exc}")
        finally:
            refused = km.processes_refused()
            if refused:
                result.events.append(
                    f"the sandbox refused {refused} new process(es) or thread(s): "
                    f"at most {options.max_processes} may run at once"
                )
            notebook_chars = client.notebook_chars
            if client.kc is not None:
                # nbclient leaves open the channels of a client whose manager it was handed; their
                # zmq context (an I/O thread's epoll and eventfds) then outlived every kernel life:
                # 12 descriptors a unit, until select() failed past 1024 and forks fell back.
                client.kc.stop_channels()
            try:
                km.shutdown_kernel(now=True)
            except Exception:  # noqa: BLE001 - it is already gone
                pass
            # Collect the dead kernel's client objects now: CPython 3.11 fails ast.parse with
            # "AST constructor recursion depth mismatch" when their finalizers run inside it.
            del client, km
            gc.collect()
            _freeze_long_lived()
        barren_lives = barren_lives + 1 if len(items) == done_before and time.monotonic() < deadline else 0
    result.seconds = time.monotonic() - start
    return result


def sandbox_spec(workdir: Path, options: ExecuteOptions) -> SandboxSpec:
    """The sandbox every kernel life of a unit runs in."""
    return SandboxSpec(
        workdir=workdir,
        readonly=options.readonly,
        memory_bytes=int(options.memory_bytes),
        max_processes=options.max_processes,
    )


def prestart(workdir: Path, options: ExecuteOptions) -> SandboxedKernelManager:
    """Launch the kernel a later :func:`execute` on ``workdir`` with ``options`` will use, and return at once.

    The sandbox is built and the kernel boots while the grader does other work; a kernel
    forked from the template is forked at ``km.complete_launch()``, or else when ``execute``
    starts it. Pass it to that one ``execute`` only: the sandbox is bound to ``workdir``.
    """
    km = SandboxedKernelManager(sandbox_spec(workdir, options), runtime_root=options.runtime_root)
    km.launch(defer_fork=True, cwd=str(workdir))
    return km


@functools.cache
def _freeze_long_lived() -> None:
    """Exempt what outlives every unit (modules, the reference's cached outputs) from later collections.

    Called once per process, after a first collection: the ``gc.collect()`` after each kernel
    life then walks only the objects made since, not the whole heap (0.35 s a unit before).
    """
    gc.freeze()


def _replay(client: NotebookClient, nb, replay: list[int], result: Execution, deadline: float, timeout: float) -> bool:
    """Re-run the definitions of earlier kernel lives, within the notebook's wall limit; a cell that now fails is dropped."""
    for index in list(replay):
        if time.monotonic() >= deadline:
            return False
        client.timeout = _cell_timeout(timeout, deadline)
        try:
            client.execute_cell(nb.cells[index], index, store_history=False)
        except (CellTimeoutError, DeadKernelError):
            if time.monotonic() >= deadline:
                return False  # the wall limit, not the cell: the loop above says so
            replay.remove(index)
            result.events.append(f"cell {index} failed when replayed after a restart; dropped")
            return False
    return True


def _cell_timeout(timeout: float, deadline: float) -> int:
    """The next cell's timeout: the per-cell limit, cut to what is left of the notebook's (whole seconds, as nbclient takes)."""
    return max(1, math.ceil(min(timeout, deadline - time.monotonic())))


def _fail_first(result: Execution, items: list, reason: str) -> None:
    if not items:
        return
    kind, what = items.pop(0)
    (result.cell_failures if kind == "cell" else result.collection_failures)[what] = reason
    result.events.append(f"{kind} {what}: {reason}")
