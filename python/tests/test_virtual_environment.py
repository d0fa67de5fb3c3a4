"""docs/python.md "In a virtual environment": the Debian package installs
napkin for Debian's interpreter (/usr/lib/python3/dist-packages), which a
virtual environment does not see unless it is made with
--system-site-packages. The recipe, tested: a venv made so (with
--without-pip, which needs no python3-venv/ensurepip) imports napkin and the
Debian packages it needs (numpy); one made without the flag does not see them."""

import importlib.util
import os
import subprocess
import sys

import pytest

import napkin

pytestmark = pytest.mark.skipif(importlib.util.find_spec("venv") is None,
                                reason="this interpreter has no venv module")


def make_venv(path, *options):
    # The interpreter the tests run under, the one the module is built for (/usr/bin/python3, Debian's:
    # python/CMakeLists.txt), as the recipe has it.
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", *options, str(path)], check=True)
    python = path / "bin" / "python3"
    assert python.exists()
    return python


def run(python, code):
    # The environment the tests run in: the module path (PYTHONPATH: the build tree or the unpacked
    # package), and a sanitized build's preloaded runtime.
    return subprocess.run([str(python), "-c", code], capture_output=True, text=True, env=dict(os.environ))


def test_a_venv_with_system_site_packages_imports_napkin(tmp_path):
    python = make_venv(tmp_path / "venv", "--system-site-packages")
    result = run(python, "import sys, napkin, numpy; "
                         "print(napkin.__version__); print(sys.prefix != sys.base_prefix); "
                         "print(napkin.hic(numpy.full(201, 100.0), 1e-4).hic)")
    assert result.returncode == 0, result.stderr
    version, in_venv, hic = result.stdout.split("\n")[:3]
    assert version == napkin.__version__
    assert in_venv == "True"  # the venv's interpreter, not the base one
    assert float(hic) == napkin.hic(__import__("numpy").full(201, 100.0), 1e-4).hic


def test_a_venv_without_it_does_not_see_debians_packages(tmp_path):
    python = make_venv(tmp_path / "isolated")
    result = run(python, "import numpy")
    assert result.returncode != 0 and "No module named 'numpy'" in result.stderr, result.stderr
