import numpy as np
import impacting_cantilever as ic

# Figure 4's N = 10 model at twenty stop stiffnesses, in one call: where the motion from
# rest settles on no period, the sweep records why and goes on.
model = ic.problems.figure4(10)
sweep = ic.sweep(model, "stop_stiffness", np.linspace(1, 20, 20))
print(sweep)
for k, status, m, n, radius in zip(sweep.values, sweep.status, sweep.period_m,
                                   sweep.impacts_n, sweep.spectral_radius):
    print(f"k = {k:4.1f}k₁  " + (f"({m},{n}) orbit, spectral radius {radius:.4f}"
                                 if status == "ok" else status))

# One value alone: the missing orbit is its own exception class, so a loop can skip it
# while a bad argument still stops the loop.
try:
    ic.find_orbit(ic.replace(model, stop_stiffness=11.29))
except ic.NoOrbitError as e:
    print(f"{type(e).__name__}: {e}")
failure = ic.find_orbit(ic.replace(model, stop_stiffness=11.29), raise_on_failure=False)
print(failure.success, failure.status)
