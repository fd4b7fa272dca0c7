"""What each tool's time includes, one sentence per tool: written into every result file
(`protocol.includes`) and shown by the book's chapter *Side by side with other tools*."""

INCLUDES = [
    ["this project",
     "CPU time of the library's run over the periods (PeriodMap::advance from the state at "
     "t = 0, the call `cantilever simulate` makes), the model and its flows built beforehand "
     "and not counted, nor process start or output; compiled Rust, one thread."],
    ["this project's Dormand–Prince 5(4)",
     "CPU time of the library's Dormand–Prince integrator with event location (engine::dopri5, "
     "restarted at each period end to record the state there), the model built beforehand "
     "and not counted; compiled Rust, one thread."],
    ["CVODE",
     "CPU time (clock_gettime of the process) of CVODE's integration from t = 0 to the end, "
     "every restart at an event and every reset included, CVODE's memory, vectors, matrix "
     "and solvers created beforehand and not counted, nor reading the input or the output; "
     "C right-hand side and exact Jacobian, compiled with cc -O2, one thread."],
    ["scipy",
     "CPU time (time.process_time) of the solve_ivp event loop (every restart at an event "
     "included) whose right-hand side is a Python closure (a @ x plus a cosine per call), "
     "the model's matrices built beforehand and the interpreter start not counted; one "
     "thread (BLAS too)."],
    ["siconos",
     "CPU time (time.process_time in the Siconos process) of the simulation loop, driven "
     "from Python one event or time step at a time through Siconos' C++ kernel (forcing "
     "from a compiled C plugin), the model and simulation objects built beforehand and the "
     "interpreter start not counted; one thread."],
]
ORBIT_INCLUDES = [
    ["this project",
     "CPU time of the library's Newton shooting for the period-1 orbit (analysis::shooting::shoot, "
     "exact monodromy), the model and its flows built beforehand and not counted; compiled "
     "Rust, one thread."],
    ["scipy",
     "CPU time (time.process_time) of the Newton shooting with solve_ivp as the period map "
     "(Python right-hand side) and a central-difference monodromy, every period integrated "
     "included, the model's matrices built beforehand not counted; one thread."],
]
