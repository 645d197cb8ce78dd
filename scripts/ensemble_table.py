#!/usr/bin/env python3
"""`clothvk-bench contact-ensemble`'s CSV as the figures' CSV (docs/figures/contact-ogc/):

    python3 scripts/ensemble_table.py BENCH.csv [BENCH.csv ...] OUT.csv [--showcases]
    python3 scripts/ensemble_table.py BENCH.csv ... OUT.csv --showcases --labels A,... --label-column NAME
    python3 scripts/ensemble_table.py BENCH.csv ... OUT.csv --solvers NAME,...
    python3 scripts/ensemble_table.py BENCH.csv ... OUT.csv --family NAME [--suffix TEXT]

ensemble.csv's rows name the variant and its settings (and, where a run stopped early, why);
with --showcases (the scenes at their
own settings) a row is a scene, and its note is kept from OUT.csv where the scene had one;
with --labels as well (one label per input), each scene's rows from every input follow one
another, the label in a first column named --label-column.
With --solvers A,B,... (one label per input) the variant rows get a first column, the solver.
With --family (families.csv: one solver family's runs of the showcases) the rows of solver NAME
whose scene ends with TEXT (default: none) are replaced by those of the inputs, named so (a scene
in several inputs: the last input's run); the other rows of OUT.csv stay.
"""
import argparse
import csv
import os


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def common(r):
    frames = "%s of %s" % (r["frames_run"], r["frames"])
    stretch = "%.1f" % (100.0 * float(r["end_max_stretch"]))
    held = r.get("held_fraction", "")  # bench CSVs before the column have none
    held = "%.2f" % (100.0 * float(held)) if held not in ("", "nan") else ""
    return (frames, r["frames_with_pairs"], r["max_pairs"], stretch, held,
            "%.0f" % float(r["step_ms"]))


def family(name, suffix, rows, out):
    header = ["solver", "scene", "frames run", "frames with an intersecting pair",
              "most pairs in a frame", "largest stretch at the end %", "wall ms per frame"]
    kept, at = [], None  # the new rows go where the first replaced row was
    if os.path.exists(out):
        for r in read(out):
            if r["solver"] == name and r["scene"].endswith(suffix) and (suffix or "," not in r["scene"]):
                at = len(kept) if at is None else at
            else:
                kept.append([r[h] for h in header])
    # A scene run again in a later input replaces its row where it first appeared.
    latest = {}
    for r in rows:
        latest[r["scene"]] = r
    new = []
    for scene in dict.fromkeys(r["scene"] for r in rows):
        frames, with_pairs, most, stretch, _held, ms = common(latest[scene])
        new.append([name, scene + suffix, frames, with_pairs, most, stretch, ms])
    with open(out, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        at = len(kept) if at is None else at
        w.writerows(kept[:at] + new + kept[at:])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("inputs", nargs="+")
    ap.add_argument("--showcases", action="store_true")
    ap.add_argument("--family")
    ap.add_argument("--suffix", default="")
    ap.add_argument("--solvers")
    ap.add_argument("--labels")
    ap.add_argument("--label-column", default="run")
    a = ap.parse_args()
    *inputs, out = a.inputs
    runs = [read(path) for path in inputs]
    rows = [r for run in runs for r in run]

    def per_row(option, text):
        """One label per input (option's comma-separated text) as one per row, or []."""
        if not text:
            return []
        labels = text.split(",")
        if len(labels) != len(inputs):
            ap.error("%s: %d labels for %d inputs" % (option, len(labels), len(inputs)))
        return [label for label, run in zip(labels, runs) for _ in run]

    solvers = per_row("--solvers", a.solvers)
    labelled = per_row("--labels", a.labels)
    if a.family:
        family(a.family, a.suffix, rows, out)
        return
    if a.showcases:
        notes = {}
        if os.path.exists(out):
            notes = {r["scene"]: r.get("note", "") for r in read(out)}
        header = ["scene", "frames run", "frames with an intersecting pair",
                  "most pairs in a frame", "largest stretch at the end %",
                  "particle-substeps held at a bound %", "wall ms per frame (loaded)", "note"]
        body = []
        for r in rows:
            note = r["error"] or notes.get(r["scene"], "")
            if int(r["diverged_frame"]) >= 0:
                note = "diverged at frame %s" % r["diverged_frame"]
            body.append([r["scene"], *common(r), note])
        if labelled:
            order = {s: i for i, s in enumerate(dict.fromkeys(r["scene"] for r in rows))}
            body = [[label] + b for label, b in zip(labelled, body)]
            body.sort(key=lambda b: order[b[1]])  # stable: each scene's rows in input order
            header = [a.label_column] + header
            if not any(b[-1] for b in body):  # no run has a note: no note column
                header, body = header[:-1], [b[:-1] for b in body]
    else:
        header = ["scene", "variant", "settings", "frames run",
                  "frames with an intersecting pair", "most pairs in a frame",
                  "largest stretch at the end %", "particle-substeps held at a bound %",
                  "wall ms per frame"]
        body = [[r["scene"], r["variant"], r["settings"], *common(r)] for r in rows]
        if solvers:
            header.insert(0, "solver")
            body = [[label] + b for label, b in zip(solvers, body)]
        # Runs that stopped early say why, in a last column only where one did.
        stops = ["diverged at frame %s" % r["diverged_frame"] if int(r["diverged_frame"]) >= 0
                 else r["error"] for r in rows]
        if any(stops):
            header.append("note")
            body = [b + [note] for b, note in zip(body, stops)]
    with open(out, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        w.writerows(body)


if __name__ == "__main__":
    main()
