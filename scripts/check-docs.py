#!/usr/bin/env python3
"""Checks that the documentation covers what the code offers.

    python3 scripts/check-docs.py [--self-test] BUILD_DIR   # e.g. scripts/check-docs.py build

Fails (exit 1, one line per gap) unless
  1. README.md has at most 200 lines (it is the front page; the reference lives in docs/);
  2. every option that `clothvk-sim --help`, `clothvk-render --help`, `clothvk-bench --help`
     and `clothvk-ab --help` print (BUILD_DIR/apps/...) appears in docs/tools.md;
  3. every public function and type `cvk_...` declared in lib/include/*.h (and
     lib/include/clothvk/*.h) appears in docs/library.md;
  4. every scene key of the JSON field tables (`.key = "..."` in lib/**/scene*.c and
     lib/scene/*.c) appears in docs/scene-format.md;
  5. every relative link in README.md and docs/*.md leads to a file that exists, and to a heading
     of it where the link names one;
  6. every table generated from docs/figures/ is what scripts/figures.py makes of the CSVs now.
A name counts as present when it stands in `code` on the page (alone, or in a longer span such
as `cloths.N.mass` or `--frames N`). Exit 2 for a usage error. Standard library only.

--self-test first runs each check on small trees written to a temporary folder (fake tools that
print their --help, a copy of scripts/figures.py) and requires exactly the gaps each tree holds,
so that each check is shown able to fail; it exits 1 naming the case that did not.
"""
import contextlib
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
README_LIMIT = 200
TOOLS = ("clothvk-sim", "clothvk-render", "clothvk-bench", "clothvk-ab")
OPTION = re.compile(r"(?<![\w-])(--?[a-z][a-z0-9-]*)")
KEY = re.compile(r'\.key\s*=\s*"([A-Za-z0-9_]+)"')
DECLARED = re.compile(r"\b(cvk_[a-z0-9_]+)\s*\(")
TYPEDEF = re.compile(r"\btypedef\s+(?:struct|enum)\s+(cvk_[a-z0-9_]+)|\(\s*\*\s*(cvk_[a-z0-9_]+)\s*\)")
LINK = re.compile(r"\]\(([^)\s]+)\)")


def read(rel):
    path = os.path.join(ROOT, rel)
    try:
        with open(path, encoding="utf-8") as f:
            return f.read()
    except OSError as e:
        return None if e.errno == 2 else ""


def code_spans(text):
    """The text of every `code` span and fenced block, one per line."""
    spans = re.findall(r"```[^\n]*\n(.*?)```", text, re.S)
    spans += re.findall(r"`([^`\n]+)`", re.sub(r"```.*?```", "", text, flags=re.S))
    return "\n".join(spans)


def mentions(code, name):
    return re.search(r"(?<![\w-])" + re.escape(name) + r"(?![\w-])", code) is not None


def check_readme(problems):
    text = read("README.md")
    if text is None:
        problems.append("README.md: missing")
        return
    lines = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
    if lines > README_LIMIT:
        problems.append(f"README.md: {lines} lines; the front page has at most {README_LIMIT} "
                        "(move the reference into docs/)")


def check_tools(build, problems):
    page = read("docs/tools.md")
    if page is None:
        problems.append("docs/tools.md: missing")
        return
    code = code_spans(page)
    for tool in TOOLS:
        exe = os.path.join(build, "apps", tool)
        if not os.access(exe, os.X_OK):
            problems.append(f"{exe}: not found or not executable (build first, or pass the build folder)")
            continue
        try:
            run = subprocess.run([exe, "--help"], capture_output=True, text=True, timeout=60,
                                 stdin=subprocess.DEVNULL)
        except (OSError, subprocess.TimeoutExpired) as e:
            problems.append(f"{exe} --help: {e}")
            continue
        if run.returncode != 0:
            problems.append(f"{exe} --help: exit status {run.returncode}")
            continue
        options = sorted(set(OPTION.findall(run.stdout + run.stderr)))
        if not options:
            problems.append(f"{exe} --help: printed no options")
        for opt in options:
            if not mentions(code, opt):
                problems.append(f"docs/tools.md: {tool}'s option {opt} (from --help) is not documented")


def public_headers():
    found = sorted(glob.glob(os.path.join(ROOT, "lib", "include", "*.h")))
    found += sorted(glob.glob(os.path.join(ROOT, "lib", "include", "clothvk", "*.h")))
    return found


def check_library(problems):
    page = read("docs/library.md")
    if page is None:
        problems.append("docs/library.md: missing")
        return
    code = code_spans(page)
    headers = public_headers()
    if not headers:
        problems.append("lib/include/: no public header found")
    for header in headers:
        with open(header, encoding="utf-8") as f:
            text = f.read()
        plain = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
        plain = re.sub(r"//[^\n]*", "", plain)
        names = set(DECLARED.findall(plain))
        names |= {a or b for a, b in TYPEDEF.findall(plain)}
        rel = os.path.relpath(header, ROOT)
        for name in sorted(names):
            if not mentions(code, name):
                problems.append(f"docs/library.md: {name} (declared in {rel}) is not documented")


def scene_sources():
    lib = os.path.join(ROOT, "lib")
    found = set(glob.glob(os.path.join(lib, "**", "scene*.c"), recursive=True))
    found |= set(glob.glob(os.path.join(lib, "scene", "*.c")))
    return sorted(found)


def check_scene_keys(problems):
    page = read("docs/scene-format.md")
    if page is None:
        problems.append("docs/scene-format.md: missing")
        return
    code = code_spans(page)
    sources = scene_sources()
    keys = {}
    for source in sources:
        with open(source, encoding="utf-8") as f:
            for key in KEY.findall(f.read()):
                keys.setdefault(key, os.path.relpath(source, ROOT))
    if not keys:
        problems.append("lib/: no scene field table found (.key = \"...\" in lib/**/scene*.c)")
    for key in sorted(keys):
        if not mentions(code, key):
            problems.append(f"docs/scene-format.md: scene key {key} (a field table in {keys[key]}) "
                            "is not documented")


def slug(heading):
    """The anchor GitHub gives a heading."""
    text = re.sub(r"`", "", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(text):
    seen = {}
    out = set()
    for line in re.sub(r"```.*?```", "", text, flags=re.S).splitlines():
        m = re.match(r"#{1,6}\s+(.*)", line)
        if not m:
            continue
        base = slug(m.group(1))
        n = seen.get(base, 0)
        out.add(base if n == 0 else f"{base}-{n}")
        seen[base] = n + 1
    return out


def check_links(problems):
    pages = ["README.md"] + sorted(os.path.relpath(p, ROOT) for p in glob.glob(os.path.join(ROOT, "docs", "*.md")))
    for page in pages:
        text = read(page)
        if text is None:
            continue
        for target in LINK.findall(re.sub(r"```.*?```", "", text, flags=re.S)):
            if re.match(r"[a-z]+:", target):
                continue  # https:, mailto:
            path, _, anchor = target.partition("#")
            dest = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
            full = os.path.join(ROOT, dest)
            if not os.path.exists(full):
                problems.append(f"{page}: link to {target}: {dest} does not exist")
                continue
            if anchor and dest.endswith(".md"):
                if anchor not in anchors(read(dest) or ""):
                    problems.append(f"{page}: link to {target}: {dest} has no heading #{anchor}")


def check_figures(problems):
    sys.dont_write_bytecode = True  # no __pycache__ beside the scripts
    sys.path.insert(0, os.path.join(ROOT, "scripts"))
    try:
        import figures
    except ImportError as e:
        problems.append(f"scripts/figures.py: cannot be loaded ({e})")
        return
    for page in [os.path.join(ROOT, "README.md")] + sorted(glob.glob(os.path.join(ROOT, "docs", "*.md"))):
        with open(page, encoding="utf-8") as f:
            text = f.read()
        for m in figures.BLOCK.finditer(text):
            name = m.group("name")
            try:
                want = figures.generate(name)
            except figures.FigureError as e:
                problems.append(f"{os.path.relpath(page, ROOT)}: table {name}: {e}")
                continue
            if m.group("body") != want:
                problems.append(f"{os.path.relpath(page, ROOT)}: table {name} differs from its CSV "
                                "(run python3 scripts/figures.py)")


@contextlib.contextmanager
def tree(files):
    """ROOT moved to a temporary folder holding `files` ({path: text}; a text starting with
    "#!" is made executable) while the block runs; then ROOT, sys.path and the figures module
    are as they were."""
    global ROOT
    saved_root, saved_path = ROOT, list(sys.path)
    with tempfile.TemporaryDirectory() as root:
        for path, text in files.items():
            full = os.path.join(root, path)
            os.makedirs(os.path.dirname(full), exist_ok=True)
            with open(full, "w", encoding="utf-8") as f:
                f.write(text)
            if text.startswith("#!"):
                os.chmod(full, 0o755)
        ROOT = root
        try:
            yield root
        finally:
            ROOT = saved_root
            sys.path[:] = saved_path
            sys.modules.pop("figures", None)


def run_check(check, files):
    """The gaps `check` finds in a tree of `files`."""
    problems = []
    with tree(files):
        check(problems)
    return problems


def case_readme():
    long = run_check(check_readme, {"README.md": "line\n" * (README_LIMIT + 1)})
    limit = run_check(check_readme, {"README.md": "line\n" * README_LIMIT})
    return long + limit, [f"README.md: {README_LIMIT + 1} lines; the front page has at most "
                          f"{README_LIMIT} (move the reference into docs/)"]


def case_tools():
    help_text = "#!/bin/sh\necho 'usage: {} [--frames N]{}'\n"
    files = {"docs/tools.md": "`--frames N` steps N frames.\n",
             "build/apps/clothvk-sim": help_text.format("clothvk-sim", " [--secret]"),
             "build/apps/clothvk-render": help_text.format("clothvk-render", ""),
             "build/apps/clothvk-bench": "#!/bin/sh\nexit 3\n",
             "build/apps/clothvk-ab": help_text.format("clothvk-ab", "")}
    problems = []
    with tree(files) as root:
        check_tools(os.path.join(root, "build"), problems)
        bench = os.path.join(root, "build", "apps", "clothvk-bench")
    return problems, ["docs/tools.md: clothvk-sim's option --secret (from --help) is not "
                      "documented", f"{bench} --help: exit status 3"]


def case_library():
    files = {"lib/include/clothvk.h": "/* cvk_in_a_comment(x) */\n"
                                      "typedef struct cvk_sim cvk_sim;\n"
                                      "int cvk_step(cvk_sim *sim);\nint cvk_hidden(void);\n",
             "lib/include/clothvk/base.h": "typedef void (*cvk_log_fn)(const char *line);\n"
                                           "enum cvk_kind cvk_kind_of(int k);\n",
             "docs/library.md": "`cvk_sim`, `cvk_step(sim)` and `cvk_log_fn`; "
                                "`cvk_kind_of`.\n"}
    return run_check(check_library, files), [
        "docs/library.md: cvk_hidden (declared in lib/include/clothvk.h) is not documented"]


def case_scene_keys():
    files = {"lib/scene/read.c": '{ .key = "gravity" }, { .key = "wind" },\n',
             "lib/sim/scene_extra.c": '{ .key = "frames" },\n',
             "lib/sim/other.c": '{ .key = "ignored" },\n',
             "docs/scene-format.md": "`gravity` and `cloths.N.wind`\n"}
    return run_check(check_scene_keys, files), [
        "docs/scene-format.md: scene key frames (a field table in lib/sim/scene_extra.c) is not "
        "documented"]


def case_links():
    files = {"README.md": "[a](docs/a.md) [b](docs/gone.md) [c](docs/a.md#title) "
                          "[d](docs/a.md#nope) [e](https://example.com/x)\n"
                          "```\n[f](in-a-fence.md)\n```\n",
             "docs/a.md": "# Title\n[back](../README.md) [self](#title) [x](#missing)\n"}
    return run_check(check_links, files), [
        "README.md: link to docs/gone.md: docs/gone.md does not exist",
        "README.md: link to docs/a.md#nope: docs/a.md has no heading #nope",
        "docs/a.md: link to #missing: docs/a.md has no heading #missing"]


def case_figures():
    with open(os.path.join(ROOT, "scripts", "figures.py"), encoding="utf-8") as f:
        figures_py = f.read()
    block = "<!-- figures:begin {0} -->\n{1}<!-- figures:end {0} -->\n"
    files = {"scripts/figures.py": figures_py, "README.md": "front\n",
             "docs/figures/runs/now.csv": "a,b\n1,2\n",
             "docs/figures/runs/stale.csv": "a\n3\n",
             "docs/t.md": block.format("runs/now", "| a | b |\n| --- | --- |\n| 1 | 2 |\n") +
             block.format("runs/stale", "| a |\n| --- |\n| 4 |\n") +
             block.format("runs/gone", "")}
    return run_check(check_figures, files), [
        "docs/t.md: table runs/stale differs from its CSV (run python3 scripts/figures.py)",
        "docs/t.md: table runs/gone: docs/figures/runs/gone.csv: no such file"]


def self_test():
    """True when each check finds exactly the gaps of its small tree; else prints, for each
    case that did not, what it expected and what it got."""
    ok = True
    for case in (case_readme, case_tools, case_library, case_scene_keys, case_links,
                 case_figures):
        got, want = case()
        if sorted(got) != sorted(want):
            ok = False
            print(f"check-docs: self-test {case.__name__}: expected\n  " +
                  "\n  ".join(sorted(want)) + "\ngot\n  " +
                  ("\n  ".join(sorted(got)) or "(nothing)"), file=sys.stderr)
    return ok


def main(argv):
    args = argv[1:]
    test = "--self-test" in args
    if test:
        args.remove("--self-test")
    if len(args) != 1 or args[0] in ("-h", "--help"):
        print(__doc__.strip().split("\n\n")[1], file=sys.stderr)
        return 2
    if test and not self_test():
        return 1
    build = os.path.abspath(args[0])
    problems = []
    check_readme(problems)
    check_tools(build, problems)
    check_library(problems)
    check_scene_keys(problems)
    check_links(problems)
    check_figures(problems)
    for p in problems:
        print(f"check-docs: {p}", file=sys.stderr)
    if problems:
        print(f"check-docs: {len(problems)} gaps between the code and the docs", file=sys.stderr)
        return 1
    print("check-docs: README.md is a front page; docs/ covers every tool option, public name and "
          "scene key; links and generated tables are current")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
