"""clothvk builds as a meson subproject: a small consumer project with subprojects/clothvk
pointing at this source tree configures, builds and runs. Whether warnings are errors is the
builder's choice, not clothvk's default: a consumer configured with -Dwerror=false builds clothvk
with -Dwerror=false too (a newer compiler may warn where ours does not); CI turns them into
errors (.ci/run)."""
import json
import os
import shutil
import subprocess
import sys
import tempfile

source_root = os.environ["CLOTHVK_SOURCE_ROOT"]

with tempfile.TemporaryDirectory() as work:
    project = os.path.join(work, "consumer")
    shutil.copytree(os.path.join(source_root, "tests", "subproject"), project)
    os.makedirs(os.path.join(project, "subprojects"))
    os.symlink(source_root, os.path.join(project, "subprojects", "clothvk"))
    for command in (["meson", "setup", "build"], ["meson", "compile", "-C", "build"],
                    [os.path.join("build", "consumer")]):
        run = subprocess.run(command, cwd=project, capture_output=True, text=True)
        if run.returncode != 0:
            print(f"FAILED: {' '.join(command)} exited {run.returncode}\n{run.stdout}\n{run.stderr}")
            sys.exit(1)
    if "consumer: 64 particles, 1 frame" not in run.stdout:
        print(f"FAILED: unexpected consumer output: {run.stdout!r}")
        sys.exit(1)
    # The consumer above makes warnings errors, for its build and clothvk's; one that does not
    # (configured only, not built) gets clothvk without them.
    subprocess.run(["meson", "setup", "lenient", "-Dwerror=false"], cwd=project, capture_output=True,
                   check=True)
    options = subprocess.run(["meson", "introspect", "lenient", "--buildoptions"], cwd=project,
                             capture_output=True, text=True, check=True)
    werror = [o["value"] for o in json.loads(options.stdout) if o["name"] == "clothvk:werror"]
    if werror != [False]:
        print(f"FAILED: with -Dwerror=false the subproject's werror is {werror}, expected [False]: "
              "warnings as errors are the builder's choice (CI's -Dwerror=true), not clothvk's default")
        sys.exit(1)
    print("clothvk builds and runs as a meson subproject")
