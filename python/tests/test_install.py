"""`cmake --install` puts the module where the system Python finds it: the default destination
is on sys.path of the interpreter the module was built for, and an install into a scratch
prefix imports and works from there (in a fresh interpreter, without build/python)."""
import os
import pathlib
import subprocess
import sys
import sysconfig

import pytest


def env_or_skip(name):
    value = os.environ.get(name)
    if not value:
        if os.environ.get("CI") == "true":
            pytest.fail(f"{name} not set under CI (run through ctest)")
        pytest.skip(f"SKIPPED: {name} not set (run through ctest)")
    return value


def test_default_destination_is_on_sys_path():
    prefix = pathlib.Path(env_or_skip("SLAMKIT_INSTALL_PREFIX"))
    rel = pathlib.Path(env_or_skip("SLAMKIT_PYTHON_INSTALL_DIR"))
    dest = rel if rel.is_absolute() else prefix / rel
    platlib = pathlib.Path(sysconfig.get_path("platlib"))
    if dest != platlib:
        pytest.skip(f"SKIPPED: installing into {dest}, not this interpreter's {platlib} (custom prefix)")
    assert str(dest) in sys.path, f"{dest} is not on {sys.executable}'s sys.path {sys.path}"


def test_install_into_prefix_and_import(tmp_path):
    cmake = env_or_skip("SLAMKIT_CMAKE")
    binary_dir = env_or_skip("SLAMKIT_BINARY_DIR")
    rel = pathlib.Path(env_or_skip("SLAMKIT_PYTHON_INSTALL_DIR"))
    subprocess.run([cmake, "--install", binary_dir, "--prefix", str(tmp_path), "--component", "python"],
                   check=True, stdout=subprocess.DEVNULL)
    site = rel if rel.is_absolute() else tmp_path / rel
    assert (site / "slamkit" / "__init__.py").exists()
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(site)
    out = subprocess.run([sys.executable, "-c", "import slamkit, numpy as np; print(slamkit.__file__); "
                          "print(slamkit.SE3.exp(np.zeros(6)).matrix().trace())"],
                         env=env, check=True, capture_output=True, text=True, cwd=str(tmp_path)).stdout.split()
    assert out[0].startswith(str(site)) and float(out[1]) == 4.0
