#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""The scaling benchmark: ISP on large synthetic T-meshes, from 10^3 to 10^6 arcs.

For every family (large_tmesh_generator.h: single, slabs, rotated with one feature plane each;
assembly16, assembly50, assembly100 with about 0.16, 0.5 and 1.0 critical entities per arc at
every size, assembly_tmesh_generator.h), size and level (5, 25, 100) it generates the mesh once
(cached in OUT/meshes), runs one quantization per process (ispq_scaling_run: CPU time in total and
per phase, LP solves, objective, validity, time and memory at the first separating q, peak memory,
and the mesh's statistics: critical entities and arcs, bundles, subproblems, interior singular
arcs, whether the block frames are global) and writes

  OUT/scaling.tsv       one row per run
  OUT/real_meshes.tsv   the same statistics for every real T-mesh under --real-meshes
  OUT/scaling.md        the table; the statistics of every family beside the real meshes' range
                        (min / median / max); the fitted growth exponents (log-log least squares
                        over the converged runs from 10k arcs up, --fit-range, selected by the
                        size asked of the generator) of the total and of every phase; the largest
                        size solved within 60 s CPU; peak memory per arc
  OUT/scaling.png       log-log plots: CPU time per family and level, per phase, the first
                        separating q as a share of the whole solve, peak memory per arc, critical
                        entities per arc against the real meshes' range

Run by hand (it takes long; not part of the test command), e.g.

  tests/bench/large/run_scaling.py --out /tmp/scaling
  tests/bench/large/run_scaling.py --out /tmp/scaling --sizes 1000,3000,10000 --families single
  tests/bench/large/run_scaling.py --out /tmp/scaling --append --sizes 300000,1000000 \
      --families assembly16,assembly50,assembly100 --time-limit 300 --no-cold-memory

Runs past --time-limit CPU seconds are stopped and recorded with termination time_limit (the
limit is in the time_limit_s column); they are left out of the fits. --append keeps the rows of
OUT/scaling.tsv and runs only the family, size and level combinations it lacks, so that the large
sizes can be run later with their own time limit. --report-only rewrites scaling.md and
scaling.png from OUT/scaling.tsv (and OUT/real_meshes.tsv). --baseline OLD/scaling.tsv adds the
CPU time and objective of every run against the same family, size and level of an earlier run
(say, of the commit before a change).

The real T-meshes are read from --real-meshes (every *.tmesh.json below it; by default the
repository's tests/data/tmesh if it exists); without them the report leaves their column out.
The assembly families' meshes are written with --compact (make_large_tmesh.cc: without the
optional critical entities and translations), since a 10^6-arc mesh in full is over the loader's
256 MiB limit.

Time and memory: each run loads the mesh and solves as `ispq quantize --local` does, reusing the
memory the loader freed (ispq_scaling_run's header says why the solve is not timed on a cold
heap). Peak memory is reported three ways: the loader's (parsing the .pb file into protobuf
messages), the process's while it solves (including what the loader left resident), and the
solve's own, from a second solve after the freed memory went back to the system
(--no-cold-memory skips that solve and its column).
"""

import argparse
import csv
import math
import os
import subprocess
import sys

FAMILIES = ["single", "slabs", "rotated", "assembly16", "assembly50", "assembly100"]
LEVELS = [5, 25, 100]
PHASES = [("cpu_s", "total"), ("greedy_cpu_s", "greedy"), ("search_cpu_s", "separation search"),
          ("separating_cpu_s", "separating updates"), ("layers_cpu_s", "layered start")]
# The mesh statistics (ispq_scaling_run's last columns), as the report names them.
STATS = [("arcs", "arcs", 0), ("entities_per_arc", "critical entities per arc", 3),
         ("critical_arc_share", "critical-arc share", 3), ("bundles", "bundles", 0),
         ("arcs_per_bundle", "arcs per bundle", 1), ("mesh_subproblems", "subproblems", 0),
         ("largest_subproblem_bundles", "largest subproblem (bundles)", 0),
         ("largest_subproblem_share", "largest subproblem's share of the bundles", 2),
         ("interior_singular_arcs", "interior singular arcs", 0),
         ("global_frames", "global block frames (1: per-axis node potentials exist)", 0)]


def seconds(row, key):
    """A CPU column, 0 for rows written before the column existed."""
    return float(row.get(key) or 0)


def first_share(row):
    """Share of the solve's CPU time before the first separating q, or None if none came."""
    first, cpu = float(row["first_separating_cpu_s"]), float(row["cpu_s"])
    return first / cpu if first >= 0 and cpu > 0 else None


def repository_root():
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")


def build_dir():
    return os.path.join(repository_root(), "build", "release", "tests", "bench")


def default_real_meshes():
    path = os.path.normpath(os.path.join(repository_root(), "tests", "data", "tmesh"))
    return path if os.path.isdir(path) else None


def stat(row, key):
    """A statistics column as a number (the largest subproblem's share is derived), None for rows
    written before the statistics existed."""
    if key == "largest_subproblem_share":
        if not row.get("largest_subproblem_bundles"):
            return None
        return float(row["largest_subproblem_bundles"]) / float(row["bundles"])
    return float(row[key]) if row.get(key) else None


def mesh_file(args, family, size):
    path = os.path.join(args.out, "meshes", f"{family}_{size}.tmesh.pb")
    if not os.path.exists(path):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        command = [os.path.join(args.bin, "ispq_make_large_tmesh"), "--family", family,
                   "--arcs", str(size), "--seed", str(args.seed), "--out", path]
        if family.startswith("assembly"):
            command.append("--compact")
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    return path


def run_one(args, path, level):
    command = [os.path.join(args.bin, "ispq_scaling_run"), "--mesh", path, "--level", str(level),
               "--header", "--time_limit", str(args.time_limit)]
    if args.cold_memory:
        command.append("--cold_solve_memory")
    done = subprocess.run(command, capture_output=True, text=True,
                          timeout=max(600, 6 * args.time_limit))
    lines = done.stdout.strip().splitlines()
    if len(lines) != 2:
        raise RuntimeError(f"{' '.join(command)}: {done.stderr.strip()}")
    return {**dict(zip(lines[0].split("\t"), lines[1].split("\t"))),
            "time_limit_s": str(args.time_limit)}


def real_mesh_stats(args, path):
    """Statistics of every real T-mesh under args.real_meshes, written to `path`; the rows kept
    there if no directory is given."""
    if not args.real_meshes:
        return read_rows(path) if os.path.exists(path) else []
    files = sorted(os.path.join(d, f) for d, _, names in os.walk(args.real_meshes)
                   for f in names if f.endswith(".tmesh.json"))
    rows = []
    for f in files:
        done = subprocess.run([os.path.join(args.bin, "ispq_scaling_run"), "--mesh", f,
                               "--stats_only", "--header"],
                              capture_output=True, text=True, check=True)
        header, row = done.stdout.strip().splitlines()
        rows.append({"mesh": os.path.relpath(f, args.real_meshes),
                     **dict(zip(header.split("\t"), row.split("\t")))})
    if rows:
        with open(path, "w") as tsv:
            writer = csv.DictWriter(tsv, fieldnames=list(rows[0]), delimiter="\t")
            writer.writeheader()
            writer.writerows(rows)
    return rows


def fit_exponent(points):
    """Least-squares slope of log(y) over log(x)."""
    points = [(math.log(x), math.log(y)) for x, y in points if x > 0 and y > 0]
    if len(points) < 2:
        return float("nan")
    mx = sum(p[0] for p in points) / len(points)
    my = sum(p[1] for p in points) / len(points)
    sxx = sum((p[0] - mx) ** 2 for p in points)
    sxy = sum((p[0] - mx) * (p[1] - my) for p in points)
    return sxy / sxx if sxx > 0 else float("nan")


def bytes_per_arc(row, key):
    """Bytes per arc of a MiB column, or None where it was not measured (-1) or rows written
    before the column existed."""
    if not row.get(key) or float(row[key]) < 0:
        return None
    return 1024 * 1024 * float(row[key]) / int(row["arcs"])


def cell(value, digits=0):
    return "-" if value is None else f"{value:.{digits}f}"


def stats_cells(r):
    """The mesh statistics of a run's row, as the main table's last four cells."""
    if stat(r, "entities_per_arc") is None:
        return "- | - | - | -"
    return (f"{r['critical_entities']} ({stat(r, 'entities_per_arc'):.3f}) | "
            f"{100 * stat(r, 'critical_arc_share'):.0f}% | "
            f"{r['bundles']} ({stat(r, 'arcs_per_bundle'):.1f}) | "
            f"{r['mesh_subproblems']} ({r['largest_subproblem_bundles']})")


def spread(values, digits):
    """min / median / max."""
    values = sorted(v for v in values if v is not None)
    if not values:
        return "-"
    middle = len(values) // 2
    median = values[middle] if len(values) % 2 else (values[middle - 1] + values[middle]) / 2
    return " / ".join(f"{v:,.{digits}f}" for v in (values[0], median, values[-1]))


def write_statistics(rows, real, out):
    """Every family's mesh statistics over its sizes beside the real meshes'."""
    families = [f for f in FAMILIES if any(r["family"] == f and stat(r, "entities_per_arc")
                                           is not None for r in rows)]
    if not families:
        return
    meshes = {f: {r["target_arcs"]: r for r in rows if r["family"] == f} for f in families}
    out.write("\nMesh statistics, min / median / max over the meshes (`ispq stats --json`, "
              "core/mesh_stats.h; subproblems before the solve):\n\n")
    columns = ([f"real T-meshes ({len(real)})"] if real else []) + \
        [f"{f} ({len(meshes[f])} sizes)" for f in families]
    out.write("| statistic | " + " | ".join(columns) + " |\n")
    out.write("|---|" + "---|" * len(columns) + "\n")
    for key, name, digits in STATS:
        cells = ([spread([stat(r, key) for r in real], digits)] if real else []) + \
            [spread([stat(r, key) for r in meshes[f].values()], digits) for f in families]
        out.write(f"| {name} | " + " | ".join(cells) + " |\n")


def write_markdown(rows, path, fit_range, baseline=None, real=None):
    lo, hi = fit_range
    with open(path, "w") as out:
        out.write("| family | arcs | level | CPU s | greedy | search | separating | layers "
                  "| LP solves | first separating q (CPU s, share, objective / final) "
                  "| objective | valid | peak RSS B/arc: solve's own (cold) | process while "
                  "solving | load | critical entities (per arc) | critical arcs | bundles (arcs "
                  "per bundle) | subproblems (largest, bundles) |\n")
        out.write("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            cpu = float(r["cpu_s"])
            first, share = float(r["first_separating_cpu_s"]), first_share(r)
            first_objective = float(r["first_separating_objective"]) / float(r["objective"]) \
                if float(r["objective"]) > 0 else 1
            first_cell = "-" if share is None else \
                f"{first:.2f} ({100 * share:.0f}%, {first_objective:.2f}x)"
            out.write(f"| {r['family']} | {r['arcs']} | {r['level']} | {cpu:.2f} | "
                      f"{seconds(r, 'greedy_cpu_s'):.2f} | {seconds(r, 'search_cpu_s'):.2f} | "
                      f"{seconds(r, 'separating_cpu_s'):.2f} | {seconds(r, 'layers_cpu_s'):.3f} | "
                      f"{r['lp_solves']} | {first_cell} | "
                      f"{float(r['objective']):.1f} | {r['valid']} {r['termination']} | "
                      f"{cell(bytes_per_arc(r, 'cold_solve_peak_rss_mib'))} | "
                      f"{cell(bytes_per_arc(r, 'peak_rss_mib'))} | "
                      f"{cell(bytes_per_arc(r, 'load_peak_rss_mib'))} | {stats_cells(r)} |\n")
        large = [first_share(r) for r in rows if int(r["arcs"]) >= 10000]
        if large:
            late = sum(s is None or s > 0.1 for s in large)
            worst = max((s for s in large if s is not None), default=float("nan"))
            out.write(f"\nFirst separating q on the {len(large)} runs of 10k arcs or more: at most "
                      f"{100 * worst:.1f}% of the solve's CPU time; {late} runs above 10% "
                      f"(or without one).\n")
        stopped = [r for r in rows if r["termination"] != "converged"]
        if stopped:
            out.write("\nRuns that did not converge (left out of the fits):\n\n")
            for r in stopped:
                limit = f" (limit {float(r['time_limit_s']):g} s)" if r.get("time_limit_s") else ""
                out.write(f"- {r['family']}, {r['arcs']} arcs, level {r['level']}: "
                          f"{r['termination']}{limit} after {float(r['cpu_s']):.1f} s CPU, "
                          f"{r['lp_solves']} LP solves, valid {r['valid']}, objective "
                          f"{float(r['objective']):.1f}\n")
        write_statistics(rows, real or [], out)
        if baseline:
            write_comparison(rows, baseline, out)
        out.write(f"\nGrowth exponents (CPU time ~ arcs^k, fitted over the converged runs from "
                  f"{lo} to {hi} arcs; the sizes column says which):\n\n")
        out.write("| family | level | sizes | " + " | ".join(name for _, name in PHASES) + " |\n")
        out.write("|---|---|---|" + "---|" * len(PHASES) + "\n")
        for family in FAMILIES:
            for level in LEVELS:
                # By the size asked of the generator: a 10^6-arc mesh may have a few more arcs.
                sel = [r for r in rows if r["family"] == family and int(r["level"]) == level
                       and lo <= int(r.get("target_arcs") or r["arcs"]) <= hi
                       and r["termination"] == "converged"]
                if not sel:
                    continue
                ks = [fit_exponent([(int(r["arcs"]), seconds(r, key)) for r in sel])
                      for key, _ in PHASES]
                arcs = sorted(int(r["arcs"]) for r in sel)
                sizes = f"{arcs[0]}-{arcs[-1]} ({len(arcs)})"
                out.write(f"| {family} | {level} | {sizes} | " +
                          " | ".join(f"{k:.2f}" for k in ks) + " |\n")
        out.write("\nLargest mesh solved within 60 s CPU, per family and level:\n\n")
        for family in FAMILIES:
            for level in LEVELS:
                ok = [int(r["arcs"]) for r in rows if r["family"] == family and
                      int(r["level"]) == level and float(r["cpu_s"]) <= 60 and
                      r["termination"] == "converged"]
                if ok:
                    out.write(f"- {family}, level {level}: {max(ok)} arcs\n")


def write_comparison(rows, baseline, out):
    """CPU and objective of every run against the same family, size and level in `baseline`."""
    before = {(r["family"], r["arcs"], r["level"]): r for r in baseline}
    out.write("\nAgainst the baseline (same meshes; objective ratio after / before):\n\n")
    out.write("| family | arcs | level | CPU s before | CPU s after | first separating q before "
              "| after | objective ratio |\n")
    out.write("|---|---|---|---|---|---|---|---|\n")
    ratios = []
    for r in rows:
        b = before.get((r["family"], r["arcs"], r["level"]))
        if b is None:
            continue
        ratio = float(r["objective"]) / float(b["objective"])
        ratios.append(ratio)
        out.write(f"| {r['family']} | {r['arcs']} | {r['level']} | {float(b['cpu_s']):.2f} | "
                  f"{float(r['cpu_s']):.2f} | {float(b['first_separating_cpu_s']):.2f} | "
                  f"{float(r['first_separating_cpu_s']):.2f} | {ratio:.5f} |\n")
    if ratios:
        worse = sum(x > 1 + 1e-9 for x in ratios)
        better = sum(x < 1 - 1e-9 for x in ratios)
        out.write(f"\n{len(ratios)} runs compared: mean objective ratio "
                  f"{sum(ratios) / len(ratios):.5f}, {worse} worse, {better} better, "
                  f"worst {max(ratios):.5f}\n")


def plot(rows, path, real=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, 3, figsize=(18, 9))
    colors = {"single": "tab:blue", "slabs": "tab:orange", "rotated": "tab:green",
              "assembly16": "tab:red", "assembly50": "tab:purple", "assembly100": "tab:brown"}
    styles = {5: ":", 25: "--", 100: "-"}
    ax = axes[0][0]
    for family in FAMILIES:
        for level in LEVELS:
            sel = sorted((int(r["arcs"]), float(r["cpu_s"])) for r in rows
                         if r["family"] == family and int(r["level"]) == level)
            if sel:
                ax.plot(*zip(*sel), styles[level], marker="o", color=colors[family],
                        label=f"{family} L{level}")
    ax.set_title("CPU time of the whole solve")
    for ax, family in [(axes[0][1], "single"), (axes[0][2], "assembly50")]:
        for key, name in PHASES[1:]:
            sel = sorted((int(r["arcs"]), max(seconds(r, key), 1e-4)) for r in rows
                         if r["family"] == family and int(r["level"]) == 100)
            if sel:
                ax.plot(*zip(*sel), marker="o", label=name)
        ax.set_title(f"CPU time per phase ({family}, level 100)")
    ax = axes[1][0]
    for family in FAMILIES:
        for level in LEVELS:
            sel = sorted((int(r["arcs"]), 100 * first_share(r)) for r in rows
                         if r["family"] == family and int(r["level"]) == level and
                         first_share(r))
            if sel:
                ax.plot(*zip(*sel), styles[level], marker="s", color=colors[family],
                        label=f"{family} L{level}")
    ax.axhline(10, color="gray", linewidth=1)
    ax.set_title("First separating q, % of the solve's CPU time")
    ax = axes[1][1]
    for family in FAMILIES:
        for key, style, marker, what in [("cold_solve_peak_rss_mib", "-", "o", "solve's own"),
                                         ("peak_rss_mib", "--", "s", "while solving"),
                                         ("load_peak_rss_mib", ":", "x", "load")]:
            sel = sorted((int(r["arcs"]), bytes_per_arc(r, key)) for r in rows
                         if r["family"] == family and int(r["level"]) == 100 and
                         bytes_per_arc(r, key) is not None)
            if sel:
                ax.plot(*zip(*sel), style, marker=marker, color=colors[family],
                        label=f"{family}: {what}")
    ax.set_title("Peak RSS per arc, bytes (level 100)")
    ax = axes[1][2]
    if real:
        density = sorted(stat(r, "entities_per_arc") for r in real)
        ax.axhspan(density[0], density[-1], color="gray", alpha=0.15,
                   label=f"real T-meshes ({len(real)}): range")
        ax.axhline(density[len(density) // 2], color="gray", linewidth=1, label="real: median")
    for family in FAMILIES:
        sel = sorted({(int(r["arcs"]), stat(r, "entities_per_arc")) for r in rows
                      if r["family"] == family and stat(r, "entities_per_arc") is not None})
        if sel:
            ax.plot(*zip(*sel), marker="o", color=colors[family], label=family)
    ax.set_title("Critical entities per arc")
    for row in axes:
        for ax in row:
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("arcs")
            ax.grid(True, which="both", alpha=0.3)
            if ax.get_legend_handles_labels()[0]:
                ax.legend(fontsize=7)
    axes[1][0].set_yscale("linear")
    axes[1][0].set_ylim(0, 100)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True)
    parser.add_argument("--bin", default=build_dir())
    parser.add_argument("--sizes", default="1000,3000,10000,30000,100000")
    parser.add_argument("--families", default=",".join(FAMILIES))
    parser.add_argument("--levels", default=",".join(map(str, LEVELS)))
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--time-limit", type=float, default=900)
    parser.add_argument("--fit-range", default="10000,1000000",
                        help="arcs: the converged runs in this range are fitted")
    parser.add_argument("--report-only", action="store_true")
    parser.add_argument("--append", action="store_true",
                        help="keep OUT/scaling.tsv and run only what it lacks")
    parser.add_argument("--baseline", help="scaling.tsv of an earlier run to compare against")
    parser.add_argument("--real-meshes", default=default_real_meshes(),
                        help="folder of the real *.tmesh.json files to set the families beside")
    parser.add_argument("--no-cold-memory", dest="cold_memory", action="store_false",
                        help="skip the second solve that measures the solve's own peak memory")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    tsv_path = os.path.join(args.out, "scaling.tsv")
    rows = read_rows(tsv_path) if args.report_only else run_all(args, tsv_path)
    real = real_mesh_stats(args, os.path.join(args.out, "real_meshes.tsv"))
    fit_range = tuple(map(int, args.fit_range.split(",")))
    baseline = read_rows(args.baseline) if args.baseline else None
    write_markdown(rows, os.path.join(args.out, "scaling.md"), fit_range, baseline, real)
    plot(rows, os.path.join(args.out, "scaling.png"), real)
    return 0 if all(r["valid"] == "1" for r in rows) else 1


def read_rows(tsv_path):
    with open(tsv_path) as tsv:
        return list(csv.DictReader(tsv, delimiter="\t"))


def run_all(args, tsv_path):
    rows = read_rows(tsv_path) if args.append and os.path.exists(tsv_path) else []
    done = {(r["family"], int(r["target_arcs"]), int(r["level"])) for r in rows}
    fields = list(rows[0]) if rows else None
    for family in args.families.split(","):
        for size in map(int, args.sizes.split(",")):
            levels = [level for level in map(int, args.levels.split(","))
                      if (family, size, level) not in done]
            if not levels:
                continue
            path = mesh_file(args, family, size)
            for level in levels:
                row = {"family": family, "target_arcs": size, **run_one(args, path, level)}
                rows.append(row)
                # Rows written before a column existed get it empty (DictWriter's restval).
                fields = fields or list(row)
                fields += [key for key in row if key not in fields]
                with open(tsv_path, "w") as tsv:
                    writer = csv.DictWriter(tsv, fieldnames=fields, delimiter="\t")
                    writer.writeheader()
                    writer.writerows(rows)
                print(f"{family} {row['arcs']} arcs L{level}: {float(row['cpu_s']):.2f} s CPU, "
                      f"valid {row['valid']}, {row['termination']}", flush=True)
    return rows


if __name__ == "__main__":
    sys.exit(main())
