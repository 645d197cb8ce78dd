#!/usr/bin/env python3
"""Regenerates every measured table and plot in docs/ from the CSV files under docs/figures/.

    python3 scripts/figures.py            # rewrite the tables and the plots
    python3 scripts/figures.py --check    # exit 1 if a table or plot is not what the CSVs give
    python3 scripts/figures.py --no-plots # tables only

Tables live in docs/*.md between two markers, and everything between them is generated:

    <!-- figures:begin NAME -->
    <!-- figures:end NAME -->

NAME is either "FOLDER/FILE" — docs/figures/FOLDER/FILE.csv printed as it is, one column per CSV
column, where a column "X min" followed by "X max" becomes one column "X" of ranges and an empty
cell prints as a dash — or "FOLDER:VIEW", one of the views below that condense a clothvk-bench
CSV (a pivot, a Pareto front, a stability limit).

Plots: every docs/figures/*/*.gp is run by gnuplot in its own folder (clothvk-bench writes these
scripts beside its CSVs); the PNG is replaced only when its bytes change. Without gnuplot the
plots are left as they are and one line says so. Standard library only.
"""
import argparse
import csv
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
FIGURES = DOCS / "figures"
BLOCK = re.compile(r"(<!-- figures:begin (?P<name>[^ ]+) -->\n)(?P<body>.*?)(<!-- figures:end (?P=name) -->)",
                   re.S)


class FigureError(Exception):
    pass


# ------------------------------------------------------------------------------------------
# Reading and formatting
# ------------------------------------------------------------------------------------------

def read_csv(folder, stem):
    path = FIGURES / folder / f"{stem}.csv"
    if not path.is_file():
        raise FigureError(f"{path.relative_to(ROOT)}: no such file")
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise FigureError(f"{path.relative_to(ROOT)}: empty")
    return rows[0], rows[1:]


def read_dicts(folder, stem):
    header, rows = read_csv(folder, stem)
    return [dict(zip(header, r)) for r in rows]


def num(text):
    try:
        value = float(text)
    except (TypeError, ValueError):
        return math.nan
    return value


def sig(value, digits=3):
    """A number to `digits` significant digits, the way the docs write it: 0.0518, 1.83e-7,
    6,550."""
    if value is None or math.isnan(value):
        return "—"
    if value == 0:
        return "0"
    if abs(value) >= 10 ** digits:
        return f"{round(value):,}"
    text = f"{value:.{digits}g}"
    if "e" in text:
        mantissa, exponent = text.split("e")
        return f"{mantissa}e{int(exponent)}"
    return text


def ms_or_s(ms):
    return f"{sig(ms / 1000)} s" if ms >= 1000 else f"{sig(ms)} ms"


def seconds(value):
    """A step length in s as ms or µs."""
    if value >= 1e-3:
        return f"{sig(value * 1e3)} ms"
    return f"{sig(value * 1e6)} µs"


def label_name(label):
    """clothvk-bench's solver labels as the docs write them."""
    if ":" in label:
        name, omega = label.split(":", 1)
        return f"{name} ω={omega}"
    return label


def cell(text):
    text = text.strip()
    return text.replace("|", "\\|") if text else "—"


def markdown(header, rows):
    lines = ["| " + " | ".join(cell(h) for h in header) + " |",
             "| " + " | ".join("---" for _ in header) + " |"]
    for r in rows:
        lines.append("| " + " | ".join(cell(c) for c in r) + " |")
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------------------------------
# A CSV printed as it is
# ------------------------------------------------------------------------------------------

def plain_table(folder, stem):
    header, rows = read_csv(folder, stem)
    columns = []  # (title, index, index of the max or None)
    i = 0
    while i < len(header):
        name = header[i]
        if name.startswith("_"):
            i += 1
            continue
        if name.endswith(" min") and i + 1 < len(header) and header[i + 1] == name[:-4] + " max":
            columns.append((name[:-4], i, i + 1))
            i += 2
            continue
        columns.append((name, i, None))
        i += 1
    out = []
    for n, r in enumerate(rows, start=2):
        if len(r) != len(header):
            raise FigureError(f"docs/figures/{folder}/{stem}.csv line {n}: {len(r)} fields, "
                              f"the header has {len(header)}")
        line = []
        for _, a, b in columns:
            low = r[a].strip()
            if b is None:
                line.append(low)
                continue
            high = r[b].strip()
            line.append(low if not high or high == low else f"{low}–{high}")
        out.append(line)
    return markdown([c[0] for c in columns], out)


# ------------------------------------------------------------------------------------------
# Views of clothvk-bench's CSVs
# ------------------------------------------------------------------------------------------

def budget_view(folder):
    rows = read_dicts(folder, "budget")
    labels = list(dict.fromkeys(r["label"] for r in rows))
    budgets = sorted({num(r["budget_ms"]) for r in rows})
    seeds = {"jacobi": "seed: Jacobi", "rbgs": "seed: RBGS", "gs-cpu": "seed: GS"}
    header = ["budget"] + [label_name(l) for l in labels] + [seeds[l] for l in seeds if l in labels]
    out = []
    for b in budgets:
        at = {r["label"]: r for r in rows if num(r["budget_ms"]) == b}
        line = [f"{sig(b)} ms"] + [at[l]["iterations"] if l in at else "" for l in labels]
        line += [sig(num(at[l]["seed_002_gtx970"])) if l in at else "" for l in seeds if l in labels]
        out.append(line)
    return markdown(header, out)


def budget_cost_view(folder):
    rows = read_dicts(folder, "budget")
    out = []
    for label in dict.fromkeys(r["label"] for r in rows):
        mine = [r for r in rows if r["label"] == label]
        last = max(mine, key=lambda r: num(r["budget_ms"]))
        start = num(last["residual"]) / num(last["residual_relative"])
        out.append([label_name(label), sig(num(last["ms_per_iteration"])),
                    sig(start), f"{sig(num(last['residual']))} (in {sig(num(last['budget_ms']))} ms)"])
    return markdown(["solver", "ms per sweep (with its local step)", "residual at the start (m²)",
                     "residual reached"], out)


CONVERGENCE_KS = [1, 10, 100, 1000, 10000]


def convergence_view(folder, column, title):
    rows = read_dicts(folder, "convergence")
    labels = list(dict.fromkeys(r["label"] for r in rows))
    out = []
    for label in labels:
        by_k = {int(num(r["iterations"])): r for r in rows if r["label"] == label}
        out.append([label_name(label)] + [sig(num(by_k[k][column])) if k in by_k else "" for k in CONVERGENCE_KS])
    return markdown([title] + [f"k = {k}" for k in CONVERGENCE_KS], out)


def convergence_targets_view(folder):
    rows = read_dicts(folder, "convergence")
    out = []
    found = {}
    for label in dict.fromkeys(r["label"] for r in rows):
        mine = sorted((r for r in rows if r["label"] == label), key=lambda r: num(r["iterations"]))
        first = lambda col: next((int(num(r["iterations"])) for r in mine if num(r[col]) <= 1e-3), None)
        found[label] = (first("residual_relative"), first("solve_error"))
    best = [min((v[i] for v in found.values() if v[i]), default=None) for i in (0, 1)]
    for label, (res, err) in found.items():
        ratio = lambda v, b: f"{v:,} ({v / b:.0f}×)" if v and b else (f"{v:,}" if v else "not reached")
        out.append([label_name(label), ratio(res, best[0]), ratio(err, best[1])])
    return markdown(["solver", "sweeps to 1e-3 of the initial residual", "sweeps to a solve error of 1e-3"], out)


def setting(r):
    label = label_name(r["label"])
    method = r.get("method", "pd")
    if method == "implicit":
        return f"implicit {r['solver']} to {sig(num(r['tolerance']))}, {r['substeps']} substeps"
    if method == "explicit":
        return f"explicit {r['solver']}, {r['substeps']} substeps (h = {seconds(num(r['dt']))})"
    return f"{label}, {r['substeps']} × {r['iterations']}"


def front_row(r, host_labels=("gs-cpu",)):
    ms = sig(num(r["frame_ms"]))
    if r["label"] in host_labels:
        ms += " (host)"
    fronts = [name for name, key in (("trajectory", "front_trajectory"), ("residual", "front_residual"))
              if r.get(key) == "1"]
    return [setting(r), ms, sig(num(r["trajectory_error"])), sig(num(r["residual"])), ", ".join(fronts)]


def pareto_front_view(folder):
    rows = [r for r in read_dicts(folder, "pareto") if r["front_trajectory"] == "1" or r["front_residual"] == "1"]
    rows.sort(key=lambda r: num(r["frame_ms"]))
    return markdown(["setting (substeps × sweeps)", "ms per frame", "RMS trajectory error (m)", "residual (m²)",
                     "on the front of"], [front_row(r) for r in rows])


def pareto_tethers_view(folder):
    rows = [r for r in read_dicts(folder, "pareto") if r["front_trajectory"] == "1"]
    rows.sort(key=lambda r: num(r["frame_ms"]))
    plain = {(r["label"], r["substeps"], r["iterations"]): r for r in read_dicts("pareto", "pareto")}
    out = []
    for r in rows:
        other = plain.get((r["label"], r["substeps"], r["iterations"]))
        without = (f"{sig(num(other['trajectory_error']))} ({sig(num(other['frame_ms']))} ms)"
                   if other and other["stable"] == "1" else "—")
        out.append([setting(r), sig(num(r["frame_ms"])), sig(num(r["trajectory_error"])), without])
    return markdown(["setting with tethers (substeps × sweeps)", "ms per frame", "RMS trajectory error (m)",
                     "the same without tethers: error (ms per frame)"], out)


def families_view(folder):
    rows = read_dicts(folder, "pareto")
    chosen = [r for r in rows if r["front_trajectory"] == "1" or r["front_residual"] == "1"]
    for method in dict.fromkeys(r["method"] for r in rows):
        stable = [r for r in rows if r["method"] == method and r["stable"] == "1"]
        if stable:
            best = min(stable, key=lambda r: num(r["trajectory_error"]))
            if best not in chosen:
                chosen.append(best)
    chosen.sort(key=lambda r: num(r["frame_ms"]))
    out = []
    for r in chosen:
        line = front_row(r)
        line[4] = line[4] or f"best {r['method']} setting"
        out.append(line)
    unstable = sorted({setting(r).split(",")[0] for r in rows if r["stable"] != "1"})
    text = markdown(["setting", "ms per frame", "RMS trajectory error (m)", "residual (m²)", "on the front of"], out)
    if unstable:
        text += "\nUnstable at some setting (left off the fronts): " + ", ".join(unstable) + ".\n"
    return text


def stability_limits_view(folder):
    rows = [r for r in read_dicts(folder, "stability") if r["kind"] == "limit"]
    out = []
    for key in dict.fromkeys((r["label"], r["iterations"]) for r in rows):
        mine = [r for r in rows if (r["label"], r["iterations"]) == key]
        stable = {r["dt"] for r in mine}
        unstable = {r["dt_unstable"] for r in mine}
        stiff = sorted(num(r["stiffness"]) for r in mine)
        same = len(stable) == 1 and len(unstable) == 1
        first = mine[0]
        dt = num(first["dt"])
        out.append([label_name(key[0]), f"{first['outer']} × {first['inner']}",
                    (seconds(dt) if not math.isnan(dt) else "none tried") + ("" if same else " (varies)"),
                    seconds(num(first["dt_unstable"])),
                    f"{stiff[0]:.0e} to {stiff[-1]:.0e}".replace("e+0", "e")])
    return markdown(["solver", "sweeps (outer × inner)", "largest stable h", "smallest unstable h",
                     "for every stiffness (N/m)"], out)


def stability_extremes_view(folder):
    rows = [r for r in read_dicts(folder, "stability") if r["kind"] == "extreme"]
    keys = list(dict.fromkeys((r["label"], r["iterations"]) for r in rows))
    many = len({k[1] for k in keys}) > 1
    header = ["case"] + [label_name(l) + (f", {i} sweeps" if many else "") for l, i in keys]
    out = []
    for case in dict.fromkeys(r["case"] for r in rows):
        line = [case]
        for k in keys:
            r = next((r for r in rows if r["case"] == case and (r["label"], r["iterations"]) == k), None)
            if r is None:
                line.append("")
                continue
            verdict = "stable" if r["stable"] == "1" else r["reason"]
            line.append(f"{verdict}, {sig(100 * num(r['max_stretch']))} %")
        out.append(line)
    return markdown(header, out) + "\nEach cell: the verdict and the largest spring stretch at the end.\n"


def explicit_view(folder):
    rows = read_dicts(folder, "explicit-stability")
    out = []
    for r in rows:
        measure = r["measure"]
        if measure == "largest stable kd":
            where = f"h = {seconds(num(r['dt']))}"
            fmt = lambda v: f"{sig(num(v))} N·s/m"
            seed = r["seed"]
        elif measure == "largest stable h":
            where = f"kd = {sig(num(r['kd']))} N·s/m"
            fmt = lambda v: seconds(num(v))
            seed = r["seed"]
            if seed and not math.isnan(num(seed)):
                seed = seconds(num(seed))
            elif "-" in seed:
                lo, hi = seed.split("-")
                seed = f"{seconds(num(lo))[:-3]}–{seconds(num(hi))}"
        else:
            where = ""
            fmt = lambda v: sig(num(v))
            seed = r["seed"]
        out.append([measure + (f" at {where}" if where else ""), r["integrator"],
                    f"{fmt(r['measured'])} / {fmt(r['unstable_at'])}", fmt(r["predicted"]), seed])
    lam = rows[0]
    text = markdown(["limit", "integrator", "measured (stable / unstable)", "predicted", "seed 001"], out)
    text += (f"\nThe stiffest mode: λ_d = {sig(num(lam['lambda_d']))} s⁻¹ per N·s/m (the largest eigenvalue "
             f"of M⁻¹D), uᵀM⁻¹Ku = {sig(num(lam['lambda_k']))} s⁻².\n")
    return text


def scaling_view(folder):
    rows = read_dicts(folder, "scaling")
    keys = list(dict.fromkeys((r["label"], r["iterations"]) for r in rows))
    grids = sorted({int(num(r["grid"])) for r in rows})
    out = []
    for g in grids:
        line = [f"{g}² = {g * g:,}"]
        for k in keys:
            r = next((r for r in rows if int(num(r["grid"])) == g and (r["label"], r["iterations"]) == k), None)
            line.append(f"{sig(num(r['fps']))} ({ms_or_s(num(r['frame_ms']))})" if r else "")
        out.append(line)
    return markdown(["particles"] + [f"{label_name(l)} {i}" for l, i in keys], out)


def scaling_ns_view(folder):
    rows = read_dicts(folder, "scaling")
    keys = list(dict.fromkeys((r["label"], r["iterations"]) for r in rows))
    grids = sorted({int(num(r["grid"])) for r in rows})
    out = []
    for g in grids:
        line = [f"{g * g:,}"]
        for k in keys:
            r = next((r for r in rows if int(num(r["grid"])) == g and (r["label"], r["iterations"]) == k), None)
            line.append(sig(num(r["ns_per_particle_iteration"])) if r else "")
        out.append(line)
    return markdown(["particles"] + [f"{label_name(l)} {i}" for l, i in keys], out)


def batch_view(folder):
    """A clothvk-bench batch run: per count of copies, the particles and dispatches per frame,
    the wall time per frame and per copy, and the cloth and particle steps per second."""
    out = []
    for r in sorted(read_dicts(folder, "batch"), key=lambda r: num(r["count"])):
        out.append([f"{int(num(r['count'])):,}", f"{int(num(r['particles'])):,}",
                    r["dispatches_per_frame"], ms_or_s(num(r["wall_ms"])),
                    ms_or_s(num(r["ms_per_copy"])), sig(num(r["copy_steps_per_s"])),
                    sig(num(r["particle_steps_per_s"]))])
    return markdown(["copies", "particles", "dispatches per frame", "wall time per frame",
                     "per copy", "cloth steps per s", "particle steps per s"], out)


def implicit_scaling_view(solver):
    rows = [r for r in read_dicts("implicit-scaling", "scaling") if r["label"] == solver]
    seed = {(r["particles"], r["iterations"]): r for r in read_dicts("implicit-scaling", "seed000")
            if r["solver"] == solver}
    iterations = sorted({int(num(r["iterations"])) for r in rows})
    out = []
    for p in sorted({int(num(r["particles"])) for r in rows}):
        line = [f"{p:,}"]
        for i in iterations:
            r = next(r for r in rows if int(num(r["particles"])) == p and int(num(r["iterations"])) == i)
            fps = f"{1000 / num(r['frame_ms_min']):,.0f}"
            s = seed.get((str(p), str(i)))
            if s:
                fps += f" ({s['seed GPU fps'] or 'x'} / {s['seed CPU fps'] or 'x'})"
            line.append(fps)
        out.append(line)
    return markdown([f"{solver}: particles"] + [f"{i} iterations" for i in iterations], out)


def soak_view(folder):
    rows = read_dicts(folder, "soak")
    frames = [int(num(r["frame"])) for r in rows]
    rss = [num(r["rss_mb"]) for r in rows]
    device = {r["device_mb"] for r in rows}
    steps = [(rss[i] - rss[i - 1], frames[i - 1], frames[i]) for i in range(2, len(rows))]
    big = max(steps) if steps else (0, 0, 0)
    out = [
        ["frames", f"{frames[-1]:,}"],
        ["wall time", f"{sig(num(rows[-1]['seconds']))} s"],
        ["resident memory at the start", f"{rss[0]:.1f} MB"],
        [f"resident memory at frame {frames[1]:,}", f"{rss[1]:.1f} MB"],
        ["largest step after that", f"{big[0]:.1f} MB, between frames {big[1]:,} and {big[2]:,}"],
        ["resident memory at the end", f"{rss[-1]:.1f} MB"],
        ["device memory the context holds", " / ".join(sorted(device)) + " MB throughout"
         if len(device) == 1 else ", ".join(sorted(device)) + " MB"],
        ["NaN or infinite coordinates at the end", rows[-1]["nan_count"]],
        ["largest stretch at the end", f"{100 * num(rows[-1]['max_stretch']):.2f} %"],
    ]
    return markdown(["soak", "value"], out)


VIEWS = {
    "budget:iterations": lambda: budget_view("budget"),
    "budget:cost": lambda: budget_cost_view("budget"),
    "budget-threads:iterations": lambda: budget_view("budget-threads"),
    "convergence-enlarged:residual": lambda: convergence_view("convergence-enlarged", "residual",
                                                              "residual (m²) after k sweeps"),
    "convergence-enlarged:solve-error": lambda: convergence_view("convergence-enlarged", "solve_error",
                                                                 "solve error after k sweeps"),
    "convergence-hanging:solve-error": lambda: convergence_view("convergence-hanging", "solve_error",
                                                                "solve error after k sweeps"),
    "convergence-wang:targets": lambda: convergence_targets_view("convergence-wang"),
    "pareto:front": lambda: pareto_front_view("pareto"),
    "pareto-tethers:front": lambda: pareto_tethers_view("pareto-tethers"),
    "families-hanging:front": lambda: families_view("families-hanging"),
    "families-flag:front": lambda: families_view("families-flag"),
    "stability:limits": lambda: stability_limits_view("stability"),
    "stability:extremes": lambda: stability_extremes_view("stability"),
    "stability-few:limits": lambda: stability_limits_view("stability-few"),
    "stability-few:extremes": lambda: stability_extremes_view("stability-few"),
    "explicit-stability:limits": lambda: explicit_view("explicit-stability"),
    "explicit-stability-viscosity:limits": lambda: explicit_view("explicit-stability-viscosity"),
    "scaling:fps": lambda: scaling_view("scaling"),
    "scaling:ns": lambda: scaling_ns_view("scaling"),
    "scaling-threads:fps": lambda: scaling_view("scaling-threads"),
    "implicit-scaling:cg": lambda: implicit_scaling_view("cg"),
    "implicit-scaling:implicit-jacobi": lambda: implicit_scaling_view("implicit-jacobi"),
    "soak:summary": lambda: soak_view("soak"),
    "batch:napkins": lambda: batch_view("batch"),
    "batch-threads:napkins": lambda: batch_view("batch-threads"),
    "batch-self:napkins": lambda: batch_view("batch-self"),
    "batch-h200:napkins": lambda: batch_view("batch-h200"),
}


def generate(name):
    if name in VIEWS:
        return VIEWS[name]()
    if "/" in name:
        folder, stem = name.split("/", 1)
        return plain_table(folder, stem)
    raise FigureError(f"unknown table {name!r}: expected FOLDER/FILE (a CSV under docs/figures/) "
                      f"or one of {', '.join(sorted(VIEWS))}")


# ------------------------------------------------------------------------------------------
# Tables into the docs, plots through gnuplot
# ------------------------------------------------------------------------------------------

def update_tables(check):
    stale = []
    used = set()
    for page in sorted(DOCS.glob("*.md")) + [ROOT / "README.md"]:
        if not page.is_file():
            continue
        text = page.read_text(encoding="utf-8")

        def fill(match):
            name = match.group("name")
            used.add(name)
            try:
                body = generate(name)
            except FigureError as e:
                raise FigureError(f"{page.relative_to(ROOT)}: {e}") from None
            return match.group(1) + body + match.group(4)

        new = BLOCK.sub(fill, text)
        if new != text:
            stale.append(str(page.relative_to(ROOT)))
            if not check:
                page.write_text(new, encoding="utf-8")
    return stale, used


def update_plots(check):
    scripts = sorted(FIGURES.glob("*/*.gp"))
    gnuplot = os.environ.get("CLOTHVK_GNUPLOT") or "gnuplot"
    if not shutil.which(gnuplot):
        print(f"figures.py: {gnuplot} not found; {len(scripts)} plots left as they are", file=sys.stderr)
        return []
    stale = []
    for script in scripts:
        png = script.with_suffix(".png")
        fd, temp = tempfile.mkstemp(suffix=".png", dir=script.parent)
        os.close(fd)
        try:
            run = subprocess.run([gnuplot, "-e", f"out='{Path(temp).name}'", script.name], cwd=script.parent,
                                 stdin=subprocess.DEVNULL, capture_output=True, text=True)
            if run.returncode != 0:
                first = (run.stderr.strip().splitlines() or ["no message"])[0]
                raise FigureError(f"{script.relative_to(ROOT)}: gnuplot failed: {first}")
            new = Path(temp).read_bytes()
            if not png.is_file() or png.read_bytes() != new:
                stale.append(str(png.relative_to(ROOT)))
                if not check:
                    os.replace(temp, png)
        finally:
            if os.path.exists(temp):
                os.unlink(temp)
    return stale


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--check", action="store_true", help="change nothing; exit 1 when something is stale")
    ap.add_argument("--no-plots", action="store_true", help="tables only")
    args = ap.parse_args()
    try:
        stale, used = update_tables(args.check)
        if not args.no_plots:
            stale += update_plots(args.check)
    except FigureError as e:
        print(f"figures.py: {e}", file=sys.stderr)
        return 2
    unused = sorted(p.parent.name + "/" + p.stem for p in FIGURES.glob("*/*.csv")
                    if p.parent.name + "/" + p.stem not in used
                    and not any(u.startswith(p.parent.name + ":") for u in used))
    if unused:
        print("figures.py: CSVs no page shows: " + ", ".join(unused), file=sys.stderr)
    if args.check:
        if stale:
            print("figures.py: not generated from the CSVs (run python3 scripts/figures.py): "
                  + ", ".join(stale), file=sys.stderr)
            return 1
        print(f"figures.py: {len(used)} tables and the plots match the CSVs")
        return 0
    print(f"figures.py: {len(used)} tables" + (f"; rewrote {', '.join(stale)}" if stale else ", nothing changed"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
