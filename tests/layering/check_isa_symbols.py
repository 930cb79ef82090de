#!/usr/bin/env python3
"""Checks the objects of one instruction-set level (cmake/isa_levels.cmake).

  check_isa_symbols.py --level LEVEL --nm NM --objdump OBJDUMP OBJECT...

A level's objects are linked into one program with every other level's and
with the code compiled once. A symbol they define globally (strong or weak:
inline functions, template instances, their static data) is safe when its
name carries the level's namespace (pt::isa_LEVEL, see
kernels/simd/isa_namespace.h), so that no other level defines it. Any other
global symbol fails the check when
  - it names the project's namespace pt (project code outside the level's
    namespace: the linker may give it to another level's code);
  - it is writable data (state the levels would share or each hold apart);
  - it is code with an instruction beyond the lowest level (x86-64-v2: no
    VEX or EVEX encoding, no mask registers, no BMI, LZCNT or MOVBE), which
    another level's code, or code compiled once, could run on a CPU without it.
A library's inline code made only of baseline instructions (oneTBB's
internals) is the same wherever the linker takes it from, and passes.
Prints each failure on one line and exits 1 when there is one."""
import argparse
import re
import subprocess
import sys

BEYOND_BASELINE = re.compile(
    r"^(v\w+|k\w+|andn|bextr|blsi|blsmsk|blsr|bzhi|mulx|pdep|pext|rorx|sarx|shlx|shrx|lzcnt|tzcnt|movbe)$")


def global_symbols(nm, obj):
    """(demangled name, class letter, section) of every defined global symbol."""
    out = subprocess.run([nm, "--defined-only", "-C", "-f", "sysv", obj], capture_output=True, text=True,
                         check=True).stdout
    for line in out.splitlines():
        parts = [p.strip() for p in line.split("|")]
        if len(parts) < 7 or not parts[2]:
            continue
        name, cls, section = parts[0], parts[2], parts[6]
        if cls.isupper() or cls in "uvw":  # global, weak or unique binding
            yield name, cls, section


def code_instructions(objdump, obj):
    """Mnemonics of every function of the object, by demangled name."""
    out = subprocess.run([objdump, "-d", "-C", "--no-show-raw-insn", obj], capture_output=True, text=True,
                         check=True).stdout
    functions, current = {}, None
    for line in out.splitlines():
        head = re.match(r"^[0-9a-f]+ <(.*)>:$", line)
        if head:
            current = functions.setdefault(head.group(1), set())
            continue
        body = re.match(r"^\s+[0-9a-f]+:\s+(\S+)", line)
        if body and current is not None:
            mnemonic = body.group(1)
            if mnemonic in ("rex", "rex.W", "data16", "lock", "rep", "repz", "repnz", "notrack", "bnd", "cs", "ds"):
                continue
            current.add(mnemonic)
    return functions


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--level", required=True)
    ap.add_argument("--nm", default="nm")
    ap.add_argument("--objdump", default="objdump")
    ap.add_argument("objects", nargs="+")
    a = ap.parse_args()
    own = f"isa_{a.level.replace('.', '')}::"
    failures = []
    for obj in a.objects:
        instructions = None
        for name, cls, section in global_symbols(a.nm, obj):
            if own in name or name.startswith("DW.ref."):  # DW.ref: the unwinder's constant personality pointer
                continue
            where = f"{obj.rsplit('/', 1)[-1]}: {name}"
            if re.search(r"(^|[^\w:])pt::", name):
                failures.append(f"{where}: project symbol outside namespace pt::{own[:-2]}")
            elif section.startswith((".data", ".bss", ".tdata", ".tbss")) and not section.startswith(".data.rel.ro"):
                failures.append(f"{where}: writable data outside the level's namespace")
            elif section.startswith(".text"):
                if instructions is None:
                    instructions = code_instructions(a.objdump, obj)
                beyond = sorted(m for m in instructions.get(name, ()) if BEYOND_BASELINE.match(m))
                if beyond:
                    failures.append(f"{where}: code outside the level's namespace uses {' '.join(beyond[:6])}")
    for f in failures:
        print(f"check_isa_symbols: {f}")
    print(f"check_isa_symbols: level {a.level}, {len(a.objects)} objects, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
