#!/usr/bin/env python3
"""`glbudget run`: a signal sent to the whole process group (Ctrl-C, `timeout` without
--foreground) reaches the app once. A launcher that forwarded the signals it got to its child
delivered such a signal twice, and ioquake3 died of its own "DOUBLE SIGNAL FAULT".
Usage: run_group_signal_test.py GLBUDGET"""
import os
import signal
import subprocess
import sys

APP = r"""
import signal, sys, time
count = 0
def taken(sig, frame):
    global count
    count += 1
signal.signal(signal.SIGUSR1, taken)
print("ready", flush=True)
end = time.monotonic() + 1.0
while time.monotonic() < end:
    time.sleep(0.01)
sys.exit(10 + count)
"""


def main():
    glbudget = sys.argv[1]
    app = subprocess.Popen([glbudget, "run", "--", sys.executable, "-c", APP], stdout=subprocess.PIPE,
                           start_new_session=True, text=True)
    line = app.stdout.readline()
    if line.strip() != "ready":
        print(f"the app did not start: {line!r}")
        return 1
    os.killpg(app.pid, signal.SIGUSR1)  # as the terminal sends Ctrl-C: to every process of the group
    code = app.wait(timeout=20)
    taken = code - 10
    print(f"the app took the group's SIGUSR1 {taken} time(s) (exit {code})")
    return 0 if taken == 1 else 1


if __name__ == "__main__":
    sys.exit(main())
