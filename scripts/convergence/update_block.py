"""Replaces a generated block of a documentation page: the text between the lines
<!-- NAME:begin --> and <!-- NAME:end --> becomes the contents of FILE.
Fails (exit 1) when the markers are missing, so a table is never lost.

Usage: /usr/bin/python3 update_block.py PAGE.md NAME FILE"""

import sys


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    page, name, source = sys.argv[1:]
    begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
    text = open(page).read()
    if begin not in text or end not in text:
        sys.exit(f"update_block: {page} has no {begin} ... {end} block")
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    body = open(source).read().strip()
    with open(page, "w") as f:
        f.write(f"{head}{begin}\n{body}\n{end}{tail}")
    print(f"update_block: {page} block '{name}' replaced from {source}")


if __name__ == "__main__":
    main()
