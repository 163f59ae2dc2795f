"""Run by test_python_package.py with a venv's Python in which `weft` was pip-installed: the
package imported is the venv's, its version is the library's, and it finds the library in the
order weft.find_library documents. argv[1] says which install this is:
  bundled      built with $WEFT_LIBRARY: the copy inside the package is opened, an explicit path
               and $WEFT_LIBRARY come before it, a wrong-ABI library is refused by name
  bare         built without it, $WEFT_LIBRARY unset, no libweft.so.10 on the search path: the
               error names each place looked in
  search-path  built without it, LD_LIBRARY_PATH holding libweft.so.10: found there
Environment: WEFT_FIXTURE_OLD_ABI, WEFT_FIXTURE_ABI, WEFT_FIXTURE_NO_SYMBOLS (the loader fixtures).
"""
import ctypes
import importlib.metadata
import os
import sys
import unittest

import weft

MODE = sys.argv[1]
PACKAGE_DIR = os.path.dirname(os.path.abspath(weft.__file__))
BUNDLED = os.path.join(PACKAGE_DIR, "libweft.so.10")


class InstalledPackage(unittest.TestCase):
    def test_imported_from_the_venv(self):
        self.assertNotEqual(sys.prefix, sys.base_prefix, "not running in a venv")
        self.assertTrue(PACKAGE_DIR.startswith(os.path.join(sys.prefix, "lib")), PACKAGE_DIR)
        self.assertNotIn("PYTHONPATH", os.environ)
        self.assertNotIn("WEFT_LIBRARY", os.environ)

    def test_version_is_the_library_version(self):
        version = "%d.%d.%d" % weft.VERSION
        self.assertEqual(importlib.metadata.version("weft"), version)
        self.assertEqual(weft.__version__, version)
        if MODE != "bare":
            with weft.Context() as ctx:
                self.assertEqual(ctx.lib.version, weft.VERSION)
                self.assertEqual(ctx.lib.abi, weft.ABI)


@unittest.skipUnless(MODE == "bundled", "the package carries libweft.so.10")
class Bundled(unittest.TestCase):
    def tearDown(self):
        os.environ.pop("WEFT_LIBRARY", None)

    def test_the_copy_inside_the_package_is_opened(self):
        self.assertTrue(os.path.isfile(BUNDLED))
        self.assertEqual(weft.find_library(), (BUNDLED, "package"))
        with weft.Context() as ctx:
            self.assertEqual((ctx.lib.path, ctx.lib.source), (BUNDLED, "package"))
            cloth = ctx.create_cloth([[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]], [[0, 1, 2, 3]])
            cloth.step(1 / 60)
            self.assertLess(cloth.get_vertices()[0, 1], 0.0)   # it falls

    def test_wrong_abi_refused_by_name(self):
        path, abi = os.environ["WEFT_FIXTURE_OLD_ABI"], int(os.environ["WEFT_FIXTURE_ABI"])
        os.environ["WEFT_LIBRARY"] = path           # $WEFT_LIBRARY comes before the copy
        self.assertEqual(weft.find_library(), (path, "WEFT_LIBRARY"))
        with self.assertRaises(weft.WeftError) as e:
            weft.Context()
        self.assertEqual(e.exception.status, weft.Status.ABI_MISMATCH)
        self.assertIn("%s: ABI %d != %d (library " % (path, abi, weft.ABI), e.exception.message)
        print("\n  $WEFT_LIBRARY of another ABI:", e.exception, file=sys.stderr)
        with self.assertRaises(weft.WeftError) as e:
            weft.Context(library=os.environ["WEFT_FIXTURE_NO_SYMBOLS"])
        self.assertEqual(e.exception.status, weft.Status.ABI_MISMATCH)
        self.assertIn("missing symbol weft_version", e.exception.message)
        with weft.Context(library=BUNDLED) as ctx:  # an explicit path comes before $WEFT_LIBRARY
            self.assertEqual(ctx.lib.source, "argument")


@unittest.skipUnless(MODE == "bare", "a package without the library, none on the search path")
class Bare(unittest.TestCase):
    def test_error_names_every_place_looked_in(self):
        try:
            ctypes.CDLL("libweft.so.10")
            self.skipTest("a libweft.so.10 is installed on this machine's search path")
        except OSError:
            pass
        self.assertFalse(os.path.exists(BUNDLED))
        self.assertEqual(weft.find_library(), ("libweft.so.10", "search path"))
        with self.assertRaises(weft.WeftError) as e:
            weft.Context()
        self.assertEqual(e.exception.status, weft.Status.IO)
        for said in ("libweft.so.10: cannot open", "$WEFT_LIBRARY: unset", PACKAGE_DIR,
                     "built without $WEFT_LIBRARY", "dlopen search path"):
            self.assertIn(said, e.exception.message)
        print("\n  no library anywhere:", e.exception, file=sys.stderr)


@unittest.skipUnless(MODE == "search-path", "a package without the library, LD_LIBRARY_PATH")
class SearchPath(unittest.TestCase):
    def test_found_on_the_search_path(self):
        with weft.Context() as ctx:
            self.assertEqual((ctx.lib.path, ctx.lib.source), ("libweft.so.10", "search path"))


if __name__ == "__main__":
    assert MODE in ("bundled", "bare", "search-path"), MODE
    unittest.main(argv=sys.argv[:1], verbosity=2)
