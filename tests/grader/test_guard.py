"""The grader's own work on one unit's outputs runs under a memory and a time cap."""

from __future__ import annotations

import resource
import time

import numpy as np
import pytest

from grader.pipeline.guard import GraderLimitExceeded, grader_limits


def test_an_allocation_past_the_cap_raises_memory_error_and_the_cap_is_lifted_after():
    before = resource.getrlimit(resource.RLIMIT_AS)
    with pytest.raises(MemoryError):
        with grader_limits(memory_bytes=256 * 2**20, seconds=60) as active:
            assert active
            np.ones(2**31 // 8 * 4)  # 4 GiB
    assert resource.getrlimit(resource.RLIMIT_AS) == before
    assert np.ones(2**27 // 8).sum() == 2**24  # 128 MiB works again


def test_work_past_the_time_cap_is_interrupted():
    started = time.monotonic()
    with pytest.raises(GraderLimitExceeded):
        with grader_limits(seconds=0.5):
            while True:
                sum(range(1000))
    assert time.monotonic() - started < 5


def test_work_within_the_caps_is_untouched():
    with grader_limits(memory_bytes=512 * 2**20, seconds=30):
        assert np.linalg.norm(np.ones((100, 100))) == 100
