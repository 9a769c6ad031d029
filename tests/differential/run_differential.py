#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Differential testing of ispq's validator against the upstream implementation's own checks.

For every T-mesh given, ispq_differential_instances writes many quantizations (ISP results at
the 8 levels and at random scalings, ISP's intermediate iterates, random consistent
perturbations, the layered q of core/isp/parametric_layers.h). Each q is then judged three times:

  ours      the product's verdict (ispq_separation_dump: consistency, simple rows, both searches)
  ours_ref  our search in reference-compatibility mode alone (unsorted block boxes)
  upstream  `oracle validate` (the upstream oracle, see below): upstream's consistency,
            block-extent, simple and separation checks, run by upstream's own code

and every disagreement is classified:

  FALSE_VALID     ours says valid, upstream finds a violation (a wrong certificate: must be 0)
  STRICTER        ours says invalid, upstream says valid (our sorted search sees more: allowed)
  REF_ROWS        ours_ref and upstream both ran the search but found different row sets
  SIMPLE          consistency / extent / link / region verdicts differ
and written to a TSV (one row per q) and a summary.

With --compare-isp it also runs upstream's ISP (`oracle isp`) at every scaling of the final q
and writes quality.tsv: both objectives, their ratio, and whether each side's q passes the other
side's checks.

A documented by-hand tool, and the one part of the repository that uses things outside the
checkout: the oracle is a small driver over the upstream research code (QGP3D a88370f, MC3D
c492ebd) that is built apart from this repository (in the development setup it lives in
../shared/oracle, beside the checkout) from upstream's sources, which are not Debian packages,
and it rebuilds each motorcycle complex from MC3D-samples' .hexex files, which are not bundled
either. So CI cannot run it, the test command does not, and the check that nothing refers
outside the checkout (tests/deploy/check_standalone.py) exempts this folder. Run it by hand,
e.g. on the bundled real set:

  tests/differential/run_differential.py --oracle ~/oracle/oracle \\
      --samples ~/oracle/src --out /tmp/diff tests/data/tmesh/*/*.tmesh.json
  tests/differential/run_differential.py --oracle ~/oracle/oracle --out /tmp/diff-ext \\
      --hexex-dir ~/oracle/src/MC3D/tests/resources ~/ext/*.tmesh.json

--hexex-dir names where the .hexex of a T-mesh exported from outside MC3D-samples lives
(<dir>/<name>.hexex); files of the real set find theirs through --samples.
"""

import argparse
import collections
import concurrent.futures
import json
import os
import re
import subprocess
import sys
import tempfile

ROW_PATTERN = re.compile(r"separation violated: (.*) >= 1 \(is (-?\d+)\)")
TERM_PATTERN = re.compile(r"([+-])(\d*)q(\d+)")


def canonical_row(terms):
    """A row as a hashable, order-free value: sorted (arc, coefficient) pairs."""
    return tuple(sorted((arc, coef) for coef, arc in terms))


def parse_upstream_row(text):
    terms = []
    for sign, magnitude, arc in TERM_PATTERN.findall(text):
        coef = int(magnitude) if magnitude else 1
        terms.append((coef if sign == "+" else -coef, int(arc)))
    return canonical_row(terms)


def run_ours(tool, tmesh, q_path, reference_only):
    args = [tool, "--tmesh", tmesh, "--q", q_path]
    if reference_only:
        args.append("--reference_block_boxes")
    done = subprocess.run(args, capture_output=True, text=True, timeout=600)
    if done.returncode not in (0, 1):
        raise RuntimeError(f"{' '.join(args)}: {done.stderr.strip()}")
    lines = [json.loads(line) for line in done.stdout.splitlines() if line.strip()]
    head, violations = lines[0], lines[1:]
    return {
        "valid": head["valid"],
        "simple_ok": head["consistent"] and head["simple_violations"] == 0,
        "searched": head["separation_checked"],
        "rows": {canonical_row(v["default"]) for v in violations},
        "starts": [(v["start"], v["entity"], v["sector"], v["target"], v["target_id"])
                   for v in violations],
    }


def run_upstream(oracle, tmesh, q_path, scaling, samples, hexex):
    args = [oracle, "validate", "--tmesh", tmesh, "--q", q_path, "--scaling", repr(scaling),
            "--all-violations"]
    if hexex:
        args += ["--hexex", hexex]
    elif samples:
        args += ["--samples", samples]
    done = subprocess.run(args, capture_output=True, text=True, timeout=1800)
    if done.returncode not in (0, 1):
        raise RuntimeError(f"{' '.join(args)}: {done.stdout.strip()} {done.stderr.strip()[-500:]}")
    verdict = json.loads(done.stdout.strip().splitlines()[-1])
    rows = set()
    for text in verdict["violations"]:
        match = ROW_PATTERN.match(text)
        if match:
            rows.add(parse_upstream_row(match.group(1)))
    return {
        "valid": verdict["valid"],
        "simple_ok": verdict["consistent"] and verdict["nonnegative"] and verdict["simple"],
        "rows": rows,
        "objective": verdict["objective"],
    }


def classify(ours, ours_ref, upstream):
    classes = []
    if ours["valid"] and not upstream["valid"]:
        classes.append("FALSE_VALID")
    if not ours["valid"] and upstream["valid"]:
        classes.append("STRICTER")
    if ours["simple_ok"] != upstream["simple_ok"]:
        classes.append("SIMPLE")
    elif ours_ref["searched"] and ours_ref["rows"] != upstream["rows"]:
        classes.append("REF_ROWS")
    return classes


def judge(task):
    index, instance, tmesh, args, hexex, workdir = task
    q_path = os.path.join(workdir, f"q{index}.json")
    with open(q_path, "w") as out:
        json.dump({"q": instance["q"]}, out)
    ours = run_ours(args.ours, tmesh, q_path, False)
    ours_ref = run_ours(args.ours, tmesh, q_path, True)
    upstream = run_upstream(args.oracle, tmesh, q_path, instance["scaling"], args.samples, hexex)
    os.remove(q_path)
    return index, ours, ours_ref, upstream


def objective(q, lengths, scaling):
    return sum((x - scaling * length) ** 2 for x, length in zip(q, lengths))


def upstream_isp(task):
    """Upstream ISP at one scaling: its q, judged by our validator too."""
    tmesh, scaling, args, hexex, workdir, tag = task
    q_path = os.path.join(workdir, f"isp-{tag}.json")
    command = [args.oracle, "isp", "--tmesh", tmesh, "--scaling", repr(scaling), "--out", q_path]
    if hexex:
        command += ["--hexex", hexex]
    elif args.samples:
        command += ["--samples", args.samples]
    done = subprocess.run(command, capture_output=True, text=True, timeout=3600)
    if done.returncode != 0 or not os.path.exists(q_path):
        raise RuntimeError(f"{' '.join(command)}: {done.stdout.strip()} {done.stderr[-500:]}")
    with open(q_path) as f:
        q = json.load(f)["q"]
    ours = run_ours(args.ours, tmesh, q_path, False)
    os.remove(q_path)
    return scaling, q, ours["valid"]


def compare_isp(args, tmesh, model, instances, hexex, workdir, out):
    with open(tmesh) as f:
        lengths = [arc["length"] for arc in json.load(f)["arcs"]]
    finals = [inst for inst in instances if inst["kind"] == "final"]
    tasks = [(tmesh, inst["scaling"], args, hexex, workdir, f"{model}-{i}")
             for i, inst in enumerate(finals)]
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        upstream = list(pool.map(upstream_isp, tasks))
    ratios = []
    for inst, (scaling, q_up, up_valid_by_ours) in zip(finals, upstream):
        ours = objective(inst["q"], lengths, scaling)
        theirs = objective(q_up, lengths, scaling)
        ratio = ours / theirs if theirs > 0 else (1.0 if ours == 0 else float("inf"))
        ratios.append(ratio)
        out.write(f"{model}\t{scaling!r}\t{ours!r}\t{theirs!r}\t{ratio:.6f}\t"
                  f"{int(up_valid_by_ours)}\n")
    out.flush()
    return ratios


def instances_of(args, tmesh):
    done = subprocess.run(
        [args.instances, "--tmesh", tmesh, "--random_scalings", str(args.random_scalings),
         "--intermediate_stride", str(args.stride), "--perturbations", str(args.perturbations),
         "--seed", str(args.seed)],
        capture_output=True, text=True, check=True)
    return [json.loads(line) for line in done.stdout.splitlines() if line.strip()]


def main():
    build = os.path.join(os.path.dirname(__file__), "..", "..", "build", "release", "tests",
                         "differential")
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("tmesh", nargs="+")
    parser.add_argument("--oracle", required=True,
                        help="the upstream oracle's driver (built outside the repository)")
    parser.add_argument("--samples", help="folder containing MC3D-samples/ (real set)")
    parser.add_argument("--hexex-dir", help="folder of <name>.hexex for other T-meshes")
    parser.add_argument("--ours", default=os.path.join(build, "ispq_separation_dump"))
    parser.add_argument("--instances", default=os.path.join(build, "ispq_differential_instances"))
    parser.add_argument("--random-scalings", type=int, default=20)
    parser.add_argument("--stride", type=int, default=10)
    parser.add_argument("--perturbations", type=int, default=2)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", required=True, help="output folder (TSV, summary, cases)")
    parser.add_argument("--compare-isp", action="store_true",
                        help="also run upstream's ISP at every scaling and compare objectives")
    args = parser.parse_args()

    os.makedirs(os.path.join(args.out, "cases"), exist_ok=True)
    tsv = open(os.path.join(args.out, "differential.tsv"), "w")
    tsv.write("model\tindex\tkind\tscaling\tours_valid\tours_ref_valid\tupstream_valid\t"
              "ours_ref_rows\tupstream_rows\tclasses\n")
    counts = collections.Counter()
    per_kind = collections.Counter()
    workdir = tempfile.mkdtemp(prefix="ispq-diff-")
    quality = None
    ratios = {}
    if args.compare_isp:
        quality = open(os.path.join(args.out, "quality.tsv"), "w")
        quality.write("model\tscaling\tours\tupstream_isp\tratio\tupstream_q_valid_by_ours\n")
    for tmesh in args.tmesh:
        model = os.path.basename(tmesh).removesuffix(".tmesh.json")
        hexex = None
        if args.hexex_dir and os.path.exists(os.path.join(args.hexex_dir, model + ".hexex")):
            hexex = os.path.join(args.hexex_dir, model + ".hexex")
        instances = instances_of(args, tmesh)
        tasks = [(i, inst, tmesh, args, hexex, workdir) for i, inst in enumerate(instances)]
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            results = sorted(pool.map(judge, tasks), key=lambda r: r[0])
        for index, ours, ours_ref, upstream in results:
            instance = instances[index]
            classes = classify(ours, ours_ref, upstream)
            per_kind[instance["kind"]] += 1
            counts["instances"] += 1
            counts["upstream_invalid"] += not upstream["valid"]
            for c in classes:
                counts[c] += 1
            if classes:
                case = os.path.join(args.out, "cases", f"{model}-{index}.json")
                with open(case, "w") as out:
                    json.dump({"tmesh": tmesh, "kind": instance["kind"],
                               "scaling": instance["scaling"], "q": instance["q"],
                               "classes": classes,
                               "ours_ref_only": sorted(ours_ref["rows"] - upstream["rows"]),
                               "upstream_only": sorted(upstream["rows"] - ours_ref["rows"]),
                               "ours_starts": ours["starts"]}, out)
            tsv.write(f"{model}\t{index}\t{instance['kind']}\t{instance['scaling']!r}\t"
                      f"{int(ours['valid'])}\t{int(ours_ref['valid'])}\t{int(upstream['valid'])}\t"
                      f"{len(ours_ref['rows'])}\t{len(upstream['rows'])}\t{','.join(classes)}\n")
        tsv.flush()
        if quality:
            ratios[model] = compare_isp(args, tmesh, model, instances, hexex, workdir, quality)
            print(f"{model}: mean objective ratio to upstream ISP "
                  f"{sum(ratios[model]) / len(ratios[model]):.4f}", flush=True)
        print(f"{model}: {len(instances)} q, classes so far {dict(counts)}", flush=True)
    summary = {"per_kind": dict(per_kind), "counts": dict(counts)}
    if ratios:
        every = [r for model_ratios in ratios.values() for r in model_ratios]
        summary["isp_ratio"] = {"instances": len(every), "mean": sum(every) / len(every),
                                "max": max(every),
                                "worse": sum(r > 1 + 1e-9 for r in every),
                                "better": sum(r < 1 - 1e-9 for r in every)}
    with open(os.path.join(args.out, "summary.json"), "w") as out:
        json.dump(summary, out, indent=1)
    print(json.dumps(summary, indent=1))
    return 1 if counts["FALSE_VALID"] else 0


if __name__ == "__main__":
    sys.exit(main())
