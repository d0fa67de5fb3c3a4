"""What the pytest suites of the Python module share: the `napkin` command
they compare with ($NAPKIN_BIN: the build's or the package's binary), the
NHTSA recordings and a demo catalogue written once per session."""

import csv
import os
import pathlib
import shutil
import subprocess

import pytest

NAPKIN_BIN = os.environ.get("NAPKIN_BIN") or shutil.which("napkin")


def run_napkin(*args, check=True):
    """Runs the napkin command; returns the CompletedProcess (text)."""
    if not NAPKIN_BIN:
        pytest.fail("set NAPKIN_BIN to the napkin executable the module is compared with")
    result = subprocess.run([NAPKIN_BIN, *map(str, args)], capture_output=True, text=True)
    if check and result.returncode != 0:
        pytest.fail("napkin {} failed ({}): {}".format(" ".join(map(str, args)), result.returncode, result.stderr))
    return result


def cli_error(*args):
    """The sentence the napkin command exits with (its stderr without "napkin: ")."""
    result = run_napkin(*args, check=False)
    assert result.returncode != 0, "napkin {} succeeded".format(args)
    lines = [line for line in result.stderr.splitlines() if line.startswith("napkin: ")]
    assert lines, result.stderr
    return lines[-1][len("napkin: "):]


def write_signals_csv(path, time_s, channels):
    """A signals CSV napkin reads back to the same doubles (repr is exact)."""
    names = list(channels)
    with open(path, "w", newline="") as out:
        out.write(",".join(["time_s", *names]) + "\n")
        for k in range(len(time_s)):
            out.write(",".join(repr(float(v)) for v in [time_s[k], *(channels[n][k] for n in names)]) + "\n")


def read_csv_cells(path):
    """{column: [cell text, ...]} of a CSV file."""
    with open(path, newline="") as source:
        rows = list(csv.reader(source))
    return {name: [row[i] for row in rows[1:]] for i, name in enumerate(rows[0])}


def cells_of(values):
    """napkin's derived-channel CSV cells of `values`: 12 significant digits
    (std::to_chars general, i.e. C's %.12g), empty for non-finite values."""
    return ["%.12g" % v if v == v and abs(v) != float("inf") else "" for v in values]


@pytest.fixture(scope="session")
def nhtsa_dir():
    beside_checkout = pathlib.Path(__file__).resolve().parents[3] / "shared" / "data" / "nhtsa-frontal"
    folder = pathlib.Path(os.environ.get("NAPKIN_NHTSA_FRONTAL_DIR") or beside_checkout)
    if not (folder / "corolla.csv").is_file():
        pytest.skip("the NHTSA recordings (../shared/data/nhtsa-frontal beside the checkout, or "
                    "$NAPKIN_NHTSA_FRONTAL_DIR) are not on this machine")
    return folder


@pytest.fixture(scope="session")
def demo_catalogue(tmp_path_factory):
    """The catalogue `napkin demo` writes (three variants of a padding series, run)."""
    folder = tmp_path_factory.mktemp("demo") / "demo"
    run_napkin("demo", "--out", folder)
    return folder / "napkin.db"
