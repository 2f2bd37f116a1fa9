"""Kernels forked from the template: confined exactly as fresh ones, started with their libraries imported."""

import json
import logging
import os
import time

import pytest

from grader.sandbox import SandboxedKernelManager, SandboxSpec, fork_server
from grader.sandbox.bwrap import bwrap_available
from grader.sandbox.limits import namespace_members

pytestmark = pytest.mark.skipif(not bwrap_available(), reason="bubblewrap cannot create namespaces here")

# Everything the sandbox decides about a process, as the process itself sees it.
PROBE = r"""
import json, os, resource, sys
def target(fd):
    try:
        return os.readlink(f"/proc/self/fd/{fd}").split(":[")[0]
    except FileNotFoundError:  # the descriptor listdir itself used
        return None
status = dict(line.split(":", 1) for line in open("/proc/self/status").read().splitlines())
print(json.dumps({
    "status": {k: v.strip() for k, v in status.items() if k.startswith(("Cap", "NoNewPrivs", "Seccomp", "Uid", "Gid", "Groups"))},
    "mounts": sorted(line.split()[4] + " " + line.split()[5].split(",")[0] for line in open("/proc/self/mountinfo")),
    "root": sorted(os.listdir("/")),
    "processes": sorted(p for p in os.listdir("/proc") if p.isdigit()),
    "limits": {n: resource.getrlimit(getattr(resource, n)) for n in ("RLIMIT_AS", "RLIMIT_CPU", "RLIMIT_FSIZE", "RLIMIT_CORE", "RLIMIT_NPROC")},
    "environ": dict(os.environ),
    "cwd": os.getcwd(),
    "path": sys.path,
    "cgroup": open("/proc/self/cgroup").read(),
    "session_leader": os.getsid(0) == os.getpid(),
    "umask": os.umask(0o022),
    "dumpable": __import__("ctypes").CDLL(None).prctl(3, 0, 0, 0, 0),
    # what each open descriptor is, without its inode: a pipe left over from the template would add one
    "descriptors": sorted(filter(None, map(target, os.listdir("/proc/self/fd")))),
    "grader_modules": sorted(m for m in sys.modules if m.split(".")[0] in ("grader", "reference", "benchmarks")),
    "preloaded": [m in sys.modules for m in ("numpy", "scipy.sparse.linalg", "igl", "starter")],
    "random": __import__("random").random(),
    "numpy_random": __import__("numpy").random.rand(),
}))
"""


def _run(km: SandboxedKernelManager, code: str) -> str:
    kc = km.blocking_client()
    kc.start_channels()
    try:
        kc.wait_for_ready(timeout=60)
        out = []
        reply = kc.execute_interactive(
            code, timeout=60, output_hook=lambda m: out.append(m["content"].get("text", "")) if m["msg_type"] == "stream" else None
        )
        assert reply["content"]["status"] == "ok", reply["content"]
        return "".join(out)
    finally:
        kc.stop_channels()


def _probe(tmp_path, name: str) -> tuple[bool, dict]:
    workdir = tmp_path / name
    workdir.mkdir()
    km = SandboxedKernelManager(SandboxSpec(workdir=workdir, max_processes=64), runtime_root=tmp_path)
    km.start_kernel()
    try:
        text = _run(km, PROBE)
    finally:
        km.shutdown_kernel(now=True)
    # what differs by construction between two sandboxes: their own folders
    text = text.replace(str(km.runtime_dir), "RUNTIME").replace(str(workdir), "WORKDIR")
    return km.forked, json.loads(text)


def test_a_forked_kernel_is_confined_exactly_as_a_fresh_one_and_starts_with_its_libraries_imported(tmp_path, monkeypatch):
    forked, inside_forked = _probe(tmp_path, "forked")
    monkeypatch.setenv("DEFORMLAB_KERNEL_TEMPLATE", "off")
    fresh, inside_fresh = _probe(tmp_path, "fresh")
    assert forked and not fresh
    assert inside_forked.pop("preloaded") == [True, True, True, True]
    assert inside_fresh.pop("preloaded") == [False, False, False, False]
    for inside in (inside_forked, inside_fresh):
        inside.pop("random"), inside.pop("numpy_random")
    # Both are out of the grader's session: bubblewrap's session is led by its own
    # process, the forked kernel leads one of its own.
    assert inside_forked.pop("session_leader") and not inside_fresh.pop("session_leader")
    assert inside_forked == inside_fresh
    # and what they are: no capability, no privilege to gain, the filter, a pid namespace of two
    assert inside_forked["status"]["CapEff"] == inside_forked["status"]["CapBnd"] == "0000000000000000"
    assert inside_forked["status"]["NoNewPrivs"] == "1"
    assert inside_forked["processes"] == ["1", "2"]
    assert inside_forked["grader_modules"] == []


def test_two_forked_kernels_draw_different_random_numbers(tmp_path):
    (_, one), (_, two) = _probe(tmp_path, "one"), _probe(tmp_path, "two")
    assert one["random"] != two["random"] and one["numpy_random"] != two["numpy_random"]


def test_the_sandbox_ends_when_its_forked_kernel_exits(tmp_path):
    km = SandboxedKernelManager(SandboxSpec(workdir=tmp_path), runtime_root=tmp_path)
    km.start_kernel()
    try:
        assert km.forked
        kc = km.blocking_client()
        kc.start_channels()
        kc.wait_for_ready(timeout=60)
        kc.execute("import os, subprocess; subprocess.Popen(['sleep', '600']); os._exit(0)")
        kc.stop_channels()
        deadline = time.monotonic() + 10
        while km.is_alive() and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not km.is_alive()
        # the waiter took the sandbox with it: the orphaned sleep too
        assert namespace_members(km.pid_namespace) == []
    finally:
        km.shutdown_kernel(now=True)


def test_a_deferred_launch_builds_the_sandbox_and_forks_its_kernel_only_when_completed(tmp_path):
    km = SandboxedKernelManager(SandboxSpec(workdir=tmp_path), runtime_root=tmp_path)
    km.launch(defer_fork=True, cwd=str(tmp_path))
    try:
        assert km.forked
        launcher = km.launcher.pid
        deadline = time.monotonic() + 10
        while km._first_in_sandbox() is None and time.monotonic() < deadline:
            time.sleep(0.01)
        # the waiter alone, waiting: no kernel yet
        assert [p.pid for p in km._sandbox_processes()] == [launcher, km._first_in_sandbox().pid]
        km.finish_start()
        assert km.forked and _run(km, "print(6 * 7)") == "42\n"
        assert len(km._sandbox_processes()) == 3  # launcher (bwrap), its waiter, the kernel
    finally:
        km.shutdown_kernel(now=True)


def test_a_sandbox_shut_down_before_its_kernel_is_forked_leaves_no_process_or_descriptor(tmp_path):
    def descriptors():
        return sorted(os.listdir("/proc/self/fd"))

    # once, so that what a process creates for its first sandbox and keeps (an event loop, the
    # seccomp program) is there before counting: only what one sandbox holds must go with it
    warm = SandboxedKernelManager(SandboxSpec(workdir=tmp_path), runtime_root=tmp_path)
    warm.launch(defer_fork=True, cwd=str(tmp_path))
    warm.shutdown_kernel(now=True)
    before = descriptors()
    km = SandboxedKernelManager(SandboxSpec(workdir=tmp_path), runtime_root=tmp_path)
    km.launch(defer_fork=True, cwd=str(tmp_path))
    assert len(descriptors()) > len(before)  # the waiter's pipes, held for complete_launch
    km.shutdown_kernel(now=True)
    assert km._sandbox_processes() == []
    assert descriptors() == before


def test_a_kernel_starts_fresh_with_a_warning_when_the_template_cannot_fork_one(tmp_path, monkeypatch, caplog):
    def broken(request):
        raise RuntimeError("no template today")

    monkeypatch.setattr(fork_server, "fork_kernel", broken)
    monkeypatch.setattr(fork_server, "_failures", 0)
    km = SandboxedKernelManager(SandboxSpec(workdir=tmp_path), runtime_root=tmp_path)
    with caplog.at_level(logging.WARNING, logger="grader.sandbox.fork_server"):
        km.start_kernel()
    try:
        assert not km.forked
        assert _run(km, "print(6 * 7)") == "42\n"
        assert "a kernel starts fresh: it could not be forked from the template (no template today)" in caplog.text
        assert fork_server.enabled()  # one failure turns nothing off
    finally:
        km.shutdown_kernel(now=True)


def test_three_failed_forks_in_a_row_start_every_later_kernel_fresh_and_a_success_resets_the_count(monkeypatch, caplog):
    monkeypatch.setattr(fork_server, "_failures", 0)
    monkeypatch.setattr(fork_server, "_disabled", None)
    monkeypatch.setattr(fork_server, "stop_template", lambda: None)
    fork_server.failed("one")
    fork_server.failed("two")
    fork_server.succeeded()
    fork_server.failed("three")
    fork_server.failed("four")
    assert fork_server.enabled()
    with caplog.at_level(logging.WARNING, logger="grader.sandbox.fork_server"):
        fork_server.failed("five")
    assert not fork_server.enabled()
    assert "3 forks failed in a row, the last because five" in caplog.text


def test_the_template_refuses_a_request_for_a_sandbox_that_is_gone_and_serves_the_next(tmp_path):
    env = {"OPENBLAS_NUM_THREADS": "1"}
    gone = {"target": os.getpid(), "start": -1, "cgroup": None, "seccomp": None, "workdir": str(tmp_path), "env": env, "argv": []}
    with pytest.raises(RuntimeError, match="waiter is gone"):
        fork_server.fork_kernel(gone)
    template = fork_server._template
    km = SandboxedKernelManager(SandboxSpec(workdir=tmp_path), runtime_root=tmp_path)
    km.start_kernel()
    try:
        assert km.forked and fork_server._template is template
        assert _run(km, "print(6 * 7)") == "42\n"
    finally:
        km.shutdown_kernel(now=True)


def test_the_template_and_its_kernels_sandbox_die_with_a_grading_process_killed_outright(tmp_path):
    import contextlib
    import signal
    import subprocess
    import sys

    import psutil

    # A grading process that starts its template from a short-lived thread (as a kernel launch
    # does): the template must outlive that thread, and not its process.
    code = (
        "import os, sys, threading, time\n"
        "from grader.sandbox import SandboxedKernelManager, SandboxSpec, fork_server\n"
        "t = threading.Thread(target=fork_server.start_template, args=({'OPENBLAS_NUM_THREADS': '1'},))\n"
        "t.start(); t.join()\n"
        f"km = SandboxedKernelManager(SandboxSpec(workdir={str(tmp_path)!r}), runtime_root={str(tmp_path)!r})\n"
        "km.start_kernel()\n"
        # a child forked now holds the template's input open: its end of file never comes
        "holder = os.fork()\n"
        "if holder == 0:\n"
        "    time.sleep(600)\n"
        "    os._exit(0)\n"
        "print(fork_server._template.pid, km.forked, holder, flush=True)\n"
        "time.sleep(600)\n"
    )
    grader = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    holder = None
    try:
        template, forked, holder = grader.stdout.readline().split()
        assert forked == "True"
        tree = [p.pid for p in psutil.Process(grader.pid).children(recursive=True) if p.pid != int(holder)]
        assert int(template) in tree and len(tree) >= 4  # template, bwrap, the waiter, the kernel
        watched = [psutil.Process(pid) for pid in tree]
        grader.send_signal(signal.SIGKILL)
        grader.wait()
        _, alive = psutil.wait_procs(watched, timeout=120)
        assert alive == []
    finally:
        grader.kill()
        grader.wait()
        if holder:
            with contextlib.suppress(psutil.Error):
                psutil.Process(int(holder)).kill()
