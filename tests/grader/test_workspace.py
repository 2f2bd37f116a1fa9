"""A unit's workspace: a size-capped working folder, removed on exit, swept when its grader died."""

from __future__ import annotations

import errno
import os
import subprocess
import sys
import time

import psutil
import pytest

from grader.sandbox.lifetime import mark
from grader.sandbox.workspace import remove_stale_workspaces, workspace

MiB = 2**20
as_root = pytest.mark.skipif(os.geteuid() != 0, reason="mounting a tmpfs needs root")


@as_root
def test_the_workdir_is_a_tmpfs_that_refuses_writes_past_its_size(tmp_path):
    with workspace(8 * MiB, parent=tmp_path) as ws:
        assert ws.capped and os.path.ismount(ws.work)
        with open(ws.work / "fill", "wb") as fh:
            with pytest.raises(OSError) as caught:
                os.posix_fallocate(fh.fileno(), 0, 64 * MiB)
        assert caught.value.errno == errno.ENOSPC
        # the host's disk under the folder is untouched: the tmpfs lives in memory
        assert os.statvfs(ws.work).f_blocks * os.statvfs(ws.work).f_frsize == 8 * MiB


def test_the_workspace_is_gone_after_the_block_even_with_links_inside(tmp_path):
    outside = tmp_path / "outside.txt"
    outside.write_text("keep me")
    with workspace(8 * MiB, parent=tmp_path) as ws:
        (ws.work / "link").symlink_to(outside)
        (ws.kernels / "k").mkdir()
        root = ws.root
    assert not root.exists() and not root.with_name(root.name + ".lock").exists()
    assert outside.read_text() == "keep me"


def test_the_kernels_folder_is_outside_the_workdir_and_private(tmp_path):
    with workspace(8 * MiB, parent=tmp_path) as ws:
        assert ws.work not in ws.kernels.parents and ws.kernels.parent == ws.root
        assert ws.kernels.stat().st_mode & 0o077 == 0 and ws.root.stat().st_mode & 0o077 == 0


def test_a_killed_graders_workspace_is_swept_at_once_and_a_live_one_is_kept(tmp_path):
    # no wait: the lock names its owner (pid and start time), whom psutil finds dead
    code = (
        "import os, sys, time\n"
        "from grader.sandbox.workspace import workspace\n"
        f"with workspace({8 * MiB}, parent={str(tmp_path)!r}) as ws:\n"
        "    (ws.work / 'hidden-inputs.npz').write_bytes(b'x')\n"
        "    print(ws.root, flush=True)\n"
        "    time.sleep(600)\n"
    )
    grader = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        root = grader.stdout.readline().strip()
        with workspace(8 * MiB, parent=tmp_path) as live:
            assert remove_stale_workspaces(tmp_path) == []  # both graders are alive
            grader.kill()
            grader.wait()
            assert [str(p) for p in remove_stale_workspaces(tmp_path)] == [root]
            assert live.root.exists()
        assert sorted(p.name for p in tmp_path.iterdir()) == []
    finally:
        grader.kill()
        grader.wait()


def test_a_free_lock_whose_owner_still_runs_is_kept(tmp_path):
    (tmp_path / "dl-unit-mine").mkdir()
    (tmp_path / "dl-unit-mine.lock").write_text("%d %r\n" % mark())
    old = time.time() - 60
    os.utime(tmp_path / "dl-unit-mine.lock", (old, old))
    assert remove_stale_workspaces(tmp_path) == []
    started = psutil.Process().create_time()
    (tmp_path / "dl-unit-mine.lock").write_text(f"{os.getpid()} {started - 5}\n")  # a pid reused since its owner died
    assert remove_stale_workspaces(tmp_path) == [tmp_path / "dl-unit-mine"]


def test_an_unmarked_lock_only_seconds_old_is_never_swept(tmp_path):
    (tmp_path / "dl-unit-fresh").mkdir()
    (tmp_path / "dl-unit-fresh.lock").write_text("")
    assert remove_stale_workspaces(tmp_path) == []
    old = time.time() - 60
    os.utime(tmp_path / "dl-unit-fresh.lock", (old, old))
    assert remove_stale_workspaces(tmp_path) == [tmp_path / "dl-unit-fresh"]
