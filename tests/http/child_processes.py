# SPDX-License-Identifier: Apache-2.0
"""Children of a test (servers, browsers) that die with the test process however it ends: a
failed assertion, an uncaught exception, or SIGKILL from ctest's timeout, where no finally,
atexit or __exit__ runs. After one failed run, 32 ispq-server processes were left behind."""
import ctypes
import os
import signal

_LIBC = ctypes.CDLL(None, use_errno=True)  # loaded here: a forked child must not load libraries
_PR_SET_PDEATHSIG = 1


def die_with_parent(signal_number=signal.SIGKILL):
    """A preexec_fn for subprocess.Popen: the child receives `signal_number` when the test process
    dies (prctl(PR_SET_PDEATHSIG)).

    Linux sends it when the *thread* that started the child exits, not the process: start
    children from the main thread (or one that lives as long as the test), never from a
    short-lived thread, or they die with it."""
    parent = os.getpid()

    def in_child():
        if _LIBC.prctl(_PR_SET_PDEATHSIG, int(signal_number), 0, 0, 0) != 0:
            os._exit(127)
        if os.getppid() != parent:  # the test died before the request: nobody would signal
            os._exit(126)

    return in_child
