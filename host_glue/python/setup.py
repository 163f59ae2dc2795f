"""Builds the `weft` package (metadata in pyproject.toml) and carries libweft.so in it.

$WEFT_LIBRARY, when set at build time, names the library to copy into the package as
weft/libweft.so.10 (weft.find_library's third choice); the wheel is then tagged for this platform
(py3-none-<platform>: ctypes needs no particular Python ABI). Without it the package is pure
Python and finds the library at run time. setuptools' scratch folders (build/, *.egg-info) go to
a temporary folder, so the source folder may be read-only (an installed
share/weft/host_glue/python) and no copy of an earlier build's library can end up in a later
package.
"""
import atexit
import os
import shutil
import sys
import tempfile

from setuptools import setup
from setuptools.command.build_py import build_py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "weft"))
from _abi import DEFAULT_LIBRARY  # noqa: E402  (the name the package looks for: libweft.so.10)

LIBRARY = os.environ.get("WEFT_LIBRARY", "")
if LIBRARY and not os.path.isabs(LIBRARY):
    sys.exit("weft: WEFT_LIBRARY=%s: give an absolute path (pip runs this build in another "
             "folder)" % LIBRARY)
if LIBRARY and not os.path.isfile(LIBRARY):
    sys.exit("weft: WEFT_LIBRARY=%s: no such file (the library to put in the package)" % LIBRARY)


class BuildPyWithLibrary(build_py):
    """build_py, then $WEFT_LIBRARY copied to weft/libweft.so.10 beside the modules."""

    def run(self):
        super().run()
        if LIBRARY:
            target = os.path.join(self.build_lib, "weft", DEFAULT_LIBRARY)
            shutil.copyfile(LIBRARY, target)   # the file itself, where LIBRARY is a link
            os.chmod(target, 0o755)

    def get_outputs(self, include_bytecode=True):
        outputs = super().get_outputs(include_bytecode)
        if LIBRARY:
            outputs.append(os.path.join(self.build_lib, "weft", DEFAULT_LIBRARY))
        return outputs


commands = {"build_py": BuildPyWithLibrary}
if LIBRARY:
    from wheel.bdist_wheel import bdist_wheel

    class BdistWheelForPlatform(bdist_wheel):
        """A wheel carrying a shared library: for this platform, any Python 3."""

        def finalize_options(self):
            super().finalize_options()
            self.root_is_pure = False

        def get_tag(self):
            return ("py3", "none", super().get_tag()[2])

    commands["bdist_wheel"] = BdistWheelForPlatform

scratch = tempfile.mkdtemp(prefix="weft-setup-")
atexit.register(shutil.rmtree, scratch, True)
setup(cmdclass=commands,
      options={"build": {"build_base": os.path.join(scratch, "build")},
               "egg_info": {"egg_base": scratch}})
