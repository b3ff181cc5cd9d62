"""What the module needs from the system at run time, and what it says when that is
missing: the Vulkan loader (libvulkan.so.1) and a Vulkan driver are opened at the first
render, not when the module is imported, so `import glyphcast` works on a machine with
neither, and the render raises a RuntimeError naming the package to install.

Each case runs a fresh Python (the same interpreter and installation as the tests) with
the machine changed for that process alone."""
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

import pytest

# Imports glyphcast (which must work), then renders four order-2 tensors; prints the
# RuntimeError's message, or "rendered" when the render worked.
PROGRAM = """
import numpy as np
import glyphcast
tensors = np.zeros((2, 2, 1, 6))
tensors[..., 0] = tensors[..., 3] = tensors[..., 5] = 1.0
try:
    glyphcast.render_tensor(tensors, order=2, width=64, height=64)
except RuntimeError as error:
    print("RuntimeError:", error)
else:
    print("rendered")
"""


def run(env, prefix=()):
    done = subprocess.run([*prefix, sys.executable, "-c", PROGRAM], env=env,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


def test_without_a_vulkan_driver_the_render_names_lavapipe(tmp_path):
    """The loader is there but finds no driver: the ICD list names a file that does not
    exist (the loader then has no driver at all, as on a machine without any)."""
    env = {**os.environ,
           "VK_DRIVER_FILES": str(tmp_path / "no-such-driver.json"),
           "VK_ICD_FILENAMES": str(tmp_path / "no-such-driver.json")}
    message = run(env)
    assert message.startswith("RuntimeError: setup: no Vulkan driver"), message
    assert "mesa-vulkan-drivers" in message, message


def loader_path():
    """Where the dynamic linker finds libvulkan.so.1 (ldconfig's cache), or None."""
    done = subprocess.run(["/sbin/ldconfig", "-p"], capture_output=True, text=True)
    for line in done.stdout.splitlines():
        name, _, path = line.strip().partition(" => ")
        if name.startswith("libvulkan.so.1 ") and ("64" in name) == (sys.maxsize > 2**32):
            return pathlib.Path(path)
    return None


def test_without_the_vulkan_loader_import_works_and_the_render_names_the_package():
    """The loader's folder seen through an overlay in which libvulkan.so.1 is deleted (a
    whiteout), in a mount namespace of the test's Python alone: the dynamic linker finds
    no libvulkan.so.1 anywhere, as on a machine without the package. Needs root (a mount
    namespace, the whiteout's device node), as the CI containers have."""
    loader = loader_path()
    if loader is None:
        pytest.skip("no libvulkan.so.1 on this machine to hide")
    if os.geteuid() != 0 or shutil.which("unshare") is None:
        pytest.skip("hiding the loader needs root and unshare(1)")
    folder = loader.resolve().parent
    names = sorted({loader.name, loader.resolve().name})
    with tempfile.TemporaryDirectory() as scratch:
        # The overlay's upper layer on a tmpfs: the root file system of a container is
        # often an overlay itself, which cannot be an upper layer.
        steps = [f"mount -t tmpfs tmpfs {scratch}", f"mkdir {scratch}/upper {scratch}/work",
                 *(f"mknod {scratch}/upper/{name} c 0 0" for name in names),
                 f"mount -t overlay overlay -o lowerdir={folder},upperdir={scratch}/upper,"
                 f"workdir={scratch}/work {folder}",
                 'exec "$@"']
        prefix = ["unshare", "--mount", "--propagation", "private", "sh", "-c",
                  " && ".join(steps), "sh"]
        probe = subprocess.run([*prefix, sys.executable, "-c",
                                "import ctypes; ctypes.CDLL('libvulkan.so.1')"],
                               capture_output=True, text=True)
        if "cannot open shared object file" not in probe.stderr:
            pytest.skip(f"cannot hide the loader here: {probe.stderr.strip()[-300:]}")
        message = run(dict(os.environ), prefix)
    assert message.startswith("RuntimeError: setup: no Vulkan loader, libvulkan.so.1"), message
    assert "install libvulkan1" in message, message
    assert "cannot open shared object file" in message, message
