"""The README's pvpython example, run as written, so it cannot go stale.

Usage: pvpython test_readme_example.py PVPYTHON README.md PLUGIN_FILE DATA_DIR WORK_DIR

Takes the first ```python block after "In pvpython:" in the README, runs it in WORK_DIR where
build/lib/paraview-plugins/BRepThickness/BRepThickness.so and Data/ point to the built plugin and
the models, and checks the files it saves.
"""
import os
import re
import shutil
import subprocess
import sys

pvpython, readme, plugin, data, work = sys.argv[1:6]
text = open(readme, encoding="utf-8").read()
start = text.index("In pvpython:")
code = re.search(r"```python\n(.*?)```", text[start:], re.S).group(1)
shutil.rmtree(work, ignore_errors=True)
plugin_dir = os.path.join(work, "build", "lib", "paraview-plugins", "BRepThickness")
os.makedirs(plugin_dir)
os.symlink(os.path.abspath(plugin), os.path.join(plugin_dir, "BRepThickness.so"))
os.symlink(os.path.abspath(data), os.path.join(work, "Data"))
script = os.path.join(work, "example.py")
with open(script, "w") as f:
    f.write(code)
r = subprocess.run([pvpython, script], cwd=work, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                   text=True, timeout=600)
print("\n".join(l for l in r.stdout.splitlines() if "INFO|" not in l))
failures = []
if r.returncode != 0:
    failures.append("the example exited with status %d" % r.returncode)
if not re.search(r"thickness [0-9.]+ \.\. [0-9.]+ mm, mean [0-9.]+, [0-9.]+% of the area below", r.stdout):
    failures.append("the example did not print its summary line")
for name in ("card-thickness.vtp", "card-medial.vtp"):
    path = os.path.join(work, name)
    if not os.path.exists(path) or os.path.getsize(path) < 100000:
        failures.append("%s missing or too small" % path)
for msg in failures:
    print("FAIL: " + msg)
sys.exit(1 if failures else 0)
