"""Dask that cannot hang (issue 26 §5): a --scheduler that accepts connections and never answers is refused by
name within the --scheduler-timeout (it held the run for minutes)."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import threading
import time

import pytest


@pytest.fixture
def silent_listener():
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    held = []
    stop = threading.Event()

    def accept():
        server.settimeout(0.2)
        while not stop.is_set():
            try:
                held.append(server.accept()[0])
            except OSError:
                pass

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    stop.set()
    thread.join()
    for conn in held:
        conn.close()
    server.close()


def test_a_scheduler_that_never_answers_is_refused_in_bounded_time(silent_listener, tmp_path):
    code = "import sys; from eulersym.cli import main; sys.exit(main(sys.argv[1:]))"
    start = time.monotonic()
    run = subprocess.run([sys.executable, "-c", code, "simulate", "sleeping-top-map", "--scheduler", silent_listener,
                          "--scheduler-timeout", "2"], capture_output=True, text=True, timeout=120,
                         env={**os.environ, "EULERSYM_CACHE": str(tmp_path / "cache")})
    assert run.returncode == 2 and "Traceback" not in run.stderr, run.stderr
    assert f"--scheduler='{silent_listener}'" in run.stderr and "within 2 s" in run.stderr
    assert time.monotonic() - start < 30


def test_the_timeout_must_be_a_number_of_seconds(tmp_path):
    from eulersym.cli import main

    assert main(["simulate", "sleeping-top-map", "--scheduler", "tcp://127.0.0.1:1", "--scheduler-timeout", "-1"]) == 2
