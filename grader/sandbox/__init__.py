"""Run one student's notebook in a Jupyter kernel confined by bubblewrap.

:mod:`grader.sandbox.bwrap` builds the sandboxed command line,
:mod:`grader.sandbox.kernel` runs an IPython kernel through it,
:mod:`grader.sandbox.limits` holds the resource limits and process accounting,
:mod:`grader.sandbox.process_limit` caps the processes of one sandbox,
:mod:`grader.sandbox.spares` holds the sandboxes started ahead of time for each
grading thread's next unit, and :mod:`grader.sandbox.lifetime` ties every helper
process to its owner's life (SIGKILL included).
"""

from grader.sandbox.bwrap import SandboxSpec, bwrap_available, wrap_command
from grader.sandbox.kernel import SandboxedKernelManager, peak_memory_bytes

__all__ = ["SandboxSpec", "bwrap_available", "wrap_command", "SandboxedKernelManager", "peak_memory_bytes"]
