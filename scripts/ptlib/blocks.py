"""Generated blocks of a Markdown page: the text between the lines
<!-- NAME:begin [ARGUMENT] --> and <!-- NAME:end -->, which a script rewrites
(a table made from data) while the rest of the page stays as written.
"""
import re


class MissingBlock(Exception):
    pass


def _find(text, path, name):
    m = re.search(rf"(<!-- {re.escape(name)}:begin(?P<arg>[^>]*)-->\n)(.*?)(<!-- {re.escape(name)}:end -->)", text, re.S)
    if not m:
        raise MissingBlock(f"{path} has no <!-- {name}:begin --> ... <!-- {name}:end --> block")
    return m


def argument(path, name):
    """What follows NAME:begin in the block's first marker (e.g. the file a table is made from)."""
    with open(path) as f:
        return _find(f.read(), path, name)["arg"].strip()


def replace(path, name, body):
    """Replaces the block's body with `body` (ended by a newline); raises MissingBlock when the markers
    are missing, so that a table is never lost. Writes only when something changed; returns whether."""
    with open(path) as f:
        text = f.read()
    m = _find(text, path, name)
    body = body.rstrip("\n") + "\n" if body.strip() else ""
    new = text[:m.start(3)] + body + text[m.end(3):]
    if new == text:
        return False
    with open(path, "w") as f:
        f.write(new)
    return True
