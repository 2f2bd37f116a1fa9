"""The course loop on a real JupyterHub: release, fetch, submit, collect, grade, return feedback.

JupyterHub runs as a course's admin runs it on one machine: as root, on 127.0.0.1, with its own
proxy (configurable-http-proxy from the npm registry, installed by ``make setup`` in
``tests/hub/node_modules``), PAM logins of local Unix users and each user's JupyterLab started as
that user (JupyterHub's default authenticator and spawner). nbgrader's exchange is configured as
its documentation says: one folder every user may write (``/srv/nbgrader/exchange``, here mode
1777) and a global ``nbgrader_config.py`` naming it and the course. The test creates an instructor
and two students as Unix users (it must run as root) and removes them afterwards.

Everything runs in a private mount namespace, so the machine's ``/srv`` and ``/usr/local/etc``
are left alone: the namespace shows a fresh ``/srv`` and ``/usr/local/etc/jupyter``. Where the
Python interpreter lives in a folder other users cannot enter (pyenv under ``/root``, mode 0700),
the namespace shows in that folder only what the users need (the interpreter's tree; the checkout,
if it is there too), as if Python had been installed where every user can run it, as a hub's
admin installs it. Every user's server runs this
checkout's environment; a course's students run the student bundle's requirements instead (README,
"Run the course on JupyterHub"), and their notebooks import ``starter`` from the release, which
carries it: the test checks that the fetched assignment holds ``starter/`` and ``data/``.

In headless Chromium each student logs in, fetches the assignment in the Assignments tab (Nbgrader >
Assignment List), opens the notebook, writes ``edges``, runs the notebook's cells, saves and
submits. The instructor, in a shell of their own account, runs ``nbgrader collect``, ``deformlab
grade``, ``deformlab export --to nbgrader-feedback`` and ``nbgrader release_feedback``; each
student fetches the feedback in the Assignments tab and opens it in JupyterLab. The grades are
checked in grades.csv, the nbgrader gradebook and the Canvas and Moodle exports.
"""

from __future__ import annotations

import contextlib
import csv
import json
import os
import pwd
import re
import secrets
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time
import urllib.request
from dataclasses import dataclass
from pathlib import Path

import nbformat
import psutil
import pytest
from tests.course_copy import copy_course_config

from tests.browser.conftest import CHROMIUM, FLAGS, NO_CHROMIUM, free_port

pytestmark = [pytest.mark.slow, pytest.mark.timeout(600)]

ROOT = Path(__file__).resolve().parents[2]
PROXY = ROOT / "tests" / "hub" / "node_modules" / ".bin" / "configurable-http-proxy"
ASSIGNMENT = "deformation"
COURSE = "deformlab"
NOTEBOOK = "00_meshes"
#: Marks the Unix users this test creates with the creating process's pid, so that a later run removes
#: those an interrupted run left (and never those of a run still going).
GECOS = "DeformLab JupyterHub test user of pid {pid}"
TOOLS = ("useradd", "userdel", "chpasswd", "unshare", "nsenter", "setpriv", "mount")

# What each student types for `edges`, each in their own words: alice's answer is right; bob forgets
# to sort each row, so the public test shows him the duplicated edge, and grading takes its points.
EDGES = {
    "alice": (
        "import numpy as np\n\n\n"
        "def edges(F):\n"
        "    F = np.asarray(F).reshape(-1, 3)\n"
        "    pairs = np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])\n"
        "    return np.unique(np.sort(pairs, axis=1), axis=0)\n"
    ),
    "bob": (
        "import numpy as np\n\n\n"
        "def edges(F):\n"
        "    T = np.array(F)\n"
        "    E = np.concatenate((T[:, :2], T[:, 1:], T[:, ::-2]))  # (i, j), (j, k), (k, i)\n"
        "    return np.unique(E, axis=0)\n"
    ),
}
EDGES_POINTS = 3.0

# JupyterLab settings for a quiet page with every cell in the DOM (as tests/browser/test_jupyterlab.py).
LAB_SETTINGS = {
    "@jupyterlab/apputils-extension/notification.jupyterlab-settings": {"fetchNews": "false", "checkForUpdates": False},
    "@jupyterlab/notebook-extension/tracker.jupyterlab-settings": {"windowingMode": "none", "autoStartDefaultKernel": True},
}
NAMESPACE_SETUP = r"""
set -e
mount -t tmpfs -o mode=0755,size=256m deformlab-hub-srv /srv
install -d -m 1777 /srv/nbgrader/exchange
mount -t tmpfs -o mode=0755,size=1m deformlab-hub-etc /usr/local/etc
install -d -m 0755 /usr/local/etc/jupyter
install -m 0644 "$NBGRADER_GLOBAL_CONFIG" /usr/local/etc/jupyter/nbgrader_config.py
if [ -n "$HIDDEN_DIR" ]; then
  IFS=:
  i=0; for keep in $KEEP_DIRS; do mkdir "$HOLD_DIR/$i"; mount --bind "$keep" "$HOLD_DIR/$i"; i=$((i + 1)); done
  mount -t tmpfs -o mode=0755,size=1m deformlab-hub-hidden "$HIDDEN_DIR"
  i=0; for keep in $KEEP_DIRS; do mkdir -p "$keep"; mount --bind "$HOLD_DIR/$i" "$keep"; umount "$HOLD_DIR/$i"; i=$((i + 1)); done
  unset IFS
fi
exec "$@"
"""


@dataclass
class User:
    name: str
    password: str
    home: Path

    @property
    def uid(self) -> int:
        return pwd.getpwnam(self.name).pw_uid


@dataclass
class Hub:
    url: str
    process: subprocess.Popen
    log: Path
    base: Path
    instructor: User
    students: dict[str, User]  # "alice"/"bob" -> the Unix user

    def log_tail(self, lines: int = 30) -> str:
        return "\n".join(self.log.read_text(errors="replace").splitlines()[-lines:])

    @property
    def course(self) -> Path:
        """The instructor's nbgrader course folder (``assignments/`` of their copy of the kit)."""
        return self.instructor.home / "deformlab" / "assignments"

    def run_as(self, user: User, argv: list[str], cwd: Path, timeout: float = 300,
               check: bool = True) -> subprocess.CompletedProcess:
        """Run ``argv`` as ``user`` in the hub's mount namespace (as a shell in their JupyterLab would);
        with ``check``, fail unless it exits with 0."""
        env = {
            "HOME": str(user.home), "USER": user.name, "LOGNAME": user.name, "LANG": "C.UTF-8",
            "PATH": os.pathsep.join([str(Path(sys.executable).parent), "/usr/local/bin", "/usr/bin", "/bin"]),
        }
        if os.environ.get("VTK_DEFAULT_OPENGL_WINDOW"):
            env["VTK_DEFAULT_OPENGL_WINDOW"] = os.environ["VTK_DEFAULT_OPENGL_WINDOW"]
        command = ["nsenter", f"--mount=/proc/{self.process.pid}/ns/mnt", f"--wd={cwd}", "--",
                   "setpriv", f"--reuid={user.name}", f"--regid={user.name}", "--init-groups", "--", *argv]
        done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=timeout)
        assert done.returncode == 0 or not check, (
            f"{user.name}$ {' '.join(argv)} exited with {done.returncode}:\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}")
        return done


def _skip_reason() -> str | None:
    """Why this machine cannot run the hub, or None."""
    if sys.platform != "linux":
        return "the JupyterHub course test runs on Linux"
    if os.geteuid() != 0:
        return ("the JupyterHub course test creates Unix users and runs JupyterHub as root, as a hub with local users "
                "runs; it is running as an ordinary user")
    missing = [tool for tool in TOOLS if shutil.which(tool) is None]
    if missing:
        return f"missing system tools: {', '.join(missing)} (Debian: passwd, util-linux, mount)"
    if subprocess.run(["unshare", "--mount", "true"], capture_output=True).returncode != 0:
        return "this machine refuses a private mount namespace (unshare --mount), in which the test runs the hub"
    if not CHROMIUM.is_file():
        return NO_CHROMIUM
    if not PROXY.is_file():
        return (f"JupyterHub's proxy is not installed ({PROXY} is missing): `make setup` installs it with npm "
                "(npm ci in tests/hub), which needs Node.js and npm")
    try:
        namespace_view()
    except ValueError as e:
        return str(e)
    return None


def namespace_view() -> tuple[Path | None, list[Path]]:
    """The folder on the way to the interpreter or this checkout that other users cannot enter, and
    the folders right under it that the namespace shows in its place; ``(None, [])`` where every
    user can reach both.

    Raises
    ------
    ValueError
        If the users' way is closed further down, or by more than one folder.
    """
    needed = [Path(p).resolve() for p in (sys.base_prefix, sys.prefix, ROOT)]
    closed = {folder for folder in map(_closed_ancestor, needed) if folder}
    if not closed:
        return None, []
    hidden = min(closed, key=lambda folder: len(folder.parts))
    kept = sorted({hidden / p.relative_to(hidden).parts[0] for p in needed if p.is_relative_to(hidden) and p != hidden})
    for p in needed:
        # past the hidden folder, every folder on the way must be open to other users
        shut = p if p == hidden else next(
            (f for f in [*reversed(p.parents), p] if f != hidden and not f.stat().st_mode & stat.S_IXOTH), None)
        if shut:
            raise ValueError(f"{shut} is a folder other users cannot enter: the course's users could not run "
                             "this checkout's Python")
    return hidden, kept


def _closed_ancestor(path: Path) -> Path | None:
    """The first folder above or at ``path`` that other users cannot enter, or None."""
    path = path.resolve()
    for folder in [*reversed(path.parents), path]:
        if folder.is_dir() and not folder.stat().st_mode & stat.S_IXOTH:
            return folder
    return None


@contextlib.contextmanager
def unix_users(names: list[str], base: Path):
    """Create local users (home under ``base/home``, a random password each); remove them afterwards."""
    for entry in pwd.getpwall():  # left by an interrupted run
        left = re.fullmatch(re.escape(GECOS).replace(r"\{pid\}", r"(\d+)"), entry.pw_gecos)
        if left and not psutil.pid_exists(int(left.group(1))):
            subprocess.run(["userdel", "--force", "--remove", entry.pw_name], capture_output=True)
    (base / "home").mkdir(mode=0o755)
    users = []
    try:
        for name in names:
            user = User(name, secrets.token_urlsafe(12), base / "home" / name)
            # Home folders 0700, not Debian's default 0755, or students read each other's work.
            subprocess.run(["useradd", "--create-home", "--key", "HOME_MODE=0700", "--home-dir", str(user.home),
                            "--shell", "/bin/bash", "--user-group", "--comment", GECOS.format(pid=os.getpid()), name],
                           check=True, capture_output=True)
            users.append(user)
            subprocess.run(["chpasswd"], input=f"{name}:{user.password}\n", text=True, check=True, capture_output=True)
        yield users
    finally:
        uids = set()
        for user in users:
            with contextlib.suppress(KeyError):
                uids.add(user.uid)
        # Whatever the hub left running as these users was started by this test: end it by pid.
        for process in psutil.process_iter(["uids"]):
            if process.info["uids"] and process.info["uids"].real in uids:
                with contextlib.suppress(psutil.Error):
                    process.kill()
        for user in users:
            subprocess.run(["userdel", "--force", "--remove", user.name], capture_output=True)


def write_as(user: User, path: Path, text: str) -> None:
    """Write ``path`` (and its missing parents) owned by ``user``."""
    entry = pwd.getpwnam(user.name)
    missing = [p for p in reversed(path.parents) if not p.exists()]
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    for p in [*missing, path]:
        os.chown(p, entry.pw_uid, entry.pw_gid)


def build_course(instructor: User) -> None:
    """The instructor's copy of the kit with the assignment's source: the notebook ``00_meshes``, and
    ``starter/`` and ``data/`` to release with it (as ``deformlab build`` writes them)."""
    from grader.build.authored import read_authored
    from grader.build.release import add_course_files
    from grader.build.source_notebook import build_source_notebook
    from grader.paths import CoursePaths

    kit = instructor.home / "deformlab"
    source = kit / "assignments" / "source" / ASSIGNMENT / f"{NOTEBOOK}.ipynb"
    write_as(instructor, source, nbformat.writes(build_source_notebook(read_authored(ROOT / "notebooks" / ASSIGNMENT / f"{NOTEBOOK}.py"))))
    copy_course_config(kit / "assignments")  # chowned to the instructor below
    for name in ("data", "starter", "notebooks"):
        (kit / name).symlink_to(ROOT / name, target_is_directory=True)
        os.lchown(kit / name, instructor.uid, pwd.getpwnam(instructor.name).pw_gid)
    add_course_files(CoursePaths(kit), ASSIGNMENT)
    subprocess.run(["chown", "-R", f"{instructor.name}:{instructor.name}", str(kit / "assignments")], check=True)


def hub_config(base: Path, port: int, users: list[User]) -> str:
    env = {"VTK_DEFAULT_OPENGL_WINDOW": os.environ["VTK_DEFAULT_OPENGL_WINDOW"]} if os.environ.get("VTK_DEFAULT_OPENGL_WINDOW") else {}
    return f"""
c = get_config()
c.JupyterHub.bind_url = "http://127.0.0.1:{port}"
c.JupyterHub.hub_ip = "127.0.0.1"
c.JupyterHub.hub_port = {free_port()}
c.ConfigurableHTTPProxy.command = [{str(PROXY)!r}]
c.ConfigurableHTTPProxy.api_url = "http://127.0.0.1:{free_port()}"
c.JupyterHub.db_url = "sqlite:///{base / 'hub' / 'jupyterhub.sqlite'}"
c.JupyterHub.cookie_secret_file = {str(base / 'hub' / 'jupyterhub_cookie_secret')!r}
c.JupyterHub.authenticator_class = "pam"
c.Authenticator.allowed_users = {sorted(u.name for u in users)!r}
c.JupyterHub.spawner_class = "localprocess"
c.Spawner.cmd = [{str(Path(sys.executable).parent / 'jupyterhub-singleuser')!r}]
c.Spawner.default_url = "/lab"
c.Spawner.args = ["--LabApp.news_url=None",
                  "--LabApp.check_for_updates_class=jupyterlab.handlers.announcements.NeverCheckForUpdate"]
c.Spawner.environment = {env!r}
c.Spawner.start_timeout = 180
c.Spawner.http_timeout = 180
"""


NBGRADER_GLOBAL_CONFIG = f"""
c = get_config()
c.CourseDirectory.course_id = "{COURSE}"
c.Exchange.root = "/srv/nbgrader/exchange"
"""


@pytest.fixture(scope="module")
def hub():
    reason = _skip_reason()
    if reason:
        print(f"skipping the JupyterHub course test: {reason}")
        pytest.skip(reason)
    base = Path(tempfile.mkdtemp(prefix="deformlab-hub-", dir="/tmp"))  # where every user may enter
    base.chmod(0o755)
    tag = secrets.token_hex(2)
    try:
        with unix_users([f"dl{tag}-ta", f"dl{tag}-alice", f"dl{tag}-bob"], base) as (instructor, alice, bob):
            build_course(instructor)
            for student in (alice, bob):
                for name, settings in LAB_SETTINGS.items():
                    write_as(student, student.home / ".jupyter" / "lab" / "user-settings" / name, json.dumps(settings))
            (base / "hub").mkdir(mode=0o700)
            (base / "hold").mkdir(mode=0o700)
            port = free_port()
            (base / "hub" / "jupyterhub_config.py").write_text(hub_config(base, port, [instructor, alice, bob]))
            (base / "hub" / "nbgrader_config.py").write_text(NBGRADER_GLOBAL_CONFIG)
            hidden, kept = namespace_view()
            env = {
                "PATH": os.pathsep.join([str(Path(sys.executable).parent), "/usr/local/bin", "/usr/sbin", "/usr/bin", "/sbin", "/bin"]),
                "HOME": str(base / "hub"), "LANG": "C.UTF-8", "NBGRADER_GLOBAL_CONFIG": str(base / "hub" / "nbgrader_config.py"),
                # what the namespace shows of the folder the users cannot enter
                "HIDDEN_DIR": str(hidden or ""), "KEEP_DIRS": ":".join(map(str, kept)), "HOLD_DIR": str(base / "hold"),
            }
            log = base / "jupyterhub.log"
            with open(log, "wb") as out:
                process = subprocess.Popen(
                    ["unshare", "--mount", "--propagation", "private", "--", "/bin/sh", "-c", NAMESPACE_SETUP, "sh",
                     str(Path(sys.executable).parent / "jupyterhub"), "-f", str(base / "hub" / "jupyterhub_config.py")],
                    cwd=base / "hub", env=env, stdout=out, stderr=subprocess.STDOUT)
            hub = Hub(f"http://127.0.0.1:{port}", process, log, base, instructor, {"alice": alice, "bob": bob})
            try:
                deadline = time.monotonic() + 90
                while True:
                    if process.poll() is not None:
                        pytest.fail(f"jupyterhub exited with code {process.returncode}:\n{hub.log_tail()}")
                    with contextlib.suppress(OSError):
                        with urllib.request.urlopen(f"{hub.url}/hub/health", timeout=5) as answer:
                            if answer.status == 200:
                                break
                    if time.monotonic() > deadline:
                        pytest.fail(f"jupyterhub did not answer within 90 s:\n{hub.log_tail()}")
                    time.sleep(0.5)
                yield hub
            finally:
                process.send_signal(signal.SIGTERM)  # the hub stops every user's server and its proxy
                try:
                    process.wait(timeout=60)
                except subprocess.TimeoutExpired:
                    process.kill()
                    process.wait()
    finally:
        shutil.rmtree(base, ignore_errors=True)



# --- the students' side, in Chromium -------------------------------------------------------------

PANEL = ".jp-NotebookPanel:not(.lm-mod-hidden)"
ASSIGNMENTS = "#nbgrader-assignment-list"
UI_TIMEOUT_MS = 300_000


def start_login(page, hub: Hub, user: User) -> None:
    """Fill in the hub's login form; the hub then starts the user's JupyterLab (waited for by :func:`lab_ready`)."""
    page.goto(f"{hub.url}/hub/login")
    page.fill("#username_input", user.name)
    page.fill("#password_input", user.password)
    page.click("#login_submit")


def lab_ready(page, hub: Hub, user: User) -> None:
    try:
        page.wait_for_url(re.compile(f"/user/{user.name}/lab"), timeout=UI_TIMEOUT_MS * 2)
        page.wait_for_selector("#jp-main-dock-panel", timeout=UI_TIMEOUT_MS)
    except Exception:
        pytest.fail(f"{user.name}'s JupyterLab did not open (page {page.url}):\n{hub.log_tail()}")


def open_assignments(page) -> None:
    """Nbgrader > Assignment List: the Assignments tab, loaded afresh."""
    page.locator(".lm-MenuBar-itemLabel", has_text=re.compile(r"^Nbgrader$")).click()
    page.locator(".lm-Menu-itemLabel", has_text=re.compile(r"^Assignment List$")).click()
    page.wait_for_selector(f"{ASSIGNMENTS}:not(.lm-mod-hidden)", timeout=UI_TIMEOUT_MS)
    page.locator(f"{ASSIGNMENTS} #refresh_assignments_list").click()


def assignment_row(page, section: str):
    """The assignment's row in ``section`` (released, fetched or submitted) of the Assignments tab."""
    return page.locator(f"{ASSIGNMENTS} #{section}_assignments_list > .list_item", has_text=ASSIGNMENT)


def click_and_wait(page, section: str, button: str, then: str, shot: Path) -> None:
    """Click ``button`` on the assignment's row in ``section`` and wait for the row to appear in ``then``."""
    row = assignment_row(page, section)
    row.wait_for(timeout=UI_TIMEOUT_MS)
    row.locator("button", has_text=re.compile(f"^{button}$")).click()
    try:
        assignment_row(page, then).wait_for(timeout=UI_TIMEOUT_MS)
    except Exception:
        page.screenshot(path=str(shot))
        pytest.fail(f"after '{button}', {ASSIGNMENT} did not show under {then}: {shot}")


def cell(page, text: str):
    return page.locator(f"{PANEL} .jp-CodeCell", has_text=text).first


def idle_kernel(page, hub: Hub, user: User, path: str) -> None:
    """Wait until the student's server runs an idle kernel for notebook ``path``.

    Run All before the notebook's kernel is up can be dropped (seen on a loaded machine; see
    tests/browser/test_jupyterlab.py), so the cells are run only once the server says it is idle.
    """
    deadline, sessions = time.monotonic() + UI_TIMEOUT_MS / 1000, []
    while time.monotonic() < deadline:
        answer = page.request.get(f"{hub.url}/user/{user.name}/api/sessions")
        sessions = [s for s in answer.json() if s.get("path") == path and s.get("kernel")] if answer.ok else []
        if len(sessions) == 1 and sessions[0]["kernel"]["execution_state"] == "idle":
            return
        time.sleep(0.5)
    pytest.fail(f"{user.name}: no idle kernel for {path}; sessions: {sessions}")


def write_edges_and_run(page, hub: Hub, user: User, code: str, shot: Path) -> str:
    """Replace the ``edges`` stub with ``code``, Run > Run All Cells, save; returns what the tests cell shows."""
    idle_kernel(page, hub, user, f"{ASSIGNMENT}/{NOTEBOOK}.ipynb")
    page.wait_for_selector(f"{PANEL} .jp-Notebook-ExecutionIndicator[data-status='idle']", timeout=UI_TIMEOUT_MS)
    editor = cell(page, "def edges(F):").locator(".cm-content")
    editor.click()
    page.keyboard.press("Control+a")
    page.keyboard.insert_text(code)  # as pasted: no auto-indent
    first_prompt = page.locator(f"{PANEL} .jp-CodeCell .jp-InputPrompt").first
    for attempt in range(3):
        # A click that lands while the notebook is still settling can be lost: retry it.
        page.locator(".lm-MenuBar-itemLabel", has_text=re.compile(r"^Run$")).click()
        page.locator(".lm-Menu-itemLabel", has_text=re.compile(r"^Run All Cells$")).click()
        try:
            page.wait_for_function("(el) => /\\[(\\*|\\d+)\\]/.test(el.textContent)", arg=first_prompt.element_handle(),
                                   polling=200, timeout=15_000)
            break
        except Exception:
            if attempt == 2:
                page.screenshot(path=str(shot))
                pytest.fail(f"{user.name}: Run > Run All Cells did not start the cells: {shot}")
    tests = cell(page, "_E = edges(F_square)")
    try:
        # Run All stops at the first failing cell: the tests cell has run once it shows a count.
        page.wait_for_function(
            "([el, panel]) => /\\[\\d+\\]/.test(el.querySelector('.jp-InputPrompt').textContent) && "
            "document.querySelector(panel + ' .jp-Notebook-ExecutionIndicator')?.dataset.status === 'idle'",
            arg=[tests.element_handle(), PANEL], polling=500, timeout=UI_TIMEOUT_MS)
    except Exception:
        page.screenshot(path=str(shot))
        pytest.fail(f"the edges tests cell did not run: {shot}")
    page.keyboard.press("Control+s")
    page.wait_for_function("() => !document.querySelector('.lm-TabBar-tab.jp-mod-current.jp-mod-dirty')",
                           polling=200, timeout=30_000)
    tests.scroll_into_view_if_needed()
    page.screenshot(path=str(shot))
    return tests.locator(".jp-OutputArea").inner_text()


def fetch_and_open_feedback(page, student: str, shot: Path) -> str:
    """Fetch Feedback in the Assignments tab, follow "(view feedback)" and open the page in JupyterLab.

    Returns
    -------
    str
        The text JupyterLab's HTML viewer shows.
    """
    open_assignments(page)
    row = assignment_row(page, "submitted")
    row.wait_for(timeout=UI_TIMEOUT_MS)
    row.get_by_text("(feedback available to fetch)").wait_for(timeout=UI_TIMEOUT_MS)
    row.locator("button", has_text=re.compile("^Fetch Feedback$")).click()
    view = assignment_row(page, "submitted").get_by_text("(view feedback)")
    try:
        view.wait_for(timeout=UI_TIMEOUT_MS)
    except Exception:
        page.screenshot(path=str(shot))
        pytest.fail(f"{student}: no '(view feedback)' link after Fetch Feedback: {shot}")
    view.click()  # the file browser goes to the feedback's folder
    item = page.locator(".jp-DirListing-item", has_text=f"{NOTEBOOK}.html")
    item.wait_for(timeout=UI_TIMEOUT_MS)
    item.dblclick()
    frame = page.frame_locator(".jp-MainAreaWidget:not(.lm-mod-hidden) iframe")
    try:
        frame.locator("p.score").wait_for(timeout=UI_TIMEOUT_MS)
    except Exception:
        page.screenshot(path=str(shot))
        pytest.fail(f"{student}: JupyterLab did not show the feedback page: {shot}")
    page.screenshot(path=str(shot))
    return frame.locator("body").inner_text()


@dataclass
class Loop:
    """What the course loop left: what each student saw, the instructor's outputs, the screenshots."""

    hub: Hub
    shots: Path
    public_tests: dict[str, str]  # student -> the output of the edges tests cell
    feedback_shown: dict[str, str]  # student -> the text of the feedback page JupyterLab showed
    grading: Path  # the instructor's `deformlab grade --out`
    commands: dict[str, str]  # what the instructor's commands printed
    seconds: dict[str, float]  # per phase of the loop
    command_seconds: dict[str, float]  # per instructor command


@pytest.fixture(scope="module")
def loop(hub, tmp_path_factory) -> Loop:
    sync_api = pytest.importorskip("playwright.sync_api", reason="the playwright package (the dev extra) is not installed")
    shots = Path(os.environ.get("DEFORMLAB_HUB_SHOTS") or tmp_path_factory.mktemp("hub-shots"))
    shots.mkdir(parents=True, exist_ok=True)
    ta, course, grading = hub.instructor, hub.course, hub.course.parent / "grading"
    commands, seconds, command_seconds, public, shown = {}, {}, {}, {}, {}
    mark = time.monotonic()

    def phase(name: str) -> None:
        nonlocal mark
        seconds[name], mark = time.monotonic() - mark, time.monotonic()

    def instructor(*argv: str) -> None:
        began = time.monotonic()
        done = hub.run_as(ta, list(argv), course)
        commands[" ".join(argv)] = done.stdout + done.stderr
        command_seconds[" ".join(a for a in argv if not a.startswith("/"))] = time.monotonic() - began

    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=str(CHROMIUM), headless=True, args=FLAGS)
        try:
            pages = {k: browser.new_context(viewport={"width": 1400, "height": 1000}).new_page() for k in hub.students}
            for k, page in pages.items():  # both servers start at once, while the instructor releases
                start_login(page, hub, hub.students[k])
            instructor("nbgrader", "generate_assignment", ASSIGNMENT, "--force")
            instructor("nbgrader", "release_assignment", ASSIGNMENT)
            for k, page in pages.items():
                lab_ready(page, hub, hub.students[k])
            phase("release; log in, JupyterLab up")
            for k, page in pages.items():
                open_assignments(page)
                click_and_wait(page, "released", "Fetch", "fetched", shots / f"{k}-fetch.png")
                row = assignment_row(page, "fetched")
                row.locator(".assignment-notebooks-link").click()
                row.locator(".nested_list_item a", has_text=NOTEBOOK).click()
                public[k] = write_edges_and_run(page, hub, hub.students[k], EDGES[k], shots / f"{k}-public-tests.png")
                open_assignments(page)
                click_and_wait(page, "fetched", "Submit", "submitted", shots / f"{k}-submit.png")
            phase("students: fetch, edit, run, submit")

            instructor("nbgrader", "collect", ASSIGNMENT)
            instructor("deformlab", "grade", "submitted", "--out", str(grading), "--workers", "1")
            instructor("deformlab", "export", str(grading), "--to", "nbgrader-feedback", "--submitted", "submitted")
            instructor("nbgrader", "release_feedback", ASSIGNMENT)
            instructor("deformlab", "export", str(grading), "--to", "canvas")
            instructor("deformlab", "export", str(grading), "--to", "moodle")
            phase("instructor: collect, grade, return feedback")

            for k, page in pages.items():
                shown[k] = fetch_and_open_feedback(page, k, shots / f"{k}-feedback.png")
            phase("students: fetch and open feedback")
        finally:
            browser.close()
    (shots / "instructor-commands.txt").write_text("".join(f"$ {c}\n{out}\n" for c, out in commands.items()))
    return Loop(hub, shots, public, shown, grading, commands, seconds, command_seconds)


def test_each_student_fetches_the_assignment_runs_the_public_tests_in_jupyterlab_and_submits(loop):
    hub = loop.hub
    assert loop.public_tests["alice"].strip() == "", f"alice's edges passes its tests: {loop.shots / 'alice-public-tests.png'}"
    assert "the shared edge (0, 2) is listed twice" in loop.public_tests["bob"], (
        f"bob's public test names his bug; it showed {loop.public_tests['bob']!r}: {loop.shots / 'bob-public-tests.png'}")
    for k, user in hub.students.items():
        fetched = user.home / ASSIGNMENT
        # The notebook imports starter and loads meshes from data/: the exchange brought both along.
        assert (fetched / "starter" / "__init__.py").is_file() and (fetched / "data" / "torus.npz").is_file(), (
            f"{k} fetched {sorted(p.name for p in fetched.iterdir())}")
        # A kernel starts in the notebook's folder: Python there imports the fetched starter, not the kit's.
        where = hub.run_as(user, [sys.executable, "-c", "import starter; print(starter.__file__)"], fetched).stdout
        assert where.strip() == str(fetched / "starter" / "__init__.py"), where
        saved = nbformat.read(fetched / f"{NOTEBOOK}.ipynb", as_version=4)
        assert any(c.source.strip() == EDGES[k].strip() for c in saved.cells), f"{k}'s notebook was saved with the typed edges"
        collected = hub.course / "submitted" / user.name / ASSIGNMENT
        assert nbformat.read(collected / f"{NOTEBOOK}.ipynb", as_version=4) == saved, f"nbgrader collect brought {k}'s notebook"
        assert (collected / "timestamp.txt").is_file() and (collected / "submission_secret.txt").is_file()


def test_the_instructors_grades_reach_grades_csv_the_gradebook_and_the_lms_exports(loop):
    from nbgrader.api import Gradebook

    hub = loop.hub
    names = {user.name: k for k, user in hub.students.items()}
    with open(loop.grading / "grades.csv", newline="") as fh:
        rows = {names[r["student_id"]]: r for r in csv.DictReader(fh)}
    assert sorted(rows) == ["alice", "bob"] and {r["notebook"] for r in rows.values()} == {NOTEBOOK}
    assert float(rows["alice"]["score"]) == EDGES_POINTS, rows["alice"]
    assert float(rows["bob"]["score"]) == 0.0, rows["bob"]
    with Gradebook(f"sqlite:///{hub.course / 'gradebook.db'}", course_id=COURSE) as gb:
        for k, user in hub.students.items():
            submission = gb.find_submission(ASSIGNMENT, user.name)
            assert submission.score == float(rows[k]["score"]), f"{k}: gradebook {submission.score}, grades.csv {rows[k]['score']}"
            edges_grade = gb.find_grade("test_edges", NOTEBOOK, ASSIGNMENT, user.name)
            assert edges_grade.score == (EDGES_POINTS if k == "alice" else 0.0)
    with open(loop.grading / "canvas.csv", newline="") as fh:
        canvas = {names[r["SIS Login ID"]]: r for r in csv.DictReader(fh) if r["SIS Login ID"] in names}
    with open(loop.grading / "moodle.csv", newline="") as fh:
        moodle = list(csv.reader(fh))
    for k in ("alice", "bob"):
        assert float(canvas[k][ASSIGNMENT]) == float(rows[k]["score"]), canvas
        assert [float(r[1]) for r in moodle[1:] if r[0] == hub.students[k].name] == [float(rows[k]["score"])], moodle


def test_each_student_fetches_the_returned_feedback_and_reads_it_in_jupyterlab(loop, report_summary):
    hub = loop.hub
    for k, user in hub.students.items():
        pages = list((user.home / ASSIGNMENT / "feedback").glob(f"*/{NOTEBOOK}.html"))
        assert len(pages) == 1, f"{k} fetched {pages}"
        text = loop.feedback_shown[k]
        score = EDGES_POINTS if k == "alice" else 0.0
        assert f"{NOTEBOOK} — {user.name}" in text and f"Autograded score: {score:.2f} / " in text, (
            f"{k}'s feedback in JupyterLab: {loop.shots / f'{k}-feedback.png'}\n{text[:500]}")
        other = next(u for j, u in hub.students.items() if j != k)
        assert other.name not in pages[0].read_text(), f"{k}'s feedback names {other.name}"
    report_summary("jupyterhub", "\n".join(
        [f"the course loop on JupyterHub ({sum(loop.seconds.values()):.0f} s; screenshots in {loop.shots}):"]
        + [f"  {what:<45} {s:6.1f} s" for what, s in loop.seconds.items()]
        + [f"    {what:<43} {s:6.1f} s" for what, s in loop.command_seconds.items()]))


def test_the_exchange_keeps_the_students_out_of_each_others_submissions_and_the_course(loop):
    hub = loop.hub
    bob, alice = hub.students["bob"], hub.students["alice"]
    exchange = Path("/srv/nbgrader/exchange")
    inbound = exchange / COURSE / "inbound"
    listing = hub.run_as(hub.instructor, ["ls", "-1", str(inbound)], hub.course).stdout.splitlines()
    # nbgrader names each submission student+assignment+timestamp+random: not guessable (nbgrader #978)
    assert sorted(name.split("+")[0] for name in listing) == sorted([alice.name, bob.name])
    assert all(len(name.split("+")) == 4 for name in listing), listing
    refused = {
        "list the submissions": ["ls", str(inbound)],
        "list the returned feedback": ["ls", str(exchange / COURSE / "feedback")],
        "change the released assignment": ["touch", str(exchange / COURSE / "outbound" / ASSIGNMENT / f"{NOTEBOOK}.ipynb")],
        "rename the course's exchange folder": ["mv", str(exchange / COURSE), str(exchange / "moved")],
        "read the course's gradebook": ["cat", str(hub.course / "gradebook.db")],
        "read the other student's home": ["ls", str(alice.home)],
    }
    for what, argv in refused.items():
        done = hub.run_as(bob, argv, bob.home, check=False)
        # EACCES, or EPERM where the sticky bit keeps the folder's owner alone from renaming it
        assert done.returncode != 0 and re.search("Permission denied|Operation not permitted", done.stderr), (
            f"bob could {what}: {done}")
