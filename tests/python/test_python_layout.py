"""The ctypes mirror in host_glue/python/weft matches weft.h as the C compiler lays it out.

Usage: test_python_layout.py LAYOUT_DUMP WEFT_H. LAYOUT_DUMP (host_glue/python/layout_dump.c)
prints sizeof/_Alignof/offsetof of every public struct and field, the enum sizes and the constant
values; weft.h itself is scanned for the structs, constants and functions it declares, so nothing
added to the header can be missed by both the dump and the bindings."""
import ctypes
import json
import re
import subprocess
import sys
import unittest

import weft

DUMP, HEADER = sys.argv[1], sys.argv[2]


class Layout(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.c = json.loads(subprocess.run([DUMP], check=True, capture_output=True,
                                          text=True).stdout)
        with open(HEADER) as f:
            cls.header = f.read()

    def test_every_struct_of_the_header_is_dumped_and_mirrored(self):
        declared = set(re.findall(r"typedef struct (weft_\w+) \{", self.header))
        self.assertEqual(declared, set(self.c["structs"]))
        self.assertEqual(declared, set(weft.STRUCTS))

    def test_sizes_alignments_and_field_offsets(self):
        for name, c in self.c["structs"].items():
            py = weft.STRUCTS[name]
            with self.subTest(struct=name):
                self.assertEqual(ctypes.sizeof(py), c["size"], "sizeof")
                self.assertEqual(ctypes.alignment(py), c["align"], "alignment")
                self.assertEqual([f[0] for f in py._fields_], [f[0] for f in c["fields"]],
                                 "field names and order")
                for fname, offset, size in c["fields"]:
                    descr = getattr(py, fname)
                    self.assertEqual((descr.offset, descr.size), (offset, size),
                                     "%s.%s (offset, size)" % (name, fname))

    def test_enums_are_int_sized(self):
        for name, size in self.c["enums"].items():
            self.assertEqual(size, ctypes.sizeof(ctypes.c_int), name)

    def test_constants(self):
        values = self.c["constants"]
        in_header = set(re.findall(r"\b(WEFT_[A-Z0-9_]+)\s*=", self.header))
        in_header |= set(re.findall(r"^#define (WEFT_(?:ABI|VERSION_\w+)) ", self.header, re.M))
        in_header |= set(re.findall(r"X\((WEFT_\w+),", open(HEADER.replace(
            "weft.h", "weft_status.h")).read()))
        self.assertEqual(in_header - set(values), set(), "constants missing from layout_dump")
        self.assertEqual(values, weft.c_constants())

    def test_every_function_has_a_prototype(self):
        declared = set(re.findall(r"WEFT_API\s[^;()]*?\b(weft_\w+)\s*\(", self.header))
        self.assertEqual(len(declared), len(re.findall(r"^WEFT_API ", self.header, re.M)))
        self.assertEqual(declared, set(weft.PROTOTYPES))


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
