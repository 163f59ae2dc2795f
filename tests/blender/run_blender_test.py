"""Runs a test script in a headless Blender: exit 77 (skipped) with the reason when Blender is not
installed, else Blender's exit status (1 when the script raised or failed).
Usage: run_blender_test.py TEST_SCRIPT ARGS... ($WEFT_BLENDER: the blender executable)"""
import os
import shutil
import subprocess
import sys

blender = os.environ.get("WEFT_BLENDER") or shutil.which("blender")
if not blender:
    print("SKIPPED: `blender` is not installed (apt-get install blender; .ci/deps.sh does)")
    sys.exit(77)
cmd = [blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python", sys.argv[1],
       "--"] + sys.argv[2:]
print(" ".join(cmd), flush=True)
sys.exit(subprocess.run(cmd, timeout=240).returncode)
