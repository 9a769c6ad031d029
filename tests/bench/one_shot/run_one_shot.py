#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""What one `ispq quantize --local` costs a user on a small mesh, with and without its lower bound.

A one-shot run is a whole process: loading the shared libraries, parsing the T-mesh's JSON, the
solve (ISP, the validator and, by default on meshes up to 5000 arcs, the lower bound), writing
the result. For every real T-mesh (every *.tmesh.json under --meshes, by default the
repository's tests/data/tmesh) at every level it runs the CLI in these configurations, in
rotating order so that a noisy machine slows all of them alike:

  default    --ispq with its default bound (auto)
  off        --ispq with --lower-bound off
  baseline   --baseline (another build's ispq, say of an older commit) with --lower-bound off;
             only if given

and records each process's CPU time (user + system, from wait4) and the solve's own seconds and
the bound's from the result's stats. Per instance the median over --repeat runs is kept.

  OUT/one_shot.tsv   per instance and configuration: median process CPU, solve and bound seconds,
                     objective, valid
  OUT/one_shot.md    medians, per-instance ratios (median and quartiles) of process CPU and solve
                     time between the configurations, the bound's share of the solve
  OUT/one_shot.png   the per-instance ratios as cumulative distributions

Exit status 1 if any result is invalid or if one binary's q differs with and without the bound
(the bound must change nothing but the reported bound). Not part of the test command; run on an
otherwise idle machine, e.g.

  tests/bench/one_shot/run_one_shot.py --out /tmp/one_shot
  tests/bench/one_shot/run_one_shot.py --out /tmp/one_shot \
      --baseline /tmp/old/build/release/client/ispq
"""

import argparse
import glob
import json
import os
import statistics
import subprocess
import sys

LEVELS = [0, 1, 5, 10, 17, 25, 50, 100]


def run_once(binary, mesh, level, bound):
    """One process: (CPU seconds, solve seconds, bound seconds, objective, valid, q)."""
    args = [binary, "quantize", mesh, "--local", "--level", str(level), "--lower-bound", bound,
            "--json"]
    process = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    out = process.stdout.read()
    _, status, usage = os.wait4(process.pid, 0)
    code = os.waitstatus_to_exitcode(status)
    if code not in (0, 4):  # client/exit_codes.h: 4 is a result that is not valid (reported)
        raise RuntimeError(f"{' '.join(args)} exited with {code}")
    result = json.loads(out)
    stats = result.get("stats", {})
    return (usage.ru_utime + usage.ru_stime, stats.get("solveSeconds", 0.0),
            stats.get("lowerBoundSeconds", 0.0), result["objective"], result["valid"],
            result["q"])


def measure(configs, meshes, levels, repeat):
    """{(mesh, level): {config: [run, ...]}} with every configuration run `repeat` times."""
    runs = {}
    for mesh in meshes:
        for level in levels:
            per_config = {name: [] for name, _, _ in configs}
            for r in range(repeat):
                for name, binary, bound in configs[r % len(configs):] + configs[:r % len(configs)]:
                    per_config[name].append(run_once(binary, mesh, level, bound))
            runs[(os.path.basename(mesh).removesuffix(".tmesh.json"), level)] = per_config
    return runs


def medians(runs):
    """{instance: {config: (cpu, solve, bound, objective, valid, q)}}, medians of the times."""
    table = {}
    for key, per_config in runs.items():
        table[key] = {}
        for name, rs in per_config.items():
            table[key][name] = tuple(statistics.median(r[i] for r in rs) for i in range(3)) + (
                rs[0][3], all(r[4] for r in rs), rs[0][5])
    return table


def ratios(table, a, b, column):
    """Sorted per-instance ratios a / b of a time column, instances where b's time is > 0."""
    return sorted(row[a][column] / row[b][column] for row in table.values() if row[b][column] > 0)


def describe(values):
    n = len(values)
    return (f"median {statistics.median(values):.3f} (quartiles {values[n // 4]:.3f}-"
            f"{values[3 * n // 4]:.3f}, max {values[-1]:.3f})")


def write_tsv(table, names, path):
    with open(path, "w") as out:
        out.write("mesh\tlevel\tconfig\tcpu_s\tsolve_s\tbound_s\tobjective\tvalid\n")
        for (mesh, level), row in sorted(table.items()):
            for name in names:
                cpu, solve, bound, objective, valid, _ = row[name]
                out.write(f"{mesh}\t{level}\t{name}\t{cpu:.5f}\t{solve:.6f}\t{bound:.6f}\t"
                          f"{objective!r}\t{int(valid)}\n")


def summary(table, names, repeat):
    lines = [f"# One-shot `ispq quantize --local`: {len(table)} instances, each the median of "
             f"{repeat} runs per configuration",
             "", "| configuration | median process CPU (ms) | total (s) | median solve (ms) | "
             "total solve (s) |", "|---|---|---|---|---|"]
    for name in names:
        cpu = [row[name][0] for row in table.values()]
        solve = [row[name][1] for row in table.values()]
        lines.append(f"| {name} | {1000 * statistics.median(cpu):.2f} | {sum(cpu):.2f} | "
                     f"{1000 * statistics.median(solve):.3f} | {sum(solve):.3f} |")
    lines += ["", "Per-instance ratios:", ""]
    for a, b in [("default", "off"), ("default", "baseline"), ("off", "baseline")]:
        if a in names and b in names:
            lines.append(f"- process CPU {a} / {b}: {describe(ratios(table, a, b, 0))}")
            lines.append(f"- solve time {a} / {b}: {describe(ratios(table, a, b, 1))}")
    shares = sorted(row["default"][2] / row["default"][1] for row in table.values()
                    if row["default"][1] > 0)
    lines.append(f"- the bound's share of the default solve: {describe(shares)}")
    return "\n".join(lines) + "\n"


def plot(table, names, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, column, title in [(axes[0], 0, "process CPU"), (axes[1], 1, "solve time")]:
        for a, b in [("default", "off"), ("default", "baseline"), ("off", "baseline")]:
            if a in names and b in names:
                values = ratios(table, a, b, column)
                ax.step(values, [(i + 1) / len(values) for i in range(len(values))],
                        where="post", label=f"{a} / {b}")
        ax.axvline(1.0, color="grey", linewidth=0.8)
        ax.set_xscale("log")
        ax.set_xlabel(f"{title}, ratio per instance")
        ax.set_ylabel("share of instances")
        ax.set_title(f"One-shot ispq quantize --local: {title}")
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def failures(table, names):
    """Invalid results, and instances whose q moved between one binary's two configurations."""
    found = []
    for key, row in sorted(table.items()):
        found += [f"{key} {name}: not valid" for name in names if not row[name][4]]
        if row["default"][5] != row["off"][5]:
            found.append(f"{key}: the default and --lower-bound off gave different q")
    return found


def main():
    root = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../.."))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", required=True)
    parser.add_argument("--ispq", default=os.path.join(root, "build/release/client/ispq"))
    parser.add_argument("--baseline", help="another build's ispq, run with --lower-bound off")
    parser.add_argument("--meshes", default=os.path.join(root, "tests/data/tmesh"))
    parser.add_argument("--levels", default=",".join(map(str, LEVELS)))
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()

    configs = [("default", args.ispq, "auto"), ("off", args.ispq, "off")]
    if args.baseline:
        configs.append(("baseline", args.baseline, "off"))
    names = [name for name, _, _ in configs]
    meshes = sorted(glob.glob(os.path.join(args.meshes, "**/*.tmesh.json"), recursive=True))
    if not meshes:
        sys.exit(f"no *.tmesh.json under {args.meshes}")
    levels = [int(level) for level in args.levels.split(",")]
    table = medians(measure(configs, meshes, levels, args.repeat))

    os.makedirs(args.out, exist_ok=True)
    write_tsv(table, names, os.path.join(args.out, "one_shot.tsv"))
    text = summary(table, names, args.repeat)
    with open(os.path.join(args.out, "one_shot.md"), "w") as out:
        out.write(text)
    plot(table, names, os.path.join(args.out, "one_shot.png"))
    print(text, end="")
    problems = failures(table, names)
    for problem in problems:
        print(problem, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
