"""The seccomp filter refuses exactly its listed system calls, and calls of another table, with EPERM."""

from __future__ import annotations

import errno
import os
import platform
import struct
import subprocess
import sys
import textwrap

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from grader.sandbox.seccomp import DENIED, denied_numbers, filter_program

ARCHES = {"x86_64": 0xC000003E, "aarch64": 0xC00000B7}
ALLOW, REFUSE = 0x7FFF0000, 0x00050000 | errno.EPERM


def _run_filter(program: bytes, nr: int, arch: int) -> int:
    """What the kernel's classic-BPF interpreter returns for ``seccomp_data`` = (nr, arch)."""
    data = struct.pack("=iI", nr, arch)
    accumulator, pc = 0, 0
    while True:
        code, jump_true, jump_false, k = struct.unpack_from("=HBBI", program, 8 * pc)
        if code == 0x20:  # load word
            accumulator = struct.unpack_from("=I", data, k)[0]
        elif code == 0x06:  # return
            return k
        elif code in (0x15, 0x35):  # jump if equal / if at least
            taken = accumulator == k if code == 0x15 else accumulator >= k
            pc += jump_true if taken else jump_false
        else:
            raise AssertionError(f"unexpected instruction {code:#x}")
        pc += 1


@pytest.mark.parametrize("machine", sorted(ARCHES))
@settings(max_examples=300, deadline=None)
@given(nr=st.one_of(st.integers(0, 1000), st.sampled_from([n for pair in DENIED.values() for n in pair])))
def test_a_native_call_is_refused_exactly_when_it_is_listed(machine, nr):
    column = 0 if machine == "x86_64" else 1
    denied = {pair[column] for pair in DENIED.values()}
    verdict = _run_filter(filter_program(machine), nr, ARCHES[machine])
    assert verdict == (REFUSE if nr in denied else ALLOW)


@pytest.mark.parametrize(("machine", "other"), [("x86_64", 0x40000003), ("aarch64", 0x40000028)])
def test_calls_of_another_table_are_all_refused(machine, other):
    program = filter_program(machine)
    assert _run_filter(program, 39, other) == REFUSE  # getpid through i386 or AArch32
    if machine == "x86_64":
        assert _run_filter(program, 0x40000000 | 39, ARCHES[machine]) == REFUSE  # x32's getpid


def test_an_unknown_architecture_gets_no_filter():
    assert filter_program("riscv64") is None


@pytest.mark.skipif(platform.machine() not in ARCHES, reason="no filter for this architecture")
def test_the_filter_installed_in_a_real_process_refuses_io_uring_keyctl_and_perf_but_numpy_still_runs(tmp_path):
    program = tmp_path / "filter.bpf"
    program.write_bytes(filter_program())
    numbers = denied_numbers()
    code = textwrap.dedent(
        f"""
        import ctypes, errno, threading
        libc = ctypes.CDLL(None, use_errno=True)
        libc.syscall.restype = ctypes.c_long
        program = open({str(program)!r}, "rb").read()
        filters = ctypes.create_string_buffer(program)

        class Fprog(ctypes.Structure):
            _fields_ = [("len", ctypes.c_ushort), ("filter", ctypes.c_void_p)]

        fprog = Fprog(len(program) // 8, ctypes.cast(filters, ctypes.c_void_p))
        assert libc.prctl(38, 1, 0, 0, 0) == 0  # PR_SET_NO_NEW_PRIVS
        assert libc.prctl(22, 2, ctypes.byref(fprog), 0, 0) == 0  # PR_SET_SECCOMP, SECCOMP_MODE_FILTER
        for name, nr in sorted({numbers!r}.items()):
            result = libc.syscall(ctypes.c_long(nr), ctypes.c_long(0), ctypes.c_long(0), ctypes.c_long(0), ctypes.c_long(0))
            print(name, result, errno.errorcode.get(ctypes.get_errno()))
        import numpy as np
        thread = threading.Thread(target=lambda: print("thread ok"))
        thread.start(); thread.join()
        print("numpy", float(np.linalg.svd(np.eye(3))[1].sum()), len(open({str(program)!r}, "rb").read()) == len(program))
        """
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, env={**os.environ, "OPENBLAS_NUM_THREADS": "2"})
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[: len(DENIED)] == [f"{name} -1 EPERM" for name in sorted(DENIED)]
    assert lines[len(DENIED):] == ["thread ok", "numpy 3.0 True"]
