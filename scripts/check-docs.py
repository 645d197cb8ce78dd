#!/usr/bin/env python3
"""Checks that the documentation covers what the code offers.

    python3 scripts/check-docs.py BUILD_DIR      # e.g. scripts/check-docs.py build

Fails (exit 1, one line per gap) unless
  1. README.md has at most 200 lines (it is the front page; the reference lives in docs/);
  2. every option that `clothvk-sim --help`, `clothvk-render --help` and `clothvk-bench --help`
     print (BUILD_DIR/apps/...) appears in docs/tools.md;
  3. every public function and type `cvk_...` declared in lib/include/*.h (and
     lib/include/clothvk/*.h) appears in docs/library.md;
  4. every scene key of the JSON field tables (`.key = "..."` in lib/**/scene*.c and
     lib/scene/*.c) appears in docs/scene-format.md;
  5. every relative link in README.md and docs/*.md leads to a file that exists, and to a heading
     of it where the link names one;
  6. every table generated from docs/figures/ is what scripts/figures.py makes of the CSVs now.
A name counts as present when it stands in `code` on the page (alone, or in a longer span such
as `cloths.N.mass` or `--frames N`). Exit 2 for a usage error. Standard library only.
"""
import glob
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
README_LIMIT = 200
TOOLS = ("clothvk-sim", "clothvk-render", "clothvk-bench")
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


def main(argv):
    if len(argv) != 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip().split("\n\n")[1], file=sys.stderr)
        return 2
    build = os.path.abspath(argv[1])
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
