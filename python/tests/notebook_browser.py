"""A Jupyter server and headless Chromium for the notebook view's tests and its
benchmark (tools/bench_notebook.py): start JupyterLab on a free port in a folder, open a
notebook in Chromium through Selenium and Debian's chromium-driver, run its cells with
JupyterLab's own commands, read the pixels the page shows, and talk to the notebook's
kernel directly (jupyter_client, through the connection file the server writes).
"""
import base64
import contextlib
import io
import json
import os
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
import uuid

import numpy as np

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")


def missing():
    """What the browser tests lack on this machine, or None."""
    if CHROMIUM is None or CHROMEDRIVER is None:
        return "chromium and chromedriver are needed (Debian: apt install chromium chromium-driver)"
    for module in ("selenium", "jupyterlab", "jupyter_rfb", "jupyter_client", "PIL"):
        try:
            __import__(module)
        except ImportError:
            return f"{module} is not installed (pip install 'glyphcast[notebook]' selenium jupyterlab pillow)"
    return None


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Server:
    """JupyterLab (``frontend="lab"``) or Notebook 7 (``"notebook"``) serving ``root`` on
    a free port of 127.0.0.1, with a token, its connection files in ``root/.runtime``;
    ``kernels=False`` lets no kernel start (no kernel spec is allowed), as a reader
    without one opens a notebook."""

    def __init__(self, root, kernels=True, frontend="lab"):
        self.root = root
        self.frontend = frontend
        app = {"lab": "LabApp", "notebook": "JupyterNotebookApp"}[frontend]
        self.port = free_port()
        self.token = uuid.uuid4().hex
        self.runtime = os.path.join(root, ".runtime")
        args = [
            sys.executable, "-m", {"lab": "jupyterlab", "notebook": "notebook"}[frontend],
            "--no-browser",
            "--ServerApp.ip=127.0.0.1", f"--ServerApp.port={self.port}",
            "--ServerApp.port_retries=0", f"--IdentityProvider.token={self.token}",
            f"--ServerApp.root_dir={root}", f"--{app}.expose_app_in_browser=True",
        ]
        if frontend == "lab":
            args += ["--LabApp.news_url=", "--LabApp.extension_manager=readonly",
                     "--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate"]
        if os.getuid() == 0:
            args.append("--allow-root")  # CI's containers run as root
        if not kernels:
            args += ["--KernelSpecManager.ensure_native_kernel=False",
                     "--KernelSpecManager.allowed_kernelspecs=none-such"]
        # The kernel is this Python's (its folder first on PATH: the kernel spec of a
        # virtual environment names `python`).
        path = os.path.dirname(sys.executable) + os.pathsep + os.environ.get("PATH", "")
        env = dict(os.environ, PATH=path, JUPYTER_RUNTIME_DIR=self.runtime,
                   JUPYTER_CONFIG_DIR=os.path.join(root, ".config"))
        self.log = open(os.path.join(root, f"server-{self.port}.log"), "w")
        self.process = subprocess.Popen(args, cwd=root, env=env, stdout=self.log,
                                        stderr=subprocess.STDOUT)
        deadline = time.monotonic() + 60
        while True:
            try:
                self.api("status")
                break
            except OSError:
                if self.process.poll() is not None or time.monotonic() > deadline:
                    raise RuntimeError(f"the Jupyter server did not start: {self.log_text()}")
                time.sleep(0.3)

    def url(self, path):
        return f"http://127.0.0.1:{self.port}/{path}?token={self.token}"

    def api(self, path, method="GET"):
        request = urllib.request.Request(self.url(f"api/{path}"), method=method)
        with urllib.request.urlopen(request, timeout=10) as response:
            body = response.read()
        return json.loads(body) if body else None

    def log_text(self):
        self.log.flush()
        with open(self.log.name) as file:
            return file.read()[-4000:]

    def kernel(self):
        """A client of the one running kernel (a notebook's), its channels started."""
        from jupyter_client import BlockingKernelClient

        sessions = self.api("sessions")
        assert len(sessions) == 1, sessions
        connection = os.path.join(self.runtime, f"kernel-{sessions[0]['kernel']['id']}.json")
        client = BlockingKernelClient(connection_file=connection)
        client.load_connection_file()
        client.start_channels()
        client.wait_for_ready(timeout=30)
        return client

    def stop(self):
        self.process.terminate()
        try:
            self.process.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        self.log.close()


def run_in_kernel(client, code, timeout=60):
    """Runs ``code`` in the kernel; returns what it printed. Raises on an error."""
    msg_id = client.execute(code, store_history=False)
    printed = []
    deadline = time.monotonic() + timeout
    while True:
        message = client.get_iopub_msg(timeout=max(deadline - time.monotonic(), 0.1))
        if message["parent_header"].get("msg_id") != msg_id:
            continue
        kind, content = message["msg_type"], message["content"]
        if kind == "stream":
            printed.append(content["text"])
        elif kind == "error":
            raise RuntimeError("\n".join(content["traceback"]))
        elif kind == "status" and content["execution_state"] == "idle":
            return "".join(printed)


def kernel_value(client, expression):
    """The JSON value of a Python expression in the kernel."""
    return json.loads(run_in_kernel(client, f"import json as _j; print(_j.dumps({expression}))"))


@contextlib.contextmanager
def chromium(width=1400, height=1100):
    """Headless Chromium under Selenium (Debian's chromium and chromium-driver)."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage",
                 f"--window-size={width},{height}", "--force-device-scale-factor=1",
                 "--disable-features=Translate", "--no-first-run"):
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
    try:
        yield driver
    finally:
        driver.quit()


def wait_for(condition, timeout, what):
    deadline = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            raise TimeoutError(f"waited {timeout} s for {what}")
        time.sleep(0.1)


def open_notebook(driver, server, name):
    """Opens ``name`` in JupyterLab or Notebook 7 and waits for it to be the page's
    document."""
    page = {"lab": "lab/tree", "notebook": "notebooks"}[server.frontend]
    driver.get(server.url(f"{page}/{name}"))
    wait_for(lambda: driver.execute_script(
        "const app = window.jupyterapp; if (!app) return false;"
        "const w = app.shell.currentWidget;"
        "return !!(w && w.context && w.context.path.endsWith(arguments[0]))", name),
        90, "JupyterLab to open the notebook")


def kernel_idle(driver):
    return driver.execute_script(
        "const w = window.jupyterapp.shell.currentWidget;"
        "const k = w.sessionContext.session && w.sessionContext.session.kernel;"
        "return !!k && k.status === 'idle'")


def command(driver, name):
    """Runs a JupyterLab command (what its menus run), waiting for it to finish."""
    driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "window.jupyterapp.commands.execute(arguments[0]).then(() => done(true),"
        " (e) => done(String(e)));", name)


VIEW_IMAGE = ".renderview-wrapper img"


def shown_image(driver, selector=VIEW_IMAGE):
    """The bytes and the type of the image an <img> shows (a blob: or data: URL)."""
    result = driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "const img = document.querySelector(arguments[0]);"
        "if (!img || !img.src) { done(null); return; }"
        "fetch(img.src).then(r => r.blob()).then(b => {"
        "  const reader = new FileReader();"
        "  reader.onload = () => done([b.type, reader.result.split(',')[1]]);"
        "  reader.readAsDataURL(b); }).catch(e => done(null));", selector)
    if result is None:
        return None, None
    kind, data = result
    return kind, base64.b64decode(data)


def decode(raw):
    """RGB pixels of a PNG or JPEG."""
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(raw)).convert("RGB"))


def settled_frame(driver, timeout=60, selector=VIEW_IMAGE):
    """The view's frame once it is the lossless one (PNG) and has not changed for a
    second: jupyter_rfb sends the last frame of an interaction again as a PNG."""
    last, since = None, time.monotonic()
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        kind, raw = shown_image(driver, selector)
        if raw != last:
            last, since = raw, time.monotonic()
        elif kind == "image/png" and time.monotonic() - since > 1.0:
            return decode(raw)
        time.sleep(0.1)
    raise TimeoutError(f"the view showed no settled PNG frame within {timeout} s")
