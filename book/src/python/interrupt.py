import signal
import threading
import time

import impacting_cantilever as ic

# A hundred million forcing periods of the N = 10 model (about 14 minutes), interrupted
# after half a second as Ctrl-C (or a notebook's "interrupt kernel") would: the call stops
# within a forcing period and raises KeyboardInterrupt; the partial run is dropped.
threading.Timer(0.5, signal.raise_signal, [signal.SIGINT]).start()
started = time.perf_counter()
try:
    ic.simulate(ic.problems.figure4(10), periods=10**8)
except KeyboardInterrupt:
    late = time.perf_counter() - started - 0.5
    print("KeyboardInterrupt:", "stopped within 0.1 s" if late < 0.1 else f"stopped {late:.2f} s late")

# A progress callback that raises stops a call the same way, with its own exception.
def progress(what, done, total):
    if done >= 5000:
        raise RuntimeError(f"enough of {what} (of {total:,})")

try:
    ic.simulate(ic.problems.figure4(10), periods=10**8, progress=progress)
except RuntimeError as e:
    print("RuntimeError:", e)
