"""What the scripts and tests that start a ROS master or a roslaunch of their own share: a free
port for the master, and stopping a process group as a terminal's ^C would.

The scripts import it from their own folder (Python puts a script's folder first on sys.path);
a test elsewhere puts scripts/ on sys.path first (test/rostest/test_stale_params.py)."""
import os
import signal
import socket
import subprocess


def free_port():
    """A TCP port on localhost that nothing listens on now."""
    s = socket.socket()
    s.bind(("localhost", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def stop_group(proc, timeout_s):
    """Stops the process group proc leads (started with start_new_session=True): SIGINT, so that
    roslaunch and roscore shut their nodes down, then SIGKILL when proc has not exited within
    timeout_s."""
    os.killpg(proc.pid, signal.SIGINT)
    try:
        proc.wait(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
