"""Run one student's notebook in a Jupyter kernel confined by bubblewrap.

:mod:`grader.sandbox.bwrap` builds the sandboxed command line,
:mod:`grader.sandbox.kernel` runs an IPython kernel through it,
:mod:`grader.sandbox.limits` holds the resource limits and process accounting,
and :mod:`grader.sandbox.process_limit` caps the processes of one sandbox.
"""

from grader.sandbox.bwrap import SandboxSpec, bwrap_available, wrap_command
from grader.sandbox.kernel import SandboxedKernelManager, peak_memory_bytes

__all__ = ["SandboxSpec", "bwrap_available", "wrap_command", "SandboxedKernelManager", "peak_memory_bytes"]
