"""The kernel template: imports an IPython kernel's libraries once, then forks one kernel per sandbox.

Run by the grader as ``python kernel_template.py OWNER_PID`` (never imported),
on the host, with the sandbox's environment; it exits when its owner, the
grading process, does (however it ends) or closes its input. It imports ipykernel, numpy, scipy,
libigl and the course's ``starter`` package, then serves requests, one JSON
object per line on stdin, each answered by one line on stdout. It never runs
student code and never holds any: a request names a sandbox that bubblewrap
has already built (its pid 1, a waiter, see :mod:`grader.sandbox.fork_server`),
and the forked child *enters* it.

Request: ``{"target": pid, "start": start time, "cgroup": cgroup.procs path
or null, "seccomp": filter program as hex or null, "workdir": path, "env":
{...}, "argv": [kernel arguments]}``. Reply: ``{"pid": host pid of the
kernel}`` or ``{"error": text}``.

The child, before it runs a line of the kernel:

1. joins the sandbox's ``pids`` cgroup (so every later task counts against
   its cap) and takes the waiter's resource limits (address space, CPU time,
   file size, core size, processes);
2. enters the waiter's namespaces: the user namespace bubblewrap set the
   sandbox up in, then its mount, pid, network, ipc, uts and cgroup
   namespaces, then the user namespace the waiter runs in (nested, where
   bubblewrap locked the mounts and allowed no further user namespace); the
   mount namespace gives it the sandbox's root;
3. forks the kernel, which starts in the sandbox's pid namespace, and exits.

The kernel then starts a session of its own, keeps only ``/dev/null`` on
0–2, drops every capability (bounding and ambient sets too), sets
``no_new_privs``, installs the seccomp filter, moves to the workdir and
replaces its environment: what bubblewrap does for a command it starts. Its
parent is this template (a child subreaper), outside the sandbox, so student
code sees no parent at all; the template reaps it.
"""

import sys

# Before anything imports ipykernel: the sandbox masks debugpy, so a kernel
# started there has no debugger, and neither may a forked one.
class _NoDebugger:
    @staticmethod
    def find_spec(name, path=None, target=None):
        if name == "debugpy" or name.startswith("debugpy."):
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)
        return None


sys.meta_path.insert(0, _NoDebugger)
# Not a path a kernel has: ipykernel_launcher drops the one `python -m` puts first.
del sys.path[0]

import ctypes  # noqa: E402
import gc  # noqa: E402
import importlib  # noqa: E402
import json  # noqa: E402
import os  # noqa: E402
import resource  # noqa: E402
import select  # noqa: E402
import signal  # noqa: E402
import struct  # noqa: E402

# imported to be in memory before the first fork (every kernel shares their pages)
import ipykernel.kernelapp  # noqa: E402
import numpy  # noqa: E402,F401
import scipy.linalg  # noqa: E402,F401
import scipy.sparse  # noqa: E402,F401
import scipy.sparse.csgraph  # noqa: E402,F401
import scipy.sparse.linalg  # noqa: E402,F401
import scipy.spatial  # noqa: E402,F401
import starter.library_policy  # noqa: E402

# what the notebooks import, in memory before the first fork: the course packs' preloads
# (``preload`` in assignment.toml, e.g. libigl and the course's starter package: 20 ms a unit),
# named by the grader in argv[2]
for _name in json.loads(sys.argv[2]) if len(sys.argv) > 2 else ():
    importlib.import_module(_name)
# and what the kernel imports as it starts (a started kernel's modules less these)
for _name in (
    "IPython.core.completerlib", "IPython.core.debugger", "IPython.core.logger", "IPython.core.oinspect",
    "IPython.extensions.storemagic", "ipykernel.debugger", "tornado.platform.asyncio", "tornado.queues",
):
    importlib.import_module(_name)

# The library-call policy wraps its routines before any kernel exists: every fork inherits the
# wrappers, so aliases a student takes later are wrappers too (each kernel loads it again as an
# IPython extension, which only points it at that kernel's namespace).
starter.library_policy.install({})

sys.meta_path.remove(_NoDebugger)
# ipykernel must not find it later either
sys.modules["debugpy"] = None

_libc = ctypes.CDLL(None, use_errno=True)
_NS_GET_PARENT = 0xB702  # ioctl: the parent of a user namespace
_PR_SET_CHILD_SUBREAPER = 36
_PR_CAPBSET_DROP = 24
_PR_SET_NO_NEW_PRIVS = 38
_PR_CAP_AMBIENT = 47
_PR_CAP_AMBIENT_CLEAR_ALL = 4
_PR_SET_SECCOMP = 22
_SECCOMP_MODE_FILTER = 2
_LINUX_CAPABILITY_VERSION_3 = 0x20080522
_LIMITS = (resource.RLIMIT_AS, resource.RLIMIT_CPU, resource.RLIMIT_FSIZE, resource.RLIMIT_CORE, resource.RLIMIT_NPROC)
_CGROUP_ROOT = "/sys/fs/cgroup/"
# the non-user namespaces, in the order they are entered
_NAMESPACES = ("mnt", "pid", "net", "ipc", "uts", "cgroup")


def _check(result: int, what: str) -> int:
    """``result`` of a libc call, which fails with -1 and ``errno``."""
    if result < 0:
        errno = ctypes.get_errno()
        raise OSError(errno, f"{what}: {os.strerror(errno)}")
    return result


def _start_time(pid: int) -> int:
    with open(f"/proc/{pid}/stat", "rb") as f:
        stat = f.read()
    return int(stat[stat.rindex(b")") + 2:].split()[19])


def _user_namespaces(target: int) -> list[int]:
    """Descriptors of the user namespaces between this process's (excluded) and the target's, outermost first."""
    own = os.stat("/proc/self/ns/user").st_ino
    chain = [os.open(f"/proc/{target}/ns/user", os.O_RDONLY)]
    while os.fstat(chain[-1]).st_ino != own:
        try:
            chain.append(_check(_libc.ioctl(chain[-1], _NS_GET_PARENT), "NS_GET_PARENT"))
        except PermissionError:  # above this process's own namespace: the target's is not nested in it
            raise OSError("the sandbox's user namespace is not nested in the template's") from None
    os.close(chain.pop())
    return chain[::-1]


def _enter(request: dict) -> None:
    """Steps 1 and 2 of the module docstring, in the forked child."""
    target = int(request["target"])
    cgroup = request.get("cgroup")
    if cgroup:
        # only ever a cgroup's own file: this process still has the grader's privileges
        if not (cgroup.startswith(_CGROUP_ROOT) and cgroup.endswith("/cgroup.procs") and "/../" not in cgroup):
            raise ValueError(f"not a cgroup's process list: {cgroup[:200]!r}")
        fd = os.open(cgroup, os.O_WRONLY | os.O_NOFOLLOW)
        try:
            os.write(fd, b"0\n")
        finally:
            os.close(fd)
    for limit in _LIMITS:
        resource.setrlimit(limit, resource.prlimit(target, limit))
    # every descriptor before the first setns: after the mount namespace, /proc is the sandbox's
    users = _user_namespaces(target)
    others = []
    for name in _NAMESPACES:
        fd = os.open(f"/proc/{target}/ns/{name}", os.O_RDONLY)
        if os.fstat(fd).st_ino == os.stat(f"/proc/self/ns/{name}").st_ino:
            os.close(fd)  # not unshared here (bubblewrap makes a cgroup namespace only where it can)
        else:
            others.append(fd)
    if _start_time(target) != int(request["start"]):
        raise OSError("the sandbox's waiter is gone")
    for fd in users[:1] + others + users[1:]:
        _check(_libc.setns(fd, 0), "setns")
        os.close(fd)


def _drop_capabilities() -> None:
    with open("/proc/sys/kernel/cap_last_cap") as f:
        last = int(f.read())
    for cap in range(last + 1):
        _check(_libc.prctl(_PR_CAPBSET_DROP, cap, 0, 0, 0), "drop a capability from the bounding set")
    _check(_libc.prctl(_PR_CAP_AMBIENT, _PR_CAP_AMBIENT_CLEAR_ALL, 0, 0, 0), "clear the ambient capabilities")
    header = struct.pack("Ii", _LINUX_CAPABILITY_VERSION_3, 0)
    data = bytes(24)  # two {effective, permitted, inheritable} sets, all empty
    _check(_libc.capset(header, data), "capset")


def _install_filter(program: bytes) -> None:
    filter_buffer = ctypes.create_string_buffer(program)
    # struct sock_fprog { unsigned short len; struct sock_filter *filter; }
    fprog = struct.pack("HxxxxxxP", len(program) // 8, ctypes.addressof(filter_buffer))
    _check(_libc.prctl(_PR_SET_SECCOMP, _SECCOMP_MODE_FILTER, fprog, 0, 0), "install the seccomp filter")


def _become_kernel(request: dict) -> None:
    """The kernel's side: confine this process as bubblewrap confines its command, then run the kernel."""
    os.setsid()
    null = os.open("/dev/null", os.O_RDWR)
    for fd in (0, 1, 2):
        os.dup2(null, fd)
    os.closerange(3, os.sysconf("SC_OPEN_MAX"))
    _drop_capabilities()
    _check(_libc.prctl(_PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0), "set no_new_privs")
    if request.get("seccomp"):
        _install_filter(bytes.fromhex(request["seccomp"]))
    os.chdir(request["workdir"])
    os.environ.clear()
    os.environ.update(request["env"])
    # every kernel draws its own random numbers, as a freshly started one would
    import random

    random.seed()
    numpy.random.seed()
    signal.signal(signal.SIGINT, signal.default_int_handler)
    from ipykernel.kernelapp import IPKernelApp

    sys.argv = [ipykernel.kernelapp.__file__, *request["argv"]]
    IPKernelApp.launch_instance(argv=list(request["argv"]))


def _fork_kernel(request: dict) -> dict:
    """Fork the child of the module docstring; the reply: ``{"pid": the kernel's host pid}`` or ``{"error": ...}``."""
    report_r, report_w = os.pipe()
    child = os.fork()
    if child == 0:
        status = 1
        try:
            os.close(report_r)
            signal.signal(signal.SIGCHLD, signal.SIG_DFL)
            _enter(request)
            kernel = os.fork()
            if kernel == 0:
                os.close(report_w)
                try:
                    _become_kernel(request)
                    status = 0
                finally:
                    os._exit(status)
            os.write(report_w, json.dumps({"pid": kernel}).encode())
            status = 0
        except BaseException as exc:  # noqa: BLE001 - whatever failed, the template says so and lives on
            try:
                os.write(report_w, json.dumps({"error": f"{type(exc).__name__}: {exc}"}).encode())
            finally:
                os._exit(1)
        os._exit(status)
    os.close(report_w)
    with os.fdopen(report_r, "rb") as report:
        text = report.read()
    return json.loads(text) if text else {"error": "the template's child died before it reported"}


def _owner_gone(owner: int) -> int | None:
    """A descriptor readable once the grading process ``owner`` has exited; ``None`` if it is gone already.

    Not ``PR_SET_PDEATHSIG``: that fires when the *thread* that started the template ends,
    and a grading process may start it from a short-lived thread.
    """
    try:
        fd = os.pidfd_open(owner)
    except ProcessLookupError:
        return None
    if os.getppid() != owner:  # re-parented before the descriptor was open
        os.close(fd)
        return None
    return fd


def _requests(owner: int):
    """The request lines on stdin, until stdin closes or the owner (the grading process that started this) exits."""
    gone = _owner_gone(owner)
    if gone is None:
        return
    requests = os.fdopen(0, "rb", buffering=0)
    poller = select.poll()
    poller.register(0, select.POLLIN)
    poller.register(gone, select.POLLIN)
    while True:
        events = dict(poller.poll())
        if gone in events:  # killed, say: its kernels' sandboxes die with it (bwrap --die-with-parent)
            return
        line = requests.readline()
        if not line:
            return
        yield line


def main() -> None:
    owner = int(sys.argv[1])
    _check(_libc.prctl(_PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0), "become a child subreaper")
    # Its children, and the kernels they leave to it (it is their subreaper), are reaped as
    # they exit: a sandbox's pid namespace ends only once every process in it is reaped.
    signal.signal(signal.SIGCHLD, signal.SIG_IGN)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the grader's ^C is for the grader: it stops this template
    replies = os.fdopen(1, "wb", buffering=0)
    # What is imported lives as long as every kernel: out of the collector's sight, a
    # kernel's collections neither walk it nor copy its pages (copy-on-write).
    gc.freeze()
    replies.write(b'{"ready": true}\n')
    for line in _requests(owner):
        try:
            reply = _fork_kernel(json.loads(line))
        except Exception as exc:  # noqa: BLE001
            reply = {"error": f"{type(exc).__name__}: {exc}"}
        replies.write(json.dumps(reply).encode() + b"\n")


if __name__ == "__main__":
    main()
