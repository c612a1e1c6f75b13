#!/usr/bin/env python3
"""Markdown tables and scaling exponents from imm_bench's JSON output (BENCHMARKS.md).

usage: bench/summarize_bench.py BENCH.json > tables.md

Scaling exponent of a family: the least-squares slope of log(time) against log(n) over the upper
half of its sizes (the ceil(k/2) largest of k sizes), where n is the complexity parameter
(input vertices for BM_BuildComplex2, background triangles for BM_Mesh2, arcs for the search).
Computed on CPU time (the machine is shared; wall time is also reported).
"""
import json
import math
import sys
from collections import OrderedDict


def slope(points):
    """Least-squares slope of log(y) on log(x) over the upper half of the points (by x)."""
    points = sorted(p for p in points if p[0] > 0 and p[1] > 0)
    upper = points[len(points) // 2:]
    if len(upper) < 2:
        return float("nan"), 0
    xs = [math.log(x) for x, _ in upper]
    ys = [math.log(y) for _, y in upper]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    sxy = sum((x - mx) * (y - my) for x, y in zip(xs, ys))
    return sxy / sxx, len(upper)


def ms(run, key):
    """A time of a run in milliseconds, whatever the run's unit."""
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[run.get("time_unit", "ns")]
    return run[key] * scale


def fmt(x, digits=3):
    if isinstance(x, float) and x.is_integer() and abs(x) < 1e15:
        return str(int(x))
    if isinstance(x, float):
        return f"{x:.{digits}g}"
    return str(x)


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(fmt(c) for c in row) + " |" for row in rows]
    return "\n".join(out)


def main(path):
    with open(path) as f:
        data = json.load(f)
    families = OrderedDict()
    for run in data["benchmarks"]:
        if run.get("run_type") != "iteration" or run.get("error_occurred"):
            continue
        families.setdefault(run["name"].split("/")[0], []).append(run)

    ctx = data["context"]
    print(f"Benchmark context: {ctx.get('date')}, {ctx.get('num_cpus')} CPUs at "
          f"{ctx.get('mhz_per_cpu')} MHz, load average {ctx.get('load_avg')}\n")

    runs = families.get("BM_BuildComplex2", [])
    if runs:
        rows = [[r["vertices"], r["arcs"], r["patches"], r["cells"], ms(r, "real_time"),
                 ms(r, "cpu_time"), 1e3 * ms(r, "cpu_time") / r["vertices"], r["iterations"]]
                for r in runs]
        print("### BM_BuildComplex2 (wobbly_circle, seed %s)\n" % fmt(runs[0]["seed"]))
        print(table(["vertices n", "arcs", "patches", "cells", "wall ms", "CPU ms",
                     "CPU us / vertex", "iterations"], rows))
        s, k = slope([(r["vertices"], ms(r, "cpu_time")) for r in runs])
        sw, _ = slope([(r["vertices"], ms(r, "real_time")) for r in runs])
        print(f"\nScaling exponent (CPU time vs n, {k} largest sizes): **{s:.2f}** "
              f"(wall time: {sw:.2f})\n")

    for name in ("BM_Search2Refute", "BM_Search2First", "BM_Search2All", "BM_Search2Generated"):
        runs = families.get(name, [])
        if not runs:
            continue
        print(f"### {name}\n")
        rows = []
        for r in runs:
            label = "/".join(r["name"].split("/")[1:]).replace("/min_time:0.100", "")
            per_state = 1e3 * ms(r, "cpu_time") / r["states"] if r["states"] else float("nan")
            rows.append([label, r["arcs"], r["cells"], r["nodes"], r["max_w"], r["states"],
                         r["branches"], r.get("probes", float("nan")), r["dead_ends"],
                         r["duplicates"], r["immersions"],
                         "yes" if r["complete"] else "no", ms(r, "real_time"), ms(r, "cpu_time"),
                         per_state])
        print(table(["input", "arcs", "cells", "nodes", "max w", "states", "branches",
                     "probes", "dead ends", "duplicates", "immersions", "complete", "wall ms", "CPU ms",
                     "CPU us / state"], rows))
        # Exponents per input series (same leading argument), only over runs that finished
        # within the budget: a budget-limited run measures the budget, not the input.
        series = OrderedDict()
        for r in runs:
            key = r["name"].split("/")[1]
            series.setdefault(key, []).append(r)
        lines = []
        for key, group in series.items():
            done = [r for r in group if r["complete"] or (r["immersible"] and name != "BM_Search2All")]
            if len(done) < 5:
                continue
            s, k = slope([(r["arcs"], ms(r, "cpu_time")) for r in done])
            lines.append(f"{key}: {s:.2f} ({k} largest of {len(done)} finished sizes)")
        if lines:
            print("\nScaling exponent of CPU time vs arcs, per series: " + "; ".join(lines) + "\n")
        else:
            print()

    runs = families.get("BM_Mesh2", [])
    if runs:
        rows = [[r["name"].split("/")[1].split(":")[1], r["background_triangles"],
                 r["cut_triangles"], r["output_triangles"], r["output_vertices"],
                 ms(r, "real_time"), ms(r, "cpu_time"), 1e3 * r["s_background"],
                 1e3 * r["s_virtual"], 1e3 * r["s_assembly"], r["iterations"]] for r in runs]
        print("### BM_Mesh2 (overlapping_disks, 4 disks x 32 vertices, seed %s, %s arcs)\n"
              % (fmt(runs[0]["seed"]), fmt(runs[0]["arcs"])))
        print(table(["resolution", "background tris N", "cut tris", "output tris", "output verts",
                     "wall ms", "CPU ms", "background ms", "virtual ms", "assembly ms",
                     "iterations"], rows))
        n = [r["background_triangles"] for r in runs]
        s, k = slope(list(zip(n, [ms(r, "cpu_time") for r in runs])))
        sw, _ = slope(list(zip(n, [ms(r, "real_time") for r in runs])))
        parts = []
        for key in ("s_background", "s_virtual", "s_assembly"):
            sp, _ = slope(list(zip(n, [r[key] for r in runs])))
            parts.append(f"{key[2:]} {sp:.2f}")
        sc, _ = slope([(r["cut_triangles"], 1e3 * r["s_virtual"]) for r in runs])
        print(f"\nScaling exponent (CPU time vs N, {k} largest sizes): **{s:.2f}** "
              f"(wall time: {sw:.2f}); per phase (wall, vs N): {', '.join(parts)}; "
              f"virtual phase vs cut triangles: {sc:.2f}\n")
        # The virtual phase has a part per cut triangle (exact clipping, local arrangements) and a
        # part per background triangle (flood fill of the uncut ones): least squares of
        # t = a * cut + b * N over all sizes, without intercept.
        cut = [r["cut_triangles"] for r in runs]
        t = [r["s_virtual"] for r in runs]
        scc = sum(c * c for c in cut)
        snn = sum(x * x for x in n)
        scn = sum(c * x for c, x in zip(cut, n))
        stc = sum(y * c for y, c in zip(t, cut))
        stn = sum(y * x for y, x in zip(t, n))
        det = scc * snn - scn * scn
        a = (stc * snn - stn * scn) / det
        b = (stn * scc - stc * scn) / det
        print(f"Virtual phase fit: {1e6 * a:.1f} us per cut triangle + {1e6 * b:.2f} us per "
              f"background triangle.\n")


if __name__ == "__main__":
    main(sys.argv[1])
