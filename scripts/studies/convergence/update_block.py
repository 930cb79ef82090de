#!/usr/bin/python3
"""Replaces a generated block of a documentation page: the text between the lines
<!-- NAME:begin --> and <!-- NAME:end --> becomes the contents of FILE.
Fails (exit 1) when the markers are missing, so a table is never lost.

Usage: /usr/bin/python3 update_block.py PAGE.md NAME FILE"""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))  # scripts/: ptlib
from ptlib import blocks  # noqa: E402


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    page, name, source = sys.argv[1:]
    try:
        blocks.replace(page, name, open(source).read())
    except blocks.MissingBlock as e:
        sys.exit(f"update_block: {e}")
    print(f"update_block: {page} block '{name}' replaced from {source}")


if __name__ == "__main__":
    main()
