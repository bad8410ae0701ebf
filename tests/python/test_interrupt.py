"""Ctrl-C cancels a render and raises KeyboardInterrupt; renders release the GIL."""
import os
import signal
import subprocess
import sys
import threading
import time

import volguide
from conftest import SCENES

# The child installs Python's own SIGINT handler explicitly: a process started with SIGINT ignored
# (a background job of a non-interactive shell, as CI may run ctest) would otherwise inherit SIG_IGN,
# and Python installs its KeyboardInterrupt handler only over the default disposition.
CHILD = r"""
import signal, sys, time, volguide
signal.signal(signal.SIGINT, signal.default_int_handler)
scene = volguide.load_scene(sys.argv[1], width=160, height=120, spp=4)
print("rendering", flush=True)
try:
    volguide.render(scene, spp=1000000, threads=1)
except KeyboardInterrupt:
    print("KeyboardInterrupt", flush=True)
    sys.exit(0)
print("finished", flush=True)
sys.exit(1)
"""


def test_sigint_cancels_the_render_and_raises_keyboard_interrupt():
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(SCENES / "fogbox.xml")],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=os.environ.copy())
    try:
        assert child.stdout.readline().strip() == "rendering"
        time.sleep(1.0)  # well into the render (1 M spp would take hours)
        assert child.poll() is None
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=30)
        stopped_after = time.monotonic() - sent
    finally:
        if child.poll() is None:
            child.kill()
    assert child.returncode == 0, err
    assert out.strip() == "KeyboardInterrupt"
    # The render stops at the end of its current pass (at most 8 spp of 160 x 120 on one thread).
    assert stopped_after < 10.0


def test_render_releases_the_gil(fogbox):
    ticks = 0
    done = threading.Event()

    def render():
        volguide.render(fogbox, time=0.5, threads=1)
        done.set()

    worker = threading.Thread(target=render)
    worker.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    # Holding the GIL for the whole render would leave this loop one or two iterations.
    assert ticks > 50
