#!/usr/bin/python3
"""The project's text describes the code as it is: the README stays within 150 lines, and
neither the README, the docs' prose nor a comment in the product's code names a CPU model or a
commit. Figures that belong to a host live in results/ as JSON; the docs' generated data-table
blocks (scripts/results.py) link to them and are left out here.
"""
import glob
import os
import re
import sys
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PRODUCT = ["kernels", "bvh", "wavefront", "io", "cli", "live", "distributed", "reference", "bench"]

# CPU models and microarchitectures as hosts are named; "AVX-512" or "x86" name levels, not hosts.
HOST = re.compile(r"\b(EPYC|Xeon|Ryzen|Zen ?[1-6]|Emerald Rapids|Sapphire Rapids|Ice Lake|Skylake|"
                  r"Cascade Lake|Graviton|family \d+,? model \d+)\b", re.I)
# A commit: 7 to 40 hex digits with a letter and a digit, not a 0x constant, not inside a word or path.
COMMIT = re.compile(r"(?<![\w/.#-])(?!0x)(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}(?![\w/.-])")
GENERATED = re.compile(r"<!-- ([\w-]+):begin.*?<!-- \1:end -->", re.S)


def comments(text):
    """The // and /* */ comments of a C++ file."""
    return re.findall(r"//[^\n]*|/\*.*?\*/", text, re.S)


def offences(text):
    return [m.group(0) for m in HOST.finditer(text)] + [m.group(0) for m in COMMIT.finditer(text)]


class ProjectText(unittest.TestCase):
    def test_readme_is_at_most_150_lines(self):
        with open(os.path.join(ROOT, "README.md")) as f:
            self.assertLessEqual(len(f.read().splitlines()), 150)

    def test_readme_and_docs_name_no_host_or_commit(self):
        for path in [os.path.join(ROOT, "README.md")] + sorted(glob.glob(os.path.join(ROOT, "docs", "*.md"))):
            with open(path) as f:
                prose = GENERATED.sub("", f.read())
            self.assertEqual(offences(prose), [], os.path.relpath(path, ROOT))

    def test_product_comments_name_no_host_or_commit(self):
        for folder in PRODUCT:
            for path in sorted(glob.glob(os.path.join(ROOT, folder, "**", "*.[ch]*"), recursive=True)):
                if not path.endswith((".h", ".cpp", ".hpp")):
                    continue
                with open(path, errors="replace") as f:
                    found = offences("\n".join(comments(f.read())))
                self.assertEqual(found, [], os.path.relpath(path, ROOT))

    def test_the_patterns_catch_what_they_guard(self):
        self.assertTrue(offences("measured on a Zen 4 at 1.3x"))
        self.assertTrue(offences("since commit ff276a7 the walk"))
        self.assertFalse(offences("the AVX-512 level, 0x9e3779b9, ../shared/a1b2c3d4"))


if __name__ == "__main__":
    sys.exit(unittest.main())
