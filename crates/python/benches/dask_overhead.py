"""The overhead of running a map on Dask against the bare command: a 40 000-point
map (`paper-damped.json`, 10 restitutions x 10 gaps x 400 frequencies) by `rattle map` on 2
threads, by `rattle.map` without a client, and on a `LocalCluster` of 2 workers x 1 thread
with 4 and 100 parts, in turn; wall and CPU seconds (user + system of every process
involved); then an idle cluster's own CPU, and the cost per task of 100 one-point tasks.
Needs the package, `dask` and `distributed`; from the repository's root:

    cargo build --release -p rattle-compare --bin rattle
    python crates/python/benches/dask_overhead.py [REPEATS]
"""

import os
import resource
import subprocess
import sys
import time
from pathlib import Path

os.environ["RAYON_NUM_THREADS"] = "1"  # one Rust thread per single-threaded Dask worker

import psutil  # noqa: E402 - installed with distributed
import rattle  # noqa: E402
from distributed import Client, LocalCluster  # noqa: E402

ROOT = Path(__file__).resolve().parents[3]
SCENE = str(ROOT / "data" / "scenes" / "paper-damped.json")
RATTLE = os.environ.get("RATTLE_BIN", str(ROOT / "target" / "release" / "rattle"))
AXES = dict(restitution=(0.0, 1.0, 10), gap=(0.05, 1.0, 10), omega=(0.1, 4.0, 400))
FLAGS = ["--restitutions", "10", "--gaps", "10", "--points", "400"]
OUT = "/tmp/rattle-dask-overhead.json"


def tree_cpu():
    """CPU seconds of this process and every process under it (the cluster's)."""
    me = psutil.Process()
    total = sum(me.cpu_times()[:2])
    for p in me.children(recursive=True):
        try:
            total += sum(p.cpu_times()[:2])
        except psutil.NoSuchProcess:
            pass
    return total


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def command():
    c, t = children_cpu(), time.perf_counter()
    subprocess.run([RATTLE, "map", SCENE, *FLAGS, "--out", OUT], check=True, capture_output=True,
                   env={**os.environ, "RAYON_NUM_THREADS": "2"})
    return time.perf_counter() - t, children_cpu() - c


def package_alone():
    code = (
        "import time, resource, rattle\n"
        f"s = rattle.Scene.from_file({SCENE!r}); t = time.perf_counter()\n"
        f"m = rattle.map(s, **{AXES!r}); w = time.perf_counter() - t\n"
        "r = resource.getrusage(resource.RUSAGE_SELF)\n"
        f"print(w, r.ru_utime + r.ru_stime, m.document == open({OUT!r}).read())\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={**os.environ, "RAYON_NUM_THREADS": "2"})
    wall, cpu, same = out.stdout.split()
    return float(wall), float(cpu), same


def main():
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 1
    scene = rattle.Scene.from_file(SCENE)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=40) as cluster, Client(cluster) as client:
        client.run(lambda: __import__("rattle"))
        for r in range(repeats):
            a, acpu = command()
            print(f"{r}: rattle map        wall {a:7.2f} s  cpu {acpu:7.2f} s", flush=True)
            w, c, same = package_alone()
            print(f"{r}: rattle.map alone  wall {w:7.2f} s  cpu {c:7.2f} s  identical {same}", flush=True)
            for parts in (4, 100):
                c0, t = tree_cpu(), time.perf_counter()
                m = rattle.map(scene, **AXES, client=client, parts=parts, progress=False)
                b, bcpu = time.perf_counter() - t, tree_cpu() - c0
                same = m.document == Path(OUT).read_text()
                print(f"{r}: dask, {parts:3} parts  wall {b:7.2f} s  cpu {bcpu:7.2f} s  "
                      f"(x{b / a:.3f}, x{bcpu / acpu:.3f})  identical {same}", flush=True)
        c0, t = tree_cpu(), time.perf_counter()
        time.sleep(20)
        print(f"idle cluster: {(tree_cpu() - c0) / (time.perf_counter() - t):.4f} cpu-s per s")
        tiny = dict(restitution=(0.0, 1.0, 10), gap=(0.05, 1.0, 10), omega=(2.0, 2.0, 1))
        c0, t = tree_cpu(), time.perf_counter()
        direct = rattle.map(scene, **tiny)
        a, acpu = time.perf_counter() - t, tree_cpu() - c0
        c0, t = tree_cpu(), time.perf_counter()
        d = rattle.map(scene, **tiny, client=client, parts=100, progress=False)
        b, bcpu = time.perf_counter() - t, tree_cpu() - c0
        print(f"per task: wall {(b - a) * 10:.1f} ms  cpu {(bcpu - acpu) * 10:.1f} ms  "
              f"identical {d.document == direct.document}")


if __name__ == "__main__":
    main()
