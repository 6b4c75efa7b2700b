"""Shared set-up of the Python tests."""

import signal

import pytest


@pytest.fixture(autouse=True)
def python_handles_ctrl_c():
    """Ctrl-C raises KeyboardInterrupt during every test, as in an interactive session.

    A process started in the background by a shell without job control inherits
    SIGINT ignored, and Python then installs no handler: `_thread.interrupt_main()`
    (the tests' Ctrl-C) would do nothing. The tests of Ctrl-C check the package, not
    how the suite was launched.
    """
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, before)
