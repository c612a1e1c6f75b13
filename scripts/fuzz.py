#!/usr/bin/python3
"""Seeded mutation fuzzer for the `immerse` program (issue 13).

Takes the small committed corpus (tests/fuzz/corpus: 2D text, SVG and OBJ curves; 3D OBJ, OFF,
PLY and STL surfaces; a background mesh), mutates one file per run (bytes, lines, numbers:
extreme and special values, truncation, splicing), and runs one command family on it:
check, cells, immersions, mesh (2D and 3D readers alike). Every run must
  - end with exit code 0, 2 or 3 (never a signal, 1 = internal error, or a hang past --timeout);
  - leave no temporary '*.tmp.*' file;
  - leave no result file (mesh, embedding) unless it exited 0, and only complete JSON reports
    (a report of the failure is a deliberate output; a half-written one is not);
  - print a bounded, text-only message (at most 64 KiB, no control bytes but tab/newline/CR).
A failing input is saved with its command under --crashes (a regression test to be).

Deterministic: the same --seed and --runs give the same inputs and commands.

  scripts/fuzz.py --immerse build/immerse --runs 200 --seed 1          # about a minute
  scripts/fuzz.py --immerse build/immerse --runs 20000 --seed 7 --jobs 2  # the long run
Debian python3 only (no third-party modules).
"""
import argparse
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

SPECIAL_NUMBERS = [b"0", b"-0", b"1", b"-1", b"1e308", b"-1e308", b"1.7976931348623157e308", b"1e309",
                   b"4.9e-324", b"1e-320", b"2.2250738585072014e-308", b"nan", b"inf", b"-inf",
                   b"1e155", b"1e110", b"-1e200", b"1e-150", b"123456789012345678901234567890",
                   b"9007199254740993", b"0.1", b"1e15", b"-1e15", b"0x10", b"1e", b"--1", b"+.5"]


def numbers_in(data):
    """(start, end) of every run that looks like a number."""
    spans, i, n = [], 0, len(data)
    while i < n:
        c = data[i]
        if chr(c) in "0123456789-+.":
            j = i + 1
            while j < n and chr(data[j]) in "0123456789.eE-+":
                j += 1
            spans.append((i, j))
            i = j
        else:
            i += 1
    return spans


def mutate(rng, data, corpus_bytes):
    kind = rng.randrange(10)
    if kind <= 2:  # replace a number with a special or scaled one
        spans = numbers_in(data)
        if spans:
            for _ in range(rng.randint(1, 3)):
                a, b = rng.choice(spans)
                if rng.random() < 0.6:
                    repl = rng.choice(SPECIAL_NUMBERS)
                else:
                    try:
                        v = float(data[a:b]) * rng.choice([2.0 ** rng.randint(-1074, 1023), -1.0, 1e15, 1e-15, 3.0])
                        repl = repr(v).encode()
                    except (ValueError, OverflowError):
                        repl = b"7"
                data = data[:a] + repl + data[b:]
                spans = numbers_in(data)
                if not spans:
                    break
        return data
    if kind == 3:  # scale every number by one power of two (exactly) or translate
        spans = numbers_in(data)
        factor = 2.0 ** rng.choice([-1000, -600, -300, 300, 500, 600, 1000])
        out, last = b"", 0
        for a, b in spans:
            try:
                v = float(data[a:b])
                repl = repr(v * factor).encode() if "." in data[a:b].decode() or rng.random() < 0.5 else data[a:b]
            except (ValueError, OverflowError):
                repl = data[a:b]
            out += data[last:a] + repl
            last = b
        return out + data[last:]
    lines = data.split(b"\n")
    if kind == 4 and len(lines) > 1:  # delete, duplicate or swap lines
        for _ in range(rng.randint(1, 3)):
            i = rng.randrange(len(lines))
            op = rng.randrange(3)
            if op == 0 and len(lines) > 1:
                del lines[i]
            elif op == 1:
                lines.insert(i, lines[rng.randrange(len(lines))])
            else:
                j = rng.randrange(len(lines))
                lines[i], lines[j] = lines[j], lines[i]
        return b"\n".join(lines)
    if kind == 5:  # truncate
        return data[:rng.randrange(len(data) + 1)]
    if kind == 6:  # random bytes
        data = bytearray(data)
        for _ in range(rng.randint(1, 8)):
            if data:
                data[rng.randrange(len(data))] = rng.randrange(256)
        return bytes(data)
    if kind == 7:  # insert junk: a token, a keyword line, an empty face
        junk = rng.choice([b"f", b"f 1/x/1", b"0", b"l 1 2", b"v 1 2 3", b"# comment", b"\x00\xff", b"f 1 1 1",
                           b"<g transform=\"scale(1e300)\">", b"</g>", b"3 0 1 2", b"end_header", b"Vertices\n0",
                           b"facet normal 0 0 0", b"M 0 0 Z", b"\r", b"f -1 -2 -3", b"v nan 0 0"])
        i = rng.randrange(len(lines) + 1)
        lines.insert(i, junk)
        return b"\n".join(lines)
    if kind == 8:  # splice with another corpus file
        other = rng.choice(corpus_bytes)
        a = rng.randrange(len(data) + 1)
        b = rng.randrange(len(other) + 1)
        return data[:a] + other[b:]
    # kind 9: repeat a block (a big but not huge input)
    if not data:
        return data
    a = rng.randrange(len(data))
    b = min(len(data), a + rng.randint(1, 200))
    return data[:b] + data[a:b] * rng.randint(2, 20) + data[b:]


def command_for(rng, path, background):
    """One command family with small, bounded options."""
    family = rng.choice(["check", "cells", "immersions", "mesh", "mesh"])
    if family == "check":
        return ["check", path], []
    if family == "cells":
        return ["cells", path, "--json", "cells.json"], []
    if family == "immersions":
        return ["immersions", path, "--max", "4", "--time-limit", "5", "--json", "imm.json"], []
    args = ["mesh", path, "--time-limit", "5", "-o", "out.mesh", "--embedding", "out.emb", "--json", "mesh.json"]
    if background and rng.random() < 0.2:
        args += ["--background", background]
    else:
        args += ["--resolution", str(rng.choice([1, 2, 3, 5, 8]))]
    return args, ["out.mesh", "out.emb"]


def printable(b):
    return all(c in (9, 10, 13) or 32 <= c < 127 or c >= 128 for c in b)


def run_one(immerse, workdir, name, data, args, outputs, timeout):
    """@return None when the run is fine, else a description of the failure."""
    os.makedirs(workdir, exist_ok=True)
    with open(os.path.join(workdir, name), "wb") as f:
        f.write(data)
    try:
        p = subprocess.run([immerse] + args, cwd=workdir, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           timeout=timeout, start_new_session=True)
    except subprocess.TimeoutExpired:
        return "no answer within %g s (hang?)" % timeout
    problems = []
    if p.returncode < 0:
        problems.append("killed by signal %d" % -p.returncode)
    elif p.returncode not in (0, 2, 3):
        problems.append("exit code %d" % p.returncode)
    left = [e for e in os.listdir(workdir) if ".tmp." in e]
    if left:
        problems.append("temporaries left: %s" % left)
    if p.returncode != 0:
        present = [o for o in outputs if os.path.exists(os.path.join(workdir, o))]
        if present:
            problems.append("outputs present after exit %d: %s" % (p.returncode, present))
    for entry in os.listdir(workdir):
        if entry.endswith(".json"):
            try:
                with open(os.path.join(workdir, entry), "rb") as f:
                    json.loads(f.read().decode("utf-8"))
            except (ValueError, UnicodeDecodeError) as e:
                problems.append("%s is not complete JSON: %s" % (entry, e))
    message = p.stdout + p.stderr
    if len(message) > 64 * 1024:
        problems.append("%d bytes of messages" % len(message))
    # Control bytes only: UTF-8 in an input file's name or a message is fine.
    if not printable(p.stderr):
        problems.append("control bytes in stderr")
    if problems:
        tail = p.stderr[-600:].decode("utf-8", "replace") if p.stderr else ""
        return "; ".join(problems) + ("\n  stderr tail: " + tail if tail else "")
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--immerse", default=os.path.join(root, "build", "app", "immerse"))
    ap.add_argument("--corpus", default=os.path.join(root, "tests", "fuzz", "corpus"))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds per run before it counts as a hang")
    ap.add_argument("--crashes", default=None, help="where failing inputs are saved (default: none saved)")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args()
    a.immerse = os.path.abspath(a.immerse)
    if not os.access(a.immerse, os.X_OK):
        print("fuzz: no immerse binary at %s" % a.immerse, file=sys.stderr)
        return 2
    files = sorted(f for f in os.listdir(a.corpus) if not f.startswith("."))
    corpus = [(f, open(os.path.join(a.corpus, f), "rb").read()) for f in files]
    corpus_bytes = [d for _, d in corpus]
    background = None
    rng = random.Random(a.seed)
    # Every input and command is drawn first, so the set does not depend on --jobs.
    cases = []
    for k in range(a.runs):
        name, data = rng.choice(corpus)
        if name.endswith(".mesh") and name.startswith("background"):
            name, data = corpus[0]
        mutated = data
        for _ in range(rng.randint(1, 3)):
            mutated = mutate(rng, mutated, corpus_bytes)
        input_name = "input" + os.path.splitext(name)[1]
        args, outputs = command_for(rng, input_name, None)
        cases.append((k, name, input_name, mutated, args, outputs))
    base = tempfile.mkdtemp(prefix="imm_fuzz_")
    failures = []
    started = time.time()

    def work(case):
        k, source, input_name, data, args, outputs = case
        wd = os.path.join(base, str(k))
        problem = run_one(a.immerse, wd, input_name, data, args, outputs, a.timeout)
        if problem is None:
            shutil.rmtree(wd, ignore_errors=True)
        return case, problem

    try:
        with ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
            for case, problem in pool.map(work, cases):
                k, source, input_name, data, args, outputs = case
                if problem is None:
                    continue
                failures.append(case)
                print("fuzz: run %d (from %s): immerse %s\n  %s" % (k, source, " ".join(args), problem),
                      file=sys.stderr)
                if a.crashes:
                    os.makedirs(a.crashes, exist_ok=True)
                    stem = os.path.join(a.crashes, "seed%d_run%d" % (a.seed, k))
                    with open(stem + os.path.splitext(input_name)[1], "wb") as f:
                        f.write(data)
                    with open(stem + ".cmd", "w") as f:
                        f.write("immerse " + " ".join(args) + "\n")
    finally:
        shutil.rmtree(base, ignore_errors=True)
    if not a.quiet or failures:
        print("fuzz: %d runs (seed %d) in %.1f s, %d failing" % (a.runs, a.seed, time.time() - started,
                                                                  len(failures)), file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
