"""napkin is a typed package (PEP 561, docs/python.md "Typing"): its stubs
(napkin/__init__.pyi, napkin/_napkin.pyi) and the marker napkin/py.typed sit
beside the module, `mypy --strict` accepts a program that uses every public
name (typing_example.py) and rejects one that misuses it, the stubs match the
module (mypy's stubtest), and every public name is documented (help(napkin))."""

import importlib.util
import os
import pathlib
import pydoc
import subprocess
import sys

import pytest

import napkin

HERE = pathlib.Path(__file__).resolve().parent
PACKAGE = pathlib.Path(napkin.__file__).resolve().parent

needs_mypy = pytest.mark.skipif(
    importlib.util.find_spec("mypy") is None,
    reason="mypy is not installed for this interpreter (Debian package mypy; `make deps` installs it)")


@pytest.fixture(scope="module")
def mypy_cache(tmp_path_factory):
    """One cache for the module's mypy runs: numpy's stubs are analysed once."""
    return str(tmp_path_factory.mktemp("mypy") / "cache")


def mypy(tmp_path, *args, module="mypy"):
    """`python3 -m mypy ...` (or mypy.stubtest) with the napkin under test first on its path:
    mypy finds it there as an installed package, by its py.typed."""
    environment = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(PACKAGE.parent), *filter(None, [os.environ.get("PYTHONPATH")])]))
    if module == "mypy":
        # mypy reads the stubs, never imports napkin: it needs no sanitizer runtime (a sanitized
        # build's tests preload one, python/CMakeLists.txt), which would only slow it down.
        environment.pop("LD_PRELOAD", None)
    return subprocess.run([sys.executable, "-m", module, *args], cwd=tmp_path, env=environment,
                          capture_output=True, text=True)


def test_the_stubs_and_the_marker_are_installed_with_the_package():
    for name in ("__init__.pyi", "_napkin.pyi", "py.typed"):
        assert (PACKAGE / name).is_file(), name


@needs_mypy
def test_mypy_strict_accepts_the_example_and_the_stubs(tmp_path, mypy_cache):
    cache = ["--cache-dir", mypy_cache]
    checked = mypy(tmp_path, "--strict", *cache, str(HERE / "typing_example.py"))
    assert checked.returncode == 0, checked.stdout + checked.stderr
    assert "Success: no issues found" in checked.stdout
    stubs = mypy(tmp_path, "--strict", *cache, str(PACKAGE / "__init__.pyi"), str(PACKAGE / "_napkin.pyi"))
    assert stubs.returncode == 0, stubs.stdout + stubs.stderr


@needs_mypy
def test_mypy_rejects_a_misuse(tmp_path, mypy_cache):
    misuse = tmp_path / "misuse.py"
    misuse.write_text("import napkin\n"
                      "import numpy as np\n"
                      "window = napkin.hic(np.ones(10), '1e-4')\n"
                      "late: str = window.t2_s\n"
                      "with napkin.Catalogue('napkin.db') as catalogue:\n"
                      "    catalogue.query('hic', limit='3')\n")
    checked = mypy(tmp_path, "--strict", "--cache-dir", mypy_cache, str(misuse))
    assert checked.returncode == 1, checked.stdout + checked.stderr
    errors = [line for line in checked.stdout.splitlines() if ": error:" in line]
    assert [line.split(":")[1] for line in errors] == ["3", "4", "6"], checked.stdout
    # Without the marker, mypy would see no types at all ("missing library stubs or py.typed marker").
    assert "py.typed" not in checked.stdout


@needs_mypy
def test_the_stubs_match_the_module(tmp_path):
    # pybind11's classes have pybind11's metaclass.
    allowlist = tmp_path / "allowlist.txt"
    allowlist.write_text("napkin._napkin.Catalogue\n")
    checked = mypy(tmp_path, "napkin", "--allowlist", str(allowlist), module="mypy.stubtest")
    assert checked.returncode == 0, checked.stdout + checked.stderr


def test_the_example_runs(demo_catalogue):
    ran = subprocess.run([sys.executable, str(HERE / "typing_example.py"), str(demo_catalogue)],
                         capture_output=True, text=True)
    assert ran.returncode == 0, ran.stderr


def test_every_public_name_is_documented():
    text = pydoc.render_doc(napkin, renderer=pydoc.plaintext)
    module_doc = napkin.__doc__
    for name in napkin.__all__:
        value = getattr(napkin, name)
        assert name in text, name
        if callable(value):
            doc = value.__doc__ or ""
            # Its own docstring, not one inherited from a base class (object, tuple, Exception, ...).
            inherited = [getattr(base, "__doc__", None) for base in type.mro(value)[1:]] if isinstance(
                value, type) else []
            assert len(doc.strip()) > 20 and doc not in inherited, name
        else:
            # Data (SUMMARY_FIELDS, RISK_CURVES): described in the module's docstring.
            assert "``{}``".format(name) in module_doc, name
    assert "napkin.Error" in text and "findings" in text
