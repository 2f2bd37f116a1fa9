"""Without bubblewrap the sandbox still applies its limits, clean env and session."""

from __future__ import annotations

import logging
import subprocess
import sys
import textwrap
import time

import pytest

from grader.sandbox import bwrap
from grader.sandbox.bwrap import SandboxSpec, wrap_command
from grader.sandbox.kernel import SandboxedKernelManager

MEMORY = 2 * 2**30
CPU = 120
WARNING = "bubblewrap not available: grading without filesystem/network isolation"


@pytest.fixture
def no_bwrap(monkeypatch):
    monkeypatch.setattr(bwrap, "bwrap_available", lambda: False)


@pytest.fixture
def spec(tmp_path):
    (tmp_path / "student").mkdir()
    return SandboxSpec(workdir=tmp_path / "student", memory_bytes=MEMORY, cpu_seconds=CPU, env={"EXTRA": "yes"})


def test_warning_is_logged_once_per_process(no_bwrap, spec, caplog):
    bwrap._warn_without_bwrap.cache_clear()
    with caplog.at_level(logging.WARNING, logger=bwrap.__name__):
        wrap_command(["true"], spec)
        wrap_command(["true"], spec)
    assert [r.getMessage() for r in caplog.records] == [WARNING]


def test_command_applies_limits_env_workdir_and_a_new_session(no_bwrap, spec, monkeypatch):
    monkeypatch.setenv("GRADER_SECRET", "must not leak")
    code = textwrap.dedent(
        """
        import os, resource
        print(resource.getrlimit(resource.RLIMIT_AS), resource.getrlimit(resource.RLIMIT_CPU))
        print(os.getsid(0) == os.getpid(), os.getcwd(), os.environ["HOME"], os.environ["EXTRA"])
        print("GRADER_SECRET" in os.environ)
        try:
            bytearray(3 * 2**30)
        except MemoryError:
            print("MemoryError")
        """
    )
    done = subprocess.run(wrap_command([sys.executable, "-c", code], spec), capture_output=True, text=True, timeout=60)
    assert done.stdout.splitlines() == [
        f"({MEMORY}, {MEMORY}) ({CPU}, {CPU})",
        f"True {spec.workdir} {spec.workdir} yes",
        "False",
        "MemoryError",
    ], done.stderr


def test_kernel_hits_the_memory_cap_and_shutdown_kills_its_children(no_bwrap, spec, host_cmdlines, started):
    km = SandboxedKernelManager(spec)
    km.start_kernel()
    kc = km.blocking_client()
    kc.start_channels()
    try:
        kc.wait_for_ready(timeout=60)
        reply = kc.execute_interactive("x = bytearray(3 * 2**30)", timeout=30, stop_on_error=False)
        assert reply["content"]["ename"] == "MemoryError"
        kc.execute_interactive(
            "import subprocess; subprocess.Popen(['sleep', '987653'], start_new_session=True)", timeout=30
        )
        assert started(b"sleep\x00987653\x00")
    finally:
        kc.stop_channels()
        km.shutdown_kernel(now=True)
    assert b"sleep\x00987653\x00" not in host_cmdlines()


def test_an_unsandboxed_command_dies_with_the_grader_killed_outright(tmp_path):
    import signal

    import psutil

    # bwrap's --die-with-parent, without bwrap: the command outlives no grader, SIGKILL included
    (tmp_path / "student").mkdir()
    code = textwrap.dedent(f"""
        import subprocess, time
        from grader.sandbox import bwrap
        bwrap.bwrap_available = lambda: False
        spec = bwrap.SandboxSpec(workdir={str(tmp_path / "student")!r})
        child = subprocess.Popen(bwrap.wrap_command(["sleep", "600"], spec))
        print(child.pid, flush=True)
        time.sleep(600)
    """)
    grader = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        command = psutil.Process(int(grader.stdout.readline()))
        deadline = time.monotonic() + 60
        while command.is_running() and command.name() != "sleep" and time.monotonic() < deadline:
            time.sleep(0.05)  # still the launcher: the prctl comes before the exec
        assert command.name() == "sleep"
        grader.send_signal(signal.SIGKILL)
        grader.wait()
        _, alive = psutil.wait_procs([command], timeout=120)
        assert alive == []
    finally:
        grader.kill()
        grader.wait()
