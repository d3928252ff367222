"""Ctrl-C stops a long call promptly with KeyboardInterrupt, and leaves the module usable.

Each child starts a call that runs for minutes uninterrupted, says so, and gets SIGINT a second
later; it must end within the timeout (a generous bound for a loaded machine, far below the
call's own length), with KeyboardInterrupt raised from the call, and answer a query afterwards.
"""

import signal
import subprocess
import sys
import textwrap
import time

import pytest

CHILD = """
import sys, time
import numpy as np
import sphray

small = sphray.Scene(np.float32([[0, 0, -2]]), np.float32([1]))
{setup}
print("calling", flush=True)
start = time.monotonic()
try:
    {call}
    print("finished", flush=True)   # the call ran to its end: not interrupted
except KeyboardInterrupt:
    print("interrupted after %.2f s" % (time.monotonic() - start), flush=True)
t, ids = small.intersect(np.float32([[0, 0, 0]]), np.float32([[0, 0, -1]]))
print("then a query:", int(ids[0]), float(t[0]), flush=True)
{after}
"""

CASES = {
    # rtiow-final's path tracer at 60,000 samples per pixel: hours on a desktop.
    "render": ("", "sphray.render('rtiow-final', mode='path', spp=60000, width=400)"),
    # 2^22 rays through 65,536 overlapping spheres by brute force: 3e11 sphere tests, none of
    # which the batch pre-test skips (minutes).
    "query": (
        "rng = np.random.default_rng(1)\n"
        "big = sphray.Scene(rng.uniform(-1, 1, (65536, 3)).astype(np.float32),"
        " np.full(65536, 1.0, np.float32), accel='brute')\n"
        "o = np.broadcast_to(np.float32([0, 0, -5]), (2**22, 3))\n"
        "d = np.broadcast_to(np.float32([0, 0, 1]), (2**22, 3))",
        "big.count_hits(o, d)"),
    # A tree over 24 million spheres: seconds, not minutes, so the child then times the whole
    # build as well (below).
    "build": (
        "rng = np.random.default_rng(2)\n"
        "c = rng.random((24_000_000, 3), dtype=np.float32)\n"
        "r = np.full(24_000_000, 1e-3, np.float32)",
        "sphray.Scene(c, r)"),
}


WHOLE_CALL = """
start = time.monotonic()
{call}
print("the whole call took %.2f s" % (time.monotonic() - start), flush=True)
"""


@pytest.mark.parametrize("case", CASES)
def test_ctrl_c_interrupts_a_long_call(case):
    setup, call = CASES[case]
    after = WHOLE_CALL.format(call=call) if case == "build" else ""
    code = textwrap.dedent(CHILD).format(setup=setup, call=call, after=after)
    child = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().strip() == "calling"
        time.sleep(1.0)
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=60)
    finally:
        child.kill()
    assert child.returncode == 0, err[-2000:]
    lines = out.splitlines()
    # KeyboardInterrupt from the call itself, not raised once it had run to its end.
    assert lines[0].startswith("interrupted after"), out
    assert float(lines[0].split()[2]) < 10.0, out
    assert lines[1] == "then a query: 0 1.0", out
    if after:
        # A signal seen only once the call returned would come after the whole call's time.
        whole = float(lines[2].split()[4])
        assert float(lines[0].split()[2]) < whole / 2, out
