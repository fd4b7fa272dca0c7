"""What every peer script shares: the project's command line and its model matrices, the
machine and the versions, CPU timing, and the result files with their checksum.

Nothing here knows a peer; nothing here computes a trajectory.
"""

import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone

PEERS = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(PEERS)
RESULTS = os.path.join(PEERS, "results")
FORMAT = "impacting-cantilever peer results v2"


def target_dir():
    return os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))


def cantilever_path():
    return os.path.join(target_dir(), "release", "cantilever")


def example_path():
    return os.path.join(target_dir(), "release", "examples", "peer_problem")


def cvode_path():
    return os.path.join(target_dir(), "peers", "cvode_peer")


def cvode_flags():
    """The C compiler's flags for SUNDIALS: $CVODE_CFLAGS and $CVODE_LIBS, by default those
    of Debian's libsundials-dev (headers in /usr/include, the libraries' .so links)."""
    cflags = os.environ.get("CVODE_CFLAGS", "").split()
    libs = os.environ.get("CVODE_LIBS", "-lsundials_cvode -lsundials_nvecserial").split()
    return cflags, libs


def build(cargo_args):
    """Builds the command line and the matrices example (release profile), and the CVODE
    peer (cc -O2)."""
    cmd = ["cargo", "build", "--release", "--bin", "cantilever", "--example", "peer_problem"]
    subprocess.run(cmd + list(cargo_args), cwd=ROOT, check=True)
    cflags, libs = cvode_flags()
    os.makedirs(os.path.dirname(cvode_path()), exist_ok=True)
    subprocess.run(["cc", "-O2", "-o", cvode_path(), *cflags, os.path.join(PEERS, "cvode_peer.c"),
                    *libs, "-lm"], check=True)


def problem_flags(p):
    """The `cantilever simulate` flags of a problem dict (see run.py's PROBLEMS)."""
    flags = ["--modes", str(p["modes"])]
    if p["model"] != "rigid":  # a rigid stop has no stiffness (the command line refuses one)
        flags += ["--stop-stiffness", repr(float(p.get("stop_stiffness_over_k1", 100.0)))]
    flags += [
        "--zeta1", repr(float(p["zeta1"])),
        "--omega", repr(float(p["omega_over_beta1_squared"])),
        "--gap", repr(float(p["gap"])),
    ]
    if p["model"] == "rigid":
        flags += ["--model", "rigid", "--law", p["law"], "--restitution", repr(float(p["restitution"]))]
    return flags


def matrices(p):
    """The model matrices of problem p, from the library (examples/peer_problem.rs)."""
    exe = example_path()
    flags = problem_flags({**p, "model": "compliant"})
    flags += ["--restitution", repr(float(p.get("restitution", 0.8)))]
    out = subprocess.run([exe] + flags, check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def run_cantilever(args, final_state=False):
    """Runs `cantilever ARGS --json` and returns (report, final state or None, child CPU
    seconds). The child's CPU time (user + system) includes the process start and the
    model's set-up; the report's own `wall_seconds` covers the run only."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "final.json")
        extra = ["--final-state", path] if final_state else []
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        proc = subprocess.run([cantilever_path()] + args + extra + ["--json"],
                              capture_output=True, text=True)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        if proc.returncode != 0:
            raise RuntimeError(f"cantilever {' '.join(args)}: exit {proc.returncode}: {proc.stderr.strip()}")
        report = json.loads(proc.stdout)
        state = json.load(open(path))["state"] if final_state else None
    return report, state, cpu


def cpu_timed(fn):
    """(result, CPU seconds of this process) of fn()."""
    t = time.process_time()
    out = fn()
    return out, time.process_time() - t


def median(xs):
    return statistics.median(xs)


def one_thread_env():
    """The environment of a timed child process: one thread (rayon and BLAS)."""
    env = dict(os.environ)
    for var in ("RAYON_NUM_THREADS", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        env[var] = "1"
    return env


def run_json(args):
    """Runs a program that prints one JSON object on its last line of output."""
    out = subprocess.run(args, capture_output=True, text=True, env=one_thread_env())
    last = out.stdout.strip().splitlines()[-1] if out.stdout.strip() else ""
    try:
        return json.loads(last)
    except json.JSONDecodeError:
        raise RuntimeError(f"{' '.join(args)}: exit {out.returncode}: {out.stderr[-500:]}")


def rel_max_error(x, ref):
    """max_i |x_i − ref_i| / max_i |ref_i| (the relative error of a state in the max norm)."""
    scale = max(abs(r) for r in ref)
    return max(abs(a - b) for a, b in zip(x, ref)) / scale


def machine():
    model = "unknown CPU"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {
        "cpu": model,
        "cores": os.cpu_count(),
        "os": f"{platform.system()} {platform.release()} {platform.machine()}",
        "load_average_when_written": list(os.getloadavg()),
    }


def _cmd(args):
    try:
        return subprocess.run(args, capture_output=True, text=True, cwd=ROOT).stdout.strip()
    except OSError:
        return None


def versions(extra=None):
    import mpmath
    import numpy
    import scipy
    commit = _cmd(["git", "rev-parse", "HEAD"])
    # the result files this run rewrites do not make the build dirty
    dirty = bool(_cmd(["git", "status", "--porcelain", "--untracked-files=no", "--", ".",
                       ":(exclude)peers/results"]))
    v = {
        "python": platform.python_version(),
        "numpy": numpy.__version__,
        "scipy": scipy.__version__,
        "mpmath": mpmath.__version__,
        "rustc": _cmd(["rustc", "--version"]),
        "cantilever": _cmd([cantilever_path(), "--version"]),
        "cc": next(iter((_cmd(["cc", "--version"]) or "").splitlines()), None),
        "sundials": ("libsundials-cvode6 " + v + " (Debian)") if (v := _cmd(
            ["dpkg-query", "-W", "-f", "${Version}", "libsundials-cvode6"])) else None,
        "commit": commit + (" (uncommitted changes)" if dirty else ""),
    }
    v.update(extra or {})
    return v


# ---------------------------------------------------------------- the result files

def canonical(v):
    """A canonical byte encoding of a JSON value, the same in Python and in Rust
    (tests/peers.rs): numbers as the 16 hex digits of their IEEE-754 double, strings with
    their UTF-8 length, object keys sorted."""
    if v is None:
        return b"n"
    if v is True:
        return b"t"
    if v is False:
        return b"f"
    if isinstance(v, (int, float)):
        import struct
        return b"d" + struct.pack(">d", float(v)).hex().encode()
    if isinstance(v, str):
        b = v.encode()
        return b"s" + str(len(b)).encode() + b":" + b
    if isinstance(v, list):
        return b"[" + b"".join(canonical(x) for x in v) + b"]"
    if isinstance(v, dict):
        keys = sorted(v.keys(), key=lambda k: k.encode())
        return b"{" + b"".join(canonical(k) + canonical(v[k]) for k in keys) + b"}"
    raise TypeError(type(v))


def fnv1a64(data):
    h = 0xCBF29CE484222325
    for byte in data:
        h ^= byte
        h = (h * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return f"{h:016x}"


def checksum(doc):
    """The checksum of everything in a result document but the checksum itself."""
    return fnv1a64(canonical({k: v for k, v in doc.items() if k != "checksum"}))


def finite(x):
    """JSON has no infinity or NaN: those become null."""
    if isinstance(x, float) and (x != x or x in (float("inf"), float("-inf"))):
        return None
    if isinstance(x, dict):
        return {k: finite(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [finite(v) for v in x]
    return x


def write_result(name, doc):
    doc = finite(doc)
    doc["checksum"] = checksum(doc)
    os.makedirs(RESULTS, exist_ok=True)
    path = os.path.join(RESULTS, name + ".json")
    with open(path + ".tmp", "w") as f:
        json.dump(doc, f, indent=1, ensure_ascii=False)
        f.write("\n")
    os.replace(path + ".tmp", path)
    return path


def header(problem, matrices_doc, extra_versions=None, load_at_start=None):
    m = machine()
    if load_at_start is not None:
        m["load_average_at_start"] = load_at_start
    return {
        "format": FORMAT,
        "date": datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "command": "python3 peers/run.py " + " ".join(sys.argv[1:]),
        "machine": m,
        "versions": versions(extra_versions),
        "problem": problem,
        "matrices": matrices_doc,
    }


def log(*args):
    print(*args, file=sys.stderr, flush=True)
