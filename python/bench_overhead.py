#!/usr/bin/python3
"""CPU time of the Python module against the `immerse` program on the same job (BENCHMARKS.md).

  /usr/bin/python3 python/bench_overhead.py BUILD_DIR INPUT.obj BACKGROUND.veg [RUNS] [THREADS]

Each run is a fresh process (so both pay their start-up: the interpreter and numpy for Python):
  program: immerse mesh INPUT --background BACKGROUND --threads T -o OUT.mesh --embedding OUT.emb
  module:  read_surface, find_immersions, mesh_immersion(background, threads), write .mesh and
           .emb-equivalent arrays (the embedding arrays are built, as a user would read them)
CPU time = user + system of the child (os.wait4), summed over its threads. Runs alternate
(program, module, program, ...) so that load changes on a shared machine hit both alike. Prints
each run, the medians and the ratio, and checks the two .mesh files are identical.
"""
import os
import statistics
import subprocess
import sys
import tempfile

MODULE_JOB = r"""
import sys
sys.path.insert(0, sys.argv[1])
import immersion
surface = immersion.read_surface(sys.argv[2])
found = immersion.find_immersions(surface, threads=int(sys.argv[5]))
mesh = immersion.mesh_immersion(found, background=sys.argv[3], threads=int(sys.argv[5]))
mesh.write(sys.argv[4])
element, weights = mesh.embedding_element, mesh.embedding_weights
"""


def cpu_seconds(argv):
    process = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(process.pid, 0)
    err = process.stderr.read().decode()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"failed: {' '.join(argv)}\n{err}")
    return usage.ru_utime + usage.ru_stime


def main():
    build, obj, veg = sys.argv[1:4]
    runs = int(sys.argv[4]) if len(sys.argv) > 4 else 5
    threads = sys.argv[5] if len(sys.argv) > 5 else "1"
    immerse = os.path.join(build, "immerse")
    module_dir = os.path.join(build, "python")
    with tempfile.TemporaryDirectory() as tmp:
        cli_out, py_out = os.path.join(tmp, "cli.mesh"), os.path.join(tmp, "py.mesh")
        program = [immerse, "mesh", obj, "--background", veg, "--threads", threads, "-o", cli_out,
                   "--embedding", os.path.join(tmp, "cli.emb")]
        module = [sys.executable, "-c", MODULE_JOB, module_dir, obj, veg, py_out, threads]
        times = {"program": [], "module": []}
        for run in range(runs):
            times["program"].append(cpu_seconds(program))
            times["module"].append(cpu_seconds(module))
            print(f"run {run}: program {times['program'][-1]:.2f} s, module {times['module'][-1]:.2f} s",
                  flush=True)
        with open(cli_out, "rb") as a, open(py_out, "rb") as b:
            identical = a.read() == b.read()
    p, m = statistics.median(times["program"]), statistics.median(times["module"])
    print(f"median CPU: program {p:.2f} s, module {m:.2f} s, module/program {m / p:.4f} "
          f"({(m / p - 1) * 100:+.1f} %); min: program {min(times['program']):.2f} s, "
          f"module {min(times['module']):.2f} s; .mesh identical: {identical}")
    return 0 if identical else 1


if __name__ == "__main__":
    sys.exit(main())
