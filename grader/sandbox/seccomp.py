"""A seccomp filter that keeps student code off the kernel's riskiest system calls.

Inside bubblewrap the student's code holds no capability, yet a few system
calls still reach large, often-exploited parts of the kernel: io_uring, the
key rings (``keyctl``), performance events, eBPF and ``userfaultfd`` (which
makes race exploits reliable). Grading needs none of them. The filter refuses
them with ``EPERM``, as Docker's default profile does for most of them, and
lets every other call through. Measured on this project's sandbox before the
filter: ``io_uring_setup``, ``keyctl`` and ``perf_event_open`` all succeeded.

Only the machine's native system-call table is allowed: a call made through
another one (the 32-bit ``int 0x80`` or x32 tables on x86-64, AArch32 on
AArch64) would dodge the numbers below, so every such call is refused.
"""

from __future__ import annotations

import errno
import functools
import platform
import struct

__all__ = ["DENIED", "denied_numbers", "filter_program"]

#: System calls refused, with their numbers on (x86-64, AArch64).
DENIED = {
    "io_uring_setup": (425, 425),
    "io_uring_enter": (426, 426),
    "io_uring_register": (427, 427),
    "keyctl": (250, 219),
    "add_key": (248, 217),
    "request_key": (249, 218),
    "perf_event_open": (298, 241),
    "bpf": (321, 280),
    "userfaultfd": (323, 282),
}

# platform.machine() -> (AUDIT_ARCH_*, column of DENIED, first number of another table or None)
_ARCHES = {
    "x86_64": (0xC000003E, 0, 0x40000000),  # x32 calls are the native numbers | 0x40000000
    "aarch64": (0xC00000B7, 1, None),
}

# Classic BPF as seccomp runs it on struct seccomp_data {int nr; u32 arch; ...}.
_LOAD_WORD = 0x20  # BPF_LD | BPF_W | BPF_ABS
_JUMP_IF_EQUAL = 0x15  # BPF_JMP | BPF_JEQ | BPF_K
_JUMP_IF_AT_LEAST = 0x35  # BPF_JMP | BPF_JGE | BPF_K
_RETURN = 0x06  # BPF_RET | BPF_K
_NR, _ARCH = 0, 4  # offsets in seccomp_data
_ALLOW = 0x7FFF0000
_REFUSE = 0x00050000 | errno.EPERM  # SECCOMP_RET_ERRNO


def _instruction(code: int, k: int, jump_true: int = 0, jump_false: int = 0) -> bytes:
    return struct.pack("=HBBI", code, jump_true, jump_false, k)


def denied_numbers(machine: str | None = None) -> dict[str, int] | None:
    """The refused system calls' numbers on ``machine`` (default this one); ``None`` if it has no table here."""
    machine = platform.machine() if machine is None else machine
    if machine not in _ARCHES:
        return None
    column = _ARCHES[machine][1]
    return {name: numbers[column] for name, numbers in DENIED.items()}


@functools.cache  # every kernel start sends it to the template
def filter_program(machine: str | None = None) -> bytes | None:
    """The filter as bubblewrap's ``--seccomp`` reads it: an array of ``struct sock_filter``.

    Parameters
    ----------
    machine : str, optional
        ``platform.machine()`` of the machine the filter is for; default this one.

    Returns
    -------
    bytes or None
        ``8 × k`` bytes of classic BPF, in this machine's byte order; ``None``
        on an architecture whose system-call numbers are not listed here.
    """
    machine = platform.machine() if machine is None else machine
    if machine not in _ARCHES:
        return None
    arch, _, foreign = _ARCHES[machine]
    numbers = sorted(set(denied_numbers(machine).values()))
    checks = ([foreign] if foreign is not None else []) + numbers
    # Layout: check the table, load the number, the checks, allow, refuse.
    program = [
        _instruction(_LOAD_WORD, _ARCH),
        _instruction(_JUMP_IF_EQUAL, arch, 0, len(checks) + 2),  # another table: straight to "refuse"
        _instruction(_LOAD_WORD, _NR),
    ]
    for i, number in enumerate(checks):
        to_refuse = len(checks) - i  # over the checks left and "allow"
        if foreign is not None and i == 0:
            program.append(_instruction(_JUMP_IF_AT_LEAST, number, to_refuse, 0))
        else:
            program.append(_instruction(_JUMP_IF_EQUAL, number, to_refuse, 0))
    program += [_instruction(_RETURN, _ALLOW), _instruction(_RETURN, _REFUSE)]
    return b"".join(program)
