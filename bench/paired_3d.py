"""slipstep and GetFEM timed in one paired run on the 3D Hertz sphere, as a user runs them.

The 3D speed target compares whole processes on the same mesh. Timed in separate series the two
codes meet different loads on a shared machine (a GetFEM run of 20 minutes measured 1143 s on a
quiet machine and 1727 s under a load of 4, both on the reference BLAS), so the ratio is taken pair by pair: slipstep's
command line, then GetFEM on the mesh slipstep wrote, then again, alternating, each one process
timed spawn to exit (wall clock, and the child's CPU seconds and peak memory from the operating
system's accounting: os.wait4). The ratio of each pair is quoted and its median.

    A  slipstep run hertz_sphere_3d --set mesh.h_contact=H --set output.snapshots=[1.0]
       (the whole product: meshing, the engine, the summary, figures and XDMF written)
    B  python bench/getfem_hertz_3d.py one SPEC  (its best setting, `tuned`: same .msh)

    python bench/paired_3d.py [--h 0.02 0.0125 0.0105] [--pairs 1]   # writes bench/paired_3d.json

One entry per mesh size (`runs`), each with its pairs and median ratio, and the BLAS the peer's
MUMPS loaded (Debian's libblas.so.3 alternative: OpenBLAS's pthread build, as ci/apt-packages.txt
installs it; on the reference BLAS GetFEM's 3D runs are 10-14x slower). bench/series_3d.py's
report takes its speed target from this file when it exists.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
PAIRED_JSON = HERE / "paired_3d.json"
H_TARGET = 0.0105  # 92.6k DOFs: the target's "~100k DOFs" run
#: The sizes of the target: 22.6k, 60.8k and 92.6k DOFs.
H_SERIES = (0.02, 0.0125, H_TARGET)
#: Where Debian's alternatives put the BLAS every process here loads.
BLAS_LINK = Path("/usr/lib/x86_64-linux-gnu/libblas.so.3")


def timed(cmd: list[str]) -> dict:
    """One whole process: wall seconds, CPU seconds (user + sys), peak resident MiB, exit code."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(
        cmd,
        cwd=ROOT,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        env=dict(os.environ, MPLBACKEND="Agg"),
    )
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    err = proc.stderr.read().decode(errors="replace").strip().splitlines()[-2:]
    proc.stderr.close()
    return {
        "wall_s": wall,
        "cpu_s": usage.ru_utime + usage.ru_stime,
        "peak_mib": usage.ru_maxrss / 1024,
        "exit": os.waitstatus_to_exitcode(status),
        "stderr_tail": " | ".join(err),
    }


def commands(h: float, tmp: Path) -> tuple[list[str], list[str]]:
    """A (slipstep's command line) and B (GetFEM on the mesh slipstep's scene writes)."""
    sys.path.insert(0, str(HERE))
    import getfem_hertz_3d

    spec = getfem_hertz_3d.scene_spec(h, "tuned", tmp / "hertz.msh")
    (tmp / "spec.json").write_text(json.dumps(spec))
    slipstep = str(Path(sys.executable).with_name("slipstep"))
    a = [
        slipstep,
        "run",
        "hertz_sphere_3d",
        "--set",
        f"mesh.h_contact={h}",
        "--set",
        "output.snapshots=[1.0]",
        "--out",
        str(tmp / "out"),
        "--quiet",
    ]
    b = [sys.executable, str(HERE / "getfem_hertz_3d.py"), "one", str(tmp / "spec.json")]
    return a, b


def paired(h: float, n_pairs: int) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        a, b = commands(h, Path(tmp))
        pairs = []
        for k in range(n_pairs):
            pair = {"slipstep": timed(a), "getfem": timed(b)}
            pair["ratio_wall"] = pair["getfem"]["wall_s"] / pair["slipstep"]["wall_s"]
            pairs.append(pair)
            print(
                f"pair {k + 1}: slipstep {pair['slipstep']['wall_s']:.1f} s, GetFEM "
                f"{pair['getfem']['wall_s']:.1f} s: {pair['ratio_wall']:.1f}x",
                flush=True,
            )
    ok = [p for p in pairs if p["slipstep"]["exit"] == 0 and p["getfem"]["exit"] == 0]
    return {
        "what": "slipstep and GetFEM alternated, whole processes (bench/paired_3d.py)",
        "h": h,
        "load_average_start": os.getloadavg()[0],
        "pairs": pairs,
        "median_ratio_wall": statistics.median(p["ratio_wall"] for p in ok) if ok else None,
    }


def blas() -> str:
    """The BLAS library the alternatives select (its resolved path), or "unknown"."""
    return str(BLAS_LINK.resolve()) if BLAS_LINK.exists() else "unknown"


def runs_of(doc: dict) -> list[dict]:
    """The per-size entries of a paired_3d.json (an older file held one size at top level)."""
    return doc.get("runs", [doc])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "--h", type=float, nargs="+", default=list(H_SERIES), help="mesh.h_contact values"
    )
    ap.add_argument("--pairs", type=int, default=1)
    ap.add_argument("--out", type=Path, default=PAIRED_JSON)
    args = ap.parse_args(argv)
    runs = [paired(h, args.pairs) for h in args.h]
    doc = {"what": runs[0]["what"], "blas": blas(), "runs": runs}
    args.out.write_text(json.dumps(doc, indent=1) + "\n")
    return 0 if all(r["median_ratio_wall"] is not None for r in runs) else 1


if __name__ == "__main__":
    raise SystemExit(main())
