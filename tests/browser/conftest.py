"""What the browser tests share: Debian's Chromium driven by playwright, and a Jupyter server on loopback.

The browser is ``/usr/bin/chromium`` driven by the ``playwright`` package's bundled driver (never a
downloaded browser); tests skip where either is missing. Servers listen on 127.0.0.1 only, with a
random token.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import socket
import subprocess
import sys
import time
import urllib.request
from dataclasses import dataclass
from pathlib import Path

import pytest

CHROMIUM = Path("/usr/bin/chromium")
NO_CHROMIUM = (f"Debian's chromium is not installed ({CHROMIUM} is missing): `make test` installs it when run as root "
               "(apt-get install chromium chromium-driver)")
# Without the background-networking flags Chromium keeps calling home, which the closed network refuses.
FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]


@dataclass
class Server:
    """A running Jupyter server: ``url`` (no trailing slash), its ``token`` and its ``log`` file."""

    url: str
    token: str
    log: Path

    def log_tail(self, lines: int = 15) -> str:
        return "\n".join(self.log.read_text(errors="replace").splitlines()[-lines:])


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextlib.contextmanager
def jupyter_server(app: str, root: Path, log: Path, env: dict[str, str], args=(), while_starting=None):
    """``jupyter <app>`` serving ``root`` on 127.0.0.1 with a random token; yields a :class:`Server` once it
    answers, and shuts it down afterwards. ``while_starting()`` runs while the server starts."""
    token, port = secrets.token_hex(16), free_port()
    command = [
        sys.executable, "-m", "jupyter", app, "--no-browser", "--allow-root",
        f"--ServerApp.token={token}", "--ServerApp.ip=127.0.0.1", f"--ServerApp.port={port}",
        "--ServerApp.port_retries=0", f"--ServerApp.root_dir={root}", *args,
    ]
    with open(log, "wb") as out:
        process = subprocess.Popen(command, env=env, stdout=out, stderr=subprocess.STDOUT, cwd=root)
    server = Server(f"http://127.0.0.1:{port}", token, log)
    try:
        if while_starting:
            while_starting()
        deadline = time.monotonic() + 90
        while True:
            if process.poll() is not None:
                pytest.fail(f"jupyter {app} exited with code {process.returncode}:\n{server.log_tail()}")
            try:
                with urllib.request.urlopen(f"{server.url}/api/status?token={token}", timeout=5) as answer:
                    if answer.status == 200:
                        break
            except OSError:
                pass
            if time.monotonic() > deadline:
                pytest.fail(f"jupyter {app} did not answer within 90 s:\n{server.log_tail()}")
            time.sleep(0.5)
        yield server
    finally:
        process.terminate()  # the server shuts its kernels down on SIGTERM
        try:
            process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def jupyter_env(workdir: Path) -> dict[str, str]:
    """The environment of a server with its own config and runtime folders, importing this checkout."""
    root = Path(__file__).resolve().parents[2]
    env = {k: v for k, v in os.environ.items() if k not in ("DEFORMLAB_NO_PLOTS", "DEFORMLAB_PLOT_BACKEND")}
    env.update(
        JUPYTER_CONFIG_DIR=str(workdir / "config"),
        JUPYTER_RUNTIME_DIR=str(workdir / "runtime"),
        PYTHONPATH=os.pathsep.join(filter(None, [str(root), os.environ.get("PYTHONPATH")])),
    )
    return env


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    """A headless Chromium (a persistent playwright context with a fresh profile), closed afterwards."""
    if not CHROMIUM.is_file():
        pytest.skip(NO_CHROMIUM)
    sync_api = pytest.importorskip("playwright.sync_api", reason="the playwright package (the dev extra) is not installed")
    with sync_api.sync_playwright() as playwright:
        context = playwright.chromium.launch_persistent_context(
            str(tmp_path_factory.mktemp("chromium-profile")), executable_path=str(CHROMIUM), headless=True, args=FLAGS,
            viewport={"width": 1400, "height": 1000},
        )
        try:
            yield context
        finally:
            context.close()
