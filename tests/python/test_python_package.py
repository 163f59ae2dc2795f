"""`pip install host_glue/python` into fresh venvs, offline, then the bindings' tests run against
the installed package, not the source tree.

    test_python_package.py PACKAGE_SOURCE LIBRARY WORK_DIR

Two venvs under WORK_DIR (emptied first), `--system-site-packages` so that NumPy, pip and
setuptools are Debian's; `--without-pip`, as the venv's own copy of pip would be Debian's too
(and costs seconds to install). Each gets `python -m pip install --no-index --no-build-isolation`
of PACKAGE_SOURCE: one with $WEFT_LIBRARY=LIBRARY (the package carries the library), one without
(after two refused builds: $WEFT_LIBRARY naming no file, and a relative one).
Then, from a folder outside the source tree, with PYTHONPATH and WEFT_LIBRARY unset:
test_python_roundtrip.py and installed_package_checks.py (copied there) with the first venv,
installed_package_checks.py with the second (no library anywhere; then LD_LIBRARY_PATH).
The source folder must be left as it was (setup.py builds in a temporary folder).
The environment's LD_PRELOAD (the ASan runtime in a sanitizer build) reaches only the runs that
load the library, not pip."""
import filecmp
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE, LIBRARY, WORK = (os.path.abspath(a) for a in sys.argv[1:4])
PYTHON = sys.executable


def env_for(loads_library, **extra):
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "WEFT_LIBRARY")}
    if not loads_library:
        env.pop("LD_PRELOAD", None)
    env.update(extra)
    return env


def run(args, env, cwd=WORK):
    print("+ " + " ".join(args), flush=True)
    done = subprocess.run(args, env=env, cwd=cwd)
    if done.returncode != 0:
        sys.exit("test_python_package: exit %d from %s" % (done.returncode, " ".join(args)))


def pip_install(python, **build_env):
    return [python, "-m", "pip", "install", "--no-index", "--no-build-isolation", "--no-cache-dir",
            "--quiet", SOURCE], env_for(False, **build_env)


def make_venv(name):
    venv = os.path.join(WORK, name)
    run([PYTHON, "-m", "venv", "--system-site-packages", "--without-pip", venv], env_for(False))
    return os.path.join(venv, "bin", "python")


def refused_build(python):
    """$WEFT_LIBRARY naming no file, or relative, at build time: pip fails saying so, and
    installs nothing."""
    missing = os.path.join(WORK, "missing", "libweft.so.10")
    for library, said in ((missing, "WEFT_LIBRARY=%s: no such file" % missing),
                          ("libweft.so.10", "WEFT_LIBRARY=libweft.so.10: give an absolute path")):
        args, env = pip_install(python, WEFT_LIBRARY=library)
        done = subprocess.run(args, env=env, cwd=WORK, capture_output=True, text=True)
        if done.returncode == 0 or said not in done.stdout + done.stderr:
            sys.exit("test_python_package: WEFT_LIBRARY=%s: expected a failed build saying %r, "
                     "got exit %d:\n%s%s" % (library, said, done.returncode, done.stdout,
                                            done.stderr))
        print("  WEFT_LIBRARY=%s refused: %s" % (library, said))
    if subprocess.run([python, "-c", "import weft"], env=env_for(False), cwd=WORK,
                      capture_output=True).returncode == 0:
        sys.exit("test_python_package: a refused build left a weft package in the venv")


def main():
    shutil.rmtree(WORK, ignore_errors=True)
    outside = os.path.join(WORK, "outside")
    os.makedirs(outside)
    for script in ("test_python_roundtrip.py", "installed_package_checks.py"):
        shutil.copy(os.path.join(HERE, script), outside)
    source_before = sorted(os.listdir(SOURCE))

    bundled = make_venv("venv_bundled")
    run(*pip_install(bundled, WEFT_LIBRARY=LIBRARY))
    bare = make_venv("venv_bare")
    refused_build(bare)
    run(*pip_install(bare))
    if sorted(os.listdir(SOURCE)) != source_before:
        sys.exit("test_python_package: pip install wrote into %s: %s"
                 % (SOURCE, sorted(set(os.listdir(SOURCE)) - set(source_before))))
    where = subprocess.run([bundled, "-c", "import weft; print(weft.__file__)"], cwd=outside,
                           env=env_for(False), capture_output=True, text=True, check=True)
    copy = os.path.join(os.path.dirname(where.stdout.strip()), "libweft.so.10")
    if not filecmp.cmp(copy, LIBRARY, shallow=False):
        sys.exit("test_python_package: %s is not a copy of %s" % (copy, LIBRARY))

    run([bundled, "test_python_roundtrip.py"], env_for(True), cwd=outside)
    run([bundled, "installed_package_checks.py", "bundled"], env_for(True), cwd=outside)
    run([bare, "installed_package_checks.py", "bare"], env_for(True), cwd=outside)
    search = os.pathsep.join(filter(None, [os.path.dirname(LIBRARY),
                                           os.environ.get("LD_LIBRARY_PATH")]))
    run([bare, "installed_package_checks.py", "search-path"],
        env_for(True, LD_LIBRARY_PATH=search), cwd=outside)
    print("test_python_package: the installed package passed (%s)" % WORK)


if __name__ == "__main__":
    main()
