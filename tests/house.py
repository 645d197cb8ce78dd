"""What the checks of the house (check_layers.py, check_sizes.py) share: a self-test on a small
tree written to a temporary folder, and the command line (an optional --self-test, then the
folder to check). Standard library only."""
import os
import sys
import tempfile


def self_test(name, check, files, want):
    """True when `check` over a tree of `files` ({path: text}) finds exactly `want`; else prints
    both lists."""
    with tempfile.TemporaryDirectory() as root:
        for path, text in files.items():
            os.makedirs(os.path.dirname(os.path.join(root, path)), exist_ok=True)
            with open(os.path.join(root, path), "w", encoding="utf-8") as f:
                f.write(text)
        got = sorted(check(root))
    if got == sorted(want):
        return True
    print(f"{name}: the self-test expected\n  " + "\n  ".join(sorted(want)) + "\ngot\n  " +
          "\n  ".join(got))
    return False


def main(name, check, default_root, passed, test=None):
    """The command line: [--self-test] [ROOT]. Prints each finding and exits 1 on any, else
    prints passed(root) and exits 0."""
    args = sys.argv[1:]
    if "--self-test" in args:
        args.remove("--self-test")
        if test and not test():
            return 1
    root = args[0] if args else default_root
    errors = check(root)
    for e in errors:
        print(e)
    if errors:
        print(f"{name}: {len(errors)} finding(s)")
        return 1
    print(passed(root))
    return 0
