"""The host part of the record every measurement carries (results/README.md):
the CPU model with its family and model numbers, its cores, the
instruction-set levels the pathtracer runs on it; and the checked-out commit.
"""
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PATHTRACER = os.path.join(ROOT, "build", "cli", "pathtracer")


def _cpuinfo():
    fields = {}
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if ":" in line:
                    key, value = (s.strip() for s in line.split(":", 1))
                    fields.setdefault(key, value)
    except OSError:
        pass
    return fields


def _git(*args):
    try:
        return subprocess.run(["git", "-C", ROOT] + list(args), capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""


def commit():
    """The checked-out commit, with "+changes" when tracked files differ from it; "unknown" outside git."""
    head = _git("rev-parse", "HEAD")
    if not head:
        return "unknown"
    return head + ("+changes" if _git("status", "--porcelain", "--untracked-files=no") else "")


def levels(pathtracer=PATHTRACER):
    """The instruction-set levels this CPU runs, as `pathtracer --list-isa` reports them; [] without the binary."""
    try:
        out = subprocess.run([pathtracer, "--list-isa"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return []
    return [f[0] for f in (line.split() for line in out.splitlines()) if len(f) > 3 and f[3] == "supported"]


def describe(pathtracer=PATHTRACER):
    """{"cpu", "cpu_family", "cpu_model", "cores", "levels"} of this machine."""
    info = _cpuinfo()
    return {
        "cpu": info.get("model name", "unknown"),
        "cpu_family": info.get("cpu family", ""),
        "cpu_model": info.get("model", ""),
        "cores": os.cpu_count(),
        "levels": levels(pathtracer),
    }
