#!/usr/bin/env python3
"""Tries every option of every subcommand with values a user might mistype,
and classifies what the program did (issue 21's "a few hundred bad inputs").

The options come from each subcommand's own --help, so a new option is swept
without editing this file. Each run starts from a small valid command (BASE
below) and replaces or adds one option's value. Outcomes:

  refused   non-zero exit below 128 with a message of our own
  accepted  exit 0: listed for review (a value may be legitimate: seed 0)
  vague     refused, but with a library's words or no message
  crash     a signal, or an uncaught exception
  hang      still running after the timeout

Usage: tools/experiments/option_sweep.py [--nuld build/nuld] [--timeout 60]
           [--csv out.csv]
"""

import argparse
import collections
import csv
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data" / "bad_inputs"
MODEL = ROOT / "tests" / "fuzz" / "corpus" / "model_file" / "graph.nuldnet"

# A small valid command per subcommand; {T} is a scratch folder, {D} the
# bad-input data folder.
BASE = {
    "generate": "generate --sequence sobol --n 16 --instances 2 -o {T}/g.txt",
    "map": "map {D}/valid.txt --target quarterdisc -o {T}/m.txt",
    "eval": "eval {D}/valid.txt",
    "optimize": "optimize --target quarterdisc --n 16 --epochs 4 -q -o {T}/o.txt",
    "train": "train --target family:gaussian --n 8 --hidden 8 --steps 2 --batch 2 "
             "--boxes 64 -q -o {T}/t.nuldnet",
    "plot": "plot {D}/valid.txt -o {T}/p.png",
    "spectrum": "spectrum {D}/valid.txt -o {T}/s.png",
    "render": "render default --res 8 --spp 1 -q -o {T}/r.exr",
    "compare": "compare {T}/ref.exr {T}/ref.exr",
    "study integrate": "study integrate --integrands gaussian*step --samplers sobol --n 16 "
                       "--instances 4 --no-plots -q -o {T}/si",
    "study render": "study render default --backends sobol --spp 2 --reference-spp 8 --res 8 "
                    "--no-report -q -o {T}/sr",
}

# Values by the option's type in --help.
NUMERIC_BAD = ["-1", "0", "1e308", "nan", "inf", "abc", "1.5", ""]
TEXT_BAD = ["", "abc", "-1", "/nonexistent/x"]

# Options not swept: output names (their checks are the corpus's), help.
SKIP = {"-h", "--help", "--help-all", "-o", "--output", "--resume", "-q", "--quiet"}


def options_of(nuld, sub):
    """(option, kind) for each option of the subcommand's --help."""
    text = subprocess.run([nuld, *sub.split(), "--help"], capture_output=True, text=True).stdout
    found = []
    for line in text.splitlines():
        m = re.match(r"\s+((?:-\w,)?--[\w-]+)\s*(\S*)", line)
        if not m:
            continue
        name = m.group(1).split(",")[-1]
        kind = m.group(2)
        if name in SKIP or not re.match(r"(TEXT|INT|UINT|FLOAT)\b", kind):
            continue  # a flag, or an option this sweep leaves to the corpus
        numeric = any(t in kind for t in ("INT", "UINT", "FLOAT", "NUMBER"))
        found.append((name, "numeric" if numeric else "text"))
    return found


def with_option(base, option, value):
    words = base.split()
    if option in words:
        i = words.index(option)
        words[i + 1] = value
    else:
        words += [option, value]
    return words


def classify(rc, stderr):
    if rc is None:
        return "hang"
    if rc >= 128 or rc < 0 or "terminate called" in stderr or "what():" in stderr:
        return "crash"
    if rc == 0:
        return "accepted"
    library = ("std::", "OpenImageIO", "json.exception", "basic_string", "stoi", "stod")
    if not stderr.strip() or any(w in stderr for w in library):
        return "vague"
    return "refused"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nuld", default=str(ROOT / "build" / "nuld"))
    parser.add_argument("--timeout", type=float, default=60)
    parser.add_argument("--csv", help="write every run as CSV")
    args = parser.parse_args()

    tmp = pathlib.Path(tempfile.mkdtemp(prefix="nuld_sweep_"))
    subprocess.run([args.nuld, "render", "default", "--res", "8", "--spp", "1", "-q", "-o",
                    str(tmp / "ref.exr")], check=True, capture_output=True)
    rows = []
    counts = collections.defaultdict(collections.Counter)
    for sub, base in BASE.items():
        base = base.format(T=tmp, D=DATA)
        for option, kind in options_of(args.nuld, sub):
            for value in NUMERIC_BAD if kind == "numeric" else TEXT_BAD:
                words = with_option(base, option, value)
                try:
                    p = subprocess.run([args.nuld, *words], capture_output=True, text=True,
                                       timeout=args.timeout, cwd=tmp)
                    rc, err = p.returncode, p.stderr
                except subprocess.TimeoutExpired:
                    rc, err = None, ""
                outcome = classify(rc, err)
                counts[sub][outcome] += 1
                message = err.strip().splitlines()[0] if err.strip() else ""
                rows.append((sub, option, value, outcome, rc, message))
                if outcome != "refused":
                    print(f"{outcome:8} nuld {sub} {option} {value!r}: {message[:150]}",
                          flush=True)
    shutil.rmtree(tmp, ignore_errors=True)

    print(f"\n{'subcommand':16} {'tried':>6} {'refused':>8} {'accepted':>9} {'vague':>6} "
          f"{'crash':>6} {'hang':>5}")
    total = collections.Counter()
    for sub in BASE:
        c = counts[sub]
        total.update(c)
        print(f"{sub:16} {sum(c.values()):6} {c['refused']:8} {c['accepted']:9} {c['vague']:6} "
              f"{c['crash']:6} {c['hang']:5}")
    print(f"{'all':16} {sum(total.values()):6} {total['refused']:8} {total['accepted']:9} "
          f"{total['vague']:6} {total['crash']:6} {total['hang']:5}")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["subcommand", "option", "value", "outcome", "exit", "message"])
            w.writerows(rows)
    return 1 if total["crash"] or total["hang"] else 0


if __name__ == "__main__":
    sys.exit(main())
