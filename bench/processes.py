"""What the bench's series share: one scene run in a process of its own (bench/run.py --one),
timed whole, the machine and code it ran on, and the numbers' formats (bench/run.py and
bench/series_3d.py import this; neither imports the other)."""

from __future__ import annotations

import json
import math
import os
import platform
import re
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def run_child(spec: dict, timeout: float, python: str = sys.executable) -> dict:
    """Run ``spec`` in a child process (``python``: this interpreter, or the old engine's);
    wall_s is that whole process, spawn to exit.  Status ok / timeout / error / rejected."""
    cmd = [python, str(HERE / "run.py"), "--one", json.dumps(spec)]
    env, cwd = dict(os.environ, MPLBACKEND="Agg"), ROOT
    if python != sys.executable:  # another build's venv: <its tree>/.venv/bin/python
        env.pop("VIRTUAL_ENV", None)
        cwd = Path(python).parents[2]
    t0 = time.perf_counter()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, cwd=cwd)
    except subprocess.TimeoutExpired:
        return {
            **spec,
            "status": "timeout",
            "error": f"no result within {timeout:.0f} s",
            "wall_s": time.perf_counter() - t0,
        }
    wall = time.perf_counter() - t0
    lines = [ln for ln in p.stdout.splitlines() if ln.startswith("BENCH ")]
    if not lines:
        tail = " | ".join((p.stderr or "").strip().splitlines()[-3:])
        return {
            **spec,
            "status": "error",
            "error": f"exit code {p.returncode}: {tail}",
            "wall_s": wall,
        }
    return {**spec, **json.loads(lines[-1][len("BENCH ") :]), "wall_s": wall}


def machine() -> dict:
    def first(path, pattern):
        try:
            m = re.search(pattern, Path(path).read_text(), re.M)
            return m.group(1).strip() if m else "?"
        except OSError:
            return "?"

    from importlib import metadata

    def version(pkg):
        try:
            return metadata.version(pkg)
        except metadata.PackageNotFoundError:
            return "?"

    try:
        commit = (
            subprocess.run(
                ["git", "describe", "--always", "--dirty"], cwd=ROOT, capture_output=True, text=True
            ).stdout.strip()
            or "?"
        )
    except OSError:
        commit = "?"
    mem_kib = first("/proc/meminfo", r"^MemTotal:\s+(\d+)")
    return {
        "cpu": first("/proc/cpuinfo", r"^model name\s*:(.*)$"),
        "cores": len(os.sched_getaffinity(0))
        if hasattr(os, "sched_getaffinity")
        else os.cpu_count(),
        "ram_gib": round(int(mem_kib) / 2**20, 1) if mem_kib.isdigit() else "?",
        "os": first("/etc/os-release", r'^PRETTY_NAME="?([^"\n]*)') + f" ({platform.release()})",
        "python": platform.python_version(),
        "numpy": version("numpy"),
        "gmsh": version("gmsh"),
        "slipstep": version("slipstep"),
        "git": commit,
        "faer": first(ROOT / "Cargo.lock", r'name = "faer"\nversion = "([^"]+)"'),
        "engine_mtime": engine_mtime(),
        "load_start": os.getloadavg()[0],
    }


def engine_mtime() -> str:
    libs = sorted((ROOT / "py" / "slipstep").glob("_engine*.so"))
    return (
        time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(libs[0].stat().st_mtime)) if libs else "?"
    )


def fmt(v, spec=".3f"):
    return "–" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, spec)


def pct(v, spec=".3f"):
    return (
        "–"
        if v is None or (isinstance(v, float) and math.isnan(v))
        else format(100 * v, spec) + " %"
    )
