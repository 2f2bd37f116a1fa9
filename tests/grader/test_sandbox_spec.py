"""Sandbox inputs are validated, and the process-tree helpers find and kill what they should."""

from __future__ import annotations

import os
import subprocess
import sys
import time

import pytest

from grader.sandbox.bwrap import SandboxSpec, wrap_command
from grader.sandbox.kernel import SandboxedKernelManager
from grader.sandbox.limits import Process, _wait_for_an_exit, is_running, kill_and_reap, peak_rss_bytes, process, process_tree


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("memory_bytes", 0, "memory_bytes must be a positive int"),
        ("memory_bytes", 2.5e9, "memory_bytes must be a positive int"),
        ("memory_bytes", True, "memory_bytes must be a positive int"),
        ("cpu_seconds", -1, "cpu_seconds must be None or a positive int"),
        ("env", {"A=B": "x"}, "env must map variable names"),
        ("env", {"A": 1}, "env must map variable names"),
        ("env", [("A", "x")], "env must be a dict of str to str"),
    ],
)
def test_bad_spec_values_raise_value_error_naming_the_field(tmp_path, field, value, message):
    with pytest.raises(ValueError, match=message):
        SandboxSpec(workdir=tmp_path, **{field: value})


def test_workdir_and_readonly_must_exist(tmp_path):
    with pytest.raises(ValueError, match="workdir must be an existing directory"):
        SandboxSpec(workdir=tmp_path / "missing")
    with pytest.raises(ValueError, match="readonly must list existing paths"):
        SandboxSpec(workdir=tmp_path, readonly=[tmp_path / "missing"])


def test_spec_paths_are_resolved(tmp_path):
    (tmp_path / "real").mkdir()
    (tmp_path / "link").symlink_to(tmp_path / "real")
    spec = SandboxSpec(workdir=str(tmp_path / "link"), readonly=[tmp_path / "link" / ".."])
    assert (spec.workdir, spec.readonly) == ((tmp_path / "real").resolve(), [tmp_path.resolve()])


def test_wrap_command_rejects_an_empty_argv(tmp_path):
    with pytest.raises(ValueError, match="argv must be a non-empty list of str"):
        wrap_command([], SandboxSpec(workdir=tmp_path))


def test_kernel_manager_rejects_socket_paths_too_long_and_fixed_traits(tmp_path):
    deep = tmp_path / ("d" * 100)
    deep.mkdir()
    with pytest.raises(ValueError, match="runtime_root is too long for Unix socket paths"):
        SandboxedKernelManager(SandboxSpec(workdir=tmp_path), runtime_root=deep)
    assert list(deep.iterdir()) == []  # the refused manager left no runtime folder
    with pytest.raises(ValueError, match=r"kw must not set \['transport'\]"):
        SandboxedKernelManager(SandboxSpec(workdir=tmp_path), transport="tcp")


def _cmdline(pid: int) -> bytes:
    try:
        return open(f"/proc/{pid}/cmdline", "rb").read()
    except OSError:
        return b""


@pytest.fixture
def shell_with_two_sleepers():
    proc = subprocess.Popen(["sh", "-c", "sleep 300 & sleep 300 & wait"])
    tree = []
    deadline = time.monotonic() + 10
    # Wait for the shell and its two children, both past exec.
    while [_cmdline(p.pid) for p in tree] != [_cmdline(proc.pid), *[b"sleep\x00300\x00"] * 2]:
        assert time.monotonic() < deadline
        time.sleep(0.01)
        tree = process_tree(proc.pid)
    yield proc, tree
    kill_and_reap(tree)
    proc.wait()


def test_process_tree_lists_the_root_then_its_children(shell_with_two_sleepers):
    proc, tree = shell_with_two_sleepers
    assert tree[0].pid == proc.pid
    assert [_cmdline(p.pid) for p in tree[1:]] == [b"sleep\x00300\x00"] * 2
    assert all(p.start_ticks >= tree[0].start_ticks for p in tree[1:])


def test_kill_and_reap_kills_the_whole_tree(shell_with_two_sleepers):
    proc, tree = shell_with_two_sleepers
    assert kill_and_reap(tree) == []
    proc.wait(timeout=5)
    assert process_tree(proc.pid) == []


def test_kill_and_reap_spares_a_recycled_pid(shell_with_two_sleepers):
    proc, tree = shell_with_two_sleepers
    imposter = Process(tree[1].pid, tree[1].start_ticks + 1)
    assert kill_and_reap([imposter]) == []
    assert [p.pid for p in process_tree(proc.pid)] == [p.pid for p in tree]


def test_a_root_given_as_a_process_counts_only_while_its_pid_is_still_its_own(shell_with_two_sleepers):
    proc, tree = shell_with_two_sleepers
    assert process(proc.pid) == tree[0]
    assert process_tree(tree[0]) == tree
    assert process_tree(Process(proc.pid, tree[0].start_ticks + 1)) == []  # the pid went to someone else
    assert process_tree(Process(proc.pid, tree[0].start_ticks + 1), tree[1].pid) == [tree[1]]


def test_peak_rss_covers_a_child_allocation():
    code = "import sys; x = b'x' * (200 * 2**20); print('ready', flush=True); sys.stdin.read()"
    child = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE)
    try:
        assert child.stdout.readline() == b"ready\n"
        assert peak_rss_bytes([os.getpid(), child.pid]) >= 200 * 2**20
    finally:
        child.kill()
        child.wait()
    assert peak_rss_bytes([child.pid]) is None


def test_waiting_for_an_exit_wakes_when_the_process_exits_not_at_the_timeout():
    proc = subprocess.Popen(["sleep", "0.3"])
    sleeper = process(proc.pid)
    start = time.monotonic()
    _wait_for_an_exit([sleeper], timeout=60)
    assert time.monotonic() - start < 30  # woken by the exit, long before the timeout
    assert not is_running(sleeper)
    proc.wait()


def test_waiting_on_a_recycled_pid_returns_at_once(shell_with_two_sleepers):
    _, tree = shell_with_two_sleepers
    start = time.monotonic()
    _wait_for_an_exit([tree[1], Process(tree[2].pid, tree[2].start_ticks + 1)], timeout=60)
    assert time.monotonic() - start < 30  # the imposter's pidfd would never have woken it
    assert is_running(tree[1])
