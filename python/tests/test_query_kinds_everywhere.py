"""Every query kind of napkin's one table (db/query_kinds.h, napkin.QUERY_KINDS) is answered alike
by the command line, the service and the module, and an unknown kind is refused by each in the same
sentence (issue 43 point 1: each front end had its own list, and the service's lacked correlation and
limits)."""

import json
import re
import selectors
import subprocess
import time
import urllib.error
import urllib.parse
import urllib.request

import pytest

import napkin
from conftest import NAPKIN_BIN, cli_error, run_napkin

LIMITS_PRESET = "fmvss208"


@pytest.fixture(scope="module")
def service(demo_catalogue):
    """`napkin serve` on the demo catalogue, on a free loopback port: its base URL."""
    if not NAPKIN_BIN:
        pytest.fail("set NAPKIN_BIN to the napkin executable the module is compared with")
    process = subprocess.Popen([NAPKIN_BIN, "--db", str(demo_catalogue), "serve", "--listen", "127.0.0.1:0"],
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        selector = selectors.DefaultSelector()
        selector.register(process.stderr, selectors.EVENT_READ)
        log, port, deadline = "", None, time.monotonic() + 60
        while port is None and time.monotonic() < deadline:
            if selector.select(timeout=1):
                line = process.stderr.readline()
                if not line:
                    break  # it exited
                log += line
                found = re.search(r"listening on http://127\.0\.0\.1:([0-9]+) ", line)
                port = found and int(found.group(1))
        assert port, "napkin serve did not listen: " + log
        yield "http://127.0.0.1:{}".format(port)
    finally:
        process.terminate()
        process.wait(timeout=30)
        process.stderr.close()


def get(base, path, **params):
    """(status, body) of GET base + path?params."""
    url = base + path + ("?" + urllib.parse.urlencode(params) if params else "")
    try:
        with urllib.request.urlopen(url, timeout=30) as answer:
            return answer.status, answer.read().decode()
    except urllib.error.HTTPError as error:
        return error.code, error.read().decode()


@pytest.mark.parametrize("kind", list(napkin.QUERY_KINDS))
def test_every_kind_is_answered_alike(demo_catalogue, service, kind):
    takes_limits = napkin.QUERY_KINDS[kind].takes_limits
    limits = ["--limits", LIMITS_PRESET] if takes_limits else []
    cli = json.loads(run_napkin("--db", demo_catalogue, "query", kind, *limits, "--format", "json").stdout)
    status, body = get(service, "/api/v1/query/" + kind, **({"limits": LIMITS_PRESET} if takes_limits else {}))
    assert status == 200, body
    assert json.loads(body) == cli
    with napkin.Catalogue(demo_catalogue) as catalogue:
        assert catalogue.query(kind, limits=LIMITS_PRESET if takes_limits else None) == cli


@pytest.mark.parametrize("kind", ["everything", "HIC", "hic\n", "limit"])
def test_an_unknown_kind_is_refused_alike(demo_catalogue, service, kind):
    sentence = cli_error("--db", demo_catalogue, "query", kind)
    assert sentence.startswith("the query kind must be tests, hic, ")
    status, body = get(service, "/api/v1/query/" + urllib.parse.quote(kind, safe=""))
    assert status == 404, body
    assert json.loads(body) == {"error": sentence}
    with napkin.Catalogue(demo_catalogue) as catalogue:
        with pytest.raises(ValueError) as error:
            catalogue.query(kind)
    assert str(error.value) == sentence
