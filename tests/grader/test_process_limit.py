"""A sandbox's pids cgroup: where it can be created, its cap, its removal."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from grader.sandbox import bwrap
from grader.sandbox.bwrap import SandboxSpec
from grader.sandbox.limits import is_alive
from grader.sandbox.process_limit import ProcessLimit, _candidates, _own_cgroups, namespace_cap_prefix, pids_parent

V1 = "12:pids:/ci/job\n11:memory:/ci\n1:name=systemd:/\n0::/\n"
V2 = "0::/user.slice/grader.service\n"

needs_cgroup = pytest.mark.skipif(pids_parent() is None, reason="no writable pids cgroup on this machine")


def test_own_cgroups_read_both_versions():
    assert _own_cgroups(V1) == {"pids": "/ci/job", "memory": "/ci", "name=systemd": "/", "": "/"}
    assert _own_cgroups(V2) == {"": "/user.slice/grader.service"}


def test_a_v1_pids_hierarchy_is_a_candidate_at_this_process_s_own_path(tmp_path):
    (tmp_path / "pids").mkdir()
    assert _candidates(tmp_path, V1) == [tmp_path / "pids" / "ci" / "job"]


def test_a_v2_cgroup_is_a_candidate_only_if_it_delegates_the_pids_controller(tmp_path):
    own = tmp_path / "user.slice" / "grader.service"
    own.mkdir(parents=True)
    (own / "cgroup.subtree_control").write_text("cpu memory\n")
    assert _candidates(tmp_path, V2) == []
    (own / "cgroup.subtree_control").write_text("cpu memory pids\n")
    assert _candidates(tmp_path, V2) == [own]


def test_no_cgroup_filesystem_means_no_parent(tmp_path):
    assert pids_parent(tmp_path) is None


@pytest.mark.parametrize("bad", [0, -3, 1.5, True, "64", None])
def test_the_cap_must_be_a_positive_int(bad, tmp_path):
    with pytest.raises(ValueError, match="max_processes must be a positive int"):
        ProcessLimit(bad, tmp_path)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("bad", [0, -1, 2.0, False])
def test_a_sandbox_spec_refuses_a_cap_that_is_not_a_positive_int_or_none(bad, tmp_path):
    with pytest.raises(ValueError, match="max_processes must be None or a positive int"):
        SandboxSpec(workdir=tmp_path, max_processes=bad)
    assert SandboxSpec(workdir=tmp_path, max_processes=None).max_processes is None


# A child that forks until refused (at most 200 times), prints how many it got, and waits.
FORKER = textwrap.dedent(
    """
    import os, sys, time
    children = 0
    for _ in range(200):
        try:
            pid = os.fork()
        except BlockingIOError:
            break
        if pid == 0:
            time.sleep(60)
            os._exit(0)
        children += 1
    print(children, flush=True)
    time.sleep(60)
    """
)


@needs_cgroup
def test_forks_beyond_the_cap_are_refused_counted_and_all_killed_on_removal():
    limit = ProcessLimit(16, pids_parent())
    proc = subprocess.Popen([*limit.join_prefix(), sys.executable, "-c", FORKER], stdout=subprocess.PIPE, text=True)
    try:
        children = int(proc.stdout.readline())
        assert children == 15  # the forker itself is the 16th task
        assert limit.refused() == 1
        members = limit.pids()
        assert proc.pid in members and len(members) == 16
        assert limit.remove()
        assert not limit.path.exists()
        proc.wait(timeout=10)
        assert proc.returncode == -9
        assert not [pid for pid in members if is_alive(pid)]
    finally:
        proc.kill()
        proc.wait()
        limit.remove()


@needs_cgroup
def test_a_command_joins_its_cgroup_before_it_starts():
    limit = ProcessLimit(8, pids_parent())
    try:
        out = subprocess.run(
            [*limit.join_prefix(), sys.executable, "-c", "print(open('/proc/self/cgroup').read())"],
            capture_output=True, text=True, timeout=30,
        )
        assert out.returncode == 0, out.stderr
        assert limit.path.name in out.stdout
        assert limit.path.name not in Path("/proc/self/cgroup").read_text()
    finally:
        assert limit.remove()


@needs_cgroup
def test_a_removed_cgroup_keeps_its_command_from_starting():
    limit = ProcessLimit(8, pids_parent())
    prefix = limit.join_prefix()
    assert limit.remove()
    out = subprocess.run([*prefix, sys.executable, "-c", "print('started')"], capture_output=True, text=True, timeout=30)
    assert out.returncode != 0 and "started" not in out.stdout



@pytest.mark.parametrize("bad", [0, -3, 1.5, True, "64"])
def test_the_namespace_cap_must_be_a_positive_int(bad):
    with pytest.raises(ValueError, match="max_processes must be a positive int"):
        namespace_cap_prefix(bad)
    assert namespace_cap_prefix(64) == ["prlimit", "--nproc=64", "--"]


# Root is exempt from RLIMIT_NPROC: as root, run the processes as nobody. The project's
# interpreter may sit in a folder nobody cannot read, so the forker runs on Debian's python3.
AS_USER = ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups", "--"] if os.geteuid() == 0 else []
SYSTEM_PYTHON = "/usr/bin/python3"
SANDBOX = [shutil.which("bwrap") or "bwrap", *bwrap._isolation_args(), *bwrap._TRIAL_MOUNTS, "--"]


def _unprivileged_sandbox_works() -> bool:
    if not Path(SYSTEM_PYTHON).exists() or (AS_USER and not shutil.which("setpriv")):
        return False
    try:
        return subprocess.run([*AS_USER, *SANDBOX, "true"], capture_output=True, timeout=30).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return False


def _forked(command: list[str]) -> tuple[int, subprocess.Popen]:
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, text=True, start_new_session=True)
    return int(proc.stdout.readline()), proc


@pytest.mark.skipif(not _unprivileged_sandbox_works(), reason="no unprivileged bubblewrap sandbox or no /usr/bin/python3 here")
def test_rlimit_nproc_inside_a_sandbox_caps_that_sandbox_alone_whatever_the_user_runs_elsewhere():
    busy = [subprocess.Popen([*AS_USER, "sleep", "60"]) for _ in range(40)]
    started = []
    try:
        # Outside a namespace the limit counts all 40 of the user's sleepers: no fork at all.
        count, plain = _forked([*AS_USER, *namespace_cap_prefix(16), SYSTEM_PYTHON, "-c", FORKER])
        started.append(plain)
        assert count == 0
        # Inside each sandbox only its own tasks count: bwrap's init, the forker and 14 children.
        counts = []
        for _ in range(2):
            count, proc = _forked([*AS_USER, *SANDBOX, *namespace_cap_prefix(16), SYSTEM_PYTHON, "-c", FORKER])
            started.append(proc)
            counts.append(count)
        assert counts == [14, 14]
    finally:
        for proc in started:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
        for proc in busy:
            proc.kill()
            proc.wait()


@pytest.mark.skipif(shutil.which("bwrap") is None, reason="bubblewrap is not installed")
@pytest.mark.parametrize(
    "euid, own_namespace, capped",
    [(1000, True, True), (0, True, False), (1000, False, False)],
    ids=["user-with-namespace", "root", "user-without-namespace"],
)
def test_without_a_cgroup_the_kernel_is_capped_inside_its_namespace_only_where_that_caps_it(
    tmp_path, monkeypatch, caplog, euid, own_namespace, capped
):
    from grader.sandbox import kernel

    monkeypatch.setattr(kernel, "pids_parent", lambda: None)
    monkeypatch.setattr(kernel.os, "geteuid", lambda: euid)
    monkeypatch.setattr(kernel, "sandbox_user_namespace", lambda: own_namespace)
    monkeypatch.setattr(bwrap, "bwrap_available", lambda: True)
    kernel._warn_without_process_limit.cache_clear()
    km = kernel.SandboxedKernelManager(SandboxSpec(workdir=tmp_path, max_processes=48))
    command, _ = km.pre_start_kernel()
    inside = command[command.index("--", command.index(shutil.which("bwrap"))) + 1:]
    if capped:
        # then the kernel, or the waiter a kernel forked from the template enters
        assert inside[:3] == ["prlimit", "--nproc=48", "--"] and inside[3] == sys.executable
        assert not caplog.records
    else:
        assert inside[0] == sys.executable and "--nproc=48" not in command
        assert "without a cap on their number of processes" in caplog.text
    km.cleanup_resources()
